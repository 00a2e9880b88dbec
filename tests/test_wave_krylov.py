"""GMRES's cheap residual (from the Arnoldi relation, no extra application) against the explicit
b − (I − K)·x, on dense random operators (oracle: NumPy's dense solve) and on a wave solve
(oracle: one explicit operator application)."""
from __future__ import annotations

import numpy as np
import pytest

from solver.wave import Incidence, bloch_vector, prepare, solve_prepared
from solver.wave.kernel1d import background_amplitudes
from solver.wave.krylov import gmres
from solver.wave.operator import apply_system
from solver.wave.validation import random_layer


def _dense_case(n: int, spread: float, seed: int):
    """K = c·I + spread·(random matrix): spread small makes K·v nearly parallel to v, so
    Gram–Schmidt cancels and takes its second pass at every iteration."""
    rng = np.random.default_rng(seed)
    k = 0.5 * np.eye(n) + spread * (rng.standard_normal((n, n))
                                    + 1j * rng.standard_normal((n, n))) / np.sqrt(n)
    b = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    return k, b


@pytest.mark.parametrize("spread,restart", [(0.3, 60), (0.3, 4), (1e-3, 60)])
@pytest.mark.parametrize("dtype", [np.complex64, np.complex128])
def test_gmres_residual_is_the_explicit_residual(spread, restart, dtype, single_blas_thread):
    k, b = _dense_case(300, spread, seed=3)
    kc = k.astype(dtype)

    def scatter(x, out):
        y = kc @ x
        if out is None:
            return y
        out[...] = y
        return out

    tol = 1e-5 if dtype == np.complex64 else 1e-10
    out = gmres(scatter, b.astype(dtype), tol=tol, maxiter=200, restart=restart)
    x = out.x.astype(complex)
    explicit = b - x + k @ x                       # in complex128
    bn = np.linalg.norm(b)
    floor = 3e-6 if dtype == np.complex64 else 1e-13
    assert np.linalg.norm(out.residual_vector - explicit) <= floor * bn
    assert abs(out.true_residual - np.linalg.norm(explicit) / bn) <= floor
    assert out.converged and out.true_residual <= tol
    exact = np.linalg.solve(np.eye(300) - k, b)
    assert np.linalg.norm(x - exact) <= 20 * tol * np.linalg.norm(exact)
    assert out.applications == len(out.residuals)  # no application besides the iterations


def test_wave_solve_residual_matches_one_explicit_application():
    """The reported residual of a complex64 wave solve is ‖b − (I − GV)w‖/‖b‖ to rounding, b
    the background (Airy) field of the unit incident wave."""
    cell = random_layer(1.4 + 0.2j, shape=(16, 16, 8))
    inc = Incidence(500.0, 0.4, 0.3)
    op = prepare(cell, inc.wavelength_nm, *bloch_vector(cell, inc))
    res = solve_prepared(op, tol=1e-4)
    coef, _, _ = background_amplitudes(op.green, False)
    b = np.broadcast_to((coef[0, 0] * op.ptop[:, 0, 0])[:, None, None, :], op.unknown_shape)
    r = b - apply_system(op, res.solution.astype(np.complex128).astype(op.dtype))
    explicit = np.linalg.norm(r) / np.linalg.norm(b)
    assert res.converged and abs(res.residual - explicit) <= 2e-6
