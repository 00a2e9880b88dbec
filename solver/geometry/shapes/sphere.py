"""Spheres of diameter D (docs/design.md §3): radius D/2, no axis; everything exact and closed form.

Bodies of spheres have half length 0 and axis (0, 0, 1).  Pair gaps are |d| − r_i − r_j from the
coordinates (1-D gathers: the fast path of 10⁵ grains); the binder over a protruding sphere is its
cap and the tangent cone of the meniscus.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...materials import SPHERE_FIELD
from ..contacts import Separation
from ..neighbours import min_image
from ..separating_axis import unit
from .base import Shape


def sphere_gaps(xyz_i, xyz_j, i, j, contact_nm, period_nm):
    """Exact sphere pair gaps from coordinate arrays (x, y, z) (fast path: 1-D gathers).

    Returns (nx, ny, nz, gap): unit normal from i to j and |d| − contact."""
    dx = xyz_j[0][j] - xyz_i[0][i]
    dx -= period_nm[0] * np.round(dx * (1.0 / period_nm[0]))
    dy = xyz_j[1][j] - xyz_i[1][i]
    dy -= period_nm[1] * np.round(dy * (1.0 / period_nm[1]))
    dz = xyz_j[2][j] - xyz_i[2][i]
    dist = np.sqrt(dx * dx + dy * dy + dz * dz)
    inv = 1.0 / np.where(dist > 0, dist, 1.0)
    dz = np.where(dist > 0, dz * inv, 1.0)          # coincident centres: push along z
    return dx * inv, dy * inv, dz, dist - contact_nm


@dataclass(frozen=True)
class Sphere(Shape):
    name = "sphere"
    plural = "spheres"
    grammar = "sphere:D"
    rsa_fraction = 0.25                 # RSA jams at ≈ 38 %
    packer_limits = {None: 0.58}
    place_cost = {None: ((0.0, 0.0, 15.0), (0.15, 0.05, 18.0), (0.30, 0.2, 30.0), (0.50, 0.6, 36.0),
                         (0.58, 2.0, 100.0))}
    agglutination_cost = (0.1, 1200.0)
    gen_bytes_per_grain = 1000.0

    def dimensions(self, diameter_nm):
        return 0.5 * diameter_nm, np.zeros_like(diameter_nm)

    def max_height_nm(self, diameter_nm, polar_range):
        return diameter_nm

    def span_nm(self, diameter_nm):
        return diameter_nm

    def volumes_nm3(self, radii_nm, half_lengths_nm):
        return 4.0 / 3.0 * np.pi * radii_nm**3

    def width(self, c, radius, half_length):
        return np.broadcast_to(radius, np.broadcast_shapes(np.shape(c), np.shape(radius))).astype(float)

    def support_point(self, axes, half_lengths, radii, n):
        return radii[:, None] * n

    def half_extent_nm(self, bodies, direction):
        return bodies.radii_nm.copy()

    def bounding_radius_nm(self, radii_nm, half_lengths_nm):
        return radii_nm

    def smallest_half_width_nm(self, radii_nm, half_lengths_nm):
        return radii_nm

    def inertia_nm5(self, bodies):
        return 0.4 * bodies.volumes_nm3 * bodies.radii_nm**2

    def z_chords(self, bodies, dx, dy):
        r = bodies.radii_nm[:, None]
        rho2 = dx * dx + dy * dy
        w = np.sqrt(np.clip(r * r - rho2, 0.0, None))
        w = np.where(rho2 < r * r, w, -1.0)
        return -w, w

    def contains(self, bodies, dx, dy, dz):
        r = bodies.radii_nm[:, None]
        return dx * dx + dy * dy + dz * dz < r * r

    def separation(self, bodies_i, centres_i, bodies_j, centres_j, i, j, period_nm, hint, margin_nm,
                   search_iterations, full_search):
        nx, ny, nz, gap = sphere_gaps(tuple(centres_i[:, k] for k in range(3)),
                                      tuple(centres_j[:, k] for k in range(3)), i, j,
                                      bodies_i.radii_nm[i] + bodies_j.radii_nm[j], period_nm)
        return Separation(np.stack([nx, ny, nz]).T, gap)

    def horizontal_separation(self, bodies, centres, i, j, period_nm):
        d = min_image(centres[j] - centres[i], period_nm)
        d[:, 2] = 0.0
        n, dist = unit(d)
        n[dist == 0] = (1.0, 0.0, 0.0)
        return Separation(n, dist - bodies.radii_nm[i] - bodies.radii_nm[j])

    def meniscus_nm(self, radius_nm, half_length_nm, axis, z_centre_nm, dx, dy, angle_rad):
        """The spherical cap z_c − √(R² − ρ²) for ρ ≤ R sin α, the tangent cone
        z_c − R/cos α + ρ tan α beyond."""
        rho = np.hypot(dx, dy)
        cap = z_centre_nm - np.sqrt(np.clip(radius_nm * radius_nm - rho * rho, 0.0, None))
        cone = z_centre_nm - radius_nm / np.cos(angle_rad) + rho * np.tan(angle_rad)
        return np.where(rho <= radius_nm * np.sin(angle_rad), cap, cone)

    def local_field(self, spec):
        return SPHERE_FIELD

    def column_group(self, diameter_nm):
        return f"Balls {diameter_nm:g} nm"
