"""Orders → BRDF grid: energy exactness, reciprocity, Δφ convention."""

import numpy as np
import pytest

from solver.table.integrals import diffuse_albedo
from solver.table.orders_to_brdf import fold_dphi, spread_orders, symmetrize_reciprocal

POLAR = np.radians([0, 15, 30, 45, 60, 70, 80, 90])
DPHI = np.linspace(0, np.pi, 13)


def test_spreading_is_energy_exact():
    rng = np.random.default_rng(1)
    theta = rng.uniform(0, np.pi / 2, 200)
    dphi = rng.uniform(0, np.pi, 200)
    power = rng.uniform(0, 1e-3, 200)
    R = spread_orders(POLAR, DPHI, theta, dphi, power)
    assert diffuse_albedo(POLAR, DPHI, R) == pytest.approx(power.sum(), rel=1e-12)
    assert np.all(R >= 0)


def test_order_on_a_node_lands_on_that_node_only():
    R = spread_orders(POLAR, DPHI, [POLAR[3]], [DPHI[4]], [0.01])
    assert np.count_nonzero(R) == 1 and R[3, 4] > 0


def test_fold_dphi_mirror_is_pi():
    assert fold_dphi(np.pi + 0.3, 0.3) == pytest.approx(np.pi)       # mirror
    assert fold_dphi(0.3, 0.3) == pytest.approx(0.0)                 # retro
    assert fold_dphi(0.1, 2 * np.pi - 0.1) == pytest.approx(0.2)
    assert np.all((fold_dphi(np.linspace(-10, 10, 50), 1.0) >= 0) & (fold_dphi(np.linspace(-10, 10, 50), 1.0) <= np.pi))


def test_symmetrize_keeps_row_albedo_and_makes_reciprocal():
    rng = np.random.default_rng(2)
    R = rng.uniform(0.0, 0.2, (3, POLAR.size, POLAR.size, DPHI.size))
    R[:, -1] = 0.0                                               # grazing incidence row: no energy
    S = symmetrize_reciprocal(R, POLAR, DPHI)
    np.testing.assert_allclose(S, np.swapaxes(S, -3, -2), atol=1e-15)
    np.testing.assert_allclose(diffuse_albedo(POLAR, DPHI, S), diffuse_albedo(POLAR, DPHI, R), rtol=1e-9, atol=1e-14)
    assert np.all(S >= 0) and np.all(S[:, -1] == 0) and np.all(S[:, :, -1] == 0)


def test_symmetrize_leaves_reciprocal_input_unchanged():
    rng = np.random.default_rng(3)
    A = rng.uniform(0.0, 0.1, (POLAR.size, POLAR.size, DPHI.size))
    A = A + np.swapaxes(A, 0, 1)
    np.testing.assert_allclose(symmetrize_reciprocal(A, POLAR, DPHI), A, rtol=1e-10)


def test_isotropize_normal_keeps_albedo_and_removes_azimuth_dependence():
    from solver.table.orders_to_brdf import isotropize_normal

    rng = np.random.default_rng(4)
    R = rng.uniform(0.0, 0.2, (2, POLAR.size, POLAR.size, DPHI.size))
    S = isotropize_normal(R, POLAR, DPHI)
    assert np.ptp(S[:, 0], axis=-1).max() < 1e-15 and np.ptp(S[:, :, 0], axis=-1).max() < 1e-15
    np.testing.assert_allclose(diffuse_albedo(POLAR, DPHI, S), diffuse_albedo(POLAR, DPHI, R), rtol=1e-12)
