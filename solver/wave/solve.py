"""Public entry points: solve one incidence, or prepare once and solve from both sides."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from .faces import DEFAULT_TM_FACES, TMFaces, preset_name
from .interfaces import FaceLayers
from . import layered
from .energy import absorption, closure, midpoint_absorption
from .fftback import DEFAULT_FFT
from .kernel1d import background_amplitudes, face_profiles, harmonic_green
from .krylov import (Callback, ConvergenceError, KrylovOutcome, WaveSolverError, bicgstab,
                     born, gmres)
from .operator import (DEFAULT_MIN_LOSS, Background, LayerOperator, Workspace, from_zmajor,
                       prepare, scatter_zmajor, system_zmajor, to_zmajor)
from .orders import OrderSet, diffraction_orders
from .types import Cell, Incidence, bloch_vector
from .vecops import one_blas_thread

METHODS = ("auto", "gmres", "bicgstab", "born")
#: what a solve does when it falls short: 'raise' (the default: a non-converged iterate, or a
#: converged one whose energy balance is implausible, is not a result) or 'truncate' (the
#: caller asked for a truncated iteration, e.g. a first-order Born series: the iterate is
#: returned, and `converged`, `residual` and `energy_error` say how far it got)
ON_FAIL = ("raise", "truncate")
#: upper bound on the memory of the GMRES basis (bytes); the restart length adapts to it.
GMRES_BASIS_BYTES = 1.0e9
#: default bound on |R + T + A − 1| (and on R, T, A leaving [0, 1]) above which a solve raises,
#: whatever its tolerance: 1e-3 is the resolution the tables need (docs/wave_solver.md).
ENERGY_BOUND = 1e-3
#: default relative residual: on the reference geometry (64×64×32; k = 0, 0.2, 1.1; σ 25°,
#: 80°) tol 1e-3 leaves |ΔR|, |ΔT|, |ΔR_spec|, |ΔT_coh| ≤ 8e-5 and Σ|ΔP| over the diffuse orders
#: ≤ 2.2e-4 against tol 1e-6, far below the discretisation error (5.6e-3), for 10–26 % fewer
#: applications than tol 1e-4 (python -m benchmarks.bench_wave, "tolerance curve").
DEFAULT_TOL = 1e-3


class EnergyClosureError(WaveSolverError):
    """A converged solve whose energy closure R + T + A − 1 (or R, T, A outside [0, 1])
    exceeds the bound: its tolerance was too loose for a result.  problem: what is wrong."""

    def __init__(self, message: str, problem: str = ""):
        super().__init__(message)
        self.problem = problem


@dataclass(frozen=True, eq=False)
class DiffractionResult:
    """Orders and diagnostics of one solve (unit incident amplitude; powers are fractions).

    reflected: orders leaving through the face of entry (above: up, referenced to z_top;
    below: down, referenced to z_bottom); transmitted: through the other face.
    R, T: totals over propagating orders, 00 included; R_spec, T_coh: the 00 orders alone.
    absorbed: the scheme's A; energy_error = R + T + absorbed − 1; energy_check: how A was
    obtained: 'residual' (Green's identity, A = 1 − R − T + E with E from the true residual:
    one inner product), 'quadrature' (∫ Im ε |u|² by quadrature, independent of R and T;
    exact_energy=True, and a converged Born series) or, for a truncated Born series without
    exact_energy (it does not conserve energy), 'midpoint'.  absorbed_midpoint: the plain cell-average sum.  residuals: relative residual after every iteration; residual: final
    explicit residual.  kz_incident: k_z of the incident wave in its medium (1/nm), the power
    normalisation.  field: total field u (with its Bloch phase) at the voxel centres as z-cell
    averages, if asked.  solution: the solved moments w (nb, nx, ny, nz), the warm start x0
    for a neighbouring solve.  polarisation: 'te' or 'tm'; tm_faces: the TM face forms
    (faces.py preset name, or 'inner=…,outer=…,evanescent=…,mean=…'), None for TE.
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
    solution: np.ndarray | None = None
    polarisation: str = "te"
    energy_check: str = "residual"
    tm_faces: str | None = None


