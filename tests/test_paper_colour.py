"""Figure pieces: the colour's standard error against sampling, the Fig. 6 picture, the grid
layout, the paper's rows and columns, and the findings (as the paper states them) on
constructed cells."""

import dataclasses
import math

import numpy as np
import pytest

from conftest import diffuse_layer_table
from solver.apps.figures.fig6 import azimuth_averaged, crossed_out, figure6, plot_figure6
from solver.apps.figures.findings import _Grid, evaluate, report, t_critical
from solver.apps.figures.layout import CellGeometry, GridLayout, column_groups
from solver.apps.figures.paper_grid import FIG7_COLUMNS, FIG7_ROWS, FIG8_ROWS, parse_columns, parse_rows
from solver.apps.figures.records import CellRecord, read_csv, write_csv
from solver.colour import measurement as M
from solver.colour.cie import saturation
from solver.colour.srgb import spectra_to_srgb8
from solver.colour.table_colour import SE_COLUMNS, lab_jacobian, node_errors, propagate_se, table_colour
from solver.inks import parse_ink
from solver.table.evaluate import diffuse_brdf
from solver.table.thinfilm_tier import build_thinfilm_table


def noisy_table(seed=0):
    """A synthetic absorbing table with a diffuse lobe and made-up standard errors (two
    realizations' worth: one degree of freedom)."""
    table = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    rng = np.random.default_rng(seed)
    errors = {n: 0.004 + 0.006 * rng.random(table.Rbar.shape) for n in SE_COLUMNS}
    errors["R"] = 0.01 * table.R * (0.5 + rng.random(table.R.shape))
    return dataclasses.replace(table, errors=errors, meta=dict(table.meta, tier="full", realizations_used=2))


def sampled_lab_sd(table, measurement, correlated: bool, n=1200, seed=1):
    """Lab spread when the table's nodes are drawn with their standard errors, evaluated by the
    measurement's own code."""
    rng = np.random.default_rng(seed)
    labs = []
    names = SE_COLUMNS + ("R",)
    for _ in range(n):
        z = {k: (rng.standard_normal() * np.ones(table.column(k).shape) if correlated
                 else rng.standard_normal(table.column(k).shape)) for k in names}
        cols = {k: table.column(k) + table.errors[k] * z[k] for k in names}
        labs.append(measurement.lab_of_spectra(table.wavelengths, measurement.reflectance(table, 0.9, **cols)))
    return np.std(labs, axis=0, ddof=1)


@pytest.mark.parametrize("geometry", ["d:0", "45:0"])
@pytest.mark.parametrize("correlated", [False, True])
def test_linearised_se_matches_sampling(correlated, geometry):
    table = noisy_table()
    m = M.parse_measurement(geometry)
    errors, source, dof = node_errors(table)
    assert source == "realizations" and dof == 1
    jac = lab_jacobian(table, 0.9, m)
    se = propagate_se(jac, errors, "correlated" if correlated else "independent")
    sd = sampled_lab_sd(table, m, correlated)
    np.testing.assert_allclose(se, sd, rtol=0.1)          # 1200 samples: ≈ 2 % noise in an SD
    assert np.all(propagate_se(jac, errors) >= se - 1e-12)


def test_colour_and_its_se_by_tier():
    table = noisy_table()
    colour = table_colour(table, 0.9)
    np.testing.assert_allclose(colour.lab, M.DEFAULT.lab(table, 0.9))
    assert colour.source == "realizations" and np.all(colour.se > 0) and colour.measurement == M.DEFAULT
    film = build_thinfilm_table(parse_ink("Y7.5+B7.5"), 1000.0, np.arange(380.0, 781.0, 50.0),
                                np.linspace(0, np.pi / 2, 7))
    exact = table_colour(film, 0.9)
    assert exact.source == "exact" and np.all(exact.se == 0) and math.isinf(exact.dof)
    em = dataclasses.replace(film, meta=dict(film.meta, tier="effective-medium", errors={"model": 0.005}))
    assert table_colour(em, 0.9).source == "model deviation" and np.all(table_colour(em, 0.9).se > 0)
    one = dataclasses.replace(noisy_table(), errors={})
    assert table_colour(one, 0.9).source == "unknown" and np.all(np.isnan(table_colour(one, 0.9).se))
    # a doubled error doubles the colour's standard error (linear propagation)
    twice = dataclasses.replace(table, errors={k: 2 * v for k, v in table.errors.items()})
    np.testing.assert_allclose(table_colour(twice, 0.9).se, 2 * colour.se, rtol=1e-9)


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
    # top: the d:0 colour (diffuse light, view 0°, the mirror included); without the mirror the
    # paper's strip, its `paper` geometry
    np.testing.assert_array_equal(strip[0, 0], spectra_to_srgb8(film.wavelengths, M.parse_measurement("d:0").reflectance(film, 0.9)))
    bare, _ = figure6(film, 0.9, size=40, strip=10, mirror=False)
    np.testing.assert_array_equal(bare[0, 0], spectra_to_srgb8(film.wavelengths, M.parse_measurement("paper").reflectance(film, 0.9)))
    assert np.all(bare.astype(int).sum(-1) <= strip.astype(int).sum(-1))      # the mirror only adds light
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


