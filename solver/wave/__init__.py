"""Wave-optics diffraction by one periodic cell of the ink layer (scalar Helmholtz).

Lippmann–Schwinger equation on a layered background (half-space | slab ε_b | half-space),
lateral pseudo-spectral Bloch harmonics, exact Galerkin z-integrals of the analytic Green's
function, GMRES by default.  See docs/wave_solver.md and ../shared/DESIGN.md §1, §4.

    res = solve(Cell(eps, (Lx, Ly), (z_top, z_bottom)), Incidence(500.0, 0.3))
    op = prepare(cell, 500.0, kx0, ky0); up = solve_prepared(op); down = solve_prepared(op, True)
"""
from .krylov import (BornDivergenceError, ConvergenceError, ConvergenceWarning,
                     WaveSolverError)
from .operator import DEFAULT_MIN_LOSS, LayerOperator, prepare
from .orders import OrderSet
from .solve import DiffractionResult, solve, solve_prepared
from .types import Cell, Incidence, bloch_vector

__all__ = ["Cell", "Incidence", "DiffractionResult", "OrderSet", "LayerOperator", "prepare",
           "solve", "solve_prepared", "bloch_vector", "BornDivergenceError",
           "ConvergenceError", "ConvergenceWarning", "WaveSolverError", "DEFAULT_MIN_LOSS"]
