"""The exact tier against an independent thin-film oracle (characteristic-matrix method)."""

import numpy as np
import pytest

from oracles import abeles
from solver.inks import molecular_eps, parse_ink
from solver.table.thinfilm_tier import build_thinfilm_table
from solver.thinfilm import slab


def abeles_te(eps_layer, d, wl, sigma):
    """(R, T) of one layer in air by the TE characteristic matrix (oracles.abeles)."""
    return abeles([eps_layer], [d], wl, sigma, "te")[1:]


CASES = [(1.558**2, 1000.0), ((1.5 + 0.05j) ** 2, 1000.0), ((1.4 + 1.1j) ** 2, 200.0),
         ((1.6 + 0.01j) ** 2, 50.0), (2.0 + 0.3j, 3000.0)]


@pytest.mark.parametrize("eps, d", CASES)
@pytest.mark.parametrize("sigma_deg", [0.0, 25.0, 60.0, 85.0])
def test_slab_matches_characteristic_matrix(eps, d, sigma_deg):
    for wl in (380.0, 500.0, 780.0):
        R, T = abeles_te(eps, d, wl, np.radians(sigma_deg))
        got = slab(eps, d, wl, np.radians(sigma_deg))
        assert float(got.R) == pytest.approx(R, abs=1e-12)
        assert float(got.T) == pytest.approx(T, abs=1e-12)


def test_lossless_conserves_energy_and_grazing_is_finite():
    s = slab(1.558**2, 1000.0, np.linspace(380, 780, 41)[:, None], np.linspace(0, np.pi / 2, 91)[None, :])
    np.testing.assert_allclose(s.R + s.T, 1.0, atol=1e-12)
    assert np.all(np.isfinite(s.R)) and np.all(s.T[:, -1] == 0) and np.allclose(s.R[:, -1], 1)


@pytest.mark.parametrize("spec", ["clear", "R15", "Y7.5+B7.5", "G50", "B50"])
def test_te_table_columns_equal_oracle(spec):
    ink = parse_ink(spec)
    wl = np.array([400.0, 530.0, 690.0])
    sigma = np.linspace(0, np.pi / 2, 7)
    table = build_thinfilm_table(ink, 1000.0, wl, sigma, polarisation="te")
    eps = molecular_eps(ink, wl)
    for i, w in enumerate(wl):
        for j, s in enumerate(sigma[:-1]):
            R, T = abeles_te(eps[i], 1000.0, w, s)
            assert table.R_spec[i, j] == pytest.approx(R, abs=1e-12)
            assert table.Tbar[i, j] == pytest.approx(T, abs=1e-12)
    assert not table.has_diffuse
    np.testing.assert_array_equal(table.Rbar, table.R_spec)
    np.testing.assert_array_equal(table.Rbar_below, table.Rbar)   # up-down symmetric film


def test_zero_or_negative_thickness_is_an_error():
    with pytest.raises(ValueError, match="thickness"):
        build_thinfilm_table(parse_ink("R15"), 0.0, [500.0, 600.0], [0.0, np.pi / 2])
