"""Public entry points: solve one incidence, or prepare once and solve from both sides."""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, replace

import numpy as np

from .energy import absorption
from .kernel1d import background_amplitudes
from .krylov import (Callback, ConvergenceError, ConvergenceWarning, KrylovOutcome,
                     WaveSolverError, bicgstab, born, gmres)
from .operator import (DEFAULT_MIN_LOSS, LayerOperator, apply_scattering, apply_system,
                       prepare)
from .orders import OrderSet, diffraction_orders
from .types import Cell, Incidence, bloch_vector

METHODS = ("auto", "gmres", "bicgstab", "born")
#: upper bound on the memory of the GMRES basis (bytes); the restart length adapts to it.
GMRES_BASIS_BYTES = 1.0e9


@dataclass(frozen=True, eq=False)
class DiffractionResult:
    """Orders and diagnostics of one solve (unit incident amplitude; powers are fractions).

    reflected: orders leaving through the face of entry (above: up, referenced to z_top;
    below: down, referenced to z_bottom); transmitted: through the other face.
    R, T: totals over propagating orders, 00 included; R_spec, T_coh: the 00 orders alone.
    absorbed: A from the scheme-exact ∫ Im ε |u|² (energy.py); absorbed_midpoint: the plain
    cell-average sum; energy_error = R + T + absorbed − 1.
    residuals: relative residual after every iteration; residual: final explicit residual.
    kz_incident: k_z of the incident wave in its medium (1/nm), the power normalisation.
    field: total field u (with its Bloch phase) at the voxel centres as z-cell averages, if asked.
    """

    wavelength_nm: float
    kx0: float
    ky0: float
    from_below: bool
    reflected: OrderSet
    transmitted: OrderSet
    R: float
    T: float
    R_spec: float
    T_coh: float
    absorbed: float
    absorbed_midpoint: float
    energy_error: float
    applications: int
    residuals: tuple[float, ...]
    residual: float
    converged: bool
    method: str
    seconds: float
    eps_background: complex
    kz_incident: float
    field: np.ndarray | None = None


