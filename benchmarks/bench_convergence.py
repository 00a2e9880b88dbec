"""Not converged is not a result (issue 22 item 4; docs/wave_solver.md, "Not converged is not a
result").

    python -m benchmarks.bench_convergence                  # 200 cells at 16×16×8, ~5–15 min on 2 cores
    python -m benchmarks.bench_convergence --count 40 --grid 8 8 4   # a quick look

1. The stagnating cell of the issue (lossless n = 3 spheres at 30 %, λ 500, σ 0.3 rad, 16×16×8):
   what the solver used to return (truncated iterates, on_fail='truncate'), what it does now
   (raises), and what the tables' ladder of stronger settings does (solver/table/retry.py).
2. A sweep of random hard cells (solver.wave.validation.hard_cells: n 1–3.5, k 0 or 0–1.5,
   5–50 % of 200-nm spheres, λ 380–780 nm, σ 0–85°, TE or TM): each solved with the defaults;
   a returned result's residual is recomputed explicitly in complex128 (not the solver's own
   estimate) and its energy closed by quadrature; every refused one goes up the table's ladder.
   Printed: how many converged, were refused, were rescued by each rung, stayed refused, and
   the count of results returned from a non-converged solve (must be 0).
"""
from __future__ import annotations

import argparse
import collections
import time

import numpy as np

from solver.table.retry import LADDER, SolveRefused, converged_solve
from solver.wave import DEFAULT_TOL, Incidence, WaveSolverError, bloch_vector, prepare, solve
from solver.wave.validation import explicit_residual, hard_cells, random_layer


def stagnating_cell() -> None:
    print("--- 1. the stagnating cell: lossless n = 3 spheres, 30 %, λ 500 nm, σ 0.3 rad, 16×16×8 ---")
    cell = random_layer(3.0, fraction=0.3, shape=(16, 16, 8))
    inc = Incidence(500.0, 0.3)
    for method in ("gmres", "bicgstab"):
        old = solve(cell, inc, method=method, maxiter=120, on_fail="truncate")
        print(f"before: {method} after {old.applications} applications: residual {old.residual:.3g}, "
              f"R {old.R:.4g}, T {old.T:.4g}, R + T {old.R + old.T:.4g} (lossless: 1) — was returned")
        try:
            solve(cell, inc, method=method, maxiter=120)
            print(f"now: {method} returned a result (wrong)")
        except WaveSolverError as exc:
            print(f"now: {method} raises {type(exc).__name__}")
    kx0, ky0 = bloch_vector(cell, inc)
    res, rung, apps = converged_solve(lambda dt=np.complex64: prepare(cell, 500.0, kx0, ky0, dtype=dt),
                                      False, tol=DEFAULT_TOL, where="the stagnating cell")
    print(f"table ladder: converged on rung {rung} ({LADDER[rung].describe(DEFAULT_TOL)}) after "
          f"{apps} applications in all ({res.applications} on that rung): residual {res.residual:.2g}, "
          f"R {res.R:.4f}, T {res.T:.4f}, R + T {res.R + res.T:.4f}, closure {res.energy_error:+.1e}")


def sweep(count: int, grid: tuple[int, int, int]) -> None:
    print(f"\n--- 2. {count} random hard cells at {'×'.join(map(str, grid))}, tol {DEFAULT_TOL:g}, "
          "the solver's defaults ---")
    tally = collections.Counter()
    worst_residual, worst_closure, violations = 0.0, 0.0, []
    t0 = time.perf_counter()
    for case in hard_cells(count, shape=grid):
        try:
            res = solve(case.cell, case.incidence, polarisation=case.polarisation, exact_energy=True)
        except WaveSolverError as exc:
            tally[f"refused by solve ({type(exc).__name__})"] += 1
            kx0, ky0 = bloch_vector(case.cell, case.incidence)
            make = (lambda c=case, k=(kx0, ky0): lambda dt=np.complex64: prepare(
                c.cell, c.incidence.wavelength_nm, *k, polarisation=c.polarisation, dtype=dt))()
            try:
                again, rung, _ = converged_solve(make, False, tol=DEFAULT_TOL, where=case.describe())
                tally[f"  rescued by ladder rung {rung}"] += 1
                worst_residual = max(worst_residual, explicit_residual(case, again) / (
                    DEFAULT_TOL * LADDER[rung].tol_factor))
            except SolveRefused as refusal:
                tally["  refused by the ladder too"] += 1
                print(f"refused: {refusal}")
            continue
        tally["converged at the defaults"] += 1
        rel = explicit_residual(case, res)
        worst_residual = max(worst_residual, rel / DEFAULT_TOL)
        worst_closure = max(worst_closure, abs(res.energy_error))
        if not res.converged or rel > DEFAULT_TOL * 1.001:
            violations.append(case.describe())
    for key in sorted(tally, key=lambda k: (k.startswith("  "), k)):
        print(f"{key}: {tally[key]}")
    print(f"returned results: worst explicit residual / tol {worst_residual:.3f}; worst quadrature "
          f"closure |R + T + A − 1| {worst_closure:.2e} (defaults)")
    print(f"results returned from a non-converged solve: {len(violations)} {violations or ''}")
    print(f"sweep: {time.perf_counter() - t0:.0f} s")


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_convergence")
    p.add_argument("--count", type=int, default=200)
    p.add_argument("--grid", type=int, nargs=3, default=(16, 16, 8))
    args = p.parse_args(argv)
    stagnating_cell()
    sweep(args.count, tuple(args.grid))


if __name__ == "__main__":
    main()
