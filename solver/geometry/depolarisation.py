"""How a layer's grains polarise: the local-field model of a particle spec (docs/polarisation.md).

A small grain in the binder polarises: the field inside it along its principal axis j is
ε_h/(ε_h + L_j(ε_p − ε_h)) times the field outside (L_j its depolarisation factor, Σ L_j = 1).
The scalar equation has no such surface condition, so the layer's pigments enter with the
permittivity whose contrast carries that response (`materials.local_field_eps`). Each axis is
weighted by the mean of (e·a_j)² over the grains' orientations and the field's directions e.
The shape supplies its factors (`Shape.local_field`):

* spheres: L = 1/3 on every axis, one pair (1, 1/3); dissolved pigment (molecular inks): the
  same for each base pigment's molecules in their Lorentz cavity (`materials.DISSOLVED_FIELD`);
* grains with a symmetry axis (`axial_field`): L_∥ along the axis and L_⊥ = (1 − L_∥)/2 across
  it — a spheroid's exact factors (`spheroid_axial_factor`), a cylinder's those of the prolate
  spheroid of the same aspect ratio (the standard stand-in for a finite cylinder). The field is
  taken in the layer's plane, unpolarised (light crosses the layer near its normal: inside the
  binder every ray is within 40° of it), so an axis a gets weight ⟨(e·a)²⟩ = (1 − ⟨a_z²⟩)/2,
  with ⟨a_z²⟩ over the spec's orientation distribution (`orientation.sample_orientations`: a_z
  uniform on its range).
"""

from __future__ import annotations

import math

from ..materials import DISSOLVED_FIELD, LocalField
from .orientation import polar_range_rad


def spheroid_axial_factor(aspect: float) -> float:
    """Depolarisation factor along the symmetry axis of a spheroid of aspect ratio
    aspect = (axial length)/(equatorial diameter) > 0 (1: a sphere, 1/3)."""
    if abs(aspect - 1.0) < 1e-9:
        return 1.0 / 3.0
    if aspect > 1.0:                                    # prolate
        e = math.sqrt(1.0 - 1.0 / aspect**2)
        return (1.0 - e * e) / (e * e) * (math.atanh(e) / e - 1.0)
    e = math.sqrt(1.0 - aspect**2)                      # oblate
    return (1.0 - math.sqrt(1.0 - e * e) * math.asin(e) / e) / (e * e)


def mean_axis_z_squared(spec) -> float:
    """⟨a_z²⟩ of the axes drawn for the spec: a_z = cos(polar angle) uniform between the
    cosines of its polar range."""
    lo, hi = polar_range_rad(spec.orientation, spec.tilt_rad)
    c0, c1 = math.cos(hi), math.cos(lo)
    if c1 - c0 < 1e-12:
        return c1 * c1
    return (c1**3 - c0**3) / (3.0 * (c1 - c0))


def axial_field(l_axial: float, spec) -> LocalField:
    """The local field of axisymmetric grains with axial factor l_axial, their axes drawn as
    the spec's orientation and tilt say (module doc)."""
    w_axial = 0.5 * (1.0 - mean_axis_z_squared(spec))
    return LocalField(((w_axial, l_axial), (1.0 - w_axial, 0.5 * (1.0 - l_axial))))


def local_field_of(spec) -> LocalField:
    """The local-field model of a layer's grains (None: dissolved pigment, molecules in the
    Lorentz sphere)."""
    return DISSOLVED_FIELD if spec is None else spec.shape.local_field(spec)
