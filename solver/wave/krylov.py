"""Iterative solvers for w − S·w = b: restarted GMRES, BiCGStab and the Born series.

Each solver counts operator applications, records the relative residual ‖b − A·x‖/‖b‖ after
every iteration, stops at the requested tolerance and ends with one explicit (true) residual.
The Born series x ← b + S·x (the paper's method) detects its own divergence.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from .fftback import FFT, HOST
from .vecops import Basis, dot, norm

#: apply(x, out): A·x written into out (None: a new array), returned
Apply = Callable[[np.ndarray, np.ndarray | None], np.ndarray]
#: called after every iteration with (operator applications so far, relative residual)
Callback = Callable[[int, float], None] | None


class WaveSolverError(RuntimeError):
    """A wave solve that cannot deliver what was asked."""


class ConvergenceError(WaveSolverError):
    """The iteration did not reach the tolerance: its iterate is not a result (raised unless
    the caller asked for a truncated iteration, on_fail='truncate').  method, applications,
    residual (the true relative residual reached) and tol say how far it got."""

    def __init__(self, message: str, *, method: str = "", applications: int = 0,
                 residual: float = float("nan"), tol: float = float("nan")):
        super().__init__(message)
        self.method, self.applications, self.residual, self.tol = method, applications, residual, tol


class BornDivergenceError(WaveSolverError):
    """The Born series diverges or stagnates; growth_factor is the measured residual ratio
    per iteration (≥ 1 means no convergence)."""

    def __init__(self, message: str, growth_factor: float, residuals: tuple[float, ...]):
        super().__init__(message)
        self.growth_factor = growth_factor
        self.residuals = residuals


@dataclass(frozen=True, eq=False)
class KrylovOutcome:
    """x: the solution; residuals: relative residual after each iteration (GMRES: its
    recurrence estimate; others: explicit); true_residual: explicit relative residual of x;
    residual_vector: b − A·x (None for the Born series, whose last residual belongs to the
    previous iterate)."""

    x: np.ndarray
    residuals: tuple[float, ...]
    applications: int
    converged: bool
    true_residual: float
    method: str
    residual_vector: np.ndarray | None = None


def gmres(scatter: Apply, b: np.ndarray, *, tol: float, maxiter: int, restart: int = 60,
          x0: np.ndarray | None = None, callback: Callback = None,
          backend: FFT = HOST) -> KrylovOutcome:
    """Restarted GMRES(restart) for x − K·x = b, classical Gram–Schmidt with selective
    reorthogonalisation.

    scatter(x, out) writes K·x into out.  The Arnoldi process runs on K (the Krylov spaces
    of K and I − K coincide) and the Hessenberg matrix of I − K is Ĩ − H_K: orthogonalising
    K·v instead of (I − K)·v avoids the cancellation of the identity part, which made the
    reorthogonalisation pass run at nearly every iteration (measured on the reference case).
    One Gram–Schmidt pass reads the basis twice: the projection (with ‖K·v‖², so that the new
    vector's norm follows from Pythagoras, ‖w − Vh‖² = ‖w‖² − ‖h‖²) and the subtraction (with
    the normalisation); a second, explicit pass runs when ‖w − Vh‖ < ‖w‖/√2 (cancellation).
    The basis (rows of one array, vecops.Basis) has the dtype of b (complex64 is enough for
    tol ≥ 1e-5); the Hessenberg matrix and Givens rotations are complex128.  maxiter counts
    operator applications.  x0: initial guess (e.g. the solution at a neighbouring
    wavelength or incidence); the iteration starts from its best multiple (one application).

    The residual b − (I − K)·x at the end of a cycle is V_{m+1}·(β e_1 − H̄ y), formed with the
    update x += V_m y in one pass over the basis instead of one more application: the Arnoldi
    relation K V_m = V_{m+1} H̄_K holds by construction to rounding, so it equals the explicit
    residual to rounding (test: ≤ 1e-5·‖b‖ in complex64).  backend: where b, x0 and the basis
    live (fftback.py).
    """
    shape, dt = b.shape, b.dtype
    bv = b.ravel()
    bnorm = norm(bv) or 1.0
    x = np.zeros_like(bv) if x0 is None else x0.ravel().astype(dt, copy=True)
    apps, history = 0, []
    if x0 is None:
        r = bv.copy()
    else:   # start from the best multiple of x0: min ‖b − s·A·x0‖ (s = 0 if x0 is useless)
        ax = x - scatter(x.reshape(shape), None).ravel()
        apps += 1
        axn = dot(ax, ax).real
        s = dot(ax, bv) / axn if axn > 0 else 0.0
        x *= s
        r = bv - s * ax
    rel = norm(r) / bnorm
    while rel > tol and apps < maxiter:
        m = min(restart, maxiter - apps)
        basis = Basis(m + 1, bv.size, dt, backend)
        hess = np.zeros((m + 1, m), dtype=complex)
        unrotated = np.zeros((m + 1, m), dtype=complex)
        cs, sn = np.zeros(m, dtype=complex), np.zeros(m, dtype=complex)
        g = np.zeros(m + 1, dtype=complex)
        beta = norm(r)
        g[0] = beta
        basis.append(r, 1.0 / beta)
        j_used = 0
        for j in range(m):
            w = basis.row(j + 1)                      # K·v_j goes straight into the next row
            scatter(basis.row(j).reshape(shape), w.reshape(shape))
            apps += 1
            hcol, w2 = basis.project(w, j + 1)
            hess[:j + 1, j] = -hcol                   # H_A = Ĩ − H_K
            h2 = float(np.vdot(hcol, hcol).real)
            if w2 - h2 > h2:                          # ‖w − Vh‖ > ‖w‖/√2: one pass is enough
                norm_out = math.sqrt(w2 - h2)
                basis.subtract(w, hcol, j + 1, 1.0 / norm_out if norm_out > 0 else 1.0)
            else:                                     # cancellation: a second, explicit pass
                basis.subtract(w, hcol, j + 1)
                hcol, w2 = basis.project(w, j + 1)
                basis.subtract(w, hcol, j + 1)
                hess[:j + 1, j] -= hcol
                norm_out = norm(w)
                if norm_out > 0:
                    w *= 1.0 / norm_out
            hess[j, j] += 1.0
            hess[j + 1, j] = -norm_out
            basis.n = j + 2
            raw = hess[:j + 2, j].copy()              # the column before the rotations
            for i in range(j):  # previous rotations: (x, y) → (c̄x + s̄y, −sx + cy)
                t = np.conj(cs[i]) * hess[i, j] + np.conj(sn[i]) * hess[i + 1, j]
                hess[i + 1, j] = -sn[i] * hess[i, j] + cs[i] * hess[i + 1, j]
                hess[i, j] = t
            a, c = hess[j, j], hess[j + 1, j]
            den = math.hypot(abs(a), abs(c))
            cs[j], sn[j] = (a / den, c / den) if den > 0 else (1.0, 0.0)
            hess[j, j] = den
            hess[j + 1, j] = 0.0
            g[j + 1] = -sn[j] * g[j]
            g[j] = np.conj(cs[j]) * g[j]
            unrotated[:j + 2, j] = raw
            j_used = j + 1
            history.append(float(abs(g[j + 1])) / bnorm)
            if callback is not None:
                callback(apps, history[-1])
            if history[-1] <= tol or apps >= maxiter or norm_out == 0:
                break
        y = np.linalg.solve(np.triu(hess[:j_used, :j_used]), g[:j_used])
        z = -unrotated[:j_used + 1, :j_used] @ y      # β e_1 − H̄ y
        z[0] += beta
        r, r2 = basis.combine(x, y, z)
        basis.release()
        rel, prev = math.sqrt(r2) / bnorm, rel
        floor = history[-1] <= tol < rel and rel > 0.5 * prev   # estimate met, truth cannot
        if floor or rel > 0.99 * prev:                           # ... or stagnation
            break
    return KrylovOutcome(x.reshape(shape), tuple(history), apps, rel <= tol, rel, "gmres",
                         r.reshape(shape))


#: BiCGStab gives up when its residual has not fallen below 0.99× its best for this many
#: iterations, or has grown beyond BLOWUP× its best (its residual is not monotone: a stagnating
#: or exploding run would otherwise spend every application it is allowed)
STAGNATION_ITERATIONS, BLOWUP = 100, 1e4


def bicgstab(apply: Apply, b: np.ndarray, *, tol: float, maxiter: int,
             x0: np.ndarray | None = None, callback: Callback = None) -> KrylovOutcome:
    """BiCGStab (van der Vorst); two applications per iteration, explicit residual each step;
    stops early on stagnation or blow-up (STAGNATION_ITERATIONS, BLOWUP)."""
    shape = b.shape
    bv = b.ravel()
    bnorm = norm(bv) or 1.0
    x = np.zeros_like(bv) if x0 is None else x0.ravel().astype(bv.dtype, copy=True)
    apps, history = 0, []
    r = bv.copy() if x0 is None else bv - apply(x.reshape(shape), None).ravel()
    apps += 0 if x0 is None else 1
    rhat = r.copy()
    rho = alpha = omega = 1.0 + 0j
    v = np.zeros_like(bv)
    p = np.zeros_like(bv)
    rel = norm(r) / bnorm
    best, best_at = rel, 0
    while rel > tol and apps + 3 <= maxiter:   # 2 per iteration + the final true residual
        rho_new = dot(rhat, r)
        if abs(rho_new) < 1e-30 * bnorm ** 2:  # breakdown: restart the shadow residual
            rhat = r.copy()
            rho_new = dot(rhat, r)
            p[:] = 0
            v[:] = 0
            rho = alpha = omega = 1.0 + 0j
        beta = (rho_new / rho) * (alpha / omega)
        rho = rho_new
        p = r + beta * (p - omega * v)
        v = apply(p.reshape(shape), None).ravel()
        alpha = rho / dot(rhat, v)
        s = r - alpha * v
        t = apply(s.reshape(shape), None).ravel()
        apps += 2
        tt = dot(t, t).real
        omega = dot(t, s) / tt if tt > 0 else 0.0
        x += alpha * p + omega * s
        r = s - omega * t
        rel = norm(r) / bnorm
        history.append(rel)
        if callback is not None:
            callback(apps, rel)
        if rel < 0.99 * best:
            best, best_at = rel, len(history)
        if (not math.isfinite(rel) or rel > BLOWUP * best
                or len(history) - best_at >= STAGNATION_ITERATIONS):
            break
    r = bv - apply(x.reshape(shape), None).ravel()
    apps += 1
    rel = norm(r) / bnorm
    return KrylovOutcome(x.reshape(shape), tuple(history), apps, rel <= tol, rel, "bicgstab",
                         r.reshape(shape))


def born(scatter: Apply, b: np.ndarray, *, tol: float, maxiter: int,
         x0: np.ndarray | None = None, patience: int = 3,
         callback: Callback = None) -> KrylovOutcome:
    """Born series x_{n+1} = b + S·x_n (one application each).  The reported residual
    ‖x_{n+1} − x_n‖/‖b‖ is the exact residual of x_n; that of the returned x_{n+1} is smaller
    by the contraction factor when the series converges.

    Raises BornDivergenceError as soon as the residual has grown `patience` times in a row or
    exceeds 10× its minimum (the series diverges: spectral radius of S ≥ 1), with the measured
    growth factor per iteration.
    """
    bnorm = norm(b.ravel()) or 1.0
    x = b.copy() if x0 is None else x0.astype(b.dtype, copy=True)
    history: list[float] = []
    apps, growth_run = 0, 0
    while apps < maxiter:
        x_new = b + scatter(x, None)
        apps += 1
        rel = norm((x_new - x).ravel()) / bnorm
        x = x_new
        history.append(rel)
        if callback is not None:
            callback(apps, rel)
        if rel <= tol:
            break
        if len(history) >= 2:
            growth_run = growth_run + 1 if rel > history[-2] else 0
        k = min(len(history) - 1, 5)
        factor = (rel / history[-1 - k]) ** (1.0 / k) if k > 0 and history[-1 - k] > 0 else 0.0
        if not math.isfinite(rel) or growth_run >= patience or rel > 10 * min(history):
            raise BornDivergenceError(
                f"Born series diverges: residual grew from {min(history):.3g} to {rel:.3g} "
                f"after {apps} iterations (≈×{factor:.3g} per iteration); use method='gmres'",
                factor, tuple(history))
    return KrylovOutcome(x, tuple(history), apps, history[-1] <= tol if history else True,
                         history[-1] if history else 0.0, "born")
