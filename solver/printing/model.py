"""Printed colour of a halftone of several inks: Clapper–Yule and Murray–Davies (NumPy).

With Demichel weights a_S over the printed primaries S (bare paper S = () included, with
T̄ = τ̄ = 1, ρ̄ = R = R_spec = 0), paper albedo r, and each primary's eq. (4) quantities
(docs/design.md §1, `optics.PrimaryOptics`):

Clapper–Yule (light enters and leaves through whatever covers the point it crosses; between the
two crossings the paper's multiple bounces see the mixed upper surface; exact when the dots are
finer than the lateral spread of light in the paper):

    f = Σ_S a_S [R_S/π + R_spec,S·δ] + r·[Σ_S a_S T̄_S(σ)]·[Σ_S a_S T̄_S(θ)] / (π·(1 − r·Σ_S a_S ρ̄_S))

Murray–Davies (each primary a separate patch, light entering under a dot leaves through it):

    f = Σ_S a_S f_S,   f_S = R_S/π + R_spec,S·δ + r·T̄_S(σ)·T̄_S(θ) / (π·(1 − r·ρ̄_S))

Directional albedo (light from σ; by reciprocity the reflectance seen from σ under uniform
diffuse light of unit radiance): T̄(θ) → τ̄ and R → R_diff(σ) in the smooth terms, plus the
specular Σ a_S R_spec,S(σ).
"""

from __future__ import annotations

import numpy as np

from ..paper import check_paper_albedo

from .demichel import all_subsets, demichel_weights
from .inkset import PrintedInks
from .optics import PrimaryOptics, primary_optics

COVERAGE_MODELS = ("clapper-yule", "murray-davies")
DEFAULT_COVERAGE_MODEL = "clapper-yule"
_MISSING_TOL = 1e-12        # area fraction above which a primary without a table is an error


def check_coverage_model(name: str) -> str:
    """The model name if known; ValueError naming the choices otherwise."""
    if name not in COVERAGE_MODELS:
        raise ValueError(f"coverage_model must be one of {', '.join(COVERAGE_MODELS)}; got {name!r}")
    return name


def mix(weights, *values):
    """Σ_S a_S·x_S of each x: weights [..., nP] against values [nP, ...] → [..., *x.shape[1:]];
    one matrix product for all of them (one array in, one out; several in, a tuple out)."""
    w = np.asarray(weights, dtype=np.float64)
    arrays = [np.asarray(v, dtype=np.float64) for v in values]
    flat = np.concatenate([a.reshape(a.shape[0], -1) for a in arrays], axis=1)
    out = w @ flat
    parts, start = [], 0
    for a in arrays:
        size = int(np.prod(a.shape[1:], dtype=np.int64))
        parts.append(out[..., start:start + size].reshape(w.shape[:-1] + a.shape[1:]))
        start += size
    return parts[0] if len(parts) == 1 else tuple(parts)


def paper_albedo(paper, wavelengths_nm) -> np.ndarray:
    """Paper albedo r (number or spectrum on `wavelengths_nm`) as [nλ], checked in [0, 1]."""
    return check_paper_albedo(paper, wavelengths_nm)


def smooth_mix(model: str, weights, r, layer, t_in, t_out, rho) -> np.ndarray:
    """The smooth part of a coverage model from per-primary terms (primary axis first):

    `layer` = R/π (BRDF) or R_diff (+ R_spec) (albedo); `t_in` = T̄(σ); `t_out` = T̄(θ) (BRDF)
    or τ̄ (albedo); `rho` = ρ̄; `r` broadcasts against one primary's term.
    """
    if check_coverage_model(model) == "clapper-yule":
        layer, t_in, t_out, rho = mix(weights, layer, t_in, t_out, rho)
        return layer + r * t_in * t_out / (1.0 - r * rho)
    return mix(weights, layer + r * t_in * t_out / (1.0 - r * rho))