def record(ink, column, s, se=0.5, L=50.0, ok=True, dof=1.0, lab_t=None):
    lab = np.array([L, s * L, 0.0]) if ok else np.full(3, np.nan)
    lab_t = np.array([70.0, 10.0, 0.0]) if lab_t is None else np.asarray(lab_t, dtype=float)
    return CellRecord("fig7", "default", ink, column, column, column, None, "preview", "full",
                      "ok" if ok else "failed", "45:0/D50/2°", lab, np.full(3, se), "realizations",
                      dof if se > 0 else math.inf, lab_t, np.full(3, se), "k", False, 0.0, "" if ok else "boom")


def test_verdicts_use_students_t_on_the_realizations():
    """Two realizations per cell (1 degree of freedom each, ≈ 2 for the difference: t = 4.3): a
    difference of 0.1 in s with SE ≈ 0.03 (3.4 SE) is undecided, the same with 30 degrees of
    freedom per cell (t ≈ 2.0) a contradiction."""
    assert t_critical(1) == pytest.approx(12.706, abs=1e-3) and t_critical(math.inf) == pytest.approx(1.960, abs=1e-3)
    for dof, verdict in ((1.0, "undecided"), (30.0, "contradicts")):
        records = [record("Y7.5+B7.5", "sphere:300", 0.3, se=1.0, dof=dof),
                   record("Y15+B15", "sphere:300", 0.2, se=1.0, dof=dof)]
        (check,) = [c for c in evaluate(records) if c.finding == 1]
        assert check.verdict == verdict and check.value == pytest.approx(-0.1)
        assert check.dof == pytest.approx(2 * dof, rel=0.1)                   # Welch–Satterthwaite: equal shares
    exact = [record("Y7.5+B7.5", "molecular", 0.3, se=0.0), record("Y15+B15", "molecular", 0.31, se=0.0)]
    (check,) = [c for c in evaluate(exact) if c.finding == 1]
    assert check.verdict == "agrees" and check.se == 0 and math.isinf(check.dof)   # exact films: any sign decides


def test_report_counts_trends_against_standard_errors(tmp_path):
    s = {"molecular": (0.5, 0.7, 0.9), "sphere:100": (0.4, 0.6, 0.61), "sphere:300": (0.3, 0.2, 0.5)}
    inks = ("Y7.5+B7.5", "Y15+B15", "Y25+B25")
    records = [record(ink, col, s[col][k], se=0.0 if col == "molecular" else 0.005, dof=30.0)
               for k, ink in enumerate(inks) for col in s]
    checks = evaluate(records)
    one = {c.where: c.verdict for c in checks if c.finding == 1}
    assert len(one) == 6
    assert one["sphere:300: Y7.5+B7.5 → Y15+B15"] == "contradicts"     # 0.3 → 0.2, SE ≈ 0.00016
    assert one["sphere:100: Y15+B15 → Y25+B25"] == "agrees"            # 0.6 → 0.61: 0.01 ≫ t·SE
    two = [c for c in checks if c.finding == 2]                          # mol > 100 > 300 per ink
    assert len(two) == 6 and all(c.verdict == "agrees" for c in two)
    sd = [c.se for c in checks if c.where == "sphere:100: Y15+B15 → Y25+B25"][0]
    expected = np.hypot(*[np.hypot(0.005 / 50, v * 0.005 / 50) for v in (0.6, 0.61)])   # linearised s = C/L
    assert sd == pytest.approx(expected, rel=0.1)
    # a failed cell makes its checks 'not testable', never silently absent
    records[-1] = record(inks[2], "sphere:300", 0.0, ok=False)
    text = report(records, "Fig. 7")
    assert "| 1. Colour saturates with concentration | 6 | 4 | 0 | 1 | 1 |" in text
    assert "- contradicts: sphere:300: Y7.5+B7.5 → Y15+B15 -0.100 ± 0.000" in text
    assert "Y25+B25 × sphere:300 (sphere:300): boom" in text and "45:0/D50/2°" in text
    # the CSV round trip keeps what the report needs
    back = read_csv(write_csv(records, tmp_path / "r.csv"))
    assert [c.verdict for c in evaluate(back)] == [c.verdict for c in evaluate(records)]
    assert saturation(back[0].lab) == pytest.approx(0.5) and back[1].se_dof == 30 and math.isinf(back[0].se_dof)


