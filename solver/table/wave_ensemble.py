"""Reduce the wave tier's unit results (realizations × wavelengths) to a table.

Per wavelength and incidence σ, with M = realizations × azimuths samples:
  R_spec = |⟨α00⟩|², T_coh = |⟨β00⟩|²   the coherent beams (ensemble-averaged amplitudes);
  Rbar, Tbar, Rbar_below = ⟨totals⟩      (00 orders included);
  R = ⟨spread non-00 orders⟩ + the incoherent part of the 00 order, ⟨|α00|²⟩ − |⟨α00⟩|²,
      placed at the mirror node (θ = σ, Δφ = π);
so Rbar = R_spec + ∫R cos θ dω/π holds exactly.  R is then made reciprocal keeping each row's
albedo (`orders_to_brdf.symmetrize_reciprocal`).  Grazing incidence σ = 90° is the analytic limit of a
layer with flat faces: the incident flux vanishes, the beam is mirrored (R_spec = 1, T = 0, R = 0).
At σ = 0 (and θ = 0) R is averaged over Δφ: a normal direction has no azimuth reference.

Standard errors are taken across realizations (azimuth samples of one realization are first
averaged, since they share a cell); R_spec's by jackknife.
"""

from __future__ import annotations

import numpy as np

from .orders_to_brdf import isotropize_normal, spread_orders, symmetrize_reciprocal
from .request import TableRequest
from .schema import InkTable


def _se(per_real: np.ndarray) -> np.ndarray:
    """Standard error of the mean over axis 0 (0 for a single realization: then unknown, and
    the table stores no error arrays)."""
    n = per_real.shape[0]
    return per_real.std(axis=0, ddof=1) / np.sqrt(n) if n > 1 else np.zeros(per_real.shape[1:])


def _coherent(amp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """|⟨a⟩|² over axes (realization, azimuth) and its jackknife standard error."""
    per_real = amp.mean(axis=2)                        # [N, σ] (azimuths averaged)
    value = np.abs(per_real.mean(axis=0)) ** 2
    n = per_real.shape[0]
    if n < 2:
        return value, np.zeros_like(value)
    loo = (per_real.sum(axis=0)[None] - per_real) / (n - 1)
    jack = np.abs(loo) ** 2
    return value, np.sqrt((n - 1) / n * np.sum((jack - jack.mean(axis=0)) ** 2, axis=0))


def reduce_units(request: TableRequest, units: list[list[dict]], meta: dict) -> InkTable:
    """units[r][λ] are solve_unit results; returns the validated-shape table (not yet written)."""
    polar, dphi, solved = np.asarray(request.grids.sigma_rad), request.grids.dphi_rad, request.grids.solved_mask
    nl, ns = len(request.grids.wavelengths_nm), polar.size
    cols = {k: np.zeros((nl, ns)) for k in ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")}
    errs = {k: np.zeros((nl, ns)) for k in cols}
    R = np.zeros((nl, ns, ns, dphi.size))
    R_err = np.zeros_like(R)
    # grazing node (analytic): mirror beam, nothing transmitted or scattered
    cols["R_spec"][:, ~solved] = cols["Rbar"][:, ~solved] = cols["Rbar_below"][:, ~solved] = 1.0
    worst_energy, apps, seconds = 0.0, [], 0.0
    for li in range(nl):
        get = lambda key: np.stack([units[r][li][key] for r in range(len(units))])   # [N, σ, az]
        alpha, beta = get("alpha00"), get("beta00")
        cols["R_spec"][li, solved], errs["R_spec"][li, solved] = _coherent(alpha)
        cols["T_coh"][li, solved], errs["T_coh"][li, solved] = _coherent(beta)
        for key in ("Rbar", "Tbar", "Rbar_below"):
            per_real = get(key).mean(axis=2)
            cols[key][li, solved], errs[key][li, solved] = per_real.mean(axis=0), _se(per_real)
        incoherent = np.mean(np.abs(alpha) ** 2, axis=(0, 2)) - cols["R_spec"][li, solved]
        per_real_R = get("R").mean(axis=2)                                            # [N, σ, θ, φ]
        Rl = per_real_R.mean(axis=0)
        for i in np.flatnonzero(solved):
            # the incoherent 00 power, at the mirror node (θ = σ_i, Δφ = π), energy-exactly
            Rl[i] += spread_orders(polar, dphi, [polar[i]], [np.pi], [max(incoherent[i], 0.0)])
        R[li, solved] = Rl
        R_err[li, solved] = _se(per_real_R)
        worst_energy = max(worst_energy, float(np.max(np.abs(get("energy_error")))))
        apps.append(get("applications"))
        seconds += float(get("seconds").sum())
    R = symmetrize_reciprocal(isotropize_normal(R, polar, dphi), polar, dphi)
    meta = dict(meta)
    sampled = len(units) > 1                 # one realization: the standard error is unknown
    meta.setdefault("errors", {}).update({
        "energy_closure_max": worst_energy,
        **{f"{k}_se_max": float(errs[k].max()) if sampled else None for k in ("Rbar", "Tbar", "R_spec")},
        "energy_sum_tol": 1e-9,
    })
    meta.setdefault("solver_stats", {}).update({
        "applications_mean": float(np.mean(apps)), "applications_max": int(np.max(apps)),
        "solve_seconds_total": seconds})
    return InkTable(wavelengths=np.asarray(request.grids.wavelengths_nm), sigma=polar, theta=polar.copy(),
                    dphi=dphi, R=R, meta=meta, errors={**errs, "R": R_err} if sampled else {}, **cols)
