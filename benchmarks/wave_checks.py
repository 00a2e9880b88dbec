"""The energy-closure numbers of docs/wave_solver.md ("Energy closure", "Errors"), printed by
benchmarks/bench_wave.py: residual closure vs quadrature on the reference case, the closure of
an under-converged solve, and the quadrature's Gauss-point count on a strongly absorbing slab."""
from __future__ import annotations

import math
import warnings

import numpy as np

import solver.wave.energy as wave_energy
from solver.wave import Cell, EnergyWarning, Incidence, bloch_vector, prepare, solve, solve_prepared


def energy_checks(cell: Cell, wavelength: float, sigma: float) -> None:
    print("\n--- 2g. energy closure: residual (default) vs quadrature on the reference case; "
          "an under-converged solve; Gauss points of the quadrature ---")
    op = prepare(cell, wavelength, *bloch_vector(cell, Incidence(wavelength, sigma)))
    for tol in (1e-4, 0.3):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWarning)
            cheap = solve_prepared(op, tol=tol)
            quad = solve_prepared(op, tol=tol, exact_energy=True)
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
