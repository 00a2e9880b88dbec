"""Halftoning (solver.apps.separation.screens, .halftone): dots keep each ink's mean coverage (AM at
the classic angles, FM), inks are placed independently (overlap = product of coverages, as the
Demichel weights assume), the FM tile is blue noise, and a render of binary dots shows the
Murray–Davies mix of the dot areas (why `auto` separates dots with murray-davies)."""

import numpy as np
import pytest

from solver.apps.separation import (Dots, DotsError, PrintColourModel, TexelGrid, am_threshold, blue_noise_mask,
                               fm_threshold, halftone_ink, parse_dots, printed_inks, resolve_coverage_model,
                               screen_angles, texture_mean)
from solver.apps.separation.colour_space import lab_from_xyz
from solver.apps.separation.halftone import coverage_at_texels
from solver.apps.separation.screens import aligned_cell, spot_area

LPI = 25.0
TEXEL_IN = 1.0 / (8 * LPI)          # the default: 8 texels per screen period


def test_spot_area_is_the_cell_fraction():
    """P(S > s) of the cosine spot against a Monte Carlo of the cell (independent)."""
    rng = np.random.default_rng(0)
    u, v = rng.random((2, 400_000)) - 0.5
    spot = 0.5 * (np.cos(2 * np.pi * u) + np.cos(2 * np.pi * v))
    for s in (-0.9, -0.4, 0.0, 0.3, 0.8):
        assert spot_area(s) == pytest.approx(np.mean(spot > s), abs=3e-3)
    assert spot_area(0.0) == pytest.approx(0.5, abs=1e-9)
    assert spot_area(1.0) == pytest.approx(0.0, abs=1e-9) and spot_area(-1.0) == pytest.approx(1.0, abs=1e-9)


def test_aligned_cell_is_a_permutation():
    for n in (4, 8, 16):
        ranks = np.sort((aligned_cell(n) * n * n - 0.5).round().ravel())
        np.testing.assert_array_equal(ranks, np.arange(n * n))


@pytest.mark.parametrize("angle", [0.0, 15.0, 45.0, 75.0])
def test_am_dots_keep_uniform_coverage(angle):
    """A constant coverage c inks a fraction c of the texels: to the 1/64 levels of an 8 × 8
    cell at 0° (half a level), to 0.003 on rotated screens."""
    t = am_threshold(slice(0, 400), 400, TEXEL_IN, LPI, angle)
    tol = 0.5 / 64 + 1e-9 if angle == 0.0 else 0.003
    for c in (0.02, 0.1, 0.3, 0.5, 0.66, 0.9, 0.99):
        assert np.mean(t < c) == pytest.approx(c, abs=tol), (angle, c)


def test_fm_tile_is_blue_noise_of_uniform_ranks():
    mask = blue_noise_mask(64, seed=3)
    np.testing.assert_array_equal(np.sort((mask * 4096 - 0.5).round().ravel()), np.arange(4096))
    for c in (0.05, 0.25, 0.5, 0.8):
        assert np.mean(mask < c) == pytest.approx(c, abs=0.5 / 4096 + 1e-12)
    # blue noise: at 10 % coverage, little power at low spatial frequencies (white noise has
    # the same power at every frequency)
    dots = (mask < 0.1).astype(float) - 0.1
    power = np.abs(np.fft.fft2(dots)) ** 2
    f = np.hypot(*np.meshgrid(np.fft.fftfreq(64), np.fft.fftfreq(64), indexing="ij"))
    low = power[(f > 0) & (f < 0.08)].mean() / power[f > 0].mean()
    assert low < 0.2, low
    assert not np.array_equal(mask, blue_noise_mask(64, seed=4))


def smooth_image(h=48, w=64):
    y, x = np.mgrid[0:h, 0:w]
    return np.clip(0.5 + 0.4 * np.sin(x / 9.0) * np.cos(y / 7.0) + 0.1 * (x / w - 0.5), 0.0, 1.0)


