"""Colour measurement (solver.colour): tristimulus weights against colour-science, the
geometries' physics (reciprocity, energy, SCI − SCE = the mirror), and the 45:0 colour of a
molecular film against an independent computation of the instrument's cones."""

import math

import colour
import numpy as np
import pytest

import oracles
from conftest import diffuse_layer_table
from solver.colour import measurement as M
from solver.colour import srgb
from solver.colour.cie import (OBSERVERS, ColourError, delta_e2000, spectra_to_lab, spectra_to_xyz, white_xyz,
                               xyz_to_lab)
from solver.inks import molecular_eps, parse_ink
from solver.table.evaluate import brdf_R_at, column_at, directional_albedo
from solver.table.integrals import band_weights, hemispherical_mean
from solver.table.thinfilm_tier import build_thinfilm_table

H_NM = 1000.0
#: colour-science says how it aligns the shapes of the data it is given: expected
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")


def smooth_spectrum(wl):
    return 0.2 + 0.6 * np.exp(-((wl - 560.0) / 60.0) ** 2)


@pytest.mark.parametrize("step", [5.0, 10.0, 20.0])
@pytest.mark.parametrize("illuminant,observer", [("D50", "2"), ("D65", "2"), ("D50", "10")])
def test_weights_are_astm_e308(step, illuminant, observer):
    """XYZ = spectrum @ W equals colour-science's ASTM E308 on the same data (linearity of the
    method: the weights are the XYZ of unit spectra)."""
    wl = np.arange(380.0, 781.0, step)
    refl = smooth_spectrum(wl)
    sd = colour.SpectralDistribution(dict(zip(wl, refl)))
    ref = colour.colorimetry.sd_to_XYZ_ASTME308(sd, colour.MSDS_CMFS[OBSERVERS[observer]],
                                                colour.SDS_ILLUMINANTS[illuminant]) / 100.0
    np.testing.assert_allclose(spectra_to_xyz(wl, refl, illuminant, observer), ref, rtol=1e-10)


def test_coarse_grids_are_interpolated_linearly_to_5nm():
    """40-nm (preview) data: weighted as their linear interpolant at 5 nm."""
    wl = np.arange(380.0, 781.0, 40.0)
    refl = smooth_spectrum(wl)
    fine = np.arange(380.0, 781.0, 5.0)
    np.testing.assert_allclose(spectra_to_xyz(wl, refl, "D50", "2"),
                               spectra_to_xyz(fine, np.interp(fine, wl, refl), "D50", "2"), rtol=1e-12)


