"""Two inks print the image on their surface of colours (solver/apps/separation/duotone.py,
docs/printing.md "Two inks: a surface"): each colour's L*, black-point compensated onto the
pair's range, printed exactly; its a*b* the nearest along that lightness, blended where two
parts are about as near, so that neighbouring colours get neighbouring coverages. References
here are the print model itself: its paper and darkest colour on a dense grid of the square,
and the nearest colour of a densely sampled curve of constant lightness (by brute force)."""

from types import SimpleNamespace

import numpy as np
import pytest

from solver.apps.separation import (DuotoneError, DuotoneSurface, PrintColourModel, SeparationLUT, Separator,
                                   delta_e76, map_to_gamut, printed_inks, separate_image, separate_lab)
from solver.apps.separation.colour_space import srgb_to_lab


@pytest.fixture(scope="module")
def yb():
    return PrintColourModel.build(printed_inks(("Y30", "B30")), 0.9, "clapper-yule")


@pytest.fixture(scope="module")
def yb_separator(yb):
    return Separator.build(yb)


def _range(model):
    """(darkest, paper) L* of the pair by brute force on a 129² grid of the square."""
    a = np.linspace(0.0, 1.0, 129)
    grid = np.stack(np.meshgrid(a, a, indexing="ij"), -1).reshape(-1, 2)
    return float(model.lab(grid)[:, 0].min()), float(model.lab(np.zeros(2))[0])


def _jump(coverages, window=8, floor=2e-3):
    """Largest coverage step along a line of samples over 4× the median of its neighbours'
    steps (plus `floor`): ≤ 1 where the coverages change without a jump."""
    step = np.abs(np.diff(coverages, axis=0)).max(axis=-1)
    worst = 0.0
    for i in range(step.size):
        around = np.concatenate([step[max(0, i - window):i], step[i + 1:i + 1 + window]])
        worst = max(worst, step[i] / (4.0 * np.median(around) + floor))
    return worst


def _nearest(model, surface, source_lab, nodes=1025):
    """The nearest-colour rule by brute force: the coverages of the nearest a*b* on a dense
    sampling of the curve of the compensated L*."""
    u = np.linspace(0.0, 1.0, nodes)
    out = []
    for L, ab in zip(surface.lightness_map(source_lab[:, 0]), source_lab[:, 1:]):
        c = surface.coverages(np.full(nodes, L), u)
        out.append(c[np.argmin(np.sum((model.lab(c)[:, 1:] - ab) ** 2, axis=-1))])
    return np.array(out)


def _line(a, b, n=256):
    t = np.linspace(0.0, 1.0, n)[:, None]
    return np.asarray(a, float) / 255 * (1 - t) + np.asarray(b, float) / 255 * t


GRADIENTS = {                                   # smooth sRGB lines (not rounded to 8 bits)
    "sweep row top": _line((0, 0, 255), (255, 0, 0)),          # the hue sweep of the report
    "sweep row bottom": _line((0, 255, 255), (255, 255, 0)),
    "sweep column left": _line((0, 0, 255), (0, 255, 255)),
    "sweep column right": _line((255, 0, 0), (255, 255, 0)),
    "sweep diagonal": _line((0, 0, 255), (255, 255, 0)),
    "sky deep → pale": _line((26, 90, 242), (135, 206, 235)),   # the photograph's sky blues
    "sky → white": _line((90, 150, 230), (255, 255, 255)),
    "steel → cornflower": _line((70, 130, 180), (100, 149, 237)),
    "grey": _line((0, 0, 0), (255, 255, 255)),
}


@pytest.mark.parametrize("name", list(GRADIENTS))
def test_smooth_gradients_give_coverages_without_jumps(yb_separator, name):
    sep, _ = yb_separator.separate_srgb(GRADIENTS[name])
    assert _jump(sep.coverages) <= 1.0, name


def test_where_the_nearest_colour_jumps_the_mapping_does_not(yb, yb_separator):
    """A dark red line (L* 20, a* 94) on the concave side of Y30+B30's curve of its lightness:
    the nearest colour jumps from one part of the curve to another (the reference, by brute
    force); the blend passes across."""
    b = np.linspace(-20.0, 40.0, 121)
    source = np.stack([np.full_like(b, 20.0), np.full_like(b, 94.0), b], -1)
    surface = yb_separator.few_inks
    assert _jump(_nearest(yb, surface, source)) > 5.0                        # the rule this replaces
    assert _jump(surface.separate(source).coverages) <= 1.0


def test_mapped_colour_is_the_printed_colour_with_the_compensated_lightness(yb, yb_separator):
    rgb = np.random.default_rng(3).random((2000, 3))
    sep, source = yb_separator.separate_srgb(rgb)
    np.testing.assert_allclose(sep.target_lab, sep.printed_lab, atol=1e-12)
    np.testing.assert_allclose(sep.printed_lab, yb.lab(sep.coverages), atol=1e-9)       # the model's own colour
    np.testing.assert_allclose(yb_separator.targets(source), sep.printed_lab, atol=1e-9)
    assert not sep.out_of_gamut.any() and np.all((sep.coverages >= 0) & (sep.coverages <= 1))
    black, paper = _range(yb)
    assert yb_separator.lightness_range == pytest.approx((black, paper), abs=0.02)
    np.testing.assert_allclose(sep.printed_lab[:, 0], black + source[:, 0] * (paper - black) / 100, atol=0.01)


