"""TM polarisation at the layer's faces, against the exact TM Airy formula (oracles.airy_slab;
the slab cases of both polarisations are in test_wave_slab.py, Wood anomalies in
test_wave_hard.py); TM energy closure with real and complex ε_f; reciprocity; Brewster; hard
cases.  The interior stays scalar (docs/wave_solver.md, "TM polarisation"); the default face
forms are the 'brewster' preset (E_x / H_y / TE conditions per harmonic, "TM faces"; every
preset is tested in test_wave_hybrid.py)."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from conftest import E_BINDER, reciprocal_order_pairs, slab_against_airy
from solver.wave import (TM_FACE_PRESETS, Cell, Incidence, bloch_vector, prepare, solve,
                         solve_prepared)
from solver.wave.validation import random_layer

LAM = 500.0


@pytest.mark.parametrize("eta,eps_b", [(1.558, 2.275 + 0.168j), (1.4 + 0.2j, 1.558 ** 2)])
@pytest.mark.parametrize("sigma_deg", [17.0, 85.0])
def test_tm_slab_as_contrast_to_a_different_background(eta, eps_b, sigma_deg):
    """The slab carried by the contrast, the faces given the slab's own ε_f."""
    cell = Cell(np.full((2, 2, 64), eta ** 2), (300.0, 300.0), (0.0, 1000.0))
    res = slab_against_airy(cell, Incidence(LAM, math.radians(sigma_deg)), 1.0, eta, 1.0, 1000.0, "tm",
                            eps_background=eps_b, eps_face=eta ** 2, preconditioner="none")
    assert res.applications > 3     # the Krylov solve, not the layered preconditioner's exact 1-D stack


def test_brewster_angle_of_a_clear_binder_film():
    """At tan σ = n_binder both faces of a clear film are at Brewster's angle: TM specular
    reflection vanishes, TE does not."""
    cell = Cell(np.full((1, 1, 32), E_BINDER), (300.0, 300.0), (0.0, 1000.0))
    brewster = math.atan(1.558)
    tm = solve(cell, Incidence(LAM, brewster), polarisation="tm", tol=1e-8)
    te = solve(cell, Incidence(LAM, brewster), tol=1e-8)
    assert tm.R_spec < 1e-8 and te.R_spec > 0.05
    near = solve(cell, Incidence(LAM, brewster - math.radians(10)), polarisation="tm", tol=1e-8)
    assert near.R_spec > 1e-3


@pytest.mark.parametrize("preset", sorted(TM_FACE_PRESETS))
def test_tm_with_face_equal_to_half_spaces_is_te(preset):
    """ε_f = ε_above = ε_below makes every TM face form (H_y, E_x) the TE face: the same
    powers; the 00 amplitudes equal up to the H_y sign convention of E_x faces (r_p = −r_s)."""
    cell = random_layer(1.4 + 0.1j, shape=(16, 16, 8))
    inc = Incidence(LAM, 0.4, 0.3)
    te = solve(cell, inc, tol=1e-10, dtype=np.complex128)
    tm = solve(cell, inc, tol=1e-10, dtype=np.complex128, polarisation="tm", eps_face=1.0,
               tm_faces=preset)
    for a, b in ((te.reflected, tm.reflected), (te.transmitted, tm.transmitted)):
        assert np.allclose(a.power, b.power, rtol=1e-9, atol=1e-15)
        assert np.allclose(np.abs(a.amplitude[a.propagating]), np.abs(b.amplitude[b.propagating]),
                           rtol=1e-9, atol=1e-15)
    faces = TM_FACE_PRESETS[preset]
    sign = -1 if "e" in (faces.inner, faces.mean) else 1
    assert tm.reflected.amp(0, 0) == pytest.approx(sign * te.reflected.amp(0, 0), abs=1e-12)
    assert tm.absorbed == pytest.approx(te.absorbed, abs=1e-10)


