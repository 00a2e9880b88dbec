"""Diffraction orders → the tabulated BRDF R(σ, θ, Δφ), energy-exactly.

Orders are discrete directions.  Each order's power P is spread onto the (θ, Δφ) nodes with
the same hat functions the plugin interpolates with, divided by the node's hemispherical
weight, so that the integral of the interpolated R equals Σ P exactly:

    R_jk += π·P·h_j(θ_o)·h_k(Δφ_o) / (w_j·u_k),   Σ_jk R_jk w_j u_k / π = Σ P

with w the cosine weights in θ and u the Δφ weights (`solver.table.integrals`).

Δφ convention (docs/plugin.md): the azimuth between the direction toward the light and the
direction toward the viewer, folded into [0, π]; the mirror direction is Δφ = π.
"""

from __future__ import annotations

import numpy as np

from .integrals import azimuth_weights, cosine_weights, diffuse_albedo
from .interpolation import lerp_weights


def fold_dphi(phi_toward_light, phi_toward_viewer) -> np.ndarray:
    """|Δφ| folded into [0, π]."""
    d = np.mod(np.asarray(phi_toward_light) - np.asarray(phi_toward_viewer), 2 * np.pi)
    return np.where(d > np.pi, 2 * np.pi - d, d)


def spread_orders(theta_grid, dphi_grid, theta_o, dphi_o, power) -> np.ndarray:
    """R contribution [nθ, nφ] of orders at (θ_o, Δφ_o) carrying power fractions `power`."""
    theta_grid = np.asarray(theta_grid, dtype=float)
    dphi_grid = np.asarray(dphi_grid, dtype=float)
    out = np.zeros((theta_grid.size, dphi_grid.size))
    theta_o, dphi_o, power = (np.ravel(a).astype(float) for a in (theta_o, dphi_o, power))
    if power.size == 0:
        return out
    i, ti = lerp_weights(theta_grid, theta_o)
    k, tk = lerp_weights(dphi_grid, dphi_o)
    for di, wi in ((0, 1 - ti), (1, ti)):
        for dk, wk in ((0, 1 - tk), (1, tk)):
            np.add.at(out, (i + di, k + dk), power * wi * wk)
    w = cosine_weights(theta_grid)[:, None] * azimuth_weights(dphi_grid)[None, :]
    return np.divide(np.pi * out, w, out=np.zeros_like(out), where=w > 0)


def isotropize_normal(R: np.ndarray, polar_rad, dphi_rad) -> np.ndarray:
    """Average R[..., σ, θ, Δφ] over Δφ where σ = 0 or θ = 0: a normal direction has no azimuth
    reference, so R cannot depend on Δφ there.  Δφ-weighted, so every albedo is unchanged."""
    R = np.array(R, dtype=float)
    u = azimuth_weights(dphi_rad)
    if abs(float(np.asarray(polar_rad)[0])) < 1e-12:
        for index in ((Ellipsis, 0, slice(None), slice(None)), (Ellipsis, slice(None), 0, slice(None))):
            R[index] = (R[index] @ u / u.sum())[..., None]
    return R


def symmetrize_reciprocal(R: np.ndarray, polar_rad, dphi_rad, iterations: int = 200,
                          rtol: float = 1e-12) -> np.ndarray:
    """Make R[..., σ, θ, Δφ] reciprocal (symmetric in σ ↔ θ) keeping every row's albedo.

    The symmetric average (R + Rᵀ)/2 is rescaled as S_ij = d_i d_j (R + Rᵀ)_ij / 2 with d found
    by a symmetric Sinkhorn iteration so that ∫S(σ_i, ·) cos θ dω/π equals the measured
    ∫R(σ_i, ·) cos θ dω/π for every incidence: reciprocity exactly, hemispherical sums exactly.
    Rows with no diffuse energy stay zero.
    """
    R = np.asarray(R, dtype=float)
    target = diffuse_albedo(polar_rad, dphi_rad, R)                  # [..., σ]
    sym = 0.5 * (R + np.swapaxes(R, -3, -2))
    # row sums as a matrix: M_ij = ∫ sym_ij(Δφ) dΔφ-weights × cosine weight of θ_j / π
    w_theta = cosine_weights(polar_rad)
    u_phi = azimuth_weights(dphi_rad)
    M = np.einsum("...ijk,k->...ij", sym, u_phi) * w_theta / np.pi    # row i: Σ_j M_ij = albedo
    d = np.ones(target.shape)
    for _ in range(iterations):
        rows = np.einsum("...ij,...j->...i", M, d)
        ok = (rows > 0) & (target > 0)
        # d_i ← sqrt(d_i · target_i / (Σ_j M_ij d_j)): the symmetric Sinkhorn–Knopp update
        new = np.where(ok, np.sqrt(d * np.divide(target, rows, out=np.ones_like(rows), where=ok)), 0.0)
        converged = np.allclose(new, d, rtol=rtol, atol=0.0)
        d = new
        if converged:
            break
    return sym * d[..., :, None, None] * d[..., None, :, None]
