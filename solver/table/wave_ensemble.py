"""Ensemble averages of the wave tier's unit results (realizations × wavelengths) → a table.

Per wavelength and incidence σ, over the realizations and each realization's samples (incidence
azimuths, each solved in TE or TM; `wave_tier.samples`), per polarisation p:
  ⟨α_p⟩, ⟨β_p⟩                          the coherent beams (ensemble-averaged amplitudes);
  R_spec = mean_p |⟨α_p⟩|², T_coh = mean_p |⟨β_p⟩|²;
  Rbar, Tbar, Rbar_below = mean_p ⟨totals_p⟩  (00 orders included);
  R = mean_p ⟨spread non-00 orders⟩ + the incoherent part of the 00 order,
      mean_p (⟨|α_p|²⟩ − |⟨α_p⟩|²), placed at the mirror node (θ = σ, Δφ = π);
so Rbar = R_spec + ∫R cos θ dω/π holds exactly.  A TE table has one polarisation; an
unpolarised one also stores the s/p split (r_s, r_p in Mitsuba's convention, Rbar_s/p, Tbar_s/p).
R is then made reciprocal keeping each row's albedo (`orders_to_brdf.symmetrize_reciprocal`).
Grazing incidence σ = 90° is the analytic limit of a layer with flat faces: the incident flux
vanishes, the beam is mirrored (R_spec = 1, T = 0, R = 0; r_s = r_p = −1 in e^(−iωt)).  At σ = 0
(and θ = 0) R is averaged over Δφ: a normal direction has no azimuth reference.

Standard errors are taken across realizations (a realization's samples are first combined,
since they share a cell); R_spec's by jackknife.  One realization: unknown, none stored.
The builder (`builder._reduce`) also reduces each leave-one-out ensemble with `reduce_units`
(`jackknife.reduce_with_replicas`) and stores their colour columns in the table.
"""

from __future__ import annotations

import numpy as np

from ..thinfilm import to_mitsuba_convention
from .orders_to_brdf import isotropize_normal, spread_orders, symmetrize_reciprocal
from .request import TableRequest
from .schema import InkTable
from .wave_tier import TE, TM


def _se(per_real: np.ndarray) -> np.ndarray:
    """Standard error of the mean over axis 0 (0 for a single realization: then unknown)."""
    n = per_real.shape[0]
    return per_real.std(axis=0, ddof=1) / np.sqrt(n) if n > 1 else np.zeros(per_real.shape[1:])


def _per_realization(values: np.ndarray, pol: np.ndarray, p: int) -> np.ndarray:
    """Mean over one realization's samples of polarisation p: [N, σ, sample, …] → [N, σ, …]."""
    return values[:, :, pol == p].mean(axis=2)


