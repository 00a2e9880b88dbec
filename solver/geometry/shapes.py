"""Single-particle geometry: spheres and finite circular cylinders (lengths in nm).

A particle set is a `Bodies` (sizes and axes; positions live elsewhere because the packer moves
them).  A sphere is a cylinder-free body with half_length 0; cylinders have half length L/2 and a
unit axis with a_z ≥ 0 (a cylinder is symmetric under a → −a).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

_EPS = 1e-12


@dataclass(frozen=True, eq=False)
class Bodies:
    """Sizes and orientations of N particles of one shape ('sphere' or 'cylinder')."""

    shape: str
    radii_nm: np.ndarray         # (N,)
    half_lengths_nm: np.ndarray  # (N,) cylinder half length; 0 for spheres
    axes: np.ndarray             # (N, 3) unit vectors, a_z >= 0; (0, 0, 1) for spheres

    def __len__(self) -> int:
        return len(self.radii_nm)

    def scaled(self, factor: float) -> "Bodies":
        """The same bodies with every length multiplied by `factor` (growth during packing)."""
        return Bodies(self.shape, self.radii_nm * factor, self.half_lengths_nm * factor, self.axes)

    def take(self, index) -> "Bodies":
        return Bodies(self.shape, self.radii_nm[index], self.half_lengths_nm[index], self.axes[index])

    @property
    def volumes_nm3(self) -> np.ndarray:
        r = self.radii_nm
        if self.shape == "sphere":
            return 4.0 / 3.0 * np.pi * r**3
        return np.pi * r**2 * (2.0 * self.half_lengths_nm)

    def half_extent_nm(self, direction: int) -> np.ndarray:
        """Half of the particle's extent along coordinate axis 0, 1 or 2 (x, y, z)."""
        if self.shape == "sphere":
            return self.radii_nm.copy()
        a = np.abs(self.axes[:, direction])
        return self.half_lengths_nm * a + self.radii_nm * np.sqrt(np.clip(1.0 - a * a, 0.0, None))

    @property
    def bounding_radii_nm(self) -> np.ndarray:
        """Radius of the sphere about the centre that encloses the particle."""
        return np.hypot(self.radii_nm, self.half_lengths_nm)


def z_chords(bodies: Bodies, dx: np.ndarray, dy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where vertical lines cross each particle, relative to its centre.

    dx, dy: lateral offsets (nm) of the lines from the particle centres, shape (N, M) for N
    bodies.  Returns (z_lo, z_hi), shape (N, M); z_lo >= z_hi marks a line that misses.
    Exact for spheres and for cylinders of any orientation (line ∩ infinite cylinder ∩ slab).
    """
    r = bodies.radii_nm[:, None]
    rho2 = dx * dx + dy * dy
    if bodies.shape == "sphere":
        w = np.sqrt(np.clip(r * r - rho2, 0.0, None))
        w = np.where(rho2 < r * r, w, -1.0)
        return -w, w
    ax, ay, az = (bodies.axes[:, k][:, None] for k in range(3))
    h = bodies.half_lengths_nm[:, None]
    ua = dx * ax + dy * ay                          # u·a for the lateral offset u
    # Infinite cylinder: A z² + B z + C <= 0.
    a_q = 1.0 - az * az
    b_q = -2.0 * az * ua
    c_q = rho2 - ua * ua - r * r
    steep = a_q <= _EPS                             # (near-)vertical axis: all z or none
    disc = b_q * b_q - 4.0 * a_q * c_q
    sq = np.sqrt(np.clip(disc, 0.0, None))
    a_safe = np.where(steep, 1.0, a_q)
    lo_c = np.where(steep, -np.inf, (-b_q - sq) / (2.0 * a_safe))
    hi_c = np.where(steep, np.inf, (-b_q + sq) / (2.0 * a_safe))
    miss_c = np.where(steep, c_q > 0.0, disc < 0.0)
    # Slab |u·a + z a_z| <= h.
    flat = az <= 1e-9
    az_safe = np.where(flat, 1.0, az)
    lo_s = np.where(flat, -np.inf, (-h - ua) / az_safe)
    hi_s = np.where(flat, np.inf, (h - ua) / az_safe)
    miss_s = flat & (np.abs(ua) > h)
    lo = np.maximum(lo_c, lo_s)
    hi = np.minimum(hi_c, hi_s)
    miss = miss_c | miss_s | (lo >= hi)
    return np.where(miss, 0.0, lo), np.where(miss, 0.0, hi)


def contains(bodies: Bodies, dx: np.ndarray, dy: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """Whether points at offsets (dx, dy, dz) (shape (N, M)) from each centre lie inside."""
    r = bodies.radii_nm[:, None]
    if bodies.shape == "sphere":
        return dx * dx + dy * dy + dz * dz < r * r
    ax, ay, az = (bodies.axes[:, k][:, None] for k in range(3))
    t = dx * ax + dy * ay + dz * az
    radial2 = dx * dx + dy * dy + dz * dz - t * t
    return (np.abs(t) < bodies.half_lengths_nm[:, None]) & (radial2 < r * r)


def sample_orientations(mode: str, n: int, rng: np.random.Generator, tilt_rad: float = 0.0) -> np.ndarray:
    """Unit axes (n, 3), a_z ≥ 0, uniform on the part of the sphere the mode allows (Archimedes:
    uniform on the sphere ⇔ a_z uniform), azimuth uniform:

    * 'isotropic': the whole sphere, a_z uniform in [0, 1];
    * 'vertical': the cap within tilt_rad of the vertical, a_z uniform in [cos tilt, 1]
      (tilt 0: all (0, 0, 1));
    * 'inplane': the band within tilt_rad of the layer plane, a_z uniform in [0, sin tilt]
      (tilt 0: a_z = 0)."""
    if mode not in ("isotropic", "inplane", "vertical"):
        raise ValueError(f"unknown orientation {mode!r}")
    if mode == "vertical" and tilt_rad == 0:
        return np.tile([0.0, 0.0, 1.0], (n, 1))
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    if mode == "isotropic":
        cos_t = rng.uniform(0.0, 1.0, n)
    elif mode == "vertical":
        cos_t = rng.uniform(np.cos(tilt_rad), 1.0, n)
    elif tilt_rad > 0:
        cos_t = rng.uniform(0.0, np.sin(tilt_rad), n)
    else:
        cos_t = np.zeros(n)
    sin_t = np.sqrt(1.0 - cos_t**2)
    return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=1)
