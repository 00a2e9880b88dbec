"""Colour separation (solver.apps.separation): printed colours of known coverage mixes separate back
to those mixes; out-of-gamut colours are clipped to the closest printable colour (checked
against a brute-force search of a fine coverage grid) and counted; colour conversions against
colour-science."""

import numpy as np
import pytest

from solver.apps.separation import (CoverageGrid, PrintColourModel, Separator, SolverSettings, delta_e2000,
                                   lab_to_srgb8, printed_inks, separate_image, separate_lab, srgb8_to_lab)
from solver.apps.separation.solve import jacobian

MODELS = ("clapper-yule", "murray-davies")


@pytest.fixture(scope="module")
def rgb_print():
    return printed_inks(("R30", "Y30", "B30"))


@pytest.fixture(scope="module", params=MODELS)
def model(request, rgb_print):
    return PrintColourModel.build(rgb_print, paper=0.9, coverage_model=request.param)


def test_lab_of_srgb_against_colour_science():
    import colour

    rng = np.random.default_rng(3)
    px = rng.integers(0, 256, size=(200, 3))
    # the separation's colorimetry is the press's (D50): sRGB adapted to D50 with Bradford
    d50 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D50"]
    want = colour.XYZ_to_Lab(colour.sRGB_to_XYZ(px / 255.0, illuminant=d50, chromatic_adaptation_transform="Bradford"),
                             d50)
    np.testing.assert_allclose(srgb8_to_lab(px), want, atol=0.05)     # E308 vs colour's D50 white
    np.testing.assert_array_equal(lab_to_srgb8(srgb8_to_lab(px)), px)


def test_known_mixes_separate_back(model):
    """Random mixes in [0, 1]³: the separated colour matches to ΔE76 ≤ 1e-3 (the solver's
    tolerance) and, where the map is well conditioned, the coverages match to 1e-3."""
    rng = np.random.default_rng(11)
    mixes = rng.random((400, 3))
    sep = separate_lab(model, model.lab(mixes))
    assert sep.delta_e76.max() <= 1e-3
    assert not sep.out_of_gamut.any()
    assert np.all((sep.coverages >= 0) & (sep.coverages <= 1))
    # conditioning: smallest singular value of ∂Lab/∂c (ΔE per unit coverage) at the true mix
    sigma_min = np.linalg.svd(jacobian(model, mixes, model.lab(mixes), 1e-6), compute_uv=False)[:, -1]
    good = sigma_min > 5.0
    assert good.mean() > 0.8, "the test would hardly check coverages"
    err = np.abs(sep.coverages - mixes).max(axis=-1)
    assert err[good].max() <= 1e-3, (mixes[good][np.argmax(err[good])], err[good].max())


@pytest.mark.parametrize("inks", [("B30",), ("R30", "Y30"), ("R30", "Y30", "B30", "G30")])
def test_other_ink_counts(inks):
    """One, two and four inks: printed colours of known mixes are matched (with four inks the
    mix is not unique, so only the colour is checked)."""
    m = PrintColourModel.build(printed_inks(inks), coverage_model="clapper-yule")
    mixes = np.random.default_rng(5).random((60, len(inks)))
    sep = separate_lab(m, m.lab(mixes))
    assert sep.delta_e76.max() <= 1e-3
    if len(inks) < 4:
        np.testing.assert_allclose(sep.coverages, mixes, atol=2e-3)


def test_out_of_gamut_clipped_to_closest_printable(model):
    """Saturated sRGB colours (and white under the absolute intent) lie outside the gamut of
    R30/Y30/B30: each is flagged, its coverages stay in [0, 1] and no node of a 41³ coverage
    grid prints closer to it (brute force)."""
    targets = srgb8_to_lab(np.array([[0, 200, 0], [0, 60, 255], [0, 255, 255], [255, 0, 255],
                                     [40, 0, 90], [250, 250, 40]]))
    sep = separate_lab(model, targets)
    assert sep.out_of_gamut.all()
    assert np.all((sep.coverages >= 0) & (sep.coverages <= 1))
    axis = np.linspace(0, 1, 41)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    brute = np.min(np.linalg.norm(model.lab(grid)[None] - targets[:, None], axis=-1), axis=1)
    assert np.all(sep.delta_e76 <= brute + 1e-6), (sep.delta_e76, brute)
    assert np.all(sep.delta_e76 >= brute - 0.5)           # the grid is fine: it cannot be far off
    np.testing.assert_allclose(sep.printed_lab, model.lab(sep.coverages), atol=1e-9)


def test_intents_and_paper_white(rgb_print):
    """relative: the image white is the bare paper (no ink, ΔE 0); absolute: white is brighter
    than paper of albedo 0.9 (L* 96), out of gamut, printed as bare paper."""
    white = srgb8_to_lab([[255, 255, 255]])
    rel = separate_lab(PrintColourModel.build(rgb_print, 0.9, intent="relative"), white)
    assert rel.coverages.max() < 1e-6 and rel.delta_e76[0] < 1e-4          # sRGB vs D65 white rounding
    absolute = separate_lab(PrintColourModel.build(rgb_print, 0.9, intent="absolute"), white)
    assert absolute.out_of_gamut[0] and absolute.coverages.max() < 1e-6
    assert absolute.delta_e76[0] == pytest.approx(100.0 - (116.0 * 0.9 ** (1 / 3) - 16.0), abs=0.05)


def test_image_report_counts_clipped_pixels(rgb_print):
    """An image of 30 printable colours and 10 pixels of pure green: the report counts exactly
    the green pixels as clipped, with their ΔE; the printable ones separate back."""
    m = PrintColourModel.build(rgb_print, 0.9, "clapper-yule")
    mixes = np.random.default_rng(2).uniform(0.05, 0.6, (30, 3))
    printable = lab_to_srgb8(m.lab(mixes))                            # 8-bit: near, not on, the mixes
    image = np.concatenate([printable, np.tile([[0, 255, 0]], (10, 1))]).reshape(5, 8, 3).astype(np.uint8)
    result = separate_image(Separator.build(m, mapping="clip"), image)
    r = result.report
    assert r.pixels == 40 and r.mapped_pixels == 10
    green = separate_lab(m, srgb8_to_lab([[0, 255, 0]]))
    green00 = delta_e2000(green.printed_lab, green.target_lab)[0]
    assert r.mapped_max_de2000 == pytest.approx(green00, rel=1e-6)
    assert r.mapped_mean_de2000 == pytest.approx(green00, rel=1e-6)
    assert r.mean_de2000 == pytest.approx(10 / 40 * green00, rel=1e-2)
    cov = result.coverages.reshape(40, 3)
    np.testing.assert_allclose(cov[:30], mixes, atol=0.02)           # 8-bit rounding of the colours
    assert "out of gamut" in r.lines()[1] and "10 pixels" in r.lines()[1]


def test_lut_initialisation_is_nearest_node(rgb_print):
    m = PrintColourModel.build(rgb_print)
    grid = CoverageGrid.build(m, 5)
    assert grid.coverages.shape == (125, 3)
    targets = grid.lab[[7, 60, 124]] + 0.01
    np.testing.assert_array_equal(grid.nearest(targets)[:, 0], grid.coverages[[7, 60, 124]])
    # no iterations: the start is returned; its colour is that node's
    sep = separate_lab(m, grid.lab[[60]], SolverSettings(max_iterations=0), grid=grid)
    np.testing.assert_array_equal(sep.coverages[0], grid.coverages[60])