def test_grey_ramp_prints_a_monotone_lightness_from_the_darkest_to_paper(yb, yb_separator):
    grey = np.linspace(0, 255, 64).round().astype(np.uint8)
    result = separate_image(yb_separator, np.repeat(grey[:, None], 3, axis=1)[None])
    L = result.printed_lab[0, :, 0].astype(np.float64)
    assert np.all(np.diff(L) > 0.5), np.diff(L)                                     # 64 steps over ~90 L*
    black, paper = _range(yb)
    assert L[0] == pytest.approx(black, abs=0.02) and L[-1] == pytest.approx(paper, abs=1e-3)
    np.testing.assert_allclose(result.coverages[0, -1], 0.0, atol=1e-6)             # white: bare paper


def test_colours_on_one_ink_alone_keep_their_hue(yb, yb_separator):
    """A saturated blue nearest the B30 tints prints (almost) B30 alone, a yellow Y30 alone: the
    pair's hues where the pair has them (the blend's pull off an end, a little of the other ink,
    grows with the distance to the surface: 5 % Y30 for the blue, ΔE 78 from it)."""
    sep, _ = yb_separator.separate_srgb(np.array([[30, 60, 200], [250, 230, 20]]) / 255)
    assert sep.coverages[0, 0] < 0.06 and sep.coverages[0, 1] > 0.3                   # blue: B30
    assert sep.coverages[1, 1] < 0.02 and sep.coverages[1, 0] > 0.3                   # yellow: Y30


@pytest.mark.parametrize("lut", [0, 5])
def test_report_says_what_was_done_and_nothing_missed(yb, lut):
    separator = Separator.build(yb, lut_nodes=lut)
    rgb = np.random.default_rng(6).integers(0, 256, (20, 20, 3)).astype(np.uint8)      # 400 colours > 5³
    result = separate_image(separator, rgb)
    report, lines = result.report, result.report.lines()
    # every colour separated directly whatever lut_nodes (the table is coarse in light yellows)
    assert report.lut_nodes == 0 and report.residual_pixels == 0 and report.mapped_pixels == 0
    assert len(lines) == 2 and lines[1].startswith("two inks: colours mapped onto the surface of colours Y30 + B30"), lines
    assert not any("out of gamut" in x or "miss" in x or "black-point" in x for x in lines), lines
    assert f"mean {report.mean_de2000:.2f}, max " in lines[1] and "two inks, no black generation" in lines[0]


def test_a_33_table_interpolates_the_same_mapping(yb, yb_separator):
    rgb = np.random.default_rng(7).random((3000, 3))
    lut, nodes = SeparationLUT.build(yb_separator, 33)
    assert np.max(nodes.delta_e76) < 1e-9                                  # its nodes are exact
    direct, _ = yb_separator.separate_srgb(rgb)
    via_table = yb.lab(lut(rgb))
    error = delta_e76(via_table, direct.printed_lab)
    # the light yellows vary fastest (Y30 spans L* 90–100, b* 0–130): there the table's cells are
    # coarse, up to ΔE76 5.7; --lut 0 separates every colour exactly
    assert np.mean(error) < 0.1 and np.percentile(error, 99) < 1.0 and np.max(error) < 8.0, error.max()


def test_three_inks_keep_the_gamut_mapping():
    ryb = PrintColourModel.build(printed_inks(("R30", "Y30", "B30")), 0.9, "clapper-yule")
    separator = Separator.build(ryb)
    assert separator.few_inks is None
    rgb = np.random.default_rng(8).random((50, 3))
    sep, source = separator.separate_srgb(rgb)
    targets = map_to_gamut(source, separator.boundary, separator.gamut, ryb.measurement)
    direct = separate_lab(ryb, targets, separator.solver, separator.grid, objective=separator.objective)
    np.testing.assert_array_equal(sep.coverages, direct.coverages)


def test_inks_whose_lightness_turns_back_are_refused():
    """A pair whose L* rises again along a ray from the paper: one line naming both inks."""
    def lab(c):
        c = np.asarray(c, dtype=np.float64)
        total = c.sum(axis=-1)
        L = 100.0 - 120.0 * total + 80.0 * total ** 2
        return np.stack([L, np.zeros_like(L), -30.0 * c[..., 1]], -1)

    inks = (SimpleNamespace(meta={"ink": "W20"}), SimpleNamespace(meta={"ink": "B30"}))
    fake = SimpleNamespace(n_inks=2, lab=lab, predictor=SimpleNamespace(printed=SimpleNamespace(inks=inks)))
    with pytest.raises(DuotoneError, match=r"two inks \(W20 \+ B30\): their printed L\* does not fall") as err:
        DuotoneSurface.build(fake)
    assert "\n" not in str(err.value)
