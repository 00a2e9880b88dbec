"""TE and TM thin-film optics of layer stacks (solver.thinfilm.stack) against the oracles of
oracles.py: the characteristic (Abelès) matrix, single-interface Fresnel formulas, Brewster's
angle; Mitsuba's own fresnel_polarized, energy balance and reciprocity."""

import warnings

import numpy as np
import pytest

from conftest import N_BINDER
from oracles import abeles, fresnel
from solver.thinfilm import slab, stack, to_mitsuba_convention

BINDER = N_BINDER**2
WL = np.array([380.0, 455.0, 530.0, 610.0, 700.0, 780.0])


STACKS = [  # (eps top first, thickness nm, eps_in, eps_out)
    ([BINDER], [1000.0], 1.0, 1.0),
    ([(1.5 + 0.05j) ** 2, (1.45 + 0.2j) ** 2], [700.0, 300.0], 1.0, 1.0),
    ([2.0 + 0.3j, BINDER, (1.4 + 1.1j) ** 2], [120.0, 500.0, 80.0], 1.0, 1.0),
    ([BINDER, 1.0, BINDER], [300.0, 150.0, 400.0], 2.25, 1.0),      # TIR and frustrated TIR
    ([(1.6 + 0.01j) ** 2, 2.2], [900.0, 60.0], 1.0, (1.5 + 0.1j) ** 2),
]


@pytest.mark.parametrize("pol", ["te", "tm"])
@pytest.mark.parametrize("layers", STACKS)
@pytest.mark.parametrize("sigma_deg", [0.0, 20.0, 45.0, 60.0, 80.0, 89.0])
def test_stack_matches_characteristic_matrix(layers, sigma_deg, pol):
    eps, d, e_in, e_out = layers
    sigma = np.radians(sigma_deg)
    got = stack(eps, d, WL[:, None], sigma, polarisation=pol, eps_in=e_in, eps_out=e_out)
    for i, wl in enumerate(WL):
        r, R, T = abeles(eps, d, wl, sigma, pol, e_in, e_out)
        assert got.r[i, 0] == pytest.approx(r, abs=1e-10)
        assert got.R[i, 0] == pytest.approx(R, abs=1e-10)
        assert got.T[i, 0] == pytest.approx(T, abs=1e-10)
        # from below: σ measured in the (lossless) exit medium, Snell-matched; the oracle on
        # the reversed stack
        n_in, n_out = np.sqrt(e_in).real, np.sqrt(e_out)
        if np.imag(e_out) == 0 and n_in * np.sin(sigma) < n_out:
            sigma_b = np.arcsin(n_in * np.sin(sigma) / n_out)
            rb, Rb, Tb = abeles(eps[::-1], d[::-1], wl, sigma_b, pol, e_out, e_in)
            below = stack(eps, d, wl, sigma_b, polarisation=pol, eps_in=e_in, eps_out=e_out, from_below=True)
            assert below.r == pytest.approx(rb, abs=1e-10)
            assert below.R == pytest.approx(Rb, abs=1e-10) and below.T == pytest.approx(Tb, abs=1e-10)


def test_slab_is_the_one_layer_stack_and_te_by_default():
    eps = (1.5 + 0.02j) ** 2
    s = np.linspace(0, np.pi / 2, 19)
    a = slab(eps, 800.0, WL[:, None], s)
    b = stack([eps], [800.0], WL[:, None], s, polarisation="te")
    for f in "rtRT":
        np.testing.assert_allclose(getattr(a, f), getattr(b, f), rtol=0, atol=1e-14)
    p = slab(eps, 800.0, WL[:, None], s, polarisation="tm")
    assert np.max(np.abs(p.R - a.R)) > 0.05                # s and p differ at oblique incidence
    np.testing.assert_allclose(p.R[:, 0], a.R[:, 0], atol=1e-14)   # but not at normal incidence


