"""TM face forms per lateral harmonic (solver/wave/faces.py, docs/wave_solver.md "TM faces").

Every preset against the exact TM film (solver.thinfilm, an independent transfer-matrix code);
energy closure of the generalised TM identity (quadrature vs residual); the normal-incidence
s/p symmetry of the default on generated ink layers (where the first TM model fails it);
reciprocity; continuity at a Wood anomaly and at Brewster's angle; TE untouched."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from solver.geometry import LayerSpec, eps_grid, generate, parse_particles, voxelize
from solver.inks import parse_ink
from solver.thinfilm import stack
from solver.wave import (DEFAULT_TM_FACES, TM_FACE_PRESETS, Cell, Incidence, TMFaces, prepare,
                         solve)
from solver.wave.faces import FORMS, parse_tm_faces
from solver.wave.validation import random_layer

LAM = 500.0
PRESETS = sorted(TM_FACE_PRESETS)


def test_default_is_reciprocal_brewster_and_presets_parse():
    assert DEFAULT_TM_FACES == "brewster"
    assert parse_tm_faces("brewster") == TMFaces("e", "h", "te")
    assert parse_tm_faces(TMFaces("h", "h", "h")) == TM_FACE_PRESETS["all"]
    with pytest.raises(ValueError, match="tm_faces"):
        parse_tm_faces("magnetic")
    with pytest.raises(ValueError, match="TMFaces.outer"):
        TMFaces("e", "x", "te")
    cell = Cell(np.full((2, 2, 4), 2.0 + 0.1j), (100.0, 100.0), (0.0, 100.0))
    with pytest.raises(ValueError, match="tm_faces"):          # refused before any work
        solve(cell, Incidence(LAM, 0.1), polarisation="tm", tm_faces="nope")


def _film(cell, inc, eta):
    return stack([eta ** 2], [cell.thickness_nm], inc.wavelength_nm, inc.polar_rad,
                 polarisation="tm", eps_in=cell.eps_above, eps_out=cell.eps_below,
                 from_below=inc.from_below)


@pytest.mark.parametrize("preset", PRESETS)
@pytest.mark.parametrize("eta", [1.558, 1.4 + 0.2j, 1.4 + 1.1j])
@pytest.mark.parametrize("sigma_deg", [0.0, 40.0, 60.0, 85.0])
@pytest.mark.parametrize("from_below", [False, True])
def test_every_preset_is_the_exact_tm_film(preset, eta, sigma_deg, from_below):
    """A homogeneous layer has no scattered harmonics: H_y and E_x faces both give the film
    (H_y amplitudes reported), and the quadrature energy identity closes."""
    cell = Cell(np.full((2, 2, 32), eta ** 2), (300.0, 300.0), (0.0, 1000.0),
                eps_below=1.33 ** 2)
    inc = Incidence(LAM, math.radians(sigma_deg), 0.3, from_below=from_below)
    res = solve(cell, inc, tol=1e-8, polarisation="tm", tm_faces=preset, exact_energy=True)
    film = _film(cell, inc, eta)
    errs = (abs(res.reflected.amp(0, 0) - complex(film.r)),
            abs(res.transmitted.amp(0, 0) - complex(film.t)),
            abs(res.R - float(film.R)), abs(res.T - float(film.T)))
    assert max(errs) <= 1e-4, errs
    assert res.converged and abs(res.energy_error) < 1e-6
    assert res.tm_faces == preset


@pytest.mark.parametrize("preset", PRESETS)
def test_lossless_cell_conserves_energy(preset):
    res = solve(random_layer(1.4), Incidence(LAM, math.radians(35), 0.5), tol=1e-6,
                polarisation="tm", tm_faces=preset, exact_energy=True)
    assert res.converged and res.reflected.propagating.sum() > 5
    assert abs(res.R + res.T - 1) <= 1e-3 and abs(res.energy_error) <= 1e-4
    assert res.R - res.R_spec > 3e-4


@pytest.mark.parametrize("preset", PRESETS)
@pytest.mark.parametrize("k", [0.05, 1.1])
def test_absorbing_cell_closure_quadrature_equals_residual(preset, k):
    """The generalised identity (energy.py): A from ∫ Im ε|u|² plus the faces' term agrees
    with A from the residual, for every form mix (complex ε_f: Im ψ terms)."""
    cell = random_layer(1.4 + 1j * k)
    inc = Incidence(LAM, 0.5, 1.0)
    quad = solve(cell, inc, tol=1e-6, polarisation="tm", tm_faces=preset, exact_energy=True)
    cheap = solve(cell, inc, tol=1e-6, polarisation="tm", tm_faces=preset)
    assert quad.absorbed > 0.05 and abs(quad.energy_error) <= 1e-4
    assert abs(cheap.absorbed - quad.absorbed) <= 1e-6
    assert abs(cheap.energy_error - quad.energy_error) <= 1e-6


def _ink_cell(ink, diameter, cell_nm, n_xy, lam):
    layer = LayerSpec(parse_ink(ink), parse_particles(f"sphere:{diameter}"),
                      thickness_nm=1000.0, cell_nm=(cell_nm, cell_nm))
    vox = voxelize(generate(layer, 5), (n_xy, n_xy, 32))
    return Cell(eps_grid(vox, lam), (cell_nm, cell_nm), vox.z_range_nm)


#: |TM − TE| of R_spec and Rbar at σ = 0 allowed for the default: Maxwell's own |p − s| on the
#: referee's cells is 0.0003–0.005 (ensembles) and up to 0.012 for one realization
#: (docs/vector_referee.md); the default gives ≤ 0.003 on these cells, the first TM model
#: ('all') 0.016–0.058.
SYMMETRY_TOL = 0.005


@pytest.mark.parametrize("ink,diameter,cell_nm,n_xy", [("Y15", 300, 1000.0, 32),
                                                       ("Y50", 100, 400.0, 16)])
@pytest.mark.parametrize("lam", [470.0, 550.0])
def test_normal_incidence_tm_is_te_like_maxwell(ink, diameter, cell_nm, n_xy, lam):
    """At σ = 0, s and p light differ only by the cell's own anisotropy (Maxwell: ≤ 0.005 on
    ensembles): the default TM stays within SYMMETRY_TOL of TE, the H_y model does not."""
    cell = _ink_cell(ink, diameter, cell_nm, n_xy, lam)
    inc = Incidence(lam, 0.0)
    te = solve(cell, inc, tol=1e-6)
    tm = solve(cell, inc, tol=1e-6, polarisation="tm")
    old = solve(cell, inc, tol=1e-6, polarisation="tm", tm_faces="all")
    assert abs(tm.R_spec - te.R_spec) <= SYMMETRY_TOL and abs(tm.R - te.R) <= SYMMETRY_TOL
    assert abs(old.R_spec - te.R_spec) > 2 * SYMMETRY_TOL


def test_electric_mean_face_is_te_at_normal_incidence():
    """The E_x face of the 00 harmonic is the TE face at σ = 0 (κ_f²/ε_f = k0²): with TE
    conditions on every other harmonic the TM solve is the TE solve, up to r_p = −r_s."""
    cell = random_layer(1.4 + 0.1j, shape=(16, 16, 8))
    te = solve(cell, Incidence(LAM, 0.0), tol=1e-10, dtype=np.complex128)
    tm = solve(cell, Incidence(LAM, 0.0), tol=1e-10, dtype=np.complex128, polarisation="tm",
               tm_faces="electric-mean")
    assert tm.reflected.amp(0, 0) == pytest.approx(-te.reflected.amp(0, 0), abs=1e-12)
    assert tm.transmitted.amp(0, 0) == pytest.approx(te.transmitted.amp(0, 0), abs=1e-12)
    assert np.allclose(tm.reflected.power, te.reflected.power, rtol=1e-9, atol=1e-14)
    assert tm.absorbed == pytest.approx(te.absorbed, abs=1e-10)


@pytest.mark.parametrize("preset", PRESETS)
def test_te_ignores_tm_faces_bitwise(preset):
    cell = random_layer(1.4 + 0.1j, shape=(16, 16, 8))
    inc = Incidence(LAM, 0.4, 0.3)
    ref = solve(cell, inc, tol=1e-6)
    other = solve(cell, inc, tol=1e-6, tm_faces=preset)
    assert np.array_equal(ref.reflected.amplitude, other.reflected.amplitude)
    assert np.array_equal(ref.transmitted.power, other.transmitted.power)
    assert ref.tm_faces is None and prepare(cell, LAM, 0.0, 0.0).tm_faces is None


@pytest.mark.parametrize("preset,reciprocal", [("brewster", True), ("all", True),
                                               ("electric-propagating", True),
                                               ("hybrid", False)])
def test_reciprocity_of_diffuse_powers(preset, reciprocal):
    """P(a → b) = P(b̄ → ā) for every realization when the face form depends on |q| only;
    a form for the 00 harmonic alone ('hybrid') breaks it, even on average.  (λ = 530 nm: at
    500 nm the 1000-nm cell has harmonics exactly on the light line, where a form that jumps
    there, 'electric-propagating', is not reciprocal either.)"""
    lam = 530.0
    k0 = 2 * math.pi / lam
    fw = bw = 0.0
    for seed in range(3):
        cell = random_layer(1.4 + 0.1j, seed=seed, shape=(24, 24, 12))
        a = solve(cell, Incidence(lam, 0.0, 0.0), tol=1e-8, polarisation="tm",
                  tm_faces=preset).reflected
        i = a.index(1, 1)
        back = Incidence(lam, math.asin(math.hypot(a.kx[i], a.ky[i]) / k0),
                         math.atan2(a.ky[i], a.kx[i]) + math.pi)
        b = solve(cell, back, tol=1e-8, polarisation="tm", tm_faces=preset).reflected
        p_ab, p_ba = a.power[i], b.power[b.index(1, 1)]
        fw, bw = fw + p_ab, bw + p_ba
        if reciprocal:
            assert p_ab == pytest.approx(p_ba, rel=1e-3)
    assert (abs(fw / bw - 1) < 1e-3) == reciprocal, fw / bw


@pytest.fixture(scope="module")
def y15_cells():
    return {lam: _ink_cell("Y15", 300, 1000.0, 32, lam) for lam in (470.0, 600.0)}


@pytest.mark.parametrize("lam", [470.0, 600.0])
def test_default_is_continuous_across_a_wood_anomaly(y15_cells, lam):
    """Order (1, 0) grazes at σ_W = asin(1 − λ/L): R stays continuous (the square-root
    Rayleigh anomaly moves it by ~5e-5 over 2e-7 rad); switching E_x → TE at the light line
    ('electric-propagating') jumps by > 1e-3."""
    cell = y15_cells[lam]
    sig_w = math.asin(1 - lam / 1000.0)

    def jump(preset):
        lo, hi = (solve(cell, Incidence(lam, sig_w + d), tol=1e-8, polarisation="tm",
                        tm_faces=preset, dtype=np.complex128) for d in (-1e-7, 1e-7))
        assert all(math.isfinite(v) for v in (lo.R, hi.R, lo.T, hi.T))
        return abs(hi.R - lo.R)

    assert jump(DEFAULT_TM_FACES) <= 3e-4
    assert jump("electric-propagating") > 1e-3


def test_default_is_continuous_at_brewster_for_a_real_face(y15_cells):
    """E_x and H_y faces coincide at Brewster's wavevector (r = 0) when ε_f is real: no jump
    where the default switches form (600 nm: the pigment is transparent)."""
    cell = y15_cells[600.0]
    ef = complex(np.mean(cell.eps))
    assert abs(ef.imag) < 1e-3
    sig_b = math.asin(math.sqrt((ef / (ef + 1)).real))
    lo, hi = (solve(cell, Incidence(600.0, sig_b + d), tol=1e-8, polarisation="tm",
                    dtype=np.complex128) for d in (-1e-7, 1e-7))
    assert abs(hi.R - lo.R) <= 1e-5 and abs(hi.T - lo.T) <= 1e-5


@pytest.mark.parametrize("preset", PRESETS)
def test_grazing_and_strong_absorption_are_finite(preset):
    cell = random_layer(1.4 + 1.1j, fraction=0.4, shape=(16, 16, 8))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = solve(cell, Incidence(LAM, math.radians(89), 0.4), tol=1e-5, polarisation="tm",
                    tm_faces=preset, exact_energy=True)
    assert res.converged and abs(res.energy_error) < 1e-4
    assert all(math.isfinite(v) for v in (res.R, res.T, res.absorbed))


def test_forms_used_per_harmonic():
    """The default's forms by |q|: E_x below Brewster, H_y above, TE for evanescent; the
    00 harmonic of a dense half-space beyond the slab's critical angle falls back to H_y."""
    cell = random_layer(1.4, shape=(8, 8, 4))
    k0 = 2 * math.pi / LAM
    op = prepare(cell, LAM, 0.3 * k0, 0.0, polarisation="tm")
    top = op.green.faces[0]
    q2 = op.kx ** 2 + op.ky ** 2
    ef = 0.5 * sum(op.eps_face)                   # one Brewster bound: the faces' mean ε_f
    q_b2 = k0 ** 2 * (ef / (ef + 1)).real
    prop = q2 < k0 ** 2
    assert np.array_equal(top.form == FORMS.index("e"), prop & (q2 < q_b2))
    assert np.array_equal(top.form == FORMS.index("h"), prop & (q2 >= q_b2))
    assert np.array_equal(top.form == FORMS.index("te"), ~prop)
    dense = Cell(cell.eps, cell.period_nm, cell.z_range_nm, eps_below=3.0)
    k_in = k0 * math.sqrt(3.0) * math.sin(1.2)                  # beyond √(Re ε_f/3)
    op = prepare(dense, LAM, k_in, 0.0, polarisation="tm", tm_faces="electric-mean")
    assert op.green.faces[1].form[0, 0] == FORMS.index("h")


