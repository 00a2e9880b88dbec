"""The measured colour of a table and its standard error: CIELAB of the ink on paper under a
`Measurement`, with its standard error from the table's realizations.

Standard error (docs/figures.md has the derivation and the measurements). Which is used is the
result's `method`:
  'jackknife'   a wave table holding its leave-one-out ensembles (`table.jackknife`, N ≥ 2
                realizations; solver/table/jackknife.py): the colour c_k of each through the same
                measurement (so Lab's nonlinearity and every correlation between nodes are in
                it), SE² = (N − 1)/N Σ_k (c_k − c̄)² per L*, a*, b*, with N − 1 degrees of freedom
                (stratified by TE/TM cells where they were solved separately: N − 2; jackknife.py).
                Every wave table built by this version has it;
  'propagated'  otherwise (older wave tables; an effective-medium table's model deviation): the
                bound below, propagated from the nodes' standard errors;
  'exact'       0 (a thin film);  'unknown'  NaN (one realization).

The propagated bound. The reflectance factor A(λ) depends on a
table's numbers at its own λ only: linearly on the diffuse lobe R and the mirror column R_spec,
and through the paper term on Tbar and Rbar_below. Lab is linearised around the table:
J = ∂Lab/∂x for every stored number x of R_spec, Tbar, Rbar_below (central differences through
the measurement's own code) and of R (exact: A is linear in R with the measurement's weights),
and the stored standard errors s_x are propagated under two assumptions about their
correlation, which the tables do not record:
  independent   var_k = Σ_x (J_kx s_x)²
  correlated    var_k = Σ_c (Σ_{x∈c} J_kx s_x)²   (one error draw per column c, shared by all
                                                 its λ and σ nodes: the same random cells)
and the larger of the two is reported (per component). It can be far from the truth: for
in-plane 200-nm cylinders the diffraction orders land in different BRDF bins in each
realization, so neighbouring bins' errors are anti-correlated and the correlated bound
overstates a* several-fold. Where the standard errors come from:
  'realizations'     the spread across the table's random cells (the wave tiers), with
                     the table's `errors.se_dof` degrees of freedom (`dof`, for Student's t:
                     realizations − 1, or − 2 where TE and TM were solved on separate cells);
  'exact'            0: the thin film of a molecular ink is exact;
  'model deviation'  an effective-medium table: the tier probe's measured deviation from the full
                     solve, used as the standard error of every node of R_spec, Tbar, Rbar_below;
  'unknown'          NaN: one realization, nothing to estimate the spread from.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..table import jackknife
from .measurement import DEFAULT, REFLECTANCE_COLUMNS, Measurement

#: the columns whose standard errors are propagated through the paper term and the mirror
SE_COLUMNS = ("R_spec", "Tbar", "Rbar_below")
_STEP = 1e-4                 # central-difference step in reflectance units (Lab is smooth there)
SE_MODES = ("independent", "correlated", "larger")
SE_METHODS = ("jackknife", "propagated", "exact", "unknown")     # how `TableColour.se` was computed


@dataclass(frozen=True)
class TableColour:
    lab: np.ndarray           # (L*, a*, b*)
    se: np.ndarray            # standard errors of (L*, a*, b*); NaN where unknown
    source: str               # where the standard errors come from (module doc)
    dof: float                # degrees of freedom of `se` (inf: exact or a model bound; 0: unknown)
    measurement: Measurement
    method: str = "propagated"  # how se was computed: one of SE_METHODS (module doc)

    @property
    def chroma(self) -> float:
        return float(np.hypot(self.lab[1], self.lab[2]))


def lab_jacobian(table, paper, measurement: Measurement = DEFAULT) -> dict:
    """∂Lab/∂x for the columns of SE_COLUMNS ([3, nλ, nσ]) and for R ([3, nλ, nσ, nθ, nφ])."""
    base = {name: table.column(name) for name in SE_COLUMNS}
    nl, ns = table.Rbar.shape
    dA = {}
    for name in SE_COLUMNS:
        d = np.zeros((nl, ns))
        for j in range(ns):
            plus, minus = base[name].copy(), base[name].copy()
            plus[:, j] += _STEP
            minus[:, j] -= _STEP
            d[:, j] = (measurement.reflectance(table, paper, **{name: plus})
                       - measurement.reflectance(table, paper, **{name: minus})) / (2 * _STEP)
        dA[name] = d
    A = measurement.reflectance(table, paper)
    eye = np.eye(nl) * _STEP
    wl = table.wavelengths
    dlab = (measurement.lab_of_spectra(wl, A[:, None] + eye, axis=0)
            - measurement.lab_of_spectra(wl, A[:, None] - eye, axis=0)) / (2 * _STEP)      # [nλ, 3]
    out = {name: dlab.T[:, :, None] * dA[name][None] for name in SE_COLUMNS}
    out["R"] = dlab.T[:, :, None, None, None] * measurement.r_weights(table)[None, None]
    return out


def propagate_se(jacobian: dict, errors: dict, mode: str = "larger") -> np.ndarray:
    """Standard errors of (L*, a*, b*) from the nodes' standard errors (module doc): errors
    independent across nodes, fully correlated within each column, or the larger of the two."""
    if mode not in SE_MODES:
        raise ValueError(f"SE propagation mode {mode!r}: choose one of {', '.join(SE_MODES)}")
    names = [n for n in jacobian if n in errors]
    axes = lambda a: tuple(range(1, a.ndim))
    independent = sum(np.sum((jacobian[n] * errors[n][None]) ** 2, axis=axes(jacobian[n])) for n in names)
    correlated = sum(np.sum(jacobian[n] * errors[n][None], axis=axes(jacobian[n])) ** 2 for n in names)
    var = {"independent": independent, "correlated": correlated}.get(mode, np.maximum(independent, correlated))
    return np.sqrt(var)


def node_errors(table) -> tuple[dict | None, str, float]:
    """The standard errors of the colour's inputs, where they come from (module doc) and their
    degrees of freedom."""
    shape = table.Rbar.shape
    if all(name in table.errors for name in SE_COLUMNS):
        errors = {n: np.asarray(table.errors[n], dtype=float) for n in SE_COLUMNS}
        if "R" in table.errors:
            errors["R"] = np.asarray(table.errors["R"], dtype=float)
        dof = (table.meta.get("errors") or {}).get("se_dof")    # wave_ensemble: N − 1, or N − 2
        if dof is None:                                          # tables before it: N − 1
            dof = (table.meta.get("realizations_used") or len(table.meta.get("seeds") or ()) or 2) - 1
        return errors, "realizations", float(dof)
    tier = table.meta.get("tier")
    model = (table.meta.get("errors") or {}).get("model")
    if tier == "thin-film":
        return {n: np.zeros(shape) for n in SE_COLUMNS}, "exact", math.inf
    if tier == "effective-medium" and model is not None:
        return {n: np.full(shape, float(model)) for n in SE_COLUMNS}, "model deviation", math.inf
    return None, "unknown", 0.0


def _jackknife_colour(table, measurement: Measurement, spectrum) -> TableColour | None:
    """The colour of spectrum(columns) (a function of {name: column}) with its jackknife standard
    error over the table's leave-one-out ensembles; None when the table has none."""
    replicas = jackknife.replicas(table)
    if replicas is None:
        return None
    wl = table.wavelengths
    own = {name: table.column(name) for name in replicas[0]}
    labs = [measurement.lab_of_spectra(wl, spectrum(r)) for r in replicas]
    groups = table.meta.get("jackknife_groups")          # TE and TM cells: independent groups
    return TableColour(measurement.lab_of_spectra(wl, spectrum(own)), jackknife.standard_error(labs, groups),
                       "realizations", float(jackknife.degrees_of_freedom(len(replicas), groups)),
                       measurement, "jackknife")