@pytest.mark.parametrize("n2", [1.558, 1.5 + 0.3j, 2.4 + 0.05j])
def test_single_interface_is_fresnel_and_brewster(n2):
    """Empty stack = one face: the textbook Fresnel r_s, r_p (H-field/Verdet sign), r_p = 0 at
    Brewster's angle for a dielectric, r_p = −r_s at normal incidence."""
    s = np.radians(np.linspace(0, 89.5, 60))
    rs, rp = (fresnel(1.0, n2**2, np.sin(s) ** 2, pol)[0] for pol in ("te", "tm"))
    got_s = stack([], [], 500.0, s, polarisation="te", eps_out=n2**2)
    got_p = stack([], [], 500.0, s, polarisation="tm", eps_out=n2**2)
    np.testing.assert_allclose(got_s.r, rs, atol=1e-13)
    np.testing.assert_allclose(got_p.r, rp, atol=1e-13)
    assert got_p.r[0] == pytest.approx(-got_s.r[0], abs=1e-15)
    if np.imag(n2) == 0:
        brewster = np.arctan(n2)
        rp_b = stack([], [], 500.0, brewster, polarisation="tm", eps_out=n2**2).r
        rs_b = stack([], [], 500.0, brewster, polarisation="te", eps_out=n2**2).r
        assert abs(rp_b) < 1e-14 and abs(rs_b) > 0.1
        # a thick clear binder film: its first face passes p light at Brewster, and so does the
        # second (binder → air at the complementary angle): a film is transparent for p there
        film = slab(n2**2, 1000.0, WL, brewster, polarisation="tm")
        np.testing.assert_allclose(film.R, 0.0, atol=1e-28)
        np.testing.assert_allclose(film.T, 1.0, atol=1e-14)


def test_amplitudes_follow_mitsuba_fresnel_polarized():
    """to_mitsuba_convention(r) equals Mitsuba's a_s, a_p for the same face: dielectric,
    absorbing (Mitsuba's κ > 0 input) and total internal reflection (its phase sign)."""
    mi = pytest.importorskip("mitsuba")
    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    try:
        import drjit as dr

        cases = [(1.0, 1.5, 45.0), (1.0, 1.5, 10.0), (1.0, 1.5 + 0.3j, 45.0), (1.0, 1.4 + 1.1j, 70.0),
                 (1.5**2, 1.0, 45.0), (1.5**2, 1.0, 41.0), (1.0, 1.558, 80.0)]
        for eps_in, n_out, deg in cases:
            n_rel = n_out / np.sqrt(eps_in)
            eta = dr.scalar.Complex2f(n_rel.real, n_rel.imag) if np.iscomplexobj(n_rel) else float(n_rel)
            a_s, a_p = mi.fresnel_polarized(float(np.cos(np.radians(deg))), eta)[:2]
            ours = [to_mitsuba_convention(stack([], [], 550.0, np.radians(deg), polarisation=p,
                                                eps_in=eps_in, eps_out=n_out**2).r) for p in ("te", "tm")]
            for theirs, mine in zip((a_s, a_p), ours):
                theirs = complex(dr.real(theirs), dr.imag(theirs)) if not isinstance(theirs, float) else theirs
                assert mine == pytest.approx(theirs, abs=2e-6), (eps_in, n_out, deg)
    finally:
        if previous is not None:
            mi.set_variant(previous)


@pytest.mark.parametrize("pol", ["te", "tm"])
def test_energy_lossless_is_one_absorbing_is_less(pol):
    s = np.linspace(0, np.pi / 2, 46)
    lossless = stack([BINDER, 2.6, BINDER, 1.0, 2.0], [300.0, 90.0, 1200.0, 50.0, 400.0],
                     WL[:, None], s, polarisation=pol)
    np.testing.assert_allclose(lossless.R + lossless.T, 1.0, atol=1e-12)
    tir = stack([BINDER, 1.0, BINDER], [300.0, 120.0, 500.0], WL[:, None], s, polarisation=pol,
                eps_in=2.25, eps_out=1.2)
    np.testing.assert_allclose(tir.R + tir.T, 1.0, atol=1e-12)
    lossy = stack([BINDER, (1.45 + 0.05j) ** 2], [500.0, 700.0], WL[:, None], s, polarisation=pol)
    assert np.all(lossy.R[:, :-1] + lossy.T[:, :-1] < 1 - 1e-4)
    assert np.all(lossy.R >= 0) and np.all(lossy.T >= 0)


