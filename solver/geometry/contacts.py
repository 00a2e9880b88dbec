"""Pair separations of grains in a cell periodic in x and y (lengths in nm).

`separation` returns, for pairs (i, j), a unit normal n (from i towards j) and a *gap* that is
never larger than the true signed distance between the two bodies (distance when apart, minus
the penetration depth when overlapping): exact for spheres, a separating-axis lower bound
(`separating_axis`) for the others, each shape choosing its candidate axes and searches
(`shapes/`).  A pair we cannot certify is treated as overlapping (conservative), so "no
overlap" is always rigorous.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .separating_axis import SEARCH_ITERATIONS

if TYPE_CHECKING:
    from .bodies import Bodies


@dataclass(frozen=True, eq=False)
class Separation:
    normal: np.ndarray   # (P, 3) unit, pointing from body i to body j
    gap_nm: np.ndarray   # (P,) lower bound of the signed distance (negative: overlap)


def separation(bodies: Bodies, centres: np.ndarray, i: np.ndarray, j: np.ndarray,
               period_nm: tuple[float, float], hint: np.ndarray | None = None,
               margin_nm: float = 0.0, centres_j: np.ndarray | None = None,
               bodies_j: Bodies | None = None, search_iterations: int = SEARCH_ITERATIONS,
               full_search: bool = True) -> Separation:
    """Separation of pairs (i, j); j indexes `centres_j`/`bodies_j` when given (cross pairs).

    Where the gap comes from a search, it stops as soon as a pair is certified apart by
    `margin_nm`; `hint` (P, 3) warm-starts it with each pair's axis from a previous call; with
    full_search=False only a local search from the best candidate follows (packing iterations).
    Fewer `search_iterations` or no full search trade the accuracy of the penetration depth
    (never the rigour of a certificate: gap >= 0 is always proven) for speed."""
    return bodies.shape.separation(bodies, centres, bodies if bodies_j is None else bodies_j,
                                   centres if centres_j is None else centres_j, i, j, period_nm, hint,
                                   margin_nm, search_iterations, full_search)


def horizontal_separation(bodies: Bodies, centres: np.ndarray, i: np.ndarray, j: np.ndarray,
                          period_nm: tuple[float, float]) -> Separation:
    """Best *horizontal* separating axis of each pair and its gap g (n_z = 0).

    Moving the pair apart by −g along it separates them, without any motion in z — the way out
    when the walls block the vertical push (a column of particles taller than the layer)."""
    return bodies.shape.horizontal_separation(bodies, centres, i, j, period_nm)
