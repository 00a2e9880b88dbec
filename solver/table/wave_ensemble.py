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
since they share a cell); R_spec's by jackknife.  Where each realization solved one polarisation
(A = 1, wave_tier.alternates) the TE and TM realizations are independent groups: the unpolarised
mean's variance is the groups' Σ_p SE_p²/4, with N − 2 degrees of freedom (meta errors.se_dof).
One realization (per group): unknown, none stored.
The builder (`builder._reduce`) also reduces each leave-one-out ensemble with `reduce_units`
(`jackknife.reduce_with_replicas`) and stores their colour columns in the table.
"""

from __future__ import annotations

import numpy as np

from ..thinfilm import to_mitsuba_convention
from .jackknife import standard_error
from .orders_to_brdf import isotropize_normal, spread_orders, symmetrize_reciprocal
from .request import TableRequest
from .schema import InkTable
from .wave_tier import TE, TM


def _se(per_real: np.ndarray) -> np.ndarray:
    """Standard error of the mean over axis 0 (0 for a single realization: then unknown)."""
    n = per_real.shape[0]
    return per_real.std(axis=0, ddof=1) / np.sqrt(n) if n > 1 else np.zeros(per_real.shape[1:])


class _Samples:
    """One wavelength's solves grouped by polarisation: per realization, the mean over its
    samples of each polarisation; realizations that solved a polarisation not at all (A = 1
    alternating, wave_tier.alternates) are left out of that polarisation's group.

    joint: every realization solved every polarisation, so a realization's unpolarised value
    exists and the standard error is taken across realizations of it (the polarisations'
    covariance within a cell included); otherwise the groups are independent cells and the
    unpolarised mean's variance is Σ_p SE_p² / P²."""

    def __init__(self, units_l: list[dict], pols: tuple[int, ...]):
        self.units, self.pols = units_l, pols
        self.which = {p: [r for r, u in enumerate(units_l) if np.any(u["polarisation"] == p)] for p in pols}
        self.joint = all(len(w) == len(units_l) for w in self.which.values())

    def per_pol(self, key: str, fn=lambda v: v) -> dict[int, np.ndarray]:
        """{p: [N_p, σ, …]} per-realization means of fn(value) over the samples of polarisation p."""
        return {p: np.stack([fn(self.units[r][key])[:, self.units[r]["polarisation"] == p].mean(axis=1)
                             for r in self.which[p]]) for p in self.pols}

    def combine(self, per: dict[int, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """(unpolarised mean, its standard error) from per_pol's groups."""
        if self.joint:
            per_real = np.mean([per[p] for p in self.pols], axis=0)
            return per_real.mean(axis=0), _se(per_real)
        mean = np.mean([per[p].mean(axis=0) for p in self.pols], axis=0)
        return mean, np.sqrt(sum(_se(per[p]) ** 2 for p in self.pols)) / len(self.pols)

    def coherent(self, key: str) -> tuple[np.ndarray, np.ndarray]:
        """mean_p |⟨a_p⟩|² of the 00 amplitude `key` and its jackknife standard error (over the
        realizations jointly, or per polarisation group when the groups are independent)."""
        per = self.per_pol(key)
        value = np.mean([np.abs(per[p].mean(axis=0)) ** 2 for p in self.pols], axis=0)
        if self.joint:
            return value, _jackknife([per[p] for p in self.pols])
        var = sum(_jackknife([per[p]]) ** 2 for p in self.pols) / len(self.pols) ** 2
        return value, np.sqrt(var)

    @property
    def dof(self) -> int:
        """Degrees of freedom of the standard errors: N − 1 (joint) or N − P (groups)."""
        return len(self.units) - (1 if self.joint else len(self.pols))

    @property
    def sampled(self) -> bool:
        """Whether a standard error can be estimated (≥ 2 realizations in every group)."""
        return min(len(w) for w in self.which.values()) > 1


def _jackknife(per_real: list[np.ndarray]) -> np.ndarray:
    """Jackknife standard error over realizations (axis 0, the same realizations in every array)
    of mean_p |⟨a_p⟩|² (0 below two realizations: unknown)."""
    n = per_real[0].shape[0]
    if n < 2:
        return np.zeros(per_real[0].shape[1:])
    return standard_error(np.mean([np.abs((a.sum(axis=0)[None] - a) / (n - 1)) ** 2 for a in per_real], axis=0))


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
    dofs = []
    for li in range(nl):
        get = lambda key: np.stack([units[r][li][key] for r in range(len(units))])   # [N, σ, sample, …]
        group = _Samples([units[r][li] for r in range(len(units))], pols)
        dofs.append(group.dof if group.sampled else 0)
        cols["R_spec"][li, solved], errs["R_spec"][li, solved] = group.coherent("alpha00")
        cols["T_coh"][li, solved], errs["T_coh"][li, solved] = group.coherent("beta00")
        for key in ("Rbar", "Tbar", "Rbar_below"):
            per = group.per_pol(key)
            cols[key][li, solved], errs[key][li, solved] = group.combine(per)
            if key != "Rbar_below" and len(pols) == 2:
                split[f"{key}_s"][li, solved] = per[TE].mean(axis=0)
                split[f"{key}_p"][li, solved] = per[TM].mean(axis=0)
        if len(pols) == 2:
            alpha = group.per_pol("alpha00")
            amp["s"][li, solved], amp["p"][li, solved] = alpha[TE].mean(axis=0), alpha[TM].mean(axis=0)
        power = group.per_pol("alpha00", lambda v: np.abs(v) ** 2)
        incoherent = np.mean([power[p].mean(axis=0) for p in pols], axis=0) - cols["R_spec"][li, solved]
        Rl, R_err[li, solved] = group.combine(group.per_pol("R"))
        for i in np.flatnonzero(solved):
            # the incoherent 00 power, at the mirror node (θ = σ_i, Δφ = π), energy-exactly
            Rl[i] += spread_orders(polar, dphi, [polar[i]], [np.pi], [max(incoherent[i], 0.0)])
        R[li, solved] = Rl
        worst = max(worst, float(np.max(np.abs(get("energy_error")))))
        worst_exact = max(worst_exact, float(np.max(np.abs(get("energy_error_exact")))))
        apps.append(get("applications"))
        seconds += float(get("seconds").sum())
        retries += int(np.count_nonzero(get("retries")))
    R = symmetrize_reciprocal(isotropize_normal(R, polar, dphi), polar, dphi)
    meta = dict(meta)
    sampled = min(dofs) > 0                  # one realization (per polarisation group): unknown
    meta.setdefault("errors", {}).update({
        "energy_closure_max": worst,
        "energy_closure_exact_sampled_max": worst_exact,
        **{f"{k}_se_max": float(errs[k].max()) if sampled else None for k in ("Rbar", "Tbar", "R_spec")},
        "energy_sum_tol": 1e-9,
        "se_dof": int(min(dofs)) if sampled else None,
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