@pytest.mark.parametrize("pol", ["te", "tm"])
def test_two_identical_layers_are_one_layer(pol):
    eps = (1.48 + 0.07j) ** 2
    s = np.linspace(0, np.pi / 2, 31)
    two = stack([eps, eps], [350.0, 650.0], WL[:, None], s, polarisation=pol)
    one = stack([eps], [1000.0], WL[:, None], s, polarisation=pol)
    for f in "rtRT":
        np.testing.assert_allclose(getattr(two, f), getattr(one, f), atol=1e-13)


@pytest.mark.parametrize("pol", ["te", "tm"])
def test_zero_thickness_and_index_matched_layers_vanish(pol):
    s = np.linspace(0, np.pi / 2, 31)
    e1, e2 = (1.5 + 0.03j) ** 2, (1.42 + 0.2j) ** 2
    base = stack([e1, e2], [600.0, 200.0], WL[:, None], s, polarisation=pol)
    with_zero = stack([e1, 3.0 + 1j, e2, 2.2], [600.0, 0.0, 200.0, 0.0], WL[:, None], s, polarisation=pol)
    for f in "rtRT":
        np.testing.assert_array_equal(getattr(with_zero, f), getattr(base, f))
    # a layer of the exit medium's ε below the stack only moves the exit plane: same R, T and r
    matched = stack([e1, e2, 1.0], [600.0, 200.0, 333.0], WL[:, None], s, polarisation=pol)
    for f in "rRT":
        np.testing.assert_allclose(getattr(matched, f), getattr(base, f), atol=1e-13)
    # an all-air stack is no interface at all, grazing included
    air = stack([1.0, 1.0], [100.0, 50.0], WL[:, None], s, polarisation=pol)
    np.testing.assert_allclose(air.r, 0.0, atol=1e-15)
    np.testing.assert_allclose(air.T[:, :-1], 1.0, atol=1e-14)


@pytest.mark.parametrize("pol", ["te", "tm"])
def test_reciprocity_from_above_and_below(pol):
    """T(above → below) = T(below → above) for an asymmetric absorbing stack, at Snell-matched
    angles when the two outer media differ; R differs (the stack is not up-down symmetric)."""
    eps = [(1.5 + 0.01j) ** 2, (1.45 + 0.3j) ** 2, BINDER]
    d = [400.0, 120.0, 700.0]
    s = np.linspace(0, np.radians(89.0), 30)
    down = stack(eps, d, WL[:, None], s, polarisation=pol)
    up = stack(eps, d, WL[:, None], s, polarisation=pol, from_below=True)
    np.testing.assert_allclose(down.T, up.T, rtol=1e-11, atol=1e-15)
    assert np.max(np.abs(down.R - up.R)) > 1e-3
    down = stack(eps, d, WL[:, None], s, polarisation=pol, eps_in=1.0, eps_out=2.25)
    s_below = np.arcsin(np.sin(s) / 1.5)
    up = stack(eps, d, WL[:, None], s_below, polarisation=pol, eps_in=1.0, eps_out=2.25, from_below=True)
    np.testing.assert_allclose(down.T, up.T, rtol=1e-10, atol=1e-15)


