"""Self-checks of the independent oracles in solver/wave/oracles.py (energy, optical theorem,
limits), and their independence from the solver's code; the tests' own Airy slab
(tests/oracles.py) in TE against solver/wave/oracles.airy_te and in TM by its limits."""
from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from oracles import airy_slab
from solver.wave import oracles
from solver.wave.oracles import airy_te, mie_scalar_amplitude, rcwa_te, sphere_fractions


def test_oracles_import_no_solver_code():
    tree = ast.parse(Path(oracles.__file__).read_text())
    imported = [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    imported += [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    assert imported and all(m.split(".")[0] in ("__future__", "math", "numpy", "scipy")
                            for m in imported), imported


@pytest.mark.parametrize("n_slab", [1.558, 1.4 + 0.2j])
def test_airy_energy_and_limits(n_slab):
    r, t, big_r, big_t = airy_te(1.0, n_slab, 1.0, 300.0, 500.0, 0.4)
    if np.imag(n_slab) == 0:
        assert big_r + big_t == pytest.approx(1.0, abs=1e-12)
    else:
        assert big_r + big_t < 0.99
    r0, t0, _, _ = airy_te(1.0, 1.0, 1.0, 300.0, 500.0, 0.4)
    assert abs(r0) < 1e-14
    assert t0 == pytest.approx(np.exp(1j * 2 * math.pi / 500 * math.cos(0.4) * 300))


@pytest.mark.parametrize("n_in,n_slab,n_out,sigma", [(1.0, 1.558, 1.0, 0.4), (1.0, 1.4 + 0.2j, 1.33, 1.2),
                                                     (1.5, 1.558, 1.0, 1.1), (1.33, 1.4 + 1.1j, 1.0, 0.0)])
def test_airy_te_equals_the_tests_airy_slab(n_in, n_slab, n_out, sigma):
    """Two independent Airy implementations (solver/wave/oracles.py, tests/oracles.py) agree,
    total internal reflection (1.5 → 1.0 at 1.1 rad) included."""
    for got, want in zip(airy_te(n_in, n_slab, n_out, 700.0, 500.0, sigma),
                         airy_slab(n_in, n_slab, n_out, 700.0, 500.0, sigma, "te")):
        assert got == pytest.approx(complex(want), abs=1e-13)


def test_airy_slab_tm_limits():
    """TM self-checks: lossless energy, TE = TM at normal incidence up to the sign convention
    (r_TM(0) = −r_TE(0) for H), Brewster zero of a single interface."""
    lam = 500.0
    r, t, big_r, big_t = airy_slab(1.0, 1.558, 1.0, 700.0, lam, 0.7, "tm")
    assert big_r + big_t == pytest.approx(1.0, abs=1e-12)
    r0, _, R0, T0 = airy_slab(1.0, 1.558, 1.0, 700.0, lam, 0.0, "tm")
    k0 = 2 * math.pi / lam
    k1, k2 = k0, k0 * 1.558
    r_te = (k1 - k2) / (k1 + k2)
    e2 = np.exp(2j * k2 * 700.0)
    assert R0 == pytest.approx(abs((r_te - r_te * e2) / (1 - r_te ** 2 * e2)) ** 2, rel=1e-12)
    assert r0 == pytest.approx(-airy_slab(1.0, 1.558, 1.0, 700.0, lam, 0.0, "te")[0], abs=1e-15)
    rb, _, _, _ = airy_slab(1.0, 1.558, 1.558, 700.0, lam, math.atan(1.558), "tm")
    assert abs(rb) < 1e-14


def test_mie_small_sphere_matches_born_and_optical_theorem():
    k, a, m = 2 * math.pi / 500, 60.0, 1.05 + 0.01j
    born = k ** 2 * (m ** 2 - 1) * a ** 3 / 3
    assert abs(mie_scalar_amplitude(m, k, a, 1.0) - born) / abs(born) < 0.1
    sca = 2 * math.pi * quad(lambda c: abs(mie_scalar_amplitude(m, k, a, c)) ** 2, -1, 1)[0]
    lossless_ext = 4 * math.pi / k * mie_scalar_amplitude(1.2, k, a, 1.0).imag
    lossless_sca = 2 * math.pi * quad(
        lambda c: abs(mie_scalar_amplitude(1.2, k, a, c)) ** 2, -1, 1)[0]
    assert lossless_ext == pytest.approx(lossless_sca, rel=1e-8)
    assert 4 * math.pi / k * mie_scalar_amplitude(m, k, a, 1.0).imag > sca


@pytest.mark.usefixtures("single_blas_thread")
def test_rcwa_reduces_to_airy_and_conserves_energy():
    m, r, t, ka, kc = rcwa_te(1.0, 1.0, 1.5 ** 2, 1.5 ** 2, 0, 100, 500, 300, 500, 0.3, 4)
    ra, ta, _, _ = airy_te(1.0, 1.5, 1.0, 300, 500, 0.3)
    assert abs(r[4] - ra) < 1e-12 and abs(t[4] - ta) < 1e-12
    m, r, t, ka, kc = rcwa_te(1.0, 1.0, 1.4 ** 2, 1.558 ** 2, 100, 400, 800, 400, 500, 0.3, 40)
    prop_a, prop_c = ka.imag == 0, kc.imag == 0
    total = (np.sum(ka.real[prop_a] * abs(r[prop_a]) ** 2)
             + np.sum(kc.real[prop_c] * abs(t[prop_c]) ** 2))
    assert total / ka[40].real == pytest.approx(1.0, abs=1e-10)


def test_sphere_fraction_volume():
    frac = sphere_fractions([[40.0, 50.0, 50.0]], 30.0, (100.0, 100.0), (0.0, 100.0),
                            (20, 20, 20), ss=6)
    vol = frac.sum() * 5.0 ** 3
    assert vol == pytest.approx(4 / 3 * math.pi * 30.0 ** 3, rel=3e-3)
