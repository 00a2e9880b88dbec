"""How far the placement goes: the reachable pigment concentrations.

RSA (random sequential addition) places particles directly up to the shape's `rsa_fraction`;
above it the particles are placed by RSA at a reduced size and grown by the packer (`packing`).

`reachable_limit(layer)` is the largest total pigment volume fraction accepted.  It is the
smaller of
* an empirical limit of the packer per shape and orientation (`Shape.packer_limit`), measured
  with `python -m benchmarks.bench_geometry --limits` (H = 1000 nm, 100-nm particles in
  1000-nm cells, larger ones in 2000-nm cells; see docs/geometry.md): the lowest fraction
  reached for every size, and
* a rigorous geometric bound where the shape knows one (`Shape.geometric_limit`: vertical
  cylinders longer than half the layer all cross its mid-plane, where their sections are
  disjoint discs).

`smallest_tilt_reaching(layer)` picks the smallest spread from a list for which the layer's
concentration is within `reachable_limit`.
"""

from __future__ import annotations

import dataclasses
import math

from .orientation import TILTED_ORIENTATIONS
from .spec import GeometryError, LayerSpec

#: Orientation spreads (degrees) tried by `smallest_tilt_reaching`.
DEFAULT_TILTS_DEG = (0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0)


def aligned_column_bound(layer: LayerSpec) -> float | None:
    """The fraction aligned grains fill when hexagonally packed, one per column (a rigorous
    upper bound for grains too long to stack two in the layer), None where that does not apply
    (`Shape.aligned_column_bound`)."""
    return layer.particles.shape.aligned_column_bound(layer)


def reachable_limit(layer: LayerSpec) -> float:
    """Largest total pigment volume fraction the generator accepts for this layer."""
    spec = layer.particles
    return min(spec.shape.packer_limit(layer), spec.shape.geometric_limit(layer))


def smallest_tilt_reaching(layer: LayerSpec, tilts_deg=DEFAULT_TILTS_DEG) -> float | None:
    """Smallest orientation spread (degrees) from tilts_deg with which the layer's concentration
    is reachable (`reachable_limit`), None if none is; the layer's own tilt is replaced.

    Particles without a spread option (spheres, isotropic axes) give 0.0 when the layer is
    reachable as it is, else None.  Spreads that make a particle higher than the layer are
    skipped."""
    spec = layer.particles
    target = layer.ink.total_fraction
    if spec.orientation not in TILTED_ORIENTATIONS:
        return 0.0 if target <= reachable_limit(layer) else None
    for tilt in sorted(float(t) for t in tilts_deg):
        try:
            tilted = dataclasses.replace(layer, particles=dataclasses.replace(spec, tilt_rad=math.radians(tilt)))
        except GeometryError:
            continue
        if target <= reachable_limit(tilted):
            return tilt
    return None