@pytest.mark.parametrize("pol", ["te", "tm"])
def test_hard_cases_are_finite_without_warnings(pol):
    """Strong absorption in thick layers, grazing 90°, evanescent micrometre gaps (TIR) and a
    layer with k_z = 0 exactly: finite, in [0, 1], no numpy warning."""
    s = np.linspace(0, np.pi / 2, 91)
    with warnings.catch_warnings(), np.errstate(over="raise", invalid="raise", divide="raise"):
        warnings.simplefilter("error")
        thick = stack([(1.5 + 3.0j) ** 2, BINDER], [1e6, 1e6], WL[:, None], s, polarisation=pol)
        half = stack([], [], WL[:, None], s, polarisation=pol, eps_out=(1.5 + 3.0j) ** 2)
        gap = stack([1.0, BINDER], [1e5, 1e3], WL[:, None], s, polarisation=pol, eps_in=2.25)
        flat = stack([BINDER, 1.0, BINDER], [0.5, 200.0, 300.0], WL[:, None], s, polarisation=pol)
        zero_kz = stack([BINDER, 2.25, 1.0], [100.0, 250.0, 80.0], WL[:, None], np.pi / 2,
                        polarisation=pol, eps_in=2.25)
        thin = stack([BINDER], [0.0], WL[:, None], s, polarisation=pol)
    for res in (thick, half, gap, flat, zero_kz, thin):
        for f in "rtRT":
            assert np.all(np.isfinite(getattr(res, f)))
        assert np.all(res.R <= 1 + 1e-12) and np.all(res.T >= 0) and np.all(res.R + res.T <= 1 + 1e-12)
    np.testing.assert_allclose(thick.R, half.R, atol=1e-14)     # opaque layer = half-space
    assert np.all(thick.T == 0)
    np.testing.assert_allclose(gap.R[:, s > np.arcsin(1 / 1.5) + 0.05], 1.0, atol=1e-12)
    np.testing.assert_allclose(thick.R[:, -1], 1.0, atol=1e-12)
    assert np.all(thick.T[:, -1] == 0) and np.all(gap.T[:, -1] == 0)
    np.testing.assert_allclose(zero_kz.R, 1.0, atol=1e-12)      # grazing entry: total reflection
    np.testing.assert_allclose(thin.r, 0.0, atol=0)            # 0-nm layer in air: nothing there


def test_degenerate_inner_layer_with_kz_zero_is_continuous():
    """A layer whose k_z is exactly 0 (ε = ε_in sin²σ: a field linear in z, 0/0 in the two-wave
    formulas) gives the limit of nearby ε (ε ± 1e-9) and the characteristic-matrix value."""
    eps_in, sigma, wl = 4.0, np.pi / 6, 500.0
    k0 = 2 * np.pi / wl
    k_par = k0 * 2.0 * np.sin(sigma)
    eps_crit = k_par**2 / k0**2
    assert k0**2 * eps_crit - k_par**2 == 0          # the precondition: k_z = 0 exactly
    layers, d = [BINDER, eps_crit, BINDER], [200.0, 150.0, 300.0]
    for pol in ("te", "tm"):
        res = stack(layers, d, wl, sigma, polarisation=pol, eps_in=eps_in, eps_out=eps_in)
        assert np.isfinite(res.r) and np.isfinite(res.t)
        for de in (1e-9, -1e-9):
            other = stack([BINDER, eps_crit + de, BINDER], d, wl, sigma, polarisation=pol,
                          eps_in=eps_in, eps_out=eps_in)
            assert res.R == pytest.approx(other.R, abs=1e-6) and res.T == pytest.approx(other.T, abs=1e-6)
        _, R, T = abeles([BINDER, eps_crit * (1 + 1e-12), BINDER], d, wl, sigma, pol, eps_in, eps_in)
        assert res.R == pytest.approx(R, abs=1e-6) and res.T == pytest.approx(T, abs=1e-6)


@pytest.mark.parametrize("bad, message", [
    (dict(polarisation="p"), "polarisation must be one of"),
    (dict(polarisation="te", thickness=[100.0, -1.0]), "thickness must be ≥ 0"),
    (dict(polarisation="te", thickness=[100.0]), "2 permittivities but 1 thicknesses"),
    (dict(polarisation="te", thickness=[100.0, np.nan]), "thickness must be ≥ 0"),
])
def test_bad_input_is_refused(bad, message):
    with pytest.raises(ValueError, match=message):
        stack([2.0, 2.1], bad.get("thickness", [100.0, 100.0]), 500.0, 0.3, polarisation=bad["polarisation"])