def _coherent(per_real: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """mean_p |⟨a_p⟩|² from per-realization mean amplitudes [N, σ] of each polarisation, and
    its jackknife standard error over realizations."""
    value = np.mean([np.abs(a.mean(axis=0)) ** 2 for a in per_real], axis=0)
    n = per_real[0].shape[0]
    if n < 2:
        return value, np.zeros_like(value)
    jack = np.mean([np.abs((a.sum(axis=0)[None] - a) / (n - 1)) ** 2 for a in per_real], axis=0)
    return value, np.sqrt((n - 1) / n * np.sum((jack - jack.mean(axis=0)) ** 2, axis=0))


def reduce_units(request: TableRequest, units: list[list[dict]], meta: dict) -> InkTable:
    """units[r][λ] are solve_unit results; returns the validated-shape table (not yet written)."""
    polar, dphi, solved = np.asarray(request.grids.sigma_rad), request.grids.dphi_rad, request.grids.solved_mask
    nl, ns = len(request.grids.wavelengths_nm), polar.size
    pols = (TE,) if request.polarisation == "te" else (TE, TM)
    names = ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")
    cols = {k: np.zeros((nl, ns)) for k in names}
    errs = {k: np.zeros((nl, ns)) for k in names}
    split = {f"{k}_{s}": np.zeros((nl, ns)) for k in ("Rbar", "Tbar") for s in "sp"}
    amp = {s: np.full((nl, ns), -1.0 + 0j) for s in "sp"}        # grazing: r = −1
    R = np.zeros((nl, ns, ns, dphi.size))
    R_err = np.zeros_like(R)
    # grazing node (analytic): mirror beam, nothing transmitted or scattered
    for key in ("R_spec", "Rbar", "Rbar_below", "Rbar_s", "Rbar_p"):
        (cols if key in cols else split)[key][:, ~solved] = 1.0
    worst, worst_exact, apps, seconds, retries = 0.0, 0.0, [], 0.0, 0
    for li in range(nl):
        get = lambda key: np.stack([units[r][li][key] for r in range(len(units))])   # [N, σ, sample, …]
        pol = units[0][li]["polarisation"]
        mean_p = lambda key: {p: _per_realization(get(key), pol, p) for p in pols}
        alpha, beta = mean_p("alpha00"), mean_p("beta00")
        cols["R_spec"][li, solved], errs["R_spec"][li, solved] = _coherent([alpha[p] for p in pols])
        cols["T_coh"][li, solved], errs["T_coh"][li, solved] = _coherent([beta[p] for p in pols])
        for key in ("Rbar", "Tbar", "Rbar_below"):
            per = mean_p(key)
            per_real = np.mean([per[p] for p in pols], axis=0)            # [N, σ] unpolarised
            cols[key][li, solved], errs[key][li, solved] = per_real.mean(axis=0), _se(per_real)
            if key != "Rbar_below" and len(pols) == 2:
                split[f"{key}_s"][li, solved] = per[TE].mean(axis=0)
                split[f"{key}_p"][li, solved] = per[TM].mean(axis=0)
        if len(pols) == 2:
            amp["s"][li, solved], amp["p"][li, solved] = alpha[TE].mean(axis=0), alpha[TM].mean(axis=0)
        incoherent = np.mean([(_per_realization(np.abs(get("alpha00")) ** 2, pol, p)).mean(axis=0)
                              for p in pols], axis=0) - cols["R_spec"][li, solved]
        per_R = mean_p("R")
        per_real_R = np.mean([per_R[p] for p in pols], axis=0)             # [N, σ, θ, φ]
        Rl = per_real_R.mean(axis=0)
        for i in np.flatnonzero(solved):
            # the incoherent 00 power, at the mirror node (θ = σ_i, Δφ = π), energy-exactly
            Rl[i] += spread_orders(polar, dphi, [polar[i]], [np.pi], [max(incoherent[i], 0.0)])
        R[li, solved] = Rl
        R_err[li, solved] = _se(per_real_R)
        worst = max(worst, float(np.max(np.abs(get("energy_error")))))
        worst_exact = max(worst_exact, float(np.max(np.abs(get("energy_error_exact")))))
        apps.append(get("applications"))
        seconds += float(get("seconds").sum())
        retries += int(np.count_nonzero(get("retries")))
    R = symmetrize_reciprocal(isotropize_normal(R, polar, dphi), polar, dphi)
    meta = dict(meta)
    sampled = len(units) > 1                 # one realization: the standard error is unknown
    meta.setdefault("errors", {}).update({
        "energy_closure_max": worst,
        "energy_closure_exact_sampled_max": worst_exact,
        **{f"{k}_se_max": float(errs[k].max()) if sampled else None for k in ("Rbar", "Tbar", "R_spec")},
        "energy_sum_tol": 1e-9,
    })
    meta.setdefault("solver_stats", {}).update({
        "applications_mean": float(np.mean(apps)), "applications_max": int(np.max(apps)),
        "solves": int(sum(a.size for a in apps)), "solve_seconds_total": seconds,
        "solves_retried": retries})
    extra = {}
    if len(pols) == 2:
        extra = dict(split, r_s=to_mitsuba_convention(amp["s"]), r_p=to_mitsuba_convention(amp["p"]))
    return InkTable(wavelengths=np.asarray(request.grids.wavelengths_nm), sigma=polar, theta=polar.copy(),
                    dphi=dphi, R=R, meta=meta, errors={**errs, "R": R_err} if sampled else {}, **cols, **extra)
