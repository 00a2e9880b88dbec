"""Figure pieces: the colour's standard error against sampling, the Fig. 6 picture, the grid
layout, the paper's rows and columns, and the findings report on constructed cells."""

import dataclasses

import numpy as np
import pytest

from conftest import diffuse_layer_table
from solver.apps.figures.cell_colour import (SE_COLUMNS, cell_colour, cell_lab, lab_jacobian, node_errors,
                                        propagate_se, saturation, spectrum_lab)
from solver.apps.figures.fig6 import azimuth_averaged, crossed_out, figure6, plot_figure6
from solver.apps.figures.findings import evaluate, report
from solver.apps.figures.layout import CellGeometry, GridLayout, column_groups
from solver.apps.figures.paper_grid import FIG7_COLUMNS, FIG7_ROWS, FIG8_ROWS, parse_columns, parse_rows
from solver.apps.figures.records import CellRecord, read_csv, write_csv
from solver.inks import parse_ink
from solver.table.evaluate import diffuse_brdf, directional_albedo
from solver.table.thinfilm_tier import build_thinfilm_table


def noisy_table(seed=0):
    """A synthetic absorbing table with a diffuse lobe and made-up standard errors."""
    table = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    rng = np.random.default_rng(seed)
    errors = {n: 0.004 + 0.006 * rng.random(table.Rbar.shape) for n in SE_COLUMNS}
    return dataclasses.replace(table, errors=errors, meta=dict(table.meta, tier="full"))


def sampled_lab_sd(table, correlated: bool, n=3000, seed=1):
    """Lab spread when the table's nodes are drawn with their standard errors, evaluated by the
    table's own BRDF code (Rbar's error carried by R_spec: Rbar = R_spec + ∫R)."""
    rng = np.random.default_rng(seed)
    labs = []
    shape = table.Rbar.shape
    for _ in range(n):
        z = {k: (rng.standard_normal() * np.ones(shape) if correlated else rng.standard_normal(shape))
             for k in SE_COLUMNS}
        t = dataclasses.replace(table, R_spec=table.R_spec + table.errors["Rbar"] * z["Rbar"],
                                Tbar=table.Tbar + table.errors["Tbar"] * z["Tbar"],
                                Rbar_below=table.Rbar_below + table.errors["Rbar_below"] * z["Rbar_below"])
        labs.append(spectrum_lab(t.wavelengths, directional_albedo(t, 0.9, 0.0)))
    return np.std(labs, axis=0, ddof=1)


@pytest.mark.parametrize("correlated", [False, True])
def test_linearised_se_matches_sampling(correlated):
    table = noisy_table()
    errors, source = node_errors(table)
    assert source == "realizations"
    se = propagate_se(lab_jacobian(table), errors, "correlated" if correlated else "independent")
    sd = sampled_lab_sd(table, correlated)
    np.testing.assert_allclose(se, sd, rtol=0.08)         # 3000 samples: ≈ 1.3 % noise in an SD
    larger = propagate_se(lab_jacobian(table), errors)
    assert np.all(larger >= se - 1e-12)


def test_colour_and_its_se_by_tier():
    table = noisy_table()
    colour = cell_colour(table)
    np.testing.assert_allclose(colour.lab, cell_lab(table))
    assert colour.source == "realizations" and np.all(colour.se > 0)
    film = build_thinfilm_table(parse_ink("Y7.5+B7.5"), 1000.0, np.arange(400.0, 701.0, 50.0),
                                np.linspace(0, np.pi / 2, 7))
    exact = cell_colour(film)
    assert exact.source == "exact" and np.all(exact.se == 0)
    em = dataclasses.replace(film, meta=dict(film.meta, tier="effective-medium", errors={"model": 0.005}))
    assert cell_colour(em).source == "model deviation" and np.all(cell_colour(em).se > 0)
    one = dataclasses.replace(noisy_table(), errors={})
    assert cell_colour(one).source == "unknown" and np.all(np.isnan(cell_colour(one).se))
    # a doubled error doubles the colour's standard error (linear propagation)
    twice = dataclasses.replace(table, errors={k: 2 * v for k, v in table.errors.items()})
    np.testing.assert_allclose(cell_colour(twice).se, 2 * colour.se, rtol=1e-9)