def test_no_check_compares_cells_that_are_not_a_step_of_one_series():
    """On the whole of Fig. 7: finding 2 steps are consecutive plain sizes of one shape (molecular
    first), never to an agglutinated or rough-top column; finding 4 only in Fig. 8's rows, between
    the agglutinated column's own size and the next larger; findings 3 and 5 on plain grains."""
    records = [record(r.spec, c.particles, 0.5, se=0.0) for r in FIG7_ROWS for c in FIG7_COLUMNS]
    checks = evaluate(records)
    grid = _Grid(records)
    series = grid.size_series()
    steps = {(a, b) for s in series for a, b in zip(s, s[1:])}
    assert ("molecular", "sphere:30") in steps and ("sphere:300", "sphere:450") in steps
    assert ("molecular", "cylinder:100:vertical") in steps and ("cylinder:200:inplane", "cylinder:300:inplane") in steps
    assert not any("agglutinated" in a + b or "rough" in a + b for a, b in steps)
    for c in checks:
        if c.finding == 2:
            small, big = c.where.split(": ", 1)[1].replace("mol", "molecular").split(" → ")
            assert (small, big) in steps, c.where
        if c.finding in (3, 5):
            assert "agglutinated" not in c.where and "rough" not in c.where, c.where
    four = [c for c in checks if c.finding == 4]
    fig8 = {r.spec for r in FIG8_ROWS}
    assert len(four) == len(FIG8_ROWS) and all(c.where.split(":")[0] in fig8 for c in four)
    assert all("sphere:100 ≥ agglutinated ≥ sphere:200" in c.where for c in four)
    assert {c.finding for c in checks} == set(range(1, 9))


def test_agglutinated_between_its_size_and_the_next():
    """Finding 4 agrees when s(100) > s(aggl) > s(200), contradicts when the agglutinated grains
    are less saturated than the next larger size."""
    def grid(s_aggl):
        return [record("Y15", col, v, se=0.001, dof=30.0) for col, v in
                (("sphere:100", 0.6), ("sphere:100:agglutinated", s_aggl), ("sphere:200", 0.4))]
    assert [c.verdict for c in evaluate(grid(0.5)) if c.finding == 4] == ["agrees"]
    assert [c.verdict for c in evaluate(grid(0.3)) if c.finding == 4] == ["contradicts"]
    assert [c.verdict for c in evaluate(grid(0.7)) if c.finding == 4] == ["contradicts"]


def test_shape_and_transmission_findings():
    """Finding 7: balls → isotropic cylinders of one size changes less than balls → next size;
    finding 8: at 15 % the transmitted colours of Fig. 9's grains (300 nm) and the molecular layer
    differ by > 1 ΔE2000 — smaller grains are not held to it (they tend to the molecular mix)."""
    rec = [record("R15", "sphere:100", 0.6, se=0.001, dof=30.0, lab_t=[60, 40, 0]),
           record("R15", "sphere:300", 0.3, se=0.001, dof=30.0, lab_t=[64, 30, 0]),
           record("R15", "sphere:200", 0.4, se=0.001, dof=30.0, lab_t=[62, 35, 0]),
           record("R15", "cylinder:100:isotropic", 0.58, se=0.001, dof=30.0, lab_t=[60, 40, 0]),
           record("R15", "molecular", 0.7, se=0.0, lab_t=[55, 50, 0]),
           record("R30", "molecular", 0.8, se=0.0, lab_t=[45, 55, 0])]
    checks = evaluate(rec)
    seven = [c for c in checks if c.finding == 7]
    assert [c.verdict for c in seven] == ["agrees"] and "cylinder:100:isotropic" in seven[0].where
    eight = [c for c in checks if c.finding == 8]
    assert len(eight) == 1 and eight[0].verdict == "agrees"                  # R15 only, 300 nm only
    assert eight[0].where.startswith("R15") and "300" in eight[0].where


def test_molecular_and_one_grain_size_is_a_size_step():
    """Molecular counts as size 0: a figure with one particle column still tests finding 2."""
    records = [record(ink, col, v, se=0.0 if col == "molecular" else 0.01, dof=30.0)
               for ink in ("G15", "R15") for col, v in (("molecular", 0.8), ("sphere:300", 0.4))]
    two = [c for c in evaluate(records) if c.finding == 2]
    assert len(two) == 2 and all(c.verdict == "agrees" for c in two)