@pytest.mark.parametrize("sigma_deg", [0.0, 50.0])
def test_lossless_particle_cell_conserves_energy_in_tm(sigma_deg):
    res = solve(random_layer(1.4), Incidence(LAM, math.radians(sigma_deg), 0.5), tol=1e-5,
                polarisation="tm", exact_energy=True)
    assert res.converged and res.reflected.propagating.sum() > 5
    assert abs(res.R + res.T - 1) <= 1e-3
    assert abs(res.energy_error) <= 1e-4
    assert res.R - res.R_spec > 1e-3


@pytest.mark.parametrize("k", [0.05, 1.1])
def test_absorbing_particle_cell_tm_closure(k):
    """Quadrature and residual closures agree; R + T + A = 1."""
    cell = random_layer(1.4 + 1j * k)
    inc = Incidence(LAM, 0.3, 1.0)
    quad = solve(cell, inc, tol=1e-6, polarisation="tm", exact_energy=True)
    cheap = solve(cell, inc, tol=1e-6, polarisation="tm")
    assert quad.absorbed > 0.05 and abs(quad.energy_error) <= 1e-4
    assert cheap.energy_check == "residual"
    assert abs(cheap.absorbed - quad.absorbed) <= 1e-6
    assert abs(cheap.energy_error - quad.energy_error) <= 1e-6


def test_tm_and_te_differ_at_oblique_incidence():
    """The faces' Fresnel coefficients differ between TE and TM at 60°: so do the layer's."""
    cell = random_layer(1.4 + 0.2j, shape=(16, 16, 8))
    te = solve(cell, Incidence(LAM, math.radians(60)), tol=1e-6)
    tm = solve(cell, Incidence(LAM, math.radians(60)), tol=1e-6, polarisation="tm")
    assert abs(te.R_spec - tm.R_spec) > 1e-3


def test_reciprocity_of_tm_orders():
    """Default face forms ('brewster'; E_x amplitudes scaled by the flux factors, faces.py).
    amp(a → b)·ε_a/k_z,a = amp(b̄ → ā)·ε_b/k_z,b (flux normalisation k_z/ε of TM waves):
    reflection within one medium (the TE relation) and transmission between unequal
    half-spaces (where the ε factor matters: checked to fail without it)."""
    base = random_layer(1.4 + 0.1j, shape=(24, 24, 12))
    cell = Cell(base.eps, base.period_nm, base.z_range_nm, eps_above=1.0, eps_below=1.33 ** 2)
    pairs = reciprocal_order_pairs(cell, LAM, "tm")
    for (m, n, side), a, b, eps_a, eps_b in pairs:
        lhs, rhs = a * eps_a, b * eps_b
        assert abs(lhs - rhs) <= 1e-3 * abs(lhs), (m, n, side, lhs, rhs)
        if side == "T":
            assert abs(a - b) > 0.1 * abs(lhs)                # the TE form fails here
    assert len(pairs) == 6


def test_tm_strong_absorption_and_grazing_are_finite():
    cell = random_layer(1.4 + 1.1j, fraction=0.4, shape=(16, 16, 8))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = solve(cell, Incidence(LAM, math.radians(85), 0.4), tol=1e-5, polarisation="tm",
                    exact_energy=True)
    assert res.converged and abs(res.energy_error) < 1e-4
    assert all(math.isfinite(v) for v in (res.R, res.T, res.absorbed))


def test_prepared_tm_operator_serves_both_sides():
    cell = random_layer(1.4 + 0.05j, seed=3, shape=(16, 16, 8))
    inc = Incidence(LAM, 0.5, 1.2)
    op = prepare(cell, LAM, *bloch_vector(cell, inc), polarisation="tm")
    above = solve_prepared(op, False)
    ref = solve(cell, inc, polarisation="tm")
    assert np.allclose(above.reflected.amplitude, ref.reflected.amplitude, atol=1e-6)
    assert solve_prepared(op, True).polarisation == "tm"


def test_bad_polarisation_and_face_are_refused():
    cell = Cell(np.full((2, 2, 2), 2.0 + 0.1j), (100.0, 100.0), (0.0, 100.0))
    with pytest.raises(ValueError, match="polarisation"):
        solve(cell, Incidence(LAM, 0.1), polarisation="p")
    with pytest.raises(ValueError, match="eps_face"):
        solve(cell, Incidence(LAM, 0.1), polarisation="tm", eps_face=-1.0)