def table_colour(table, paper, measurement: Measurement = DEFAULT) -> TableColour:
    """CIELAB of the ink on paper under `measurement`, with its standard error: the jackknife's
    where the table holds its leave-one-out ensembles, else propagated (module doc; `method`)."""
    measurement.check(table)
    reflectance = lambda cols: measurement.reflectance(table, paper, **{n: cols[n] for n in REFLECTANCE_COLUMNS})
    jack = _jackknife_colour(table, measurement, reflectance)
    if jack is not None:
        return jack
    lab = measurement.lab(table, paper)
    errors, source, dof = node_errors(table)
    if errors is None:
        return TableColour(lab, np.full(3, np.nan), source, dof, measurement, "unknown")
    if source == "exact":
        return TableColour(lab, np.zeros(3), source, dof, measurement, "exact")
    return TableColour(lab, propagate_se(lab_jacobian(table, paper, measurement), errors), source, dof,
                       measurement, "propagated")


def transmitted_colour(table, measurement: Measurement = DEFAULT) -> TableColour:
    """CIELAB of the layer's total transmittance Tbar at normal incidence (the paper's Fig. 9
    quantity) as a transmission colour under the measurement's illuminant and observer, with
    its standard error as `table_colour` gives it (jackknife, else propagated from Tbar's)."""
    from .cie import check_range

    check_range(table.wavelengths, f"the table ({table.meta.get('ink', 'ink')})")
    jack = _jackknife_colour(table, measurement, lambda cols: cols["Tbar"][:, 0])
    if jack is not None:
        return jack
    wl = table.wavelengths
    T = table.Tbar[:, 0]
    lab = measurement.lab_of_spectra(wl, T)
    errors, source, dof = node_errors(table)
    if errors is None:
        return TableColour(lab, np.full(3, np.nan), source, dof, measurement, "unknown")
    if source == "exact":
        return TableColour(lab, np.zeros(3), source, dof, measurement, "exact")
    eye = np.eye(wl.size) * _STEP
    dlab = (measurement.lab_of_spectra(wl, T[:, None] + eye, axis=0)
            - measurement.lab_of_spectra(wl, T[:, None] - eye, axis=0)) / (2 * _STEP)      # [nλ, 3]
    se = propagate_se({"Tbar": dlab.T}, {"Tbar": errors["Tbar"][:, 0]})
    return TableColour(lab, se, source, dof, measurement, "propagated")
