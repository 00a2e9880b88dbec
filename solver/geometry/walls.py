"""Where a particle's centre may be in z (z grows downward; layer 0 ≤ z ≤ thickness).

Flat top: the whole particle lies in 0 ≤ z ≤ H.  Rough top (paper Fig. 5): particle k may stand
out of the binder's top surface by a fraction f_k of its height (f_k drawn uniformly in
[0, rough_top] per particle), i.e. its top may reach z = −f_k·2·h_z.  With h_z the particle's
half height, the centre's range is

    (1 − 2 f_k)·h_z  ≤  z_c  ≤  H − h_z .
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bodies import Bodies


@dataclass(frozen=True, eq=False)
class Walls:
    thickness_nm: float
    protrusion: np.ndarray      # (N,) f_k, fraction of the particle's height allowed above z = 0

    def centre_bounds(self, bodies: Bodies) -> tuple[np.ndarray, np.ndarray]:
        """Lowest and highest allowed centre z (nm) for bodies (already scaled)."""
        hz = bodies.half_extent_nm(2)
        return (1.0 - 2.0 * self.protrusion) * hz, self.thickness_nm - hz

    def clamp(self, xyz: np.ndarray, bodies: Bodies) -> None:
        """Clamp centre z (row 2 of xyz, shape (3, N)) into the allowed range, in place."""
        lo, hi = self.centre_bounds(bodies)
        np.clip(xyz[2], lo, hi, out=xyz[2])

    def take(self, index) -> "Walls":
        return Walls(self.thickness_nm, self.protrusion[index])


def draw_protrusion(rough_top: float, n: int, rng: np.random.Generator) -> np.ndarray:
    """Per-particle protruding fraction: 0 for a flat top, uniform in [0, rough_top] otherwise."""
    if rough_top <= 0:
        return np.zeros(n)
    return rng.uniform(0.0, rough_top, n)
