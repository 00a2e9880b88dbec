"""Neighbour pairs and pair separations in a cell periodic in x and y (lengths in nm).

`separation` returns, for pairs (i, j), a unit normal n (from i towards j) and a *gap* that is
never larger than the true signed distance between the two bodies (distance when apart, minus
the penetration depth when overlapping):

* spheres: exact, gap = |d| − r_i − r_j;
* cylinders: by the separating-axis theorem for convex bodies the signed distance is
  max over unit n of  g(n) = |d·n| − Σ_k [h_k |a_k·n| + r_k √(1 − (a_k·n)²)]
  (the support half-widths of the two cylinders along n).  Any n with g(n) ≥ 0 is a certificate
  that the pair is disjoint.  We take the enclosing capsules first (segment–segment distance:
  capsules apart ⇒ cylinders apart), then evaluate g on the candidate axes of the contact types
  (face: a_i, a_j; side–side: a_i×a_j and the capsule direction; side–rim: d ⟂ a_i, d ⟂ a_j;
  the centre line; the pair's previous axis) and refine the best by a pattern search on the
  sphere.  The result is a lower bound: a pair we cannot certify is treated as overlapping
  (conservative), so "no overlap" is always rigorous.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .neighbours import min_image
from .shapes import Bodies

#: Pattern-search directions and iterations for the cylinder separating axis.
_SEARCH_DIRECTIONS = 8
_SEARCH_ITERATIONS = 60


@dataclass(frozen=True, eq=False)
class Separation:
    normal: np.ndarray   # (P, 3) unit, pointing from body i to body j
    gap_nm: np.ndarray   # (P,) lower bound of the signed distance (negative: overlap)


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    norm = np.sqrt(np.einsum("...c,...c->...", v, v))
    return v / np.where(norm > 0, norm, 1.0)[..., None], norm


def _parallel_axis(d, ai, aj, ri, rj, hi, hj):
    """Optimal separating axis of pairs with parallel axes (zero where not parallel).

    Two parallel cylinders differ by a cylinder of radius R = r_i + r_j and half length
    H = h_i + h_j about the common axis; with d split into axial z and radial ρ parts, the
    signed distance is ρ − R (beside), z − H (above), √((ρ−R)² + (z−H)²) (off the rim) or
    max(ρ − R, z − H) (overlapping), along the matching combination of the two directions."""
    parallel = np.abs(np.einsum("pc,pc->p", ai, aj)) > 1.0 - 1e-12
    z = np.einsum("pc,pc->p", d, ai)
    radial, rho = _unit(d - z[:, None] * ai)
    along = np.abs(z) - hi - hj
    beside = rho - ri - rj
    off = (along > 0) & (beside > 0)
    wa = np.where(off, along, np.where(along > beside, 1.0, 0.0))
    wr = np.where(off, beside, np.where(along > beside, 0.0, 1.0))
    n = wa[:, None] * np.sign(z)[:, None] * ai + wr[:, None] * radial
    return np.where(parallel[:, None], _unit(n)[0], 0.0), parallel


def support_gap(n, d, ai, aj, ri, rj, hi, hj):
    """g(n): separation of the projections of two cylinders on axis n (see module doc).

    n: (..., K, 3) unit axes; d, ai, aj: (..., 3); ri, rj, hi, hj: (...,)."""
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]

    def dot(v):
        return nx * v[..., None, 0] + ny * v[..., None, 1] + nz * v[..., None, 2]

    dn = np.abs(dot(d))
    ci = dot(ai)
    cj = dot(aj)
    wi = hi[..., None] * np.abs(ci) + ri[..., None] * np.sqrt(np.clip(1.0 - ci * ci, 0.0, None))
    wj = hj[..., None] * np.abs(cj) + rj[..., None] * np.sqrt(np.clip(1.0 - cj * cj, 0.0, None))
    return dn - wi - wj


def segment_closest_params(d, ai, aj, hi, hj):
    """Closest points of segments c_i + s·a_i (|s| ≤ h_i) and c_j + t·a_j (|t| ≤ h_j), c_i = 0,
    c_j = d (Ericson's clamped solution).  Returns (s, t) in nm along the axes."""
    p1 = -hi[:, None] * ai
    d1 = 2.0 * hi[:, None] * ai
    p2 = d - hj[:, None] * aj
    d2 = 2.0 * hj[:, None] * aj
    r = p1 - p2
    a = np.einsum("pc,pc->p", d1, d1)
    e = np.einsum("pc,pc->p", d2, d2)
    f = np.einsum("pc,pc->p", d2, r)
    c = np.einsum("pc,pc->p", d1, r)
    b = np.einsum("pc,pc->p", d1, d2)
    denom = a * e - b * b
    a_s = np.where(a > 0, a, 1.0)
    e_s = np.where(e > 0, e, 1.0)
    s = np.where(denom > 1e-12 * a * e, np.clip((b * f - c * e) / np.where(denom > 0, denom, 1.0), 0, 1), 0.0)
    t = (b * s + f) / e_s
    s = np.where(t < 0, np.clip(-c / a_s, 0, 1), np.where(t > 1, np.clip((b - c) / a_s, 0, 1), s))
    t = np.clip(t, 0.0, 1.0)
    return (2.0 * s - 1.0) * hi, (2.0 * t - 1.0) * hj


def segment_closest(d, ai, aj, hi, hj):
    """Vector from segment i's closest point to segment j's (see segment_closest_params)."""
    s, t = segment_closest_params(d, ai, aj, hi, hj)
    return d + t[:, None] * aj - s[:, None] * ai


def _tangent_basis(n: np.ndarray):
    pick = np.argmin(np.abs(n), axis=-1)
    e = np.zeros_like(n)
    np.put_along_axis(e, pick[..., None], 1.0, axis=-1)
    u, _ = _unit(np.cross(n, e))
    return u, np.cross(n, u)


def _refine_axis(n, g, d, ai, aj, ri, rj, hi, hj, target, iterations=_SEARCH_ITERATIONS, step0=0.25):
    """Pattern search on the unit sphere for a larger g(n); stops once g >= target."""
    angles = 2.0 * np.pi * np.arange(_SEARCH_DIRECTIONS) / _SEARCH_DIRECTIONS
    step = np.broadcast_to(np.asarray(step0, dtype=float), (len(g),)).copy()
    live = np.flatnonzero(g < target)
    for it in range(iterations):
        if live.size == 0:
            break
        offset = 0.6180339887 * it * 2.0 * np.pi / _SEARCH_DIRECTIONS   # rotate the pattern
        cos_k, sin_k = np.cos(angles + offset), np.sin(angles + offset)
        nl = n[live]
        u, v = _tangent_basis(nl)
        s = step[live][:, None, None]
        tangent = cos_k[None, :, None] * u[:, None, :] + sin_k[None, :, None] * v[:, None, :]
        trial, _ = _unit(nl[:, None, :] + s * tangent)
        gt = support_gap(trial, d[live], ai[live], aj[live], ri[live], rj[live], hi[live], hj[live])
        best = np.argmax(gt, axis=1)
        g_best = gt[np.arange(live.size), best]
        better = g_best > g[live]
        n[live[better]] = trial[better, best[better]]
        g[live[better]] = g_best[better]
        step[live] = np.where(better, step[live] * 1.5, step[live] * 0.5)
        keep = (g[live] < target[live]) & (step[live] > 1e-5)
        live = live[keep]
    return n, g


def _ridge_search(d, ai, aj, ri, rj, hi, hj, axis, samples=24, golden=28):
    """Best g(n) over the great circle n ⟂ axis (where a cylinder's side faces the other body):
    `samples` samples on the half circle, then `golden` golden-section steps around the best."""
    u, v = _tangent_basis(axis)
    args = (d, ai, aj, ri, rj, hi, hj)

    def g_at(theta):                                  # theta (P, K)
        n = np.cos(theta)[..., None] * u[:, None, :] + np.sin(theta)[..., None] * v[:, None, :]
        return support_gap(n, *args), n

    k = samples
    theta = np.broadcast_to(np.pi * np.arange(k) / k, (len(d), k))
    g, _ = g_at(theta)
    best = np.argmax(g, axis=1)
    lo = np.pi * (best - 1) / k
    hi_ = np.pi * (best + 1) / k
    ratio = 0.6180339887498949
    x1 = hi_ - ratio * (hi_ - lo)
    x2 = lo + ratio * (hi_ - lo)
    g1 = g_at(x1[:, None])[0][:, 0]
    g2 = g_at(x2[:, None])[0][:, 0]
    for _ in range(golden):
        left = g1 >= g2                                # the maximum lies in [lo, x2]
        hi_ = np.where(left, x2, hi_)
        lo = np.where(left, lo, x1)
        xn = np.where(left, hi_ - ratio * (hi_ - lo), lo + ratio * (hi_ - lo))
        gn = g_at(xn[:, None])[0][:, 0]
        x1, x2 = np.where(left, xn, x2), np.where(left, x1, xn)
        g1, g2 = np.where(left, gn, g2), np.where(left, g1, gn)
    g_mid, n_mid = g_at((0.5 * (lo + hi_))[:, None])
    return n_mid[:, 0], g_mid[:, 0]


def _cylinder_separation(d, ai, aj, ri, rj, hi, hj, hint, margin, iterations=_SEARCH_ITERATIONS,
                         full_search=True):
    caps = segment_closest(d, ai, aj, hi, hj)
    n_caps, dist = _unit(caps)
    gap = dist - ri - rj                       # capsule gap: a lower bound of the cylinder gap
    normal = n_caps.copy()
    need = np.flatnonzero(gap < margin)
    if need.size == 0:
        return normal, gap
    dd, a1, a2 = d[need], ai[need], aj[need]
    sub = (dd, a1, a2, ri[need], rj[need], hi[need], hj[need])
    cands = [n_caps[need], _unit(dd)[0], a1, a2, _unit(np.cross(a1, a2))[0],
             _unit(dd - np.einsum("pc,pc->p", dd, a1)[:, None] * a1)[0],
             _unit(dd - np.einsum("pc,pc->p", dd, a2)[:, None] * a2)[0]]
    if hint is not None:
        cands.append(hint[need])
    n_par, parallel = _parallel_axis(*sub)
    cands.append(n_par)
    stack = np.stack(cands, axis=1)
    g_all = np.where(np.einsum("pkc,pkc->pk", stack, stack) > 0.25, support_gap(stack, *sub), -np.inf)
    best = np.argmax(g_all, axis=1)
    n_best = stack[np.arange(need.size), best].copy()
    g_best = g_all[np.arange(need.size), best].copy()
    # Parallel axes (vertical cylinders): that candidate is the optimum, exactly; no search.
    # Warm start (packing iterations between full searches): a short local search from the
    # best of the candidates and the pair's previous axis.
    warm = np.zeros(need.size, dtype=bool)
    if hint is not None and not full_search:
        warm = (g_best < margin) & ~parallel
        if warm.any():
            w = np.flatnonzero(warm)
            part = tuple(x[w] for x in sub)
            n_best[w], g_best[w] = _refine_axis(n_best[w], g_best[w], *part, np.full(w.size, margin),
                                                iterations, step0=0.05)
    # Side contacts: the optimum lies on a circle n ⟂ a_i or n ⟂ a_j (a coarser 1-D search when
    # the caller asked for a short search: packing iterations).
    ridge = {} if iterations >= _SEARCH_ITERATIONS else {"samples": 16, "golden": 12}
    open_ = np.flatnonzero((g_best < margin) & ~warm & ~parallel)
    for which in (1, 2):
        if open_.size == 0:
            break
        part = tuple(x[open_] for x in sub)
        n_r, g_r = _ridge_search(*part, axis=part[which], **ridge)
        better = g_r > g_best[open_]
        n_best[open_[better]] = n_r[better]
        g_best[open_[better]] = g_r[better]
        open_ = open_[g_best[open_] < margin]
    # Rim contacts: a smooth interior maximum; pattern search from the best so far.
    if open_.size:
        part = tuple(x[open_] for x in sub)
        n_o, g_o = _refine_axis(n_best[open_], g_best[open_], *part, np.full(open_.size, margin),
                                iterations)
        n_best[open_], g_best[open_] = n_o, g_o
    gap[need] = g_best
    normal[need] = n_best
    sign = np.where(np.einsum("pc,pc->p", normal, d) < 0, -1.0, 1.0)
    return normal * sign[:, None], gap


def separation(bodies: Bodies, centres: np.ndarray, i: np.ndarray, j: np.ndarray,
               period_nm: tuple[float, float], hint: np.ndarray | None = None,
               margin_nm: float = 0.0, centres_j: np.ndarray | None = None,
               bodies_j: Bodies | None = None, search_iterations: int = _SEARCH_ITERATIONS,
               full_search: bool = True) -> Separation:
    """Separation of pairs (i, j); j indexes `centres_j`/`bodies_j` when given (cross pairs).

    For cylinders the axis search stops as soon as a pair is certified apart by `margin_nm`;
    `hint` (P, 3) warm-starts it with each pair's axis from a previous call; with
    full_search=False only a local search from the best candidate follows (packing iterations).
    Fewer `search_iterations` or no full search trade the accuracy of the penetration depth
    (never the rigour of a certificate: gap >= 0 is always proven) for speed."""
    cj_all = centres if centres_j is None else centres_j
    bj = bodies if bodies_j is None else bodies_j
    ri, rj = bodies.radii_nm[i], bj.radii_nm[j]
    if bodies.shape == "sphere":
        nx, ny, nz, gap = sphere_gaps(tuple(centres[:, k] for k in range(3)),
                                      tuple(cj_all[:, k] for k in range(3)), i, j, ri + rj, period_nm)
        return Separation(np.stack([nx, ny, nz], axis=1), gap)
    d = min_image(cj_all[j] - centres[i], period_nm)
    normal, gap = _cylinder_separation(d, bodies.axes[i], bj.axes[j], ri, rj,
                                       bodies.half_lengths_nm[i], bj.half_lengths_nm[j], hint, margin_nm,
                                       search_iterations, full_search)
    return Separation(normal, gap)


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


def horizontal_separation(bodies: Bodies, centres: np.ndarray, i: np.ndarray, j: np.ndarray,
                          period_nm: tuple[float, float]) -> Separation:
    """Best *horizontal* separating axis of each pair and its gap g (n_z = 0).

    Moving the pair apart by −g along it separates them, without any motion in z — the way out
    when the walls block the vertical push (a column of particles taller than the layer)."""
    d = min_image(centres[j] - centres[i], period_nm)
    ri, rj = bodies.radii_nm[i], bodies.radii_nm[j]
    if bodies.shape == "sphere":
        dxy = d.copy()
        dxy[:, 2] = 0.0
        n, dist = _unit(dxy)
        n[dist == 0] = (1.0, 0.0, 0.0)
        return Separation(n, dist - ri - rj)
    ez = np.tile([0.0, 0.0, 1.0], (len(i), 1))
    n, g = _ridge_search(d, bodies.axes[i], bodies.axes[j], ri, rj, bodies.half_lengths_nm[i],
                         bodies.half_lengths_nm[j], axis=ez)
    sign = np.where(np.einsum("pc,pc->p", n, d) < 0, -1.0, 1.0)
    return Separation(n * sign[:, None], g)