def test_azimuth_average_in_one_evaluation():
    table = diffuse_layer_table(lossless=False)
    dphi = np.linspace(0.0, np.pi, 9)
    light, view = np.radians(np.linspace(0, 60, 7))[None, :], np.radians(np.linspace(0, 60, 5))[:, None]
    loop = np.mean([diffuse_brdf(table, 0.9, light, view, p) for p in dphi], axis=0)
    averaged = azimuth_averaged(table, dphi)
    for p in (0.0, 1.0, np.pi):
        np.testing.assert_allclose(diffuse_brdf(averaged, 0.9, light, view, p), loop, rtol=1e-12, atol=1e-15)
    assert np.ptp(loop) > 0 and not np.allclose(diffuse_brdf(table, 0.9, light, view, 0.0), loop)


def test_figure6_arrays_and_picture(tmp_path):
    film = build_thinfilm_table(parse_ink("R15"), 1000.0, np.arange(380.0, 781.0, 20.0), np.linspace(0, np.pi / 2, 19))
    strip, square = figure6(film, 0.9, size=40, strip=10)
    assert strip.shape == (40, 10, 3) and square.shape == (40, 40, 3) and strip.dtype == np.uint8
    assert np.all(strip == strip[:, :1])                         # one colour per view angle
    np.testing.assert_array_equal(strip[0, 0], cell_colour(film).srgb8)   # top = the CSV colour (0° view)
    # a film has no diffuse lobe: the square is the paper term, symmetric in light ↔ view
    np.testing.assert_array_equal(square, square.transpose(1, 0, 2))
    assert square[0, 0, 0] > square[0, 0, 2]                     # red ink: red above blue
    x = crossed_out(20, 30)
    assert tuple(x[0, 0]) == (200, 30, 30) and tuple(x[19, 29]) == (200, 30, 30) and tuple(x[0, 15]) == (235,) * 3
    png = tmp_path / "f6.png"
    plot_figure6(film, png)
    import matplotlib.image
    image = matplotlib.image.imread(png)
    assert image.shape[0] > 256 and image.shape[1] > 256 + 64    # axes and caption around the picture


def test_layout_follows_rows_and_columns():
    g = CellGeometry()
    for n_rows, n_cols, sub in ((1, 1, False), (3, 5, True), (21, 17, True)):
        lay = GridLayout(n_rows, n_cols, g, sub)
        width, height = lay.size
        assert width == g.margin + g.row_label + n_cols * (g.width + g.pad) + g.margin
        assert height == g.title + g.group_header + (g.sub_header if sub else 0) + n_rows * (g.square + g.pad) + g.caption
        boxes = [lay.cell_box(i, j) for i in range(n_rows) for j in range(n_cols)]
        for k, (x0, y0, x1, y1) in enumerate(boxes):
            assert 0 <= x0 < x1 <= width and lay.cells_top <= y0 < y1 <= height - g.caption
            for (u0, v0, u1, v1) in boxes[k + 1:]:
                assert x1 <= u0 or u1 <= x0 or y1 <= v0 or v1 <= y0          # no overlap
        for i in range(n_rows):
            _, r0, r1x, r1 = lay.row_label_box(i)
            _, c0, _, c1 = lay.cell_box(i, 0)
            assert r0 <= c0 and c1 <= r1 and r1x <= lay.cell_box(i, 0)[0]   # label beside its row
        for j in range(n_cols):
            hx0, _, hx1, hy1 = lay.columns_box(j, 1, sub=sub)
            cx0, cy0, cx1, _ = lay.cell_box(0, j)
            assert hx0 <= cx0 and cx1 <= hx1 + g.pad and hy1 <= cy0          # header above its column
    assert column_groups(["a", "b", "b", "c", "b"]) == [("a", 0, 1), ("b", 1, 2), ("c", 3, 1), ("b", 4, 1)]


