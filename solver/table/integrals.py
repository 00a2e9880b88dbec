"""Angular integrals that are exact for the tables' piecewise-linear interpolation.

The plugin interpolates every tabulated quantity linearly in σ (and θ, Δφ, λ).  Energy sums
must use the same interpolant, otherwise a lossless layer on white paper would not reflect
exactly 1 (white furnace).  Every integral over angles in the project goes through here.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

_GAUSS_ORDER = 12   # per interval; exact to round-off for (linear) × (smooth trig weight)


@lru_cache(maxsize=None)
def _gauss(order: int) -> tuple[np.ndarray, np.ndarray]:
    return np.polynomial.legendre.leggauss(order)


def hat_integrals(nodes, weight) -> np.ndarray:
    """w_i = ∫ hat_i(x)·weight(x) dx over [nodes[0], nodes[-1]] for the piecewise-linear hats.

    Σ_i w_i·f_i is then the exact integral of (linear interpolant of f) × weight.
    """
    x = np.asarray(nodes, dtype=float)
    if x.ndim != 1 or x.size < 2 or np.any(np.diff(x) <= 0):
        raise ValueError("integration nodes must be a strictly increasing 1-D grid of ≥ 2 points")
    gx, gw = _gauss(_GAUSS_ORDER)
    a, b = x[:-1, None], x[1:, None]
    t = 0.5 * (gx[None, :] + 1.0)                    # position inside each interval, 0..1
    xs = a + (b - a) * t
    wq = 0.5 * (b - a) * gw[None, :] * weight(xs)
    w = np.zeros_like(x)
    w[:-1] += np.sum(wq * (1.0 - t), axis=1)
    w[1:] += np.sum(wq * t, axis=1)
    return w


@lru_cache(maxsize=64)
def _cos_sin_weights(nodes: tuple[float, ...]) -> np.ndarray:
    return hat_integrals(np.array(nodes), lambda s: 2.0 * np.cos(s) * np.sin(s))


def cosine_weights(polar_rad) -> np.ndarray:
    """Weights w with Σ w_i f(s_i) = 2∫ f(s) cos s sin s ds over the grid (σ from 0 to π/2).

    For f ≡ 1 on [0, π/2] the sum is 1: the cosine-weighted hemispherical mean.
    """
    return _cos_sin_weights(tuple(float(s) for s in np.asarray(polar_rad, dtype=float)))


def hemispherical_mean(polar_rad, values, axis: int = -1) -> np.ndarray:
    """2∫ f(s) cos s sin s ds of a table column sampled on `polar_rad` (e.g. ρ̄ from Rbar_below)."""
    w = cosine_weights(polar_rad)
    return np.tensordot(np.moveaxis(np.asarray(values), axis, -1), w, axes=([-1], [0]))


def band_weights(polar_rad, lo_rad: float, hi_rad: float) -> np.ndarray:
    """Weights w with Σ w_i f(s_i) = ∫_lo^hi f(s) cos s sin s ds / ∫_lo^hi cos s sin s ds for the
    linear interpolant of f on the grid: the mean of f over a cone or an annular band of polar
    angles seen by a detector (or lit by a source) whose signal goes as cos s dω (a
    measurement's cones, docs/design.md §7). lo < hi within the grid; exact to round-off."""
    x = np.asarray(polar_rad, dtype=float)
    if not (x[0] <= lo_rad < hi_rad <= x[-1]):
        raise ValueError(f"band {np.degrees(lo_rad):g}°–{np.degrees(hi_rad):g}° lies outside the grid "
                         f"{np.degrees(x[0]):g}°–{np.degrees(x[-1]):g}°")
    gx, gw = _gauss(_GAUSS_ORDER)
    a = np.clip(x[:-1], lo_rad, hi_rad)[:, None]
    b = np.clip(x[1:], lo_rad, hi_rad)[:, None]
    s = a + (b - a) * 0.5 * (gx[None, :] + 1.0)
    wq = 0.5 * (b - a) * gw[None, :] * np.cos(s) * np.sin(s)
    t = (s - x[:-1, None]) / (x[1:, None] - x[:-1, None])      # hat of the upper node
    w = np.zeros_like(x)
    w[:-1] += np.sum(wq * (1.0 - t), axis=1)
    w[1:] += np.sum(wq * t, axis=1)
    return w / w.sum()


def azimuth_weights(dphi_rad) -> np.ndarray:
    """Trapezoid weights over Δφ ∈ [0, π] (exact for the linear interpolant)."""
    return hat_integrals(dphi_rad, np.ones_like)


def diffuse_albedo(theta_rad, dphi_rad, R) -> np.ndarray:
    """∫ R(θ, Δφ) cos θ dω / π over the upper hemisphere, R mirror-symmetric in Δφ ∈ [0, π].

    R has θ and Δφ as its last two axes; the result drops them.  R ≡ 1 gives 1.
    """
    w_theta = cosine_weights(theta_rad)             # 2∫ · cos sin dθ
    w_phi = azimuth_weights(dphi_rad)               # ∫_0^π dΔφ
    return np.einsum("...ij,i,j->...", np.asarray(R), w_theta, w_phi) / np.pi
