"""Ensemble reduction of the units and the ink-on-paper colour (docs/design.md §1, eq. 4).

Per case, solver, λ and σ, over the realizations (the same ones for both solvers):
  Rbar, Tbar = realization means; R_spec = Σ_out |⟨r00[pol, out]⟩|² (coherent beam from the
  ensemble-averaged amplitude, as the table builder does); unpolarised = mean of s and p.

Colour of the ink on paper under uniform diffuse light, seen from θ: by reciprocity the
directional albedo of eq. (4),

    a(θ) = Rbar(θ) + r·τ·Tbar(θ) / (1 − r·ρ̄),   τ = 2∫Tbar cos s sin s ds,  ρ̄ = same of Rbar,

(Rbar already holds the coherent mirror beam; Rbar_below = Rbar for these up-down symmetric
layers).  The angular integrals use the computed σ nodes plus the exact grazing limit of a
layer with flat faces (σ = 90°: Rbar = 1, Tbar = 0), linearly interpolated — the same for both
solvers, so the difference in colour is the solvers' difference.  a(θ) at the computed λ is
weighted by `solver.colour.cie` (ASTM E308, D65, CIE 1931 2°) → CIELAB → ΔE2000
(colour-science).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.colour import spectra_to_lab
from solver.paper import PAPER_ALBEDO
from solver.table.integrals import hemispherical_mean

POL_NAMES = ("s", "p", "unpol")


@dataclass(frozen=True)
class Ensemble:
    """Arrays [λ, σ, pol] with pol = s, p, unpolarised (NaN where not computed)."""

    wavelengths_nm: np.ndarray
    polar_deg: np.ndarray
    Rbar: np.ndarray
    Tbar: np.ndarray
    R_spec: np.ndarray
    Rbar_se: np.ndarray      # standard error over realizations (NaN for one realization)
    Tbar_se: np.ndarray


def reduce_units(units, wavelengths_nm, polar_deg) -> Ensemble:
    """units[λ][σ] = list of `runs.Unit` over realizations (all present)."""
    nl, ns = len(wavelengths_nm), len(polar_deg)
    out = {k: np.full((nl, ns, 3), np.nan) for k in ("Rbar", "Tbar", "R_spec", "Rbar_se", "Tbar_se")}
    for i in range(nl):
        for j in range(ns):
            us = units[i][j]
            R = np.array([u.R for u in us])                   # (M, 2)
            T = np.array([u.T for u in us])
            r00 = np.array([u.r00 for u in us])               # (M, 2, 2)
            spec = np.sum(np.abs(r00.mean(axis=0)) ** 2, axis=1)
            m = len(us)
            for name, arr in (("Rbar", R), ("Tbar", T)):
                out[name][i, j, :2] = arr.mean(axis=0)
                if m > 1:
                    out[name + "_se"][i, j, :2] = arr.std(axis=0, ddof=1) / np.sqrt(m)
            out["R_spec"][i, j, :2] = spec
    for k in ("Rbar", "Tbar", "R_spec"):
        out[k][..., 2] = out[k][..., :2].mean(axis=-1)
    for k in ("Rbar_se", "Tbar_se"):
        out[k][..., 2] = 0.5 * np.sqrt(np.sum(out[k][..., :2] ** 2, axis=-1))
    return Ensemble(np.asarray(wavelengths_nm, float), np.asarray(polar_deg, float), **out)


def _with_grazing(polar_deg, values, grazing_value):
    """Append the σ = 90° limit to a [λ, σ] array."""
    s = np.radians(np.append(polar_deg, 90.0))
    v = np.concatenate([values, np.full(values.shape[:-1] + (1,), grazing_value)], axis=-1)
    return s, v


def albedo_on_paper(ens: Ensemble, pol: int, paper: float = PAPER_ALBEDO) -> np.ndarray:
    """a(θ) at the computed view angles θ = σ nodes: [λ, θ] for polarisation index pol."""
    R, T = ens.Rbar[..., pol], ens.Tbar[..., pol]
    s_r, r_ext = _with_grazing(ens.polar_deg, R, 1.0)
    s_t, t_ext = _with_grazing(ens.polar_deg, T, 0.0)
    rho = hemispherical_mean(s_r, r_ext)
    tau = hemispherical_mean(s_t, t_ext)
    gain = paper * tau / (1.0 - paper * rho)
    return R + gain[:, None] * T


def lab_of(ens: Ensemble, pol: int) -> np.ndarray:
    """CIELAB [θ, 3] of the ink on paper seen from each computed view angle."""
    a = albedo_on_paper(ens, pol)
    return spectra_to_lab(ens.wavelengths_nm, a, "D65", "2", axis=0)


def delta_e2000(lab1, lab2) -> np.ndarray:
    import colour
    return np.asarray(colour.delta_E(np.asarray(lab1), np.asarray(lab2), method="CIE 2000"))
