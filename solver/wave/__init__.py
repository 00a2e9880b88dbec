"""Wave-optics diffraction by one periodic cell of the ink layer (scalar Helmholtz).

Lippmann–Schwinger equation on a layered background (half-space | slab ε_b | half-space),
lateral pseudo-spectral Bloch harmonics, exact Galerkin z-integrals of the analytic Green's
function, GMRES by default; TE or TM face conditions (TM: per-harmonic face forms, faces.py).  See docs/wave_solver.md and
docs/design.md §1, §4.

    res = solve(Cell(eps, (Lx, Ly), (z_top, z_bottom)), Incidence(500.0, 0.3))   # raises if not converged
    op = prepare(cell, 500.0, kx0, ky0); up = solve_prepared(op); down = solve_prepared(op, True)
    bg = prepare_background(shape, (Lx, Ly), H, 500.0, kx0, ky0, eps_b)   # shared by
    op = with_contrast(bg, cell)                                           # many realizations
"""
from .faces import DEFAULT_TM_FACES, PRESETS as TM_FACE_PRESETS, TMFaces
from .interfaces import FaceLayers
from .krylov import BornDivergenceError, ConvergenceError, WaveSolverError
from .operator import (DEFAULT_MIN_LOSS, Background, LayerOperator, prepare,
                       prepare_background, with_contrast)
from .orders import OrderSet
from .solve import (DEFAULT_TOL, ENERGY_BOUND, ON_FAIL, DiffractionResult, EnergyClosureError,
                    memory_restart, solve, solve_prepared)
from .types import Cell, Incidence, bloch_vector

__all__ = ["Cell", "Incidence", "DiffractionResult", "OrderSet", "LayerOperator", "Background",
           "prepare", "prepare_background", "with_contrast", "solve", "solve_prepared",
           "bloch_vector", "BornDivergenceError", "ConvergenceError",
           "WaveSolverError", "EnergyClosureError", "ON_FAIL", "memory_restart", "DEFAULT_MIN_LOSS",
           "ENERGY_BOUND", "DEFAULT_TOL", "TMFaces", "TM_FACE_PRESETS", "DEFAULT_TM_FACES", "FaceLayers"]
