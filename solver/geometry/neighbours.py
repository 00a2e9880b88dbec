"""Neighbour search in a cell periodic in x and y (not in z); lengths in nm.

* `neighbour_pairs`: all pairs of one point set closer than a cut-off (k-d tree);
* `cross_pairs`: pairs between two point sets (RSA candidates against placed particles);
* `PairList`: a Verlet list with a skin, rebuilt only when a particle has moved too far;
* `spatial_order`: a permutation that sorts particles by coarse grid cell (memory locality).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree


def wrap_xy(centres: np.ndarray, period_nm: tuple[float, float]) -> np.ndarray:
    """Centres with x, y brought into [0, L)."""
    out = np.array(centres, dtype=float, copy=True)
    for k in (0, 1):
        out[:, k] = np.mod(out[:, k], period_nm[k])
        out[out[:, k] >= period_nm[k], k] = 0.0
    return out


def min_image(d: np.ndarray, period_nm: tuple[float, float]) -> np.ndarray:
    """Nearest periodic image of separation vectors d (..., 3) in x and y (in place, returned)."""
    for k in (0, 1):
        d[..., k] -= period_nm[k] * np.round(d[..., k] / period_nm[k])
    return d


def _tree(centres: np.ndarray, period_nm) -> cKDTree:
    return cKDTree(wrap_xy(centres, period_nm), boxsize=[period_nm[0], period_nm[1], 0.0])


def neighbour_pairs(centres: np.ndarray, cutoff_nm: float, period_nm: tuple[float, float]):
    """All pairs i < j whose centres lie closer than cutoff (periodic in x, y; not in z)."""
    if len(centres) < 2:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    pairs = _tree(centres, period_nm).query_pairs(cutoff_nm, output_type="ndarray")
    return pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)


def cross_pairs(centres_a: np.ndarray, centres_b: np.ndarray, cutoff_nm: float, period_nm):
    """Pairs (ia, ib) between two point sets whose centres lie closer than cutoff."""
    if len(centres_a) == 0 or len(centres_b) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    tree_b = _tree(centres_b, period_nm)
    tree_a = _tree(centres_a, period_nm)
    matrix = tree_a.sparse_distance_matrix(tree_b, cutoff_nm, output_type="ndarray")
    return matrix["i"].astype(np.int64), matrix["j"].astype(np.int64)


def spatial_order(centres: np.ndarray, cell_nm: float) -> np.ndarray:
    """Permutation that sorts particles by coarse grid cell (memory locality of pair gathers)."""
    if len(centres) == 0:
        return np.zeros(0, dtype=np.int64)
    cell = np.floor(centres / max(cell_nm, 1e-9)).astype(np.int64)
    cell -= cell.min(axis=0)
    span = cell.max(axis=0) + 1
    return np.argsort((cell[:, 2] * span[1] + cell[:, 1]) * span[0] + cell[:, 0], kind="stable")


class PairList:
    """Verlet pair list with a skin: the pairs (i < j, sorted) whose centres were closer than
    `cutoff` at the last build; valid while reach + 2·(largest move since the build) ≤ cutoff.

    `hint` is free for the caller to keep per-pair data (e.g. the last separating axes); it is
    reset to None at every rebuild, when the pair set changes."""

    def __init__(self, period_nm, skin_nm: float):
        self.period, self.skin = period_nm, float(skin_nm)
        self.ref: np.ndarray | None = None
        self.cutoff = -1.0
        self.rebuilds = 0
        self.hint = None
        self.i = self.j = np.zeros(0, dtype=np.int64)

    def pairs(self, xyz: np.ndarray, reach_nm: float, reach_max_nm: float):
        """(i, j) of all pairs that may be closer than reach_nm; xyz is (3, N)."""
        stale = self.ref is None
        if not stale:
            moved = np.sqrt(np.max(np.sum((xyz - self.ref) ** 2, axis=0), initial=0.0))
            stale = reach_nm + 2.0 * moved > self.cutoff
        if stale:
            self.cutoff = reach_max_nm + self.skin
            i, j = neighbour_pairs(xyz.T, self.cutoff, self.period)
            order = np.argsort(i * (xyz.shape[1] + 1) + j)
            self.i, self.j = i[order], j[order]
            self.hint = None
            self.ref = xyz.copy()
            self.rebuilds += 1
        return self.i, self.j
