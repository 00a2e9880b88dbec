"""Random sequential addition (RSA) of hard particles in the periodic slab.

Particles are taken in order; each tries a uniformly random position (x, y in the cell, z in its
allowed range) and is kept if it overlaps nothing placed before it, otherwise it tries again
later.  Tries are made in batches (vectorised): a candidate is checked against the placed
particles, then against the earlier candidates of its batch that were kept, which is exactly the
sequential rule.  RSA stalls near its jamming limit (≈ 38 % for spheres): it stops after a try
budget and reports who is left for the packer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .contacts import separation
from .neighbours import cross_pairs, neighbour_pairs
from .bodies import Bodies
from .walls import Walls


@dataclass(frozen=True, eq=False)
class RsaResult:
    centres: np.ndarray      # (N, 3); NaN rows for particles not placed
    placed: np.ndarray       # (N,) bool
    tries: int


def random_positions(bodies: Bodies, walls: Walls, period_nm, rng: np.random.Generator) -> np.ndarray:
    """Uniform positions: x, y in the cell, z uniform in each particle's allowed centre range."""
    lo, hi = walls.centre_bounds(bodies)
    n = len(bodies)
    return np.stack([rng.uniform(0.0, period_nm[0], n), rng.uniform(0.0, period_nm[1], n),
                     lo + (hi - lo) * rng.uniform(0.0, 1.0, n)], axis=1)


def _sequential_keep(owner: np.ndarray, first: np.ndarray, second: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Sequential rule inside a batch of candidates (in try order): candidate b is kept if its
    particle has no earlier kept candidate and no earlier kept candidate conflicts with it."""
    order = np.argsort(second, kind="stable")
    first, second = first[order].tolist(), second[order].tolist()
    kept = np.zeros_like(ok)
    done: set[int] = set()
    p = 0
    for b in np.flatnonzero(ok).tolist():
        clash = False
        while p < len(second) and second[p] < b:
            p += 1
        q = p
        while q < len(second) and second[q] == b:
            clash = clash or kept[first[q]]
            q += 1
        if not clash and owner[b] not in done:
            kept[b] = True
            done.add(owner[b])
    return kept


def rsa(bodies: Bodies, walls: Walls, period_nm, rng: np.random.Generator,
        max_tries_per_particle: float = 40.0, min_batch: int = 512, progress=None) -> RsaResult:
    """Place bodies by RSA; stop when the tries run out.

    Each round, every waiting particle gets `t` tries (t grows as the acceptance falls); the
    tries are ordered try-major (all first tries, then all second tries, ...) and accepted by
    the sequential rule, so a round is equivalent to taking them one after another.
    progress(fraction placed) is called after each round when given."""
    n = len(bodies)
    centres = np.full((n, 3), np.nan)
    placed = np.zeros(n, dtype=bool)
    queue = np.arange(n)
    budget = int(max_tries_per_particle * n) + min_batch
    tries = 0
    reach_max = float(bodies.bounding_radii_nm.max()) if n else 0.0
    accept = 1.0
    while queue.size and tries < budget:
        head = queue[:max(min_batch, int(placed.sum()) // 2)]
        per = int(np.clip(np.ceil(0.7 / max(accept, 1e-3)), 1, 64))
        owner = np.tile(head, per)
        cand = random_positions(bodies.take(owner), walls.take(owner), period_nm, rng)
        tries += owner.size
        ok = np.ones(owner.size, dtype=bool)
        done = np.flatnonzero(placed)
        ia, ib = cross_pairs(cand, centres[done], 2.0 * reach_max, period_nm)
        if ia.size:
            sep = separation(bodies.take(owner), cand, ia, ib, period_nm,
                             centres_j=centres[done], bodies_j=bodies.take(done))
            ok[np.unique(ia[sep.gap_nm < 0])] = False
        live = np.flatnonzero(ok)
        a, b = neighbour_pairs(cand[live], 2.0 * reach_max, period_nm)
        first = second = np.zeros(0, dtype=np.int64)
        if a.size:
            sep = separation(bodies.take(owner[live]), cand[live], a, b, period_nm)
            hit = sep.gap_nm < 0
            first, second = live[np.minimum(a[hit], b[hit])], live[np.maximum(a[hit], b[hit])]
        kept = _sequential_keep(owner, first, second, ok)
        centres[owner[kept]] = cand[kept]
        placed[owner[kept]] = True
        accept = kept.sum() / max(1, owner.size)
        queue = np.concatenate([queue[head.size:], head[~placed[head]]])
        if progress is not None:
            progress(float(placed.sum()) / max(1, n))
    return RsaResult(centres, placed, tries)
