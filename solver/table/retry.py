"""A table's solves are converged or refused: the ladder of stronger settings
(docs/wave_solver.md, "Not converged is not a result").

A solve that stops short of its tolerance is not a result (solver.wave raises). A table solve
then tries the next, stronger setting; when the last one fails too, the cell is refused with
the reason (`SolveRefused`, naming the solve and every attempt) — never a number with a
warning.  The ladder:

1. the request's own setting: GMRES with the default restart (≤ 60), complex64, 500
   applications, the request's tolerance;
2. GMRES without restarts as far as memory allows (`solver.wave.memory_restart`: restarted
   GMRES stagnates on strongly scattering lossless cells where the full Krylov space converges),
   complex128 (no rounding floor), 3000 applications, a tolerance 10× tighter (a solve that
   met its tolerance but not the energy bound needs a smaller residual, not more memory);
3. BiCGStab (another Krylov method: fixed memory per iteration, for grids where memory cuts
   GMRES's restart short), complex128, 3000 applications, the tighter tolerance.

A finer grid is not on the ladder: a table is a function of its request, its grid included, so
one cell may not be solved on another grid than its neighbours.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..wave import ConvergenceError, DiffractionResult, EnergyClosureError, WaveSolverError
from ..wave import memory_restart, solve_prepared


@dataclass(frozen=True)
class Attempt:
    """One rung: Krylov method, operator applications, restart ('memory': the longest that fits,
    None: the solver's default), the dtype of the operator and the Krylov vectors, and the
    factor on the requested tolerance."""

    method: str
    maxiter: int
    restart: str | None
    dtype: type
    tol_factor: float = 1.0

    def describe(self, tol: float) -> str:
        restart = {None: "", "memory": ", no restart within memory"}[self.restart]
        return (f"{self.method}{restart}, {np.dtype(self.dtype).name}, tol {tol * self.tol_factor:g}, "
                f"≤ {self.maxiter} applications")


LADDER = (Attempt("auto", 500, None, np.complex64),
          Attempt("gmres", 3000, "memory", np.complex128, 0.1),
          Attempt("bicgstab", 3000, None, np.complex128, 0.1))


class SolveRefused(WaveSolverError):
    """No setting of the ladder converged: the table refuses the cell (the message says which
    solve and how far every attempt got)."""


def converged_solve(make_op: Callable, from_below: bool, *, tol: float, where: str,
                    ladder: tuple[Attempt, ...] | None = None, **kw
                    ) -> tuple[DiffractionResult, int, int]:
    """(result, rungs climbed, operator applications of every attempt) of the first attempt of
    `ladder` that converges.

    make_op(dtype) → the prepared operator in that dtype (the caller caches it: both sides of an
    incidence share it).  where: the cell in words (ink, λ, σ, azimuth, polarisation) for the
    refusal.  ladder: LADDER unless given.  kw: further solve_prepared arguments (exact_energy, …).  Raises SolveRefused
    when every attempt fails; other errors (bad input, non-finite results) pass through.
    """
    failures, spent = [], 0
    for rung, attempt in enumerate(LADDER if ladder is None else ladder):
        op = make_op(attempt.dtype)
        restart = min(attempt.maxiter, memory_restart(op)) if attempt.restart == "memory" else None
        try:
            res = solve_prepared(op, from_below, tol=tol * attempt.tol_factor, method=attempt.method,
                                 maxiter=attempt.maxiter, restart=restart, **kw)
            return res, rung, spent + res.applications
        except ConvergenceError as exc:
            spent += exc.applications
            failures.append(f"{attempt.describe(tol)}: stopped at relative residual "
                            f"{exc.residual:.3g} after {exc.applications} applications")
        except EnergyClosureError as exc:
            failures.append(f"{attempt.describe(tol)}: converged, but {exc.problem}")
    raise SolveRefused(f"no converged solve for {where} (tol {tol:g}), table refused: "
                       + "; ".join(failures))
