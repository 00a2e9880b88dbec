"""Structure statistics of a realization and its overlap check.

* `find_overlaps`: every pair of particles that may overlap (rigorous: exact for spheres; for
  cylinders a pair counts as apart only with a separating-axis certificate, `contacts`).
* `pair_correlation`: g(r) of the centres, periodic in x and y, with the exact correction for
  the slab walls (a sphere of radius r about a point at depth z has the fraction
  (min(z + r, z1) − max(z − r, z0)) / 2r of its surface inside z0 ≤ z ≤ z1 — Archimedes).
* `cluster_statistic`: clusters are groups of particles linked by gaps below `bond_gap`
  (default a tenth of the mean diameter); reports the mean cluster size seen by a particle
  (Σ s² / Σ s), the largest cluster's share, and the mean number of bonds per particle.
  Agglutination raises all three (paper Fig. 4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .contacts import separation
from .neighbours import neighbour_pairs


def close_pairs(real, extra_gap_nm: float = 0.0):
    """Pairs whose bounding spheres come closer than extra_gap_nm, with their separations."""
    bodies = real.bodies
    reach = 2.0 * float(bodies.bounding_radii_nm.max()) + extra_gap_nm if len(bodies) else 0.0
    i, j = neighbour_pairs(real.centres_nm, reach, real.period_nm)
    return i, j, separation(bodies, real.centres_nm, i, j, real.period_nm, margin_nm=extra_gap_nm)


def find_overlaps_of(bodies, centres, period_nm, tolerance_nm: float = 0.0) -> np.ndarray:
    """(K, 2) index pairs that overlap by more than tolerance_nm (or cannot be certified apart)."""
    if len(bodies) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    i, j = neighbour_pairs(centres, 2.0 * float(bodies.bounding_radii_nm.max()), period_nm)
    bad = separation(bodies, centres, i, j, period_nm).gap_nm < -tolerance_nm
    return np.stack([i[bad], j[bad]], axis=1)


def find_overlaps(real, tolerance_nm: float = 0.0) -> np.ndarray:
    """(K, 2) index pairs of a realization that overlap (see find_overlaps_of)."""
    return find_overlaps_of(real.bodies, real.centres_nm, real.period_nm, tolerance_nm)


def wall_violations(real, tolerance_nm: float = 1e-6) -> np.ndarray:
    """Indices of particles reaching outside their allowed z range."""
    hz = real.bodies.half_extent_nm(2)
    top = real.centres_nm[:, 2] - hz
    bottom = real.centres_nm[:, 2] + hz
    allowed_top = -2.0 * real.protrusion * hz
    return np.flatnonzero((top < allowed_top - tolerance_nm) | (bottom > real.layer.thickness_nm + tolerance_nm))


def pair_correlation(real, r_max_nm: float, bins: int = 50):
    """(r_centres_nm, g) of particle centres for 0 < r < r_max (r_max < half the cell side)."""
    c = real.centres_nm
    n = len(c)
    edges = np.linspace(0.0, r_max_nm, bins + 1)
    if n < 2:
        return 0.5 * (edges[1:] + edges[:-1]), np.zeros(bins)
    i, j = neighbour_pairs(c, r_max_nm, real.period_nm)
    d = c[j] - c[i]
    for k in (0, 1):
        d[:, k] -= real.period_nm[k] * np.round(d[:, k] / real.period_nm[k])
    counts = np.histogram(np.linalg.norm(d, axis=1), bins=edges)[0] * 2.0
    z0, z1 = 0.0, real.layer.thickness_nm
    z = np.clip(c[:, 2], z0, z1)
    mid = 0.5 * (edges[1:] + edges[:-1])
    inside = (np.minimum(z[:, None] + mid, z1) - np.maximum(z[:, None] - mid, z0)) / (2.0 * mid)
    density = n / (real.period_nm[0] * real.period_nm[1] * (z1 - z0))
    shell = 4.0 / 3.0 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    expected = density * shell * inside.sum(axis=0)
    return mid, np.where(expected > 0, counts / np.where(expected > 0, expected, 1.0), 0.0)


@dataclass(frozen=True)
class ClusterStats:
    bond_gap_nm: float
    mean_cluster_size: float        # Σ s² / Σ s: size of the cluster a random particle is in
    largest_cluster_fraction: float
    bonds_per_particle: float
    clusters: int


def cluster_statistic(real, bond_gap_nm: float | None = None) -> ClusterStats:
    """Clusters of particles closer than bond_gap (default: 0.1 × mean (effective) diameter)."""
    n = len(real.radii_nm)
    if bond_gap_nm is None:
        bond_gap_nm = 0.1 * float(np.mean(real.effective_diameters_nm)) if n else 0.0
    if n == 0:
        return ClusterStats(bond_gap_nm, 0.0, 0.0, 0.0, 0)
    i, j, sep = close_pairs(real, bond_gap_nm)
    bond = sep.gap_nm < bond_gap_nm
    graph = coo_matrix((np.ones(int(bond.sum())), (i[bond], j[bond])), shape=(n, n))
    count, label = connected_components(graph, directed=False)
    sizes = np.bincount(label).astype(float)
    return ClusterStats(bond_gap_nm, float((sizes**2).sum() / sizes.sum()), float(sizes.max() / n),
                        2.0 * float(bond.sum()) / n, int(count))
