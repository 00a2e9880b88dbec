"""Checks printed by benchmarks/bench_wave.py (docs/wave_solver.md): TE vs TM cost, the energy
closure (residual vs quadrature, an under-converged solve, the quadrature's Gauss points), the
fictitious loss; and the small helpers the wave benchmarks share."""
from __future__ import annotations

import math
import time

import numpy as np

import solver.wave.energy as wave_energy
from solver.wave import Cell, Incidence, bloch_vector, prepare, solve, solve_prepared

TOL = 1e-4


def print_rows(rows, cols):
    print("  ".join(f"{c:>11}" for c in cols))
    for r in rows:
        cells = []
        for c in cols:
            v = r.get(c, "")
            cells.append(f"{v:>11.4g}" if isinstance(v, float) else f"{str(v):>11}")
        print("  ".join(cells), flush=True)


def cpu_time(fn):
    """(fn(), CPU seconds it took)."""
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def quiet_solve(op, tol=TOL, **kw):
    """(result, CPU s) of solve_prepared, truncated rather than refused (a study of the
    solver itself: `converged` and `energy_error` say how far each solve got)."""
    return cpu_time(lambda: solve_prepared(op, tol=tol, maxiter=1000, on_fail="truncate", **kw))


def polarisation_cost(cell: Cell, wavelength: float, sigma: float) -> None:
    print("\n--- 2e. TE vs TM on the reference case (tol 1e-4) ---")
    kx0, ky0 = bloch_vector(cell, Incidence(wavelength, sigma))
    for pol in ("te", "tm"):
        op, tp = cpu_time(lambda: prepare(cell, wavelength, kx0, ky0, workers=1,
                                          polarisation=pol))
        res, cpu = quiet_solve(op)
        print(f"{pol}: prepare {tp:.3f} s, solve {cpu:.3f} s, {res.applications} applications, "
              f"R {res.R:.4f} T {res.T:.4f} R_spec {res.R_spec:.4f} A {res.absorbed:.4f} "
              f"E {res.energy_error:.1e}")


def loss_study(cell: Cell, wavelength: float, sigma: float) -> None:
    print("\n--- 2f. fictitious loss δ = min Im ε_b on a lossless layer (η = 1.4), "
          f"{'×'.join(map(str, cell.shape))}, tol 1e-5 ---")
    kx0, ky0 = bloch_vector(cell, Incidence(wavelength, sigma))
    rows = []
    for delta in (0.003, 0.01, 0.03, 0.1, 0.3):
        op = prepare(cell, wavelength, kx0, ky0, min_loss=delta, workers=1)
        res, cpu = quiet_solve(op, tol=1e-5, exact_energy=True)
        rows.append(dict(delta=delta, apps=res.applications, cpu_s=cpu, A=res.absorbed,
                         energy=res.energy_error))
    print_rows(rows, ["delta", "apps", "cpu_s", "A", "energy"])


def energy_checks(cell: Cell, wavelength: float, sigma: float) -> None:
    print("\n--- 2g. energy closure: residual (default) vs quadrature on the reference case; "
          "an under-converged solve; Gauss points of the quadrature ---")
    op = prepare(cell, wavelength, *bloch_vector(cell, Incidence(wavelength, sigma)))
    for tol in (1e-4, 0.3):
        cheap = solve_prepared(op, tol=tol, on_fail="truncate")
        quad = solve_prepared(op, tol=tol, exact_energy=True, on_fail="truncate")
        print(f"tol {tol:g}: {cheap.applications} applications, converged {cheap.converged}, "
              f"A residual {cheap.absorbed:.10f} / quadrature {quad.absorbed:.10f}, "
              f"E {cheap.energy_error:+.3e} / {quad.energy_error:+.3e}")
    slab = Cell(np.full((2, 2, 32), (1.4 + 1.1j) ** 2), (300.0, 300.0), (0.0, 1000.0))
    default = wave_energy.GAUSS_POINTS
    try:
        for n in (3, 4, 6):
            wave_energy.GAUSS_POINTS = n
            wave_energy.slab_field_energy.__defaults__ = (n,)
            errs = [solve(slab, Incidence(500.0, math.radians(60), 0.3), tol=1e-8,
                          polarisation=pol, exact_energy=True).energy_error
                    for pol in ("te", "tm")]
            print(f"k = 1.1 slab, 60°, 32 cells, {n} Gauss points: quadrature closure "
                  f"TE {errs[0]:+.1e}, TM {errs[1]:+.1e}")
    finally:
        wave_energy.GAUSS_POINTS = default
        wave_energy.slab_field_energy.__defaults__ = (default,)