def memory_restart(op: "LayerOperator | Background") -> int:
    """The longest GMRES restart whose basis fits GMRES_BASIS_BYTES for this operator (its
    unknowns and dtype)."""
    per_vec = int(np.prod(op.unknown_shape)) * np.dtype(op.dtype).itemsize
    return int(GMRES_BASIS_BYTES // per_vec - 1)


def _gmres_restart(op: LayerOperator) -> int:
    """The default restart length: the memory bound, at most 60 (docs/wave_solver.md)."""
    return min(60, memory_restart(op))


def _layered_gmres(op: LayerOperator, b: np.ndarray, ws: Workspace, tol: float, maxiter: int,
                   restart: int, x0: np.ndarray | None, callback: Callback) -> KrylovOutcome:
    """GMRES on the layered-preconditioned system w − M⁻¹GV′w = M⁻¹b (layered.py), iterated on
    the lateral spectra of w (layered.scatter), until the *true* relative residual
    ‖b − (I − GV)w‖/‖b‖ meets tol: each round ends with the true residual, P times the
    preconditioned one that GMRES's Arnoldi relation gives (layered.unpreconditioned: no
    application); a round that met its own tolerance but not the true one is followed by a
    tighter one from its iterate.  The outcome's residual vector is the true one (the energy
    closure reads it)."""
    lay = layered.prepare_layered(op)
    bp = layered.right_hand_side(op, lay, b)
    bnorm = float(np.linalg.norm(b.ravel())) or 1.0
    xh = None if x0 is None else layered.to_fourier(op, lay, x0)
    apps, history, inner_tol, rel, r = 0, [], tol, math.inf, None
    for _ in range(4):
        out = gmres(lambda v, o: layered.scatter(op, lay, v, ws, o), bp, tol=inner_tol,
                    maxiter=maxiter - apps, restart=restart, backend=op.fft, x0=xh, callback=callback)
        apps += out.applications
        history.extend(out.residuals)
        xh = out.x
        r = layered.unpreconditioned(op, lay, out.residual_vector)
        rel = float(np.linalg.norm(r.ravel())) / bnorm
        if rel <= tol or apps >= maxiter or not out.converged:
            break
        inner_tol = out.true_residual * 0.5 * tol / rel        # the ratio seen, with a margin
    return KrylovOutcome(layered.from_fourier(op, xh), tuple(history), apps, rel <= tol, rel, "gmres", r)


def _run(op: LayerOperator, b: np.ndarray, method: str, tol: float, maxiter: int,
         restart: int | None, x0: np.ndarray | None, callback: Callback,
         preconditioner: str = "auto") -> KrylovOutcome:
    """The iteration on the z-major layout (operator.py) for the z-major right-hand side b;
    x0 is in the public layout (nb, nx, ny, nz), the returned solution and residual are
    z-major."""
    if method == "auto":  # GMRES unless its basis would not fit in memory (docs/wave_solver.md)
        method = "gmres" if (restart or _gmres_restart(op)) >= 10 else "bicgstab"
    ws = Workspace(op)
    kw = dict(tol=tol, maxiter=maxiter, callback=callback,
              x0=None if x0 is None else to_zmajor(np.asarray(x0, dtype=op.dtype), op.fft))
    try:
        if method == "gmres" and layered.wanted(op, preconditioner):
            return _layered_gmres(op, b, ws, restart=max(1, restart or _gmres_restart(op)), **kw)
        if method == "gmres":
            m = max(1, restart or _gmres_restart(op))
            return gmres(lambda x, o: scatter_zmajor(op, x, ws, o), b, restart=m, backend=op.fft,
                         **kw)
        if method == "bicgstab":
            return bicgstab(lambda x, o: system_zmajor(op, x, ws, o), b, **kw)
        return born(lambda x, o: scatter_zmajor(op, x, ws, o), b, **kw)
    finally:
        ws.release()


def source(op: LayerOperator, from_below: bool = False) -> np.ndarray:
    """The right-hand side w_b of w − G V w = w_b: the moments of the background (Airy) field
    of a unit plane wave from above or below, (nb, nx, ny, nz) in the operator's dtype (the
    00 harmonic only: laterally uniform)."""
    green00 = harmonic_green(op.green, (slice(0, 1), slice(0, 1)))
    coef, _, _ = background_amplitudes(green00, from_below)
    prof = coef[0, 0] * face_profiles(green00)[1 if from_below else 0][:, 0, 0]   # (nb, nz)
    inner = op.interfaces
    if inner is not None:     # the inner interfaces' sources in the background wave (00)
        sigma = inner.background(from_below)
        prof = prof + inner.coherent_profile(sigma, op.fft.to_host).reshape(prof.shape)
    return np.broadcast_to(prof[:, None, None, :].astype(op.dtype), op.unknown_shape).copy()


def _check_energy(res: DiffractionResult, bound: float) -> str | None:
    """Why the energy balance of `res` is implausible, or None."""
    e = res.energy_error
    problems = []
    if abs(e) > bound:
        problems.append(f"energy closure R+T+A−1 = {e:+.3g} exceeds ±{bound:g}")
    for name, v in (("R", res.R), ("T", res.T), ("A", res.absorbed)):
        if v < -bound or v > 1 + bound:
            problems.append(f"{name} = {v:.4g} outside [0, 1]")
    return "; ".join(problems) or None


def solve_prepared(op: LayerOperator, from_below: bool = False, *, tol: float = DEFAULT_TOL,
                   method: str = "auto", maxiter: int = 500, restart: int | None = None,
                   on_fail: str = "raise", return_field: bool = False,
                   exact_energy: bool = False, energy_bound: float = ENERGY_BOUND,
                   x0: np.ndarray | None = None, callback: Callback = None,
                   preconditioner: str = "auto") -> DiffractionResult:
    """Solve for a unit plane wave with the Bloch vector of `op`, from above or below.

    tol: relative residual ‖b − A·w‖/‖b‖ at which the iteration stops.  method: 'auto'
    (= 'gmres', see docs/wave_solver.md), 'gmres', 'bicgstab' or 'born' (raises
    BornDivergenceError when the series diverges).  maxiter: operator applications.
    on_fail: 'raise' (the default: ConvergenceError when tol is not reached — the iterate is
    not a result —, EnergyClosureError when a converged solve has |R + T + A − 1| >
    energy_bound or R, T, A leaving [0, 1] by more than it) or 'truncate' (only where a
    truncated iteration is the intent, e.g. first-order Born: the iterate is returned,
    `converged`, `residual` and `energy_error` say how far it got).
    exact_energy: A by quadrature of ∫ Im ε |u|² (≈ 3 applications' worth) instead of from the
    residual (one inner product); see DiffractionResult.energy_check.
    x0: initial guess, e.g. `solution` of a solve at a neighbouring wavelength or incidence
    (same grid; GMRES and BiCGStab).  callback(applications, relative_residual) is called
    after every iteration.  preconditioner: 'auto' (GMRES on a cell with a strong
    laterally uniform contrast, such as a rough top's air, runs on the layered-preconditioned
    system: layered.py), 'layered' (wherever it applies) or 'none'.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if preconditioner not in layered.MODES:
        raise ValueError(f"preconditioner must be one of {layered.MODES}, got {preconditioner!r}")
    if on_fail not in ON_FAIL:
        raise ValueError(f"on_fail must be one of {ON_FAIL} (a non-converged solve is never a "
                         f"result with a warning), got {on_fail!r}")
    if not tol > 0:
        raise ValueError("tol must be positive")
    if not energy_bound > 0:
        raise ValueError("energy_bound must be positive")
    if x0 is not None and np.shape(x0) != op.unknown_shape:
        raise ValueError(f"x0 must have the shape of the unknowns {op.unknown_shape} (a "
                         f"previous result's `solution` on the same grid), got {np.shape(x0)}")
    t0 = time.perf_counter()
    nx, ny, nz = op.shape
    b = to_zmajor(source(op, from_below), op.fft)
    with one_blas_thread():     # vector work on one BLAS thread (vecops.py), not only Krylov's
        out = _run(op, b, method, tol, maxiter, restart, x0, callback, preconditioner)
        f_z = op.contrast_zmajor * out.x                          # z-major, as out.x
        w = op.fft.to_host(from_zmajor(out.x))                     # the solution, on the host
        refl, trans, kz_inc = diffraction_orders(op, f_z, from_below, zmajor=True)
        big_r, big_t = refl.total, trans.total
        a_mid = midpoint_absorption(op, w, from_below, kz_inc)
        if exact_energy or (out.residual_vector is None and out.converged):
            a_exact = absorption(op, w, f_z, from_below, kz_inc, refl, trans)
            check = "quadrature"
        elif out.residual_vector is None:
            # a truncated (unconverged) Born series is not meant to conserve energy: the cheap
            # midpoint absorption (O(h²)) reports it; exact_energy=True measures it by quadrature
            a_exact, check = a_mid, "midpoint"
        else:
            a_exact, _ = closure(op, out.residual_vector, f_z, big_r, big_t, from_below, kz_inc)
            check = "residual"
    vals = (big_r, big_t, a_exact, a_mid, out.true_residual)
    if not all(math.isfinite(v) for v in vals) or not np.all(np.isfinite(refl.amplitude)) \
            or not np.all(np.isfinite(trans.amplitude)):
        raise WaveSolverError(f"non-finite result (R={big_r}, T={big_t}, A={a_exact}, "
                              f"residual={out.true_residual}) after {out.applications} "
                              f"applications of {out.method}")
    field = None
    if return_field:
        lx, ly = op.cell.period_nm
        x = (np.arange(nx) + 0.5) * lx / nx
        y = (np.arange(ny) + 0.5) * ly / ny
        phase = np.exp(1j * (op.kx0 * x[:, None] + op.ky0 * y[None, :]))
        field = w[0] * phase[:, :, None]
    res = DiffractionResult(
        op.wavelength_nm, op.kx0, op.ky0, bool(from_below), refl, trans, big_r, big_t,
        refl.pwr(0, 0), trans.pwr(0, 0), a_exact, a_mid, big_r + big_t + a_exact - 1.0,
        out.applications, out.residuals, out.true_residual, out.converged,
        out.method, time.perf_counter() - t0, op.eps_background, kz_inc, field, w,
        op.polarisation, check,
        None if op.tm_faces is None else preset_name(op.tm_faces))
    where = (f"(λ = {op.wavelength_nm:g} nm, Bloch vector ({op.kx0:.6g}, {op.ky0:.6g}) 1/nm, "
             f"from {'below' if from_below else 'above'}, {op.polarisation.upper()}, grid "
             f"{op.shape})")
    if on_fail == "truncate":
        return res
    if not out.converged:
        raise ConvergenceError(
            f"wave solver ({out.method}) stopped after {out.applications} operator applications "
            f"at relative residual {out.true_residual:.3g} > tol {tol:.3g} {where}; energy error "
            f"R+T+A−1 = {res.energy_error:.2g}", method=out.method,
            applications=out.applications, residual=out.true_residual, tol=tol)
    problem = _check_energy(res, energy_bound)
    if problem is not None:
        raise EnergyClosureError(
            f"wave solver ({out.method}, tol {tol:.3g}, residual {out.true_residual:.3g}, "
            f"{out.applications} applications): {problem} {where}; lower tol", problem)
    return res


def solve(cell: Cell, incidence: Incidence, *, tol: float = DEFAULT_TOL, method: str = "auto",
          maxiter: int = 500, restart: int | None = None, on_fail: str = "raise",
          return_field: bool = False, exact_energy: bool = False,
          energy_bound: float = ENERGY_BOUND, x0: np.ndarray | None = None,
          callback: Callback = None, eps_background: complex | None = None,
          min_loss: float = DEFAULT_MIN_LOSS, z_order: int = 1, dtype: type | None = None,
          workers: int | None = None, polarisation: str = "te",
          eps_face: "complex | FaceLayers | None" = None,
          background: Background | None = None,
          fft: str = DEFAULT_FFT, tm_faces: "str | TMFaces" = DEFAULT_TM_FACES,
          preconditioner: str = "auto") -> DiffractionResult:
    """Diffraction of a unit plane wave by one periodic cell (see solve_prepared, prepare).

    For several incidences with the same Bloch vector (above and below), call prepare() once
    and solve_prepared() per side.  The returned `seconds` include the preparation.
    dtype None: complex64 when tol ≥ 1e-5 (its rounding floor is ~1e-6), else complex128.
    polarisation 'te' | 'tm', eps_face, tm_faces: the face conditions; fft: 'scipy' | 'fftw' | 'cupy' | 'auto'
    (operator.prepare_background).
    """
    if dtype is None:
        dtype = np.complex64 if tol >= 1e-5 else np.complex128
    t0 = time.perf_counter()
    kx0, ky0 = bloch_vector(cell, incidence)
    op = prepare(cell, incidence.wavelength_nm, kx0, ky0, eps_background=eps_background,
                 min_loss=min_loss, z_order=z_order, dtype=dtype, workers=workers,
                 polarisation=polarisation, eps_face=eps_face, background=background, fft=fft,
                 tm_faces=tm_faces)
    res = solve_prepared(op, incidence.from_below, tol=tol, method=method, maxiter=maxiter,
                         restart=restart, on_fail=on_fail, return_field=return_field,
                         exact_energy=exact_energy, energy_bound=energy_bound, x0=x0,
                         callback=callback, preconditioner=preconditioner)
    return replace(res, seconds=time.perf_counter() - t0)


__all__ = ["DiffractionResult", "solve", "solve_prepared", "EnergyClosureError", "ENERGY_BOUND",
           "DEFAULT_TOL", "ON_FAIL", "memory_restart", "source"]
