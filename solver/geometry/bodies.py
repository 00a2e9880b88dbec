"""A set of N grains of one shape: sizes and axes (positions live elsewhere: the packer moves them).

Every grain is axisymmetric: a radius r, a half length h along its unit axis a (a_z ≥ 0: a and
−a are one axis) — a sphere has h = 0 and a = (0, 0, 1); what r and h mean (a cylinder's radius
and half length, a spheroid's equatorial and polar semi-axes) is the shape's (`shapes/`), and
every question about the grains' geometry is answered by it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .shapes.base import Shape


@dataclass(frozen=True, eq=False)
class Bodies:
    """Sizes and orientations of N particles of one shape."""

    shape: Shape
    radii_nm: np.ndarray         # (N,)
    half_lengths_nm: np.ndarray  # (N,) half length along the axis (0 for spheres)
    axes: np.ndarray             # (N, 3) unit vectors, a_z >= 0; (0, 0, 1) without an axis

    @classmethod
    def of(cls, shape: Shape, diameters_nm: np.ndarray, axes: np.ndarray) -> "Bodies":
        """Grains of the given effective diameters (spheres of equal volume) and axes."""
        radii, half_lengths = shape.dimensions(np.asarray(diameters_nm, dtype=float))
        return cls(shape, radii, half_lengths, axes)

    def __len__(self) -> int:
        return len(self.radii_nm)

    def scaled(self, factor: float) -> "Bodies":
        """The same bodies with every length multiplied by `factor` (growth during packing)."""
        return Bodies(self.shape, self.radii_nm * factor, self.half_lengths_nm * factor, self.axes)

    def take(self, index) -> "Bodies":
        return Bodies(self.shape, self.radii_nm[index], self.half_lengths_nm[index], self.axes[index])

    def turned(self, axes: np.ndarray) -> "Bodies":
        """The same bodies with new axes."""
        return Bodies(self.shape, self.radii_nm, self.half_lengths_nm, axes)

    @property
    def volumes_nm3(self) -> np.ndarray:
        return self.shape.volumes_nm3(self.radii_nm, self.half_lengths_nm)

    def half_extent_nm(self, direction: int) -> np.ndarray:
        """Half of the particle's extent along coordinate axis 0, 1 or 2 (x, y, z)."""
        return self.shape.half_extent_nm(self, direction)

    @property
    def bounding_radii_nm(self) -> np.ndarray:
        """Radius of the sphere about the centre that encloses the particle."""
        return self.shape.bounding_radius_nm(self.radii_nm, self.half_lengths_nm)

    @property
    def smallest_half_width_nm(self) -> np.ndarray:
        """Smallest half-width of each particle over all directions (its thinnest part)."""
        return self.shape.smallest_half_width_nm(self.radii_nm, self.half_lengths_nm)

    @property
    def inertia(self) -> np.ndarray:
        """Transverse moment of inertia per unit density (nm⁵) of each particle."""
        return self.shape.inertia_nm5(self)


def z_chords(bodies: Bodies, dx: np.ndarray, dy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where vertical lines cross each particle, relative to its centre.

    dx, dy: lateral offsets (nm) of the lines from the particle centres, shape (N, M) for N
    bodies.  Returns (z_lo, z_hi), shape (N, M); z_lo >= z_hi marks a line that misses."""
    return bodies.shape.z_chords(bodies, dx, dy)


def contains(bodies: Bodies, dx: np.ndarray, dy: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """Whether points at offsets (dx, dy, dz) (shape (N, M)) from each centre lie inside."""
    return bodies.shape.contains(bodies, dx, dy, dz)