def _gmres_restart(b: np.ndarray) -> int:
    """Restart length that keeps the GMRES basis under GMRES_BASIS_BYTES (at most 60)."""
    per_vec = b.size * b.dtype.itemsize
    return int(min(60, GMRES_BASIS_BYTES // per_vec - 1))


def _run(op: LayerOperator, b: np.ndarray, method: str, tol: float, maxiter: int,
         restart: int | None, callback: Callback) -> KrylovOutcome:
    if method == "auto":  # GMRES unless its basis would not fit in memory (docs/wave_solver.md)
        method = "gmres" if (restart or _gmres_restart(b)) >= 10 else "bicgstab"
    kw = dict(tol=tol, maxiter=maxiter, callback=callback)
    if method == "gmres":
        m = max(1, restart or _gmres_restart(b))
        return gmres(lambda x: apply_system(op, x), b, restart=m, **kw)
    if method == "bicgstab":
        return bicgstab(lambda x: apply_system(op, x), b, **kw)
    return born(lambda x: apply_scattering(op, x), b, **kw)


def solve_prepared(op: LayerOperator, from_below: bool = False, *, tol: float = 1e-4,
                   method: str = "auto", maxiter: int = 500, restart: int | None = None,
                   on_fail: str = "warn", return_field: bool = False,
                   exact_energy: bool = True, callback: Callback = None) -> DiffractionResult:
    """Solve for a unit plane wave with the Bloch vector of `op`, from above or below.

    tol: relative residual ‖b − A·w‖/‖b‖ at which the iteration stops.  method: 'auto'
    (= 'gmres', see docs/wave_solver.md), 'gmres', 'bicgstab' or 'born' (raises
    BornDivergenceError when the series diverges).  maxiter: operator applications.
    on_fail: 'warn' (ConvergenceWarning) or 'raise' (ConvergenceError) when tol is not reached;
    'ignore' only where a truncated iteration is the intent (e.g. first-order Born): the result's
    `converged` and `residual` still say how far it got.
    callback(applications, relative_residual) is called after every iteration.
    exact_energy False skips the scheme-exact ∫|u|² (absorbed = absorbed_midpoint then).
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if on_fail not in ("warn", "raise", "ignore"):
        raise ValueError("on_fail must be 'warn', 'raise' or 'ignore'")
    if not tol > 0:
        raise ValueError("tol must be positive")
    t0 = time.perf_counter()
    nx, ny, nz = op.shape
    coef, _, _ = background_amplitudes(op.green, from_below)
    prof = op.pbot if from_below else op.ptop
    b = np.broadcast_to((coef[0, 0] * prof[:, 0, 0])[:, None, None, :].astype(op.dtype),
                        op.unknown_shape).copy()
    out = _run(op, b, method, tol, maxiter, restart, callback)
    w = out.x
    f = op.contrast * w
    refl, trans, kz_inc = diffraction_orders(op, f, from_below)
    a_exact, a_mid = absorption(op, w, f, from_below, kz_inc, exact=exact_energy)
    big_r, big_t = refl.total, trans.total
    vals = (big_r, big_t, a_exact, a_mid, out.true_residual)
    if not all(math.isfinite(v) for v in vals) or not np.all(np.isfinite(refl.amplitude)) \
            or not np.all(np.isfinite(trans.amplitude)):
        raise WaveSolverError(f"non-finite result (R={big_r}, T={big_t}, A={a_exact}, "
                              f"residual={out.true_residual}) after {out.applications} "
                              f"applications of {out.method}")
    if not out.converged:
        msg = (f"wave solver ({out.method}) stopped after {out.applications} operator "
               f"applications at relative residual {out.true_residual:.3g} > tol {tol:.3g} "
               f"(λ = {op.wavelength_nm:g} nm, Bloch vector ({op.kx0:.6g}, {op.ky0:.6g}) 1/nm, "
               f"from {'below' if from_below else 'above'}, grid {op.shape}); energy error "
               f"R+T+A−1 = {big_r + big_t + a_exact - 1:.2g}")
        if on_fail == "raise":
            raise ConvergenceError(msg)
        if on_fail == "warn":
            warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    field = None
    if return_field:
        lx, ly = op.cell.period_nm
        x = (np.arange(nx) + 0.5) * lx / nx
        y = (np.arange(ny) + 0.5) * ly / ny
        phase = np.exp(1j * (op.kx0 * x[:, None] + op.ky0 * y[None, :]))
        field = w[0] * phase[:, :, None]
    return DiffractionResult(
        op.wavelength_nm, op.kx0, op.ky0, bool(from_below), refl, trans, big_r, big_t,
        refl.pwr(0, 0), trans.pwr(0, 0), a_exact, a_mid, big_r + big_t + a_exact - 1.0,
        out.applications, out.residuals, out.true_residual, out.converged,
        out.method, time.perf_counter() - t0, op.eps_background, kz_inc, field)


def solve(cell: Cell, incidence: Incidence, *, tol: float = 1e-4, method: str = "auto",
          maxiter: int = 500, restart: int | None = None, on_fail: str = "warn",
          return_field: bool = False, exact_energy: bool = True, callback: Callback = None,
          eps_background: complex | None = None, min_loss: float = DEFAULT_MIN_LOSS,
          z_order: int = 1, dtype: type | None = None,
          workers: int | None = None) -> DiffractionResult:
    """Diffraction of a unit plane wave by one periodic cell (see solve_prepared, prepare).

    For several incidences with the same Bloch vector (above and below), call prepare() once
    and solve_prepared() per side.  The returned `seconds` include the preparation.
    dtype None: complex64 when tol ≥ 1e-5 (its rounding floor is ~1e-6), else complex128.
    """
    if dtype is None:
        dtype = np.complex64 if tol >= 1e-5 else np.complex128
    t0 = time.perf_counter()
    kx0, ky0 = bloch_vector(cell, incidence)
    op = prepare(cell, incidence.wavelength_nm, kx0, ky0, eps_background=eps_background,
                 min_loss=min_loss, z_order=z_order, dtype=dtype, workers=workers)
    res = solve_prepared(op, incidence.from_below, tol=tol, method=method, maxiter=maxiter,
                         restart=restart, on_fail=on_fail, return_field=return_field,
                         exact_energy=exact_energy, callback=callback)
    return replace(res, seconds=time.perf_counter() - t0)


__all__ = ["DiffractionResult", "solve", "solve_prepared"]