def test_local_field_permittivity_option():
    """Material data with the sphere's local field: each pigment's ε replaced by the Clausius–Mossotti local-field
    permittivity (written here), binder and air untouched; its volume mix is Maxwell Garnett to
    first order in the fill (the dipole response the scalar contrast lacks)."""
    from solver.materials import binder_eps, default_materials, pigment_eps
    layer = LayerSpec(parse_ink("Y15"), parse_particles("sphere:300"), thickness_nm=1000.0,
                      cell_nm=(1000.0, 1000.0))
    vox = voxelize(generate(layer, 5), (8, 8, 8))
    lam = 450.0
    e_h, e_p = complex(binder_eps(lam)), complex(pigment_eps("Y", lam))
    e_lf = e_h + 3 * e_h * (e_p - e_h) / (e_p + 2 * e_h)
    frac = dict(zip(vox.materials, vox.fractions))
    diff = eps_grid(vox, lam, default_materials().with_local_field()) - eps_grid(vox, lam)
    assert np.allclose(diff, frac["Y"] * (e_lf - e_p), atol=1e-12)
    # absorbed power ∝ Im ε·|E_inside|²: Im ε' = Im ε_p·|3ε_h/(ε_p + 2ε_h)|² for a real binder ε
    assert e_lf.imag / e_p.imag == pytest.approx(abs(3 * e_h / (e_p + 2 * e_h)) ** 2, rel=1e-9)
    for f in (1e-2, 1e-3):
        beta = (e_p - e_h) / (e_p + 2 * e_h)
        mg = e_h * (1 + 2 * f * beta) / (1 - f * beta)
        assert abs((1 - f) * e_h + f * e_lf - mg) < 5 * f ** 2 * abs(e_h)