def test_white_is_the_reference_and_srgb_round_trips():
    for ill, obs in (("D50", "2"), ("D65", "10")):
        wl = np.arange(380.0, 781.0, 20.0)
        np.testing.assert_allclose(spectra_to_lab(wl, np.ones(wl.size), ill, obs), [100.0, 0.0, 0.0], atol=1e-9)
        # the 5-nm reference white (sRGB conversions) differs by less than 0.02 in a*, b*
        lab = xyz_to_lab(spectra_to_xyz(wl, np.ones(wl.size), ill, obs), white_xyz(ill, obs))
        np.testing.assert_allclose(lab, [100.0, 0.0, 0.0], atol=0.02)
    # D50 white = the tabulated D50 chromaticity (colour-science)
    xy = colour.XYZ_to_xy(white_xyz("D50", "2"))
    np.testing.assert_allclose(xy, colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D50"], atol=2e-4)
    wl = np.arange(380.0, 781.0, 10.0)
    assert tuple(srgb.spectra_to_srgb8(wl, np.ones(wl.size))) == (255, 255, 255)
    pixels = np.array([[0, 0, 0], [255, 255, 255], [200, 30, 90], [12, 180, 250], [128, 128, 128]])
    for ill in ("D50", "D65"):
        lab = srgb.srgb8_to_lab(pixels, ill)
        np.testing.assert_allclose(lab[1], [100.0, 0.0, 0.0], atol=1e-6)       # sRGB white → the white
        assert abs(lab[4, 1]) < 1e-6 and abs(lab[4, 2]) < 1e-6                # grey stays neutral
        np.testing.assert_array_equal(srgb.lab_to_srgb8(lab, ill), pixels)
    # the transfer curve: IEC 61966-2-1 at its break point and mid grey
    assert srgb.encode(0.0031308) == pytest.approx(0.04045, abs=1e-5)
    assert srgb.decode(srgb.encode(0.214)) == pytest.approx(0.214)


def test_bad_names_and_ranges_are_one_line_lists():
    with pytest.raises(ColourError, match="choose one of 45:0, d:8:sci, d:8:sce, d:0, paper"):
        M.parse_measurement("45/0")
    with pytest.raises(ColourError, match="illuminant 'A'.*D50, D65"):
        M.parse_measurement("45:0", "A")
    with pytest.raises(ColourError, match="observer '5'.*2°, 10°"):
        M.parse_measurement("45:0", "D50", "5")
    assert M.from_label(M.DEFAULT.label) == M.DEFAULT and M.DEFAULT.label == "45:0/D50/2°"
    film = build_thinfilm_table(parse_ink("R30"), H_NM, np.arange(450.0, 651.0, 50.0), np.linspace(0, np.pi / 2, 7))
    with pytest.raises(ColourError, match="wavelengths 450–650 nm; a colour needs at least 400–700 nm"):
        M.DEFAULT.lab(film, 0.9)
    with pytest.raises(ColourError, match="needs light angles 40–50°.*holds 0–30°"):
        M.DEFAULT.check_grids(np.arange(380.0, 781.0, 20.0), np.radians([0.0, 15.0, 30.0]), "the grids")


def test_band_weights_are_exact_for_the_linear_interpolant():
    grid = np.radians([0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0, 90.0])
    f = np.array([0.3, 0.1, 0.7, 0.2, 0.9, 0.4, 0.5, 0.05])
    lo, hi = np.radians(40.0), np.radians(50.0)
    from scipy.integrate import quad
    num = quad(lambda s: np.interp(s, grid, f) * np.cos(s) * np.sin(s), lo, hi, points=[np.radians(45.0)])[0]
    den = quad(lambda s: np.cos(s) * np.sin(s), lo, hi)[0]
    assert band_weights(grid, lo, hi) @ f == pytest.approx(num / den, rel=1e-12)


def film(spec="B30", n_angle=46, step=10.0):
    return build_thinfilm_table(parse_ink(spec), H_NM, np.arange(380.0, 781.0, step), np.linspace(0, np.pi / 2, n_angle))


def test_geometries_against_each_other():
    """d:0 is the directional albedo (reciprocity); SCI − SCE is the mirror at 8°; `paper` is
    d:0 without the mirror; 45:0 is the lobe and the paper term averaged over the two cones."""
    t = diffuse_layer_table(lossless=False, n_lambda=21, n_angle=10)
    r = 0.85
    refl = {name: M.parse_measurement(name).reflectance(t, r) for name in M.GEOMETRIES}
    np.testing.assert_allclose(refl["d:0"], directional_albedo(t, r, 0.0), rtol=1e-12)
    np.testing.assert_allclose(refl["d:8:sci"], directional_albedo(t, r, np.radians(8.0)), rtol=1e-12)
    np.testing.assert_allclose(refl["d:8:sci"] - refl["d:8:sce"], column_at(t, "R_spec", np.radians(8.0)), atol=1e-15)
    np.testing.assert_allclose(refl["d:0"] - refl["paper"], t.R_spec[:, 0], atol=1e-15)
    # 45:0's diffuse lobe by dense midpoint quadrature of the reference interpolant (brdf_R_at)
    sig = np.radians(40.0 + 10.0 * (np.arange(100) + 0.5) / 100)
    the = np.radians(5.0 * (np.arange(40) + 0.5) / 40)
    phi = np.pi * (np.arange(48) + 0.5) / 48
    w_s, w_t = np.cos(sig) * np.sin(sig), np.cos(the) * np.sin(the)
    lobe = brdf_R_at(t, sig[:, None, None], the[None, :, None], phi[None, None, :]).mean(axis=-1)
    lobe = np.einsum("lst,s,t->l", lobe, w_s / w_s.sum(), w_t / w_t.sum())
    gain = r / (1 - r * hemispherical_mean(t.sigma, t.Rbar_below))
    t_band = np.array([np.interp(sig, t.sigma, row) @ w_s / w_s.sum() for row in t.Tbar])
    t_cone = np.array([np.interp(the, t.sigma, row) @ w_t / w_t.sum() for row in t.Tbar])
    np.testing.assert_allclose(refl["45:0"], lobe + gain * t_band * t_cone, rtol=2e-4)


def test_45_0_of_clear_varnish_on_white_paper_is_analytic():
    """A lossless layer on paper r = 1: ρ̄ = 1 − τ̄, so the 45:0 factor is T̄_band(45°)·T̄_cone(0°)/τ̄
    and the d:0 factor is exactly 1 (white furnace)."""
    clear = film("clear")
    tau = hemispherical_mean(clear.sigma, clear.Tbar)
    np.testing.assert_allclose(M.parse_measurement("d:0").reflectance(clear, 1.0), 1.0, atol=1e-9)
    band = clear.Tbar @ band_weights(clear.sigma, np.radians(40.0), np.radians(50.0))
    cone = clear.Tbar @ band_weights(clear.sigma, 0.0, np.radians(5.0))
    np.testing.assert_allclose(M.DEFAULT.reflectance(clear, 1.0), band * cone / tau, rtol=1e-12)


def test_45_0_of_a_film_agrees_with_an_independent_computation():
    """The 45:0 D50 colour of molecular films, computed another way: the instrument's cones
    sampled by quasi-random directions, T̄ of each direction from the characteristic-matrix
    oracle (s and p averaged), ρ̄ by adaptive quadrature of the oracle, tristimulus values by
    colour-science's ASTM E308 called on the spectrum itself: ΔE2000 ≤ 0.01."""
    from scipy.integrate import quad
    from scipy.stats import qmc

    wl = np.arange(380.0, 781.0, 10.0)
    r = 0.9
    # polar angles with density ∝ cos θ sin θ (the cones' cos-weighted solid angle), by inverting
    # the CDF of sin²θ at Sobol points: light 40–50° (annular), view 0–5°
    light = np.arcsin(np.sqrt(np.sin(np.radians(40)) ** 2 + qmc.Sobol(1, seed=1).random(256)[:, 0]
                              * (np.sin(np.radians(50)) ** 2 - np.sin(np.radians(40)) ** 2)))
    view = np.arcsin(np.sqrt(qmc.Sobol(1, seed=2).random(256)[:, 0] * np.sin(np.radians(5)) ** 2))
    for spec in ("B30", "R15", "Y50"):
        table = film(spec)
        eps = molecular_eps(parse_ink(spec), wl)      # the film's own: bulk pigment ε

        def T(lam_i, s):
            return 0.5 * sum(oracles.abeles([eps[lam_i]], [H_NM], wl[lam_i], s, pol)[2] for pol in ("te", "tm"))

        def R_below(lam_i, s):
            return 0.5 * sum(oracles.abeles([eps[lam_i]], [H_NM], wl[lam_i], s, pol)[1] for pol in ("te", "tm"))

        refl = np.empty(wl.size)
        for i in range(wl.size):
            rho = quad(lambda s: 2 * R_below(i, s) * math.cos(s) * math.sin(s), 0.0, math.pi / 2, limit=200)[0]
            t_light = np.mean([T(i, s) for s in light])
            t_view = np.mean([T(i, s) for s in view])
            refl[i] = r * t_light * t_view / (1 - r * rho)
        cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
        xyz, white = (colour.sd_to_XYZ(colour.SpectralDistribution(dict(zip(wl, values))), cmfs,
                                       colour.SDS_ILLUMINANTS["D50"], method="ASTM E308") / 100.0
                      for values in (refl, np.ones(wl.size)))
        want = colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(white))
        got = M.DEFAULT.lab(table, r)
        assert float(delta_e2000(got, want)) <= 0.01, (spec, got, want)
