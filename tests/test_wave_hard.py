"""Hard cases: Wood anomaly, guided-mode resonance, grazing incidence, dense and strongly
absorbing layers, very thin layers, Born divergence, non-convergence, bad input."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from conftest import E_BINDER
from oracles import te0_propagation_constant
from solver.wave import BornDivergenceError, Cell, ConvergenceError, Incidence, solve
from solver.wave.oracles import random_spheres, sphere_fractions
from solver.wave.validation import random_layer



def _finite(res):
    arrays = (res.reflected.amplitude, res.transmitted.amplitude, res.reflected.power,
              res.transmitted.power)
    return all(np.all(np.isfinite(a)) for a in arrays) and all(
        math.isfinite(v) for v in (res.R, res.T, res.absorbed, res.residual))


@pytest.mark.parametrize("pol", ["te", "tm"])
@pytest.mark.parametrize("from_below", [False, True])
@pytest.mark.parametrize("k", [0.0, 0.2])
def test_exact_wood_anomaly(from_below, k, pol):
    """λ = 600 nm, period 800 nm, sin σ = 1 − λ/L: order (1, 0) grazes, k_z = 0 exactly."""
    period, lam = 800.0, 600.0
    rng = np.random.default_rng(3)
    centres = random_spheres(rng, 6, (period, period), (0.0, 400.0), 75.0)
    frac = sphere_fractions(centres, 75.0, (period, period), (0.0, 400.0), (24, 24, 12))
    cell = Cell(E_BINDER + ((1.4 + 1j * k) ** 2 - E_BINDER) * frac, (period, period), (0.0, 400.0))
    sigma = math.asin(1 - lam / period)
    res = solve(cell, Incidence(lam, sigma, from_below=from_below), tol=1e-6, polarisation=pol,
                exact_energy=True)
    for orders in (res.reflected, res.transmitted):
        i = orders.index(1, 0)
        assert orders.kz[i] == 0 and orders.power[i] == 0
        assert 0 < abs(orders.amplitude[i]) < 1
    assert _finite(res) and res.converged
    assert abs(res.energy_error) < 1e-4
    if k == 0:
        assert abs(res.R + res.T - 1) < 1e-3
    for d in (-1e-6, 1e-6):   # the physics is continuous through the anomaly
        near = solve(cell, Incidence(lam, sigma + d, from_below=from_below), tol=1e-6, polarisation=pol)
        assert abs(near.R - res.R) < 1e-4 and abs(near.T - res.T) < 1e-4


def _film_grating(period, thickness, fill, offset, nx=32, nz=16):
    x = np.arange(nx) / nx
    a, b = offset - fill / 2, offset + fill / 2
    frac = np.clip(np.minimum(x + 1 / nx, b) - np.maximum(x, a), 0, 1 / nx) * nx
    eps = E_BINDER + (1.4 ** 2 - E_BINDER) * frac
    return Cell(np.broadcast_to(eps[:, None, None], (nx, 1, nz)).copy(), (period, period),
                (0.0, thickness))


def test_harmonic_on_the_guided_mode_pole_of_the_lossless_background():
    """Lossless film + weak lossless grating; the period puts harmonics ±1 exactly on the TE0
    pole of the (lossless) mean-ε film, i.e. on a real pole of the background Green's function
    that the fictitious loss δ moves off the axis."""
    lam, thick, fill = 600.0, 500.0, 0.05
    k0 = 2 * math.pi / lam
    eps_mean = (1 - fill) * E_BINDER + fill * 1.4 ** 2
    period = 2 * math.pi / te0_propagation_constant(k0, eps_mean, thick)
    cell = _film_grating(period, thick, fill, 0.5)
    assert np.mean(cell.eps) == pytest.approx(eps_mean, rel=1e-12)
    res = solve(cell, Incidence(lam, 0.0), tol=1e-6, dtype=np.complex128)
    assert res.converged and _finite(res)
    assert abs(res.R + res.T - 1) < 1e-3


def test_guided_mode_resonance_scan():
    """Sweep λ across the physical guided-mode resonance of the film grating: a sharp Fano
    feature in R, finite everywhere, energy conserved at every point including the peak."""
    thick, fill = 500.0, 0.05
    k0 = 2 * math.pi / 600.0
    period = 2 * math.pi / te0_propagation_constant(k0, E_BINDER, thick)
    cell = _film_grating(period, thick, fill, 0.3)
    lams = np.linspace(594.0, 602.0, 81)
    big_r = []
    for lam in lams:
        res = solve(cell, Incidence(lam, 0.005), tol=1e-6, dtype=np.complex128)
        assert res.converged and _finite(res)
        assert abs(res.R + res.T - 1) < 1e-3
        big_r.append(res.R)
    big_r = np.array(big_r)
    assert np.abs(np.diff(big_r)).max() > 20 * np.median(np.abs(np.diff(big_r)))   # a resonance


@pytest.mark.parametrize("case", ["grazing85", "fill50", "k1.1_fill50", "thin50", "lossless"])
def test_hard_layers_are_finite_and_balanced(case):
    shape, thick, eta, fill, sigma = (16, 16, 8), 500.0, 1.4 + 0.2j, 0.2, 0.3
    if case == "grazing85":
        sigma = math.radians(85)
    elif case == "fill50":
        fill = 0.5
    elif case == "k1.1_fill50":
        eta, fill = 1.4 + 1.1j, 0.5
    elif case == "thin50":
        thick, shape = 50.0, (16, 16, 4)
    elif case == "lossless":
        eta = 1.4
    if fill == 0.5:   # Boolean model of overlapping spheres: 1 − e^{−n v} = 0.5
        rng = np.random.default_rng(5)
        n = int(round(math.log(2) * 1000.0 ** 2 * thick / (math.pi / 6 * 200.0 ** 3)))
        centres = random_spheres(rng, n, (1000.0, 1000.0), (0.0, thick), 100.0)
        frac = sphere_fractions(centres, 100.0, (1000.0, 1000.0), (0.0, thick), shape, ss=3)
        assert 0.4 < frac.mean() < 0.6
        cell = Cell(E_BINDER + (eta ** 2 - E_BINDER) * frac, (1000.0, 1000.0), (0.0, thick))
    elif case == "thin50":
        rng = np.random.default_rng(9)
        frac = sphere_fractions(random_spheres(rng, 40, (1000.0, 1000.0), (0.0, 50.0), 25.0),
                                25.0, (1000.0, 1000.0), (0.0, 50.0), shape, ss=3)
        cell = Cell(E_BINDER + (eta ** 2 - E_BINDER) * frac, (1000.0, 1000.0), (0.0, 50.0))
    else:
        cell = random_layer(eta, fraction=fill, shape=shape)
    res = solve(cell, Incidence(500.0, sigma, 0.4), tol=1e-5, exact_energy=True)
    assert res.converged and _finite(res)
    assert abs(res.R + res.T + res.absorbed - 1) < 1e-3
    assert res.applications < 150


def test_born_series_converges_on_a_dilute_layer_and_agrees():
    """Weak particles (1.05 + 0.01i, 10 %) in air: the paper's Born series converges, to the
    same orders as GMRES, which needs fewer applications (GMRES minimises the residual over
    the Krylov space that contains the Born iterates)."""
    rng = np.random.default_rng(2)
    centres = random_spheres(rng, 12, (1000.0, 1000.0), (0.0, 500.0), 100.0)
    frac = sphere_fractions(centres, 100.0, (1000.0, 1000.0), (0.0, 500.0), (16, 16, 8), ss=3)
    cell = Cell(1 + ((1.05 + 0.01j) ** 2 - 1) * frac, (1000.0, 1000.0), (0.0, 500.0))
    born = solve(cell, Incidence(500.0, 0.2), method="born", tol=1e-7)
    gm = solve(cell, Incidence(500.0, 0.2), method="gmres", tol=1e-7)
    assert born.method == "born" and born.converged
    assert np.allclose(born.reflected.amplitude, gm.reflected.amplitude, atol=1e-6)
    assert np.allclose(born.transmitted.amplitude, gm.transmitted.amplitude, atol=1e-6)
    assert gm.applications <= born.applications


def test_born_series_detects_divergence():
    cell = random_layer(1.4 + 0.2j, fraction=0.3, shape=(16, 16, 8))
    with pytest.raises(BornDivergenceError) as err:
        solve(cell, Incidence(500.0, 0.2), method="born", eps_background=1.0 + 0.01j)
    assert err.value.growth_factor > 1 and "diverges" in str(err.value)


def test_bicgstab_agrees_with_gmres():
    cell = random_layer(1.4 + 0.2j, shape=(16, 16, 8))
    a = solve(cell, Incidence(500.0, 0.4), method="bicgstab", tol=1e-6)
    b = solve(cell, Incidence(500.0, 0.4), method="gmres", tol=1e-6)
    assert a.method == "bicgstab" and a.converged
    assert np.allclose(a.reflected.amplitude, b.reflected.amplitude, atol=1e-4)


def test_non_convergence_is_not_a_result():
    """A solve short of its tolerance raises (no iterate with a warning); truncation is asked
    for explicitly, and then says how far it got."""
    cell = random_layer(1.4 + 0.2j, shape=(16, 16, 8))
    with pytest.raises(ConvergenceError, match=r"after 3 operator applications at relative "
                                               r"residual .* > tol") as err:
        solve(cell, Incidence(500.0, 0.4), maxiter=3)
    assert err.value.applications == 3 and err.value.residual > 1e-3 and err.value.method == "gmres"
    res = solve(cell, Incidence(500.0, 0.4), maxiter=3, on_fail="truncate")
    assert not res.converged and res.residual > 1e-4 and _finite(res)
    with pytest.raises(ValueError, match="on_fail"):
        solve(cell, Incidence(500.0, 0.4), on_fail="warn")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert solve(cell, Incidence(500.0, 0.4)).converged


@pytest.mark.parametrize("method", ["gmres", "bicgstab"])
def test_the_stagnating_cell_is_refused_not_reported(method):
    """Lossless n = 3 spheres at 30 % (issue 22): GMRES(60) stagnates (residual ≈ 0.6 after 120
    applications, R + T ≈ 0.64 for a lossless layer); BiCGStab blows up (R, T ≫ 1).  Neither
    iterate may come back as a result."""
    cell = random_layer(3.0, fraction=0.3, shape=(16, 16, 8))
    with pytest.raises(ConvergenceError) as err:
        solve(cell, Incidence(500.0, 0.3), method=method, maxiter=120)
    assert err.value.residual > 0.1 and err.value.method == method
    bad = solve(cell, Incidence(500.0, 0.3), method=method, maxiter=120, on_fail="truncate")
    assert not bad.converged and abs(bad.R + bad.T - 1) > 0.05        # what was refused


def test_bad_input_is_refused():
    good = np.full((4, 4, 4), 2.0 + 0.1j)
    with pytest.raises(ValueError, match="NaN"):
        Cell(np.where(good.real > 0, np.nan, good), (100.0, 100.0), (0.0, 100.0))
    with pytest.raises(ValueError, match="gain"):
        Cell(good - 0.2j, (100.0, 100.0), (0.0, 100.0))
    with pytest.raises(ValueError):
        Cell(good, (100.0, 100.0), (100.0, 0.0))
    with pytest.raises(ValueError):
        Cell(good, (100.0, 100.0), (0.0, 100.0), eps_above=1.0 + 0.1j)
    with pytest.raises(ValueError):
        Incidence(500.0, math.pi / 2)
    with pytest.raises(ValueError):
        solve(Cell(good, (100.0, 100.0), (0.0, 100.0)), Incidence(500.0, 0.1), method="magic")


@pytest.mark.parametrize("method", ["gmres", "bicgstab", "born"])
def test_every_iteration_reports_its_residual(method):
    cell = random_layer(1.4 + 0.1j, shape=(16, 16, 8))
    seen = []
    res = solve(cell, Incidence(500.0, 0.3), method=method, tol=1e-5,
                callback=lambda apps, rel: seen.append((apps, rel)))
    assert [r for _, r in seen] == list(res.residuals)
    assert res.converged and res.residuals[-1] <= 1e-5 and res.residual <= 1e-5
    assert seen[-1][0] <= res.applications
    if method == "gmres":
        assert all(b <= a * (1 + 1e-12) for a, b in zip(res.residuals, res.residuals[1:]))


def test_truncated_born_on_request_is_silent_but_reports_its_residual():
    import warnings

    from solver.wave import Cell, Incidence, bloch_vector, prepare, solve_prepared

    eps = np.full((8, 8, 4), 1.558**2, complex)
    eps[:4, :4, :2] = (1.4 + 0.2j) ** 2
    cell = Cell(eps, (1000.0, 1000.0), (0.0, 500.0))
    kx0, ky0 = bloch_vector(cell, Incidence(500.0, 0.3))
    op = prepare(cell, 500.0, kx0, ky0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = solve_prepared(op, method="born", maxiter=1, on_fail="truncate")
    assert not res.converged and res.residual > 1e-4 and res.applications == 1
    with pytest.raises(ConvergenceError, match="stopped after 1 operator"):
        solve_prepared(op, method="born", maxiter=1)
