"""Windows of a regular 1-D lattice around particles (shared by the voxeliser and the pictures).

Lattice points sit at x_k = (k + ½)·spacing, k = 0, 1, ... (periodic: k wraps modulo the count
in the caller).  For a particle centred at c with half extent h, the points inside [c − h, c + h]
are k = k0 ... k0 + count − 1; windows of all particles are padded to the same width m and
masked.
"""

from __future__ import annotations

import numpy as np


def windows(centre_nm: np.ndarray, half_extent_nm: np.ndarray, spacing_nm: float):
    """Lattice windows covering [c − h, c + h] for each particle.

    Returns (k, valid, offset_nm): k (N, m) integer lattice indices (not wrapped), valid (N, m)
    mask, offset_nm (N, m) = x_k − c (position of the point relative to the centre)."""
    lo = np.ceil((centre_nm - half_extent_nm) / spacing_nm - 0.5).astype(np.int64)
    hi = np.floor((centre_nm + half_extent_nm) / spacing_nm - 0.5).astype(np.int64)
    count = np.maximum(hi - lo + 1, 0)
    m = int(count.max()) if count.size else 0
    k = lo[:, None] + np.arange(max(m, 1))[None, :]
    valid = np.arange(max(m, 1))[None, :] < count[:, None]
    offset = (k + 0.5) * spacing_nm - centre_nm[:, None]
    return k, valid, offset


def grid_windows(cx, cy, hx, hy, spacing_x_nm: float, spacing_y_nm: float):
    """2-D windows (outer product of x and y windows), flattened to (N, mx·my).

    Returns (kx, ky, valid, dx, dy), each (N, mx·my)."""
    kx, vx, ox = windows(cx, hx, spacing_x_nm)
    ky, vy, oy = windows(cy, hy, spacing_y_nm)
    my = ky.shape[1]
    mx = kx.shape[1]
    kx2, vx2, dx2 = (np.repeat(a, my, axis=1) for a in (kx, vx, ox))
    ky2, vy2, dy2 = (np.tile(a, (1, mx)) for a in (ky, vy, oy))
    return kx2, ky2, vx2 & vy2, dx2, dy2


def chunks(n: int, per_item: int, budget: int = 4_000_000):
    """Slices of range(n) so that chunk_size × per_item stays under budget (memory)."""
    size = max(1, budget // max(1, per_item))
    return [slice(a, min(n, a + size)) for a in range(0, n, size)]
