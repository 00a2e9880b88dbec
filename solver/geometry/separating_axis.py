"""The separating-axis machinery of convex grains (lengths in nm), whatever their shape.

By the separating-axis theorem for convex bodies, the signed distance of two bodies i and j
(centres 0 and d) is the maximum over unit axes n of

    g(n) = |d·n| − w_i(n) − w_j(n),

w_k(n) the half-width of body k along n (its support function; for an axisymmetric body a
function of c = a_k·n, its radius r_k and half length h_k: the shape's `width(c, r, h)`).  Any n
with g(n) ≥ 0 certifies that the pair is disjoint; max g is the distance when apart and minus
the penetration depth when not.  Here: g on many axes at once (`support_gap`), a pattern search
on the sphere (`refine_axis`), the best axis on a great circle (`ridge_search`), and the closest
points of two segments (the axes of two grains).  The shapes pick their candidate axes and
searches (`shapes/`).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

#: width(c, r, h): half-width along n of a body with c = a·n (broadcasting arrays)
Width = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]

#: Pattern-search directions and iterations of `refine_axis`.
SEARCH_DIRECTIONS = 8
SEARCH_ITERATIONS = 60


def unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(v / |v|, |v|) over the last axis (zero vectors stay zero)."""
    norm = np.sqrt(np.einsum("...c,...c->...", v, v))
    return v / np.where(norm > 0, norm, 1.0)[..., None], norm


def support_gap(width: Width, n, d, ai, aj, ri, rj, hi, hj):
    """g(n): separation of the projections of two bodies on axis n (module doc).

    n: (..., K, 3) unit axes; d, ai, aj: (..., 3); ri, rj, hi, hj: (...,)."""
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]

    def dot(v):
        return nx * v[..., None, 0] + ny * v[..., None, 1] + nz * v[..., None, 2]

    dn = np.abs(dot(d))
    wi = width(dot(ai), ri[..., None], hi[..., None])
    wj = width(dot(aj), rj[..., None], hj[..., None])
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


def tangent_basis(n: np.ndarray):
    """Two unit vectors completing n (..., 3) to an orthonormal basis."""
    pick = np.argmin(np.abs(n), axis=-1)
    e = np.zeros_like(n)
    np.put_along_axis(e, pick[..., None], 1.0, axis=-1)
    u, _ = unit(np.cross(n, e))
    return u, np.cross(n, u)


def refine_axis(width: Width, n, g, d, ai, aj, ri, rj, hi, hj, target, iterations=SEARCH_ITERATIONS, step0=0.25):
    """Pattern search on the unit sphere for a larger g(n) from n (P, 3) with g(n) = g (P,)
    (both updated in place); stops once g >= target (P,)."""
    angles = 2.0 * np.pi * np.arange(SEARCH_DIRECTIONS) / SEARCH_DIRECTIONS
    step = np.broadcast_to(np.asarray(step0, dtype=float), (len(g),)).copy()
    live = np.flatnonzero(g < target)
    for it in range(iterations):
        if live.size == 0:
            break
        offset = 0.6180339887 * it * 2.0 * np.pi / SEARCH_DIRECTIONS   # rotate the pattern
        cos_k, sin_k = np.cos(angles + offset), np.sin(angles + offset)
        nl = n[live]
        u, v = tangent_basis(nl)
        s = step[live][:, None, None]
        tangent = cos_k[None, :, None] * u[:, None, :] + sin_k[None, :, None] * v[:, None, :]
        trial, _ = unit(nl[:, None, :] + s * tangent)
        gt = support_gap(width, trial, d[live], ai[live], aj[live], ri[live], rj[live], hi[live], hj[live])
        best = np.argmax(gt, axis=1)
        g_best = gt[np.arange(live.size), best]
        better = g_best > g[live]
        n[live[better]] = trial[better, best[better]]
        g[live[better]] = g_best[better]
        step[live] = np.where(better, step[live] * 1.5, step[live] * 0.5)
        keep = (g[live] < target[live]) & (step[live] > 1e-5)
        live = live[keep]
    return n, g


def ridge_search(width: Width, d, ai, aj, ri, rj, hi, hj, axis, samples=24, golden=28):
    """Best g(n) over the great circle n ⟂ axis (P, 3): `samples` samples on the half circle,
    then `golden` golden-section steps around the best.  Returns (n (P, 3), g (P,))."""
    u, v = tangent_basis(axis)
    args = (d, ai, aj, ri, rj, hi, hj)

    def g_at(theta):                                  # theta (P, K)
        n = np.cos(theta)[..., None] * u[:, None, :] + np.sin(theta)[..., None] * v[:, None, :]
        return support_gap(width, n, *args), n

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