def primary_weights(printed: PrintedInks, coverages, subsets=None) -> tuple[tuple, np.ndarray]:
    """(primaries, Demichel weights [..., nP]) for coverages [..., k]; ValueError when a primary
    with no table (an overprint without a stack table) gets a non-zero area."""
    c = np.asarray(coverages, dtype=np.float64)
    if c.ndim < 1 or c.shape[-1] != printed.n_inks:
        raise ValueError(f"coverages need a last axis of {printed.n_inks} values (one per ink), "
                         f"got shape {c.shape}")
    primaries = printed.primaries() if subsets is None else tuple(subsets)
    missing = [s for s in all_subsets(printed.n_inks) if s not in primaries]
    if missing:
        lost = demichel_weights(c, missing)
        worst = np.max(lost.reshape(-1, len(missing)), axis=0)
        bad = [s for s, w in zip(missing, worst) if w > _MISSING_TOL]
        if bad:
            raise ValueError(f"coverages overlap inks {bad[0]} (0-based) but that overprint has no "
                             "stack table (PrintedInks.stacks)")
    return primaries, demichel_weights(c, primaries)


def _setup(printed, coverages, paper, wavelengths_nm):
    primaries, weights = primary_weights(printed, np.atleast_1d(coverages))
    if weights.ndim != 1:
        raise ValueError("one coverage mix (k values) here; use predict.reflectance for many")
    optics = primary_optics(printed, primaries, wavelengths_nm)
    return optics, weights, paper_albedo(paper, optics.wavelengths_nm)


def _expand(r, ndim):
    return r.reshape(r.shape + (1,) * ndim)


def brdf_smooth(printed: PrintedInks, coverages, paper, sigma_rad, theta_rad, dphi_rad,
                coverage_model: str = DEFAULT_COVERAGE_MODEL, wavelengths_nm=None) -> np.ndarray:
    """Smooth part of f(σ, θ, Δφ) in 1/sr (no cos θ), [nλ, *shape of the broadcast angles].

    coverages: k values in printing order; paper: r, a number or a spectrum on the wavelengths
    (default: the first ink's grid); Δφ = 0 retro-reflection, π mirror (docs/plugin.md).
    """
    optics, w, r = _setup(printed, coverages, paper, wavelengths_nm)
    s, th, ph = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64)
                                      for a in (sigma_rad, theta_rad, dphi_rad)))
    _, _, t_in = optics.at_polar(s)
    _, _, t_out = optics.at_polar(th)
    layer = optics.layer_brdf(s, th, ph) / np.pi
    rho = _expand(optics.rho, s.ndim)
    return smooth_mix(coverage_model, w, _expand(r, s.ndim), layer, t_in / np.pi, t_out, rho)


def specular_reflectance(printed: PrintedInks, coverages, sigma_rad, wavelengths_nm=None) -> np.ndarray:
    """Weight of the mirror (delta) lobe, Σ_S a_S R_spec,S(σ), [nλ, *shape(σ)]; both models."""
    optics, w, _ = _setup(printed, coverages, 0.0, wavelengths_nm)
    spec, _, _ = optics.at_polar(sigma_rad)
    return mix(w, spec)


def albedo_terms(optics: PrimaryOptics, model: str, weights, r, polar_rad, specular=True):
    """Directional albedo from prepared optics: weights [..., nP] with polar angles of shape ()
    give [..., nλ]; weights [nP] with angles of any shape give [nλ, *shape]."""
    spec, rdiff, tbar = optics.at_polar(polar_rad)
    nd = np.ndim(polar_rad)
    return smooth_mix(model, weights, _expand(r, nd), rdiff + spec if specular else rdiff, tbar,
                      _expand(optics.tau, nd), _expand(optics.rho, nd))


def directional_albedo(printed: PrintedInks, coverages, paper, polar_rad,
                       coverage_model: str = DEFAULT_COVERAGE_MODEL, wavelengths_nm=None,
                       specular: bool = True) -> np.ndarray:
    """Total reflectance for light from `polar_rad` ([nλ, *shape]); by reciprocity also the
    reflectance seen from `polar_rad` under uniform diffuse light. `specular=False` leaves out
    the mirror lobe (a "specular excluded" measurement)."""
    optics, w, r = _setup(printed, coverages, paper, wavelengths_nm)
    return albedo_terms(optics, coverage_model, w, r, polar_rad, specular)
