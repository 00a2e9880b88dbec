"""The colour of a cell and its standard error: CIELAB of the ink on paper, propagated from the
table's standard errors.

The colour (docs/design.md §1, §2): the ink on a Lambertian paper of albedo `paper` (0.9 in the
paper) under uniform diffuse light, seen at `view` (0°), as CIELAB under D65 — the brightness of
the Fig. 6 strip at its top.  By reciprocity it is the directional albedo

    A(λ) = Rbar(λ, θ) + r·τ̄(λ)·Tbar(λ, θ) / (1 − r·ρ̄(λ)),   τ̄, ρ̄ the hemispherical means of
                                                             Tbar and Rbar_below,

(Rbar = R_spec + ∫R: the mirror and diffuse parts of the layer's own reflection).

Standard error (docs/figures.md has the derivation).  Lab is linearised around the table:
J = ∂Lab/∂x for every stored number x of Rbar(·, view), Tbar and Rbar_below (by central
differences through the same evaluation code), and the stored standard errors s_x are
propagated under two assumptions about their correlation, which the tables do not record:
  independent   var_k = Σ_x (J_kx s_x)²
  correlated    var_k = Σ_c (Σ_{x∈c} J_kx s_x)²   (one error draw per column c, shared by all
                                                 its λ and σ nodes: the same random cells)
and the larger of the two is reported (per component).  Where the standard errors come from:
  'realizations'     the spread across the table's random cells (the wave tiers);
  'exact'            0: the thin film of a molecular ink is exact;
  'model deviation'  an effective-medium table: the tier probe's measured deviation from the full
                     solve, used as the standard error of every node of Rbar, Tbar, Rbar_below;
  'unknown'          NaN: one realization, nothing to estimate the spread from.

Saturation is CIELAB's s = C*/L* (a denser layer is darker at similar chroma: "more saturated"
for an absorbing ink); ΔE is CIE76.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from solver.colour import lab_hue_chroma, reflectance_to_srgb8, reflectance_to_xyz, xyz_to_lab
from solver.table.evaluate import directional_albedo
from solver.table.schema import InkTable

#: the paper's paper albedo (docs/design.md §1) and the view of the CSV colour
PAPER_ALBEDO = 0.9
VIEW_DEG = 0.0
#: inputs of the colour whose standard errors are propagated
SE_COLUMNS = ("Rbar", "Tbar", "Rbar_below")
_STEP = 1e-4                 # central-difference step in reflectance units (Lab is smooth there)


@dataclass(frozen=True)
class CellColour:
    lab: np.ndarray           # (L*, a*, b*)
    se: np.ndarray            # standard errors of (L*, a*, b*); NaN where unknown
    source: str               # where the standard errors come from (see module doc)
    srgb8: tuple[int, int, int]

    @property
    def chroma(self) -> float:
        return float(lab_hue_chroma(self.lab)[1])

    @property
    def saturation(self) -> float:
        return saturation(self.lab)


def saturation(lab) -> np.ndarray:
    """CIELAB saturation s = C*/L* (any leading shape)."""
    lab = np.asarray(lab, dtype=float)
    return np.hypot(lab[..., 1], lab[..., 2]) / lab[..., 0]


def delta_e(a, b) -> np.ndarray:
    """CIE76 colour difference."""
    return np.linalg.norm(np.asarray(a, dtype=float) - np.asarray(b, dtype=float), axis=-1)


def _albedo(table: InkTable, paper, view_rad: float, Rbar, Tbar, Rbar_below) -> np.ndarray:
    t = dataclasses.replace(table, R_spec=Rbar, R=np.zeros_like(table.R), Tbar=Tbar, Rbar_below=Rbar_below)
    return directional_albedo(t, paper, view_rad)


def spectrum_lab(wavelengths_nm, reflectance) -> np.ndarray:
    """CIELAB (D65) of reflectance spectra with the wavelength axis first."""
    return xyz_to_lab(reflectance_to_xyz(wavelengths_nm, reflectance, axis=0))


def cell_lab(table: InkTable, paper=PAPER_ALBEDO, view_deg: float = VIEW_DEG) -> np.ndarray:
    """CIELAB of the ink on paper under diffuse light seen at view_deg (no error estimate)."""
    return spectrum_lab(table.wavelengths, directional_albedo(table, paper, np.radians(view_deg)))


def cell_srgb8(table: InkTable, paper=PAPER_ALBEDO, view_deg: float = VIEW_DEG) -> np.ndarray:
    """8-bit sRGB of the same colour (a white Lambertian of albedo 1 is 255, 255, 255)."""
    return reflectance_to_srgb8(table.wavelengths, directional_albedo(table, paper, np.radians(view_deg)))


def lab_jacobian(table: InkTable, paper=PAPER_ALBEDO, view_deg: float = VIEW_DEG) -> dict:
    """∂Lab/∂x for x in the columns of SE_COLUMNS: {name: array [3, nλ, nσ]}.

    A(λ) depends only on the columns' values at its own λ, so one perturbation of a σ node at
    every λ at once gives ∂A(λ)/∂x(λ, σ) for all λ; ∂Lab/∂A(λ) by central differences."""
    view = np.radians(view_deg)
    wl = table.wavelengths
    base = {name: table.column(name) for name in SE_COLUMNS}
    nl, ns = table.Rbar.shape
    dA = {}
    for name in SE_COLUMNS:
        d = np.zeros((nl, ns))
        for j in range(ns):
            plus, minus = dict(base), dict(base)
            plus[name] = base[name].copy()
            minus[name] = base[name].copy()
            plus[name][:, j] += _STEP
            minus[name][:, j] -= _STEP
            d[:, j] = (_albedo(table, paper, view, **plus) - _albedo(table, paper, view, **minus)) / (2 * _STEP)
        dA[name] = d
    A = _albedo(table, paper, view, **base)
    eye = np.eye(nl) * _STEP
    dlab = (spectrum_lab(wl, A[:, None] + eye) - spectrum_lab(wl, A[:, None] - eye)) / (2 * _STEP)   # [nλ, 3]
    return {name: dlab.T[:, :, None] * dA[name][None] for name in SE_COLUMNS}


SE_MODES = ("independent", "correlated", "larger")


def propagate_se(jacobian: dict, errors: dict, mode: str = "larger") -> np.ndarray:
    """Standard errors of (L*, a*, b*) from the nodes' standard errors (module doc): errors
    independent across nodes, fully correlated within each column, or the larger of the two."""
    if mode not in SE_MODES:
        raise ValueError(f"SE propagation mode {mode!r}: choose one of {', '.join(SE_MODES)}")
    independent = sum(np.sum((jacobian[n] * errors[n][None]) ** 2, axis=(1, 2)) for n in jacobian)
    correlated = sum(np.sum(jacobian[n] * errors[n][None], axis=(1, 2)) ** 2 for n in jacobian)
    var = {"independent": independent, "correlated": correlated}.get(mode, np.maximum(independent, correlated))
    return np.sqrt(var)


def node_errors(table: InkTable) -> tuple[dict | None, str]:
    """The standard errors of the colour's inputs and where they come from (module doc)."""
    shape = table.Rbar.shape
    if all(name in table.errors for name in SE_COLUMNS):
        return {n: np.asarray(table.errors[n], dtype=float) for n in SE_COLUMNS}, "realizations"
    tier = table.meta.get("tier")
    model = (table.meta.get("errors") or {}).get("model")
    if tier == "thin-film":
        return {n: np.zeros(shape) for n in SE_COLUMNS}, "exact"
    if tier == "effective-medium" and model is not None:
        return {n: np.full(shape, float(model)) for n in SE_COLUMNS}, "model deviation"
    return None, "unknown"


def cell_colour(table: InkTable, paper=PAPER_ALBEDO, view_deg: float = VIEW_DEG) -> CellColour:
    """CIELAB of the cell, its propagated standard error and its sRGB (8 bit)."""
    view = np.radians(view_deg)
    refl = directional_albedo(table, paper, view)
    lab = spectrum_lab(table.wavelengths, refl)
    errors, source = node_errors(table)
    if errors is None:
        se = np.full(3, np.nan)
    elif source == "exact":
        se = np.zeros(3)
    else:
        se = propagate_se(lab_jacobian(table, paper, view_deg), errors)
    rgb = reflectance_to_srgb8(table.wavelengths, refl)
    return CellColour(lab, se, source, tuple(int(v) for v in rgb))