def test_the_papers_rows_and_columns():
    assert len(FIG7_ROWS) == 21 and len(FIG7_COLUMNS) == 17 and FIG8_ROWS == FIG7_ROWS[:14]
    totals = [round(r.ink.total_fraction, 6) for r in FIG7_ROWS]
    assert totals == [0.15] * 7 + [0.3] * 7 + [0.5] * 7                  # every row of a block: same total
    assert [r.label for r in FIG7_ROWS[:6]] == ["R15%", "Y15%", "Y12.5% + B2.5%", "Y7.5% + B7.5%", "G15%",
                                                "Y2.5% + B12.5%"]
    across = [c.particles for c in FIG7_COLUMNS if c.across]
    assert across == ["cylinder:100:vertical", "cylinder:200:vertical", "cylinder:300:vertical"]
    # the paper's labels survive --columns; others are labelled in its style
    cols = parse_columns("sphere:100:agglutinated,cylinder:200:inplane,sphere:250", "fig8")
    assert [(c.group, c.sub) for c in cols] == [("100 nm Aggl.", ""), ("cylinders D_eff = 200 nm", "horiz aligned"),
                                               ("Balls 250 nm", "")]
    assert [r.spec for r in parse_rows("R15, Y7.5+B7.5", "fig7")] == ["R15", "Y7.5+B7.5"]


def record(ink, column, s, se=0.5, L=50.0, ok=True):
    lab = np.array([L, s * L, 0.0]) if ok else np.full(3, np.nan)
    return CellRecord("fig7", ink, column, column, column, None, "preview", "full", "ok" if ok else "failed",
                      lab, np.full(3, se), "realizations", "k", False, 0.0, "" if ok else "boom")


def test_report_counts_trends_against_standard_errors(tmp_path):
    s = {"molecular": (0.5, 0.7, 0.9), "sphere:100": (0.4, 0.6, 0.61), "sphere:300": (0.3, 0.2, 0.5)}
    inks = ("Y7.5+B7.5", "Y15+B15", "Y25+B25")
    records = [record(ink, col, s[col][k], se=0.0 if col == "molecular" else 0.5)
               for k, ink in enumerate(inks) for col in s]
    checks = evaluate(records)
    one = {c.where: c.verdict for c in checks if c.finding == 1}
    assert len(one) == 6
    assert one["sphere:300: Y7.5+B7.5 → Y15+B15"] == "contradicts"     # 0.3 → 0.2, SE ≈ 0.016
    assert one["sphere:100: Y15+B15 → Y25+B25"] == "not resolved"      # 0.6 → 0.61: within 2 SE
    assert sorted(one.values()).count("agrees") == 4
    two = [c for c in checks if c.finding == 2]                          # mol < 100 < 300 per ink
    assert len(two) == 6 and all(c.verdict == "agrees" for c in two)
    sd = [c.se for c in checks if c.where == "sphere:100: Y15+B15 → Y25+B25"][0]
    expected = np.hypot(*[np.hypot(0.5 / 50, v * 0.5 / 50) for v in (0.6, 0.61)])   # linearised s = C/L
    assert sd == pytest.approx(expected, rel=0.1)
    # a failed cell makes its checks 'not testable', never silently absent
    records[-1] = record(inks[2], "sphere:300", 0.0, ok=False)
    text = report(records, "Fig. 7")
    assert "| 1. Colour saturates with concentration | 6 | 3 | 1 | 1 | 0 | 1 |" in text
    assert "- contradicts: sphere:300: Y7.5+B7.5 → Y15+B15 -0.100 ± 0.0" in text
    assert "Y25+B25 × sphere:300 (sphere:300): boom" in text
    # the CSV round trip keeps what the report needs
    back = read_csv(write_csv(records, tmp_path / "r.csv"))
    assert [c.verdict for c in evaluate(back)] == [c.verdict for c in evaluate(records)]
    assert saturation(back[0].lab) == pytest.approx(0.5)


def test_molecular_and_one_grain_size_is_a_size_step():
    """Molecular counts as size 0: a figure with one particle column still tests finding 2."""
    records = [record(ink, col, v, se=0.0 if col == "molecular" else 0.01)
               for ink in ("G15", "R15") for col, v in (("molecular", 0.8), ("sphere:300", 0.4))]
    two = [c for c in evaluate(records) if c.finding == 2]
    assert len(two) == 2 and all(c.verdict == "agrees" for c in two)
