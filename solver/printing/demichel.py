"""Which printed primaries a halftone of several inks shows, and how much of each (Demichel).

With k inks printed one after another, dots placed independently of each other, a point of the
page carries the set S ⊆ {0, …, k−1} of inks with probability (area fraction)

    a_S = Π_{i∈S} c_i · Π_{j∉S} (1 − c_j)        (Demichel; Σ_S a_S = 1)

where c_i is the coverage of ink i. S = () is bare paper. Inks are numbered in printing order
(index 0 printed first): the stack of S, read from the top, is `stack_order(S)`. Subsets are
tuples of ascending 0-based indices everywhere in this package.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np

Subset = tuple[int, ...]


def all_subsets(n_inks: int) -> tuple[Subset, ...]:
    """Every subset of {0, …, n_inks−1}: bare paper first, then by size, then lexicographic."""
    if n_inks < 1:
        raise ValueError(f"need at least one ink, got {n_inks}")
    return tuple(s for size in range(n_inks + 1) for s in combinations(range(n_inks), size))


def stack_order(subset: Subset) -> Subset:
    """The inks of a printed primary from the top down (the last printed lies on top)."""
    return tuple(sorted(subset, reverse=True))


def check_subset(subset, n_inks: int) -> Subset:
    """A subset as a tuple of ascending distinct indices in [0, n_inks); ValueError otherwise."""
    s = tuple(int(i) for i in subset)
    if list(s) != sorted(set(s)) or any(i < 0 or i >= n_inks for i in s):
        raise ValueError(f"subset {subset!r} must list distinct ink indices 0..{n_inks - 1} in "
                         "ascending order")
    return s


def clamp_coverages(coverages) -> np.ndarray:
    """Coverages as floats clamped to [0, 1] (as the BSDF clamps its coverage textures)."""
    c = np.asarray(coverages, dtype=np.float64)
    if c.ndim < 1 or c.shape[-1] < 1:
        raise ValueError("coverages need a last axis with one value per ink")
    if not np.all(np.isfinite(c)):
        raise ValueError("coverages must be finite")
    return np.clip(c, 0.0, 1.0)


def demichel_weights(coverages, subsets=None) -> np.ndarray:
    """Area fractions a_S of `subsets` (default: all) for coverages [..., k] → [..., n_subsets]."""
    c = clamp_coverages(coverages)
    k = c.shape[-1]
    subsets = all_subsets(k) if subsets is None else tuple(check_subset(s, k) for s in subsets)
    out = np.empty(c.shape[:-1] + (len(subsets),))
    for n, s in enumerate(subsets):
        w = np.ones(c.shape[:-1])
        for i in range(k):
            w = w * (c[..., i] if i in s else 1.0 - c[..., i])
        out[..., n] = w
    return out