@pytest.mark.parametrize("dots", ["AM:25", "FM"])
def test_dots_keep_mean_coverage_of_an_image(dots):
    """Over a smooth coverage image the dotted texture's mean equals the coverage at the
    texels' mean, for each ink's angle / tile (also per quarter of the image)."""
    d = parse_dots(dots)
    img = smooth_image()
    grid = TexelGrid.for_print((4.0, 3.0), img.shape, d)
    assert grid.shape == (236, 315) if d.kind == "AM" else grid.shape == (709, 945)
    target = coverage_at_texels(img, grid, slice(0, grid.shape[0]))
    for i, angle in enumerate((0.0, 15.0, 75.0)):
        tex = halftone_ink(img, grid, d, angle, seed=i + 1)
        assert set(np.unique(tex)) <= {0, 255}
        assert texture_mean(tex) == pytest.approx(float(target.mean()), abs=0.004)
        h, w = grid.shape
        for q in (np.s_[: h // 2, : w // 2], np.s_[h // 2:, w // 2:]):
            assert tex[q].mean() / 255 == pytest.approx(float(target[q].mean()), abs=0.01)


def test_continuous_texture_is_the_coverage():
    img = smooth_image()
    d = Dots("none")
    grid = TexelGrid.for_print((4.0, 3.0), img.shape, d)
    assert grid.shape == img.shape
    np.testing.assert_array_equal(halftone_ink(img, grid, d), np.round(255 * img).astype(np.uint8))
    ramp = np.tile(np.linspace(0.0, 1.0, 50), (10, 1))                 # bilinear keeps a linear ramp
    fine = TexelGrid.for_print((5.0, 1.0), ramp.shape, d, dpi=50.8 * 2)  # 2× the pixels
    vals = coverage_at_texels(ramp, fine, slice(0, fine.shape[0]))
    x = ((np.arange(fine.shape[1]) + 0.5) * 50 / fine.shape[1] - 0.5).clip(0, 49) / 49
    np.testing.assert_allclose(vals[3], x, atol=1e-6)


@pytest.mark.parametrize("dots", ["AM:25", "FM"])
def test_inks_are_placed_independently(dots):
    """The fraction inked by two inks at once is c₁·c₂ (Demichel's assumption)."""
    d = parse_dots(dots)
    shape = (600, 600)
    if d.kind == "AM":
        t1, t2 = (am_threshold(slice(0, 600), 600, TEXEL_IN, LPI, a) for a in (15.0, 75.0))
    else:
        t1, t2 = fm_threshold(slice(0, 600), 600, seed=1), fm_threshold(slice(0, 600), 600, seed=2)
    assert t1.shape == shape
    for c1, c2 in ((0.3, 0.6), (0.5, 0.5), (0.8, 0.2)):
        assert np.mean((t1 < c1) & (t2 < c2)) == pytest.approx(c1 * c2, abs=0.01)


def test_binary_dots_render_as_murray_davies():
    """The BSDF is local: a texel of binary dots is bare paper or a full overprint, so the mean
    over texels of the printed reflectance is the Murray–Davies mix of the dot areas. That is
    within ΔE 0.6 of Murray–Davies at the mean coverages and far from Clapper–Yule."""
    from solver.colour.measurement import parse_measurement

    printed = printed_inks(("R30", "Y30", "B30"))
    render = parse_measurement("d:0", "D65")          # a render's light: uniform, seen from above
    md = PrintColourModel.build(printed, coverage_model="murray-davies", measurement=render)
    cy = PrintColourModel.build(printed, coverage_model="clapper-yule", measurement=render)
    cov = np.array([0.35, 0.5, 0.25])
    img = np.ones((8, 8))
    for kind in ("AM:25", "FM"):
        d = parse_dots(kind)
        grid = TexelGrid.for_print((1.5, 1.5), img.shape, d)
        texels = np.stack([halftone_ink(img * c, grid, d, a, seed=i + 1) / 255.0
                           for i, (c, a) in enumerate(zip(cov, (75.0, 0.0, 15.0)))], axis=-1)
        mean_refl = md.reflectance(texels.reshape(-1, 3)).mean(axis=0)   # 0/1: the models agree
        np.testing.assert_allclose(mean_refl, cy.reflectance(texels.reshape(-1, 3)).mean(axis=0), atol=1e-12)
        lab = lab_from_xyz(mean_refl @ md.to_xyz, md.white_xyz)
        assert np.linalg.norm(lab - md.lab(cov)) < 0.6, kind
        assert np.linalg.norm(lab - cy.lab(cov)) > 3.0, kind
    assert resolve_coverage_model("auto", parse_dots("FM")) == "murray-davies"
    assert resolve_coverage_model("auto", parse_dots("none")) == "clapper-yule"


def test_screen_angles_follow_lightness():
    assert screen_angles([53.0, 91.0, 35.0]) == (75.0, 0.0, 15.0)          # R30, Y30, B30
    assert screen_angles([55.0, 48.0, 89.0, 20.0]) == (75.0, 15.0, 0.0, 45.0)   # C, M, Y, K
    assert screen_angles([40.0]) == (45.0,)


@pytest.mark.parametrize("text", ["AM", "AM:0", "AM:-5", "AM:x", "XM:100", "FM:3", ""])
def test_bad_dots_refused(text):
    with pytest.raises(DotsError, match="dots"):
        parse_dots(text)


def test_huge_textures_refused_before_work():
    with pytest.raises(DotsError, match="texels per ink"):
        TexelGrid.for_print((200.0, 200.0), (100, 100), parse_dots("AM:300"))
