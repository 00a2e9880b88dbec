"""`ink-tables paper`: a tiny Fig. 7 (layout, CSV, cache), a failing cell, Fig. 9, bad input."""

import csv
import subprocess
import sys

import matplotlib.image
import numpy as np
import pytest

import solver.apps.figures.cells as cells_mod
from conftest import run_main
from oracles import airy_slab
from solver.apps.cli import main
from solver.apps.figures.cells import FigureSettings, across_particles, build_cells, plan_cells
from solver.apps.figures.draw import RULE_GREY
from solver.apps.figures.fig6 import crossed_out, figure6
from solver.apps.figures.layout import CellGeometry, GridLayout, grid_labels, header_rules
from solver.apps.figures.make import grid_caption, spectra_panels
from solver.apps.figures.paper_grid import TITLES, parse_columns, parse_rows
from solver.inks import molecular_eps, parse_ink
from solver.materials import DISSOLVED_FIELD, default_materials
from solver.table.builder import BuildOptions
from solver.table.cache import TableCache
from solver.table.schema import read_table

TINY = ["--wavelengths", "400:700:150", "--angles", "3", "--grid", "16", "16", "8", "--realizations", "2",
        "--azimuths", "1", "--tier", "full", "--workers", "1", "--no-progress"]
ROWS, COLUMNS = "Y7.5+B7.5", "molecular,sphere:300,sphere:300:rough"


def read_png(path) -> np.ndarray:
    return np.round(matplotlib.image.imread(path)[..., :3] * 255).astype(int)


def read_rows(path) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def overridden(base, extra) -> list:
    """The options of `base` that `extra` does not give, then `extra` (an option given twice is
    refused; every value after an option up to the next option is its own)."""
    groups, given = [], {a for a in extra if str(a).startswith("--")}
    for arg in base:
        if str(arg).startswith("--") or not groups:
            groups.append([arg])
        else:
            groups[-1].append(arg)
    return [a for g in groups if g[0] not in given for a in g] + list(extra)


def run_fig7(tmp_path, out_name="f.png", extra=(), status=0):
    out = tmp_path / out_name
    code = main(["paper", "fig7", "-o", str(out),
                 *overridden(["--rows", ROWS, "--columns", COLUMNS, "--cache", str(tmp_path / "cache"), *TINY],
                             extra)])
    assert code == status
    return out


def layout_of(n_rows, n_cols, has_sub=True, argv=()):
    return GridLayout(n_rows, n_cols, CellGeometry(), has_sub, grid_caption(settings_of([*TINY, *argv])))


def settings_of(argv):
    """The FigureSettings the paper command makes of these options."""
    from solver.apps.cli import make_parser
    from solver.apps.cli.paper import settings_from_args

    return settings_from_args(make_parser().parse_args(["paper", "fig7", "-o", "x.png", *argv]))


def test_the_papers_model_one_option_away(tmp_path):
    """--model paper: TE tables with bulk pigment ε, colour measured in the paper's strip
    geometry (no coherent mirror), strips drawn without the mirror; --geometry overrides."""
    out = run_fig7(tmp_path, extra=["--model", "paper", "--columns", "molecular,sphere:300"])
    rows = read_rows(out.with_suffix(".csv"))
    assert {r["model"] for r in rows} == {"paper"} and {r["measurement"] for r in rows} == {"paper/D50/2°"}
    tables = [read_table(tmp_path / "cache" / "tables" / f"{r['cache_key']}.npz") for r in rows]
    assert all(t.meta["polarisation"] == "te" and not t.meta["local_field"] for t in tables)
    from solver.colour import measurement as M
    np.testing.assert_allclose([float(rows[0][k]) for k in "Lab"], M.parse_measurement("paper").lab(tables[0], 0.9),
                               atol=1e-3)
    settings = settings_of([*TINY, "--model", "paper"])
    assert not settings.model.mirror_in_strip and "without the layer's mirror" in grid_caption(settings)
    image, layout = read_png(out), layout_of(1, 2, argv=["--model", "paper"])
    strip, _ = figure6(tables[0], 0.9, size=layout.geometry.square, strip=layout.geometry.strip, mirror=False)
    x0, y0, x1, y1 = layout.strip_box(0, 0)
    np.testing.assert_array_equal(image[y0:y1, x0:x1], strip)
    again = run_fig7(tmp_path, "g.png", extra=["--model", "paper", "--columns", "molecular", "--geometry", "d:8:sce",
                                                "--illuminant", "D65"])
    assert read_rows(again.with_suffix(".csv"))[0]["measurement"] == "d:8:sce/D65/2°"


@pytest.mark.parametrize("argv, message", [
    (["--geometry", "45/0"], "--geometry: geometry '45/0': choose one of 45:0, d:8:sci, d:8:sce, d:0, paper"),
    (["--illuminant", "F2"], "--illuminant: illuminant 'F2': choose one of D50, D65"),
    (["--observer", "4"], "--observer: observer '4': choose one of 2°, 10°"),
    (["--wavelengths", "450:650:100"], "wavelengths 450–650 nm; a colour needs at least 400–700 nm"),
])
def test_measurement_refused_before_any_work(tmp_path, capsys, argv, message):
    code = main(["paper", "fig7", "-o", str(tmp_path / "f.png"),
                 *overridden(["--rows", ROWS, "--columns", "molecular,sphere:300", "--cache", str(tmp_path / "cache"),
                              *TINY], argv)])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1
    assert not (tmp_path / "cache" / "tables").exists() or not any((tmp_path / "cache" / "tables").iterdir())


def test_tiny_fig7_layout_csv_and_cache_hits(tmp_path, monkeypatch):
    out = run_fig7(tmp_path, extra=["--report", str(tmp_path / "f.md")])
    image = read_png(out)
    layout = layout_of(1, 3)          # sphere:300 has the sub-label 'normal'
    assert image.shape[1::-1] == layout.size

    rows = read_rows(out.with_suffix(".csv"))
    assert [(r["ink"], r["column"]) for r in rows] == [("Y7.5+B7.5", "molecular"), ("Y7.5+B7.5", "sphere:300"),
                                                       ("Y7.5+B7.5", "sphere:300:rough")]
    cache = tmp_path / "cache" / "tables"
    tables = []
    for r in rows:
        assert r["status"] == "ok" and r["computed"] == "yes" and r["reason"] == ""
        lab = [float(r[k]) for k in ("L", "a", "b")]
        se = [float(r[k]) for k in ("L_se", "a_se", "b_se")]
        assert np.all(np.isfinite(lab)) and np.all(np.isfinite(se)) and 0 < lab[0] < 100
        table = read_table(cache / f"{r['cache_key']}.npz")
        assert table.meta["cache_key"] == r["cache_key"]
        tables.append(table)
    assert rows[0]["se_source"] == "exact" and all(float(rows[0][k]) == 0 for k in ("L_se", "a_se", "b_se"))
    assert rows[1]["se_source"] == "realizations" and float(rows[1]["L_se"]) > 0
    assert rows[0]["se_method"] == "exact" and rows[1]["se_method"] == "jackknife"       # a wave table's replicas
    assert rows[2]["particles"] == "sphere:300:rough=0.5" and rows[2]["grains"] == "Balls 300 nm rough surface"
    assert rows[1]["tier"] == "full" and "grid=16x16x8" in rows[1]["accuracy"]
    assert {r["model"] for r in rows} == {"default"} and {r["measurement"] for r in rows} == {"45:0/D50/2°"}
    assert all(tables[k].meta["polarisation"] == "unpolarised" and tables[k].meta["local_field"] for k in range(3))
    assert all(np.isfinite(float(r["T_L"])) for r in rows) and rows[0]["se_dof"] == "inf" and rows[1]["se_dof"] == "1"

    # each cell holds the Fig. 6 picture of its table, pixel for pixel
    g = layout.geometry
    for j, table in enumerate(tables):
        strip, square = figure6(table, 0.9, size=g.square, strip=g.strip)
        for picture, (x0, y0, x1, y1) in ((strip, layout.strip_box(0, j)), (square, layout.square_box(0, j))):
            np.testing.assert_array_equal(image[y0:y1, x0:x1], picture)

    # every mark outside the cells is a label inside its box, and every label left a mark
    groups = ["infinitesimal particles", "Balls 300 nm", "Balls 300 nm"]
    labels = grid_labels(layout, ["Y7.5% + B7.5%"], groups, ["", "normal", "rough surface"],
                         TITLES["fig7"], grid_caption(settings_of(TINY)))
    (rx0, ry0, rx1, ry1), = header_rules(layout, groups)           # one group spans two columns
    assert rx0 > layout.cell_box(0, 1)[0] and rx1 < layout.cell_box(0, 2)[2]
    assert np.all(image[ry0:ry1, rx0:rx1] == RULE_GREY)
    ink = np.any(image < 200, axis=2)
    for i, j in ((0, 0), (0, 1), (0, 2)):
        x0, y0, x1, y1 = layout.cell_box(i, j)
        ink[y0:y1, x0:x1] = False
    inside = np.zeros_like(ink)
    for label in labels:
        x0, y0, x1, y1 = label.box
        assert ink[y0:y1, x0:x1].any(), f"label {label.text!r} not drawn in its box"
        inside[y0:y1, x0:x1] = True
    assert not (ink & ~inside).any(), "text drawn outside the label boxes"
    assert "| 1. Colour saturates" in (tmp_path / "f.md").read_text()

    # again: everything from the cache, nothing computed
    import solver.table.builder as builder
    import solver.table.wave_tier as wt

    def boom(*a, **k):
        raise AssertionError("computed on a cache hit")

    for module, name in ((builder, "build_table"), (wt, "solve_unit"), (wt, "geometry_unit")):
        monkeypatch.setattr(module, name, boom)
    again = run_fig7(tmp_path, "g.png")
    rows2 = read_rows(again.with_suffix(".csv"))
    assert [r["computed"] for r in rows2] == ["no"] * 3 and all(r["status"] == "ok" for r in rows2)
    assert [r["cache_key"] for r in rows2] == [r["cache_key"] for r in rows]
    np.testing.assert_array_equal(read_png(again), image)


@pytest.fixture()
def particle_tables_fail(monkeypatch):
    """Every particle table's build raises (molecular ones build as usual)."""
    real = cells_mod.get_or_build

    def flaky(request, opts):
        if not request.molecular:
            raise RuntimeError("solver diverged\nat λ = 450 nm")
        return real(request, opts)

    monkeypatch.setattr(cells_mod, "get_or_build", flaky)


def test_failing_cell_is_crossed_out_not_dropped(tmp_path, particle_tables_fail, capsys):
    out = run_fig7(tmp_path, status=1)                      # drawn, and the run says it failed
    rows = read_rows(out.with_suffix(".csv"))
    assert [r["status"] for r in rows] == ["ok", "failed", "failed"]
    assert rows[1]["reason"] == "RuntimeError: solver diverged at λ = 450 nm"
    assert rows[1]["L"] == "" and rows[1]["cache_key"]          # the request's key, for a rerun
    layout = layout_of(1, 3)
    for j in (1, 2):
        x0, y0, x1, y1 = layout.cell_box(0, j)
        np.testing.assert_array_equal(read_png(out)[y0:y1, x0:x1], crossed_out(y1 - y0, x1 - x0))
    assert "2 failed" in capsys.readouterr().out


def test_a_table_that_cannot_be_drawn_fails_its_cell_only(tmp_path, monkeypatch):
    import solver.apps.figures.make as make

    real = make.figure6

    def picky(table, *a, **k):
        if table.meta["ink"] == "Y15":
            raise FloatingPointError("NaN in the square")
        return real(table, *a, **k)

    monkeypatch.setattr(make, "figure6", picky)
    out = tmp_path / "m.png"
    assert main(["paper", "fig8", "--rows", "R15,Y15", "--columns", "molecular", "--no-progress",
                 "--cache", str(tmp_path / "cache"), "-o", str(out)]) == 1
    rows = read_rows(out.with_suffix(".csv"))
    assert [r["status"] for r in rows] == ["ok", "failed"]
    assert rows[1]["reason"] == "evaluating the table: FloatingPointError: NaN in the square"
    layout = GridLayout(2, 1, CellGeometry(), has_sub=False, caption_text=grid_caption(FigureSettings()))
    x0, y0, x1, y1 = layout.cell_box(1, 0)
    np.testing.assert_array_equal(read_png(out)[y0:y1, x0:x1], crossed_out(y1 - y0, x1 - x0))


def test_across_cylinders_use_the_smallest_reaching_tilt(tmp_path, monkeypatch):
    import solver.geometry as geometry

    seen = []

    def smallest(layer, tilts):
        seen.append((layer.ink.label, layer.particles.label, tuple(tilts)))
        return {0.15: 0.0, 0.5: 15.0}.get(round(layer.ink.total_fraction, 2))

    monkeypatch.setattr(geometry, "smallest_tilt_reaching", smallest, raising=False)
    settings = FigureSettings("preview")
    column = parse_columns("cylinder:300:vertical", "fig7")[0]
    assert column.across and column.sub == "vertically aligned"
    assert across_particles(parse_rows("R15", "fig7")[0], column, settings) == ("cylinder:300:vertical", 0.0)
    assert across_particles(parse_rows("R50", "fig7")[0], column, settings) == ("cylinder:300:vertical:tilt=15", 15.0)
    assert seen[0][:2] == ("R15", "cylinder:300:vertical") and 0.0 in seen[0][2]
    # no spread reaches it: the cell is planned as failed (drawn, with the reason), not skipped
    plans = plan_cells(parse_rows("R30", "fig7"), (column,), settings)
    assert len(plans) == 1 and plans[0].request is None and "cannot hold R30" in plans[0].error
    opts = BuildOptions(workers=1, progress=False, cache=TableCache(tmp_path / "cache"))
    results = build_cells(plans, opts, [0.0], progress=False)
    assert not results[0].ok and results[0].error == plans[0].error


def film_transmittance(ink: str, wl_nm: np.ndarray, thickness_nm: float = 1000.0) -> np.ndarray:
    """Airy transmittance of an absorbing slab in air at normal incidence (oracles.airy_slab); the
    figures' tables are unpolarised, so dissolved pigment has its molecules' local field."""
    n = np.sqrt(molecular_eps(parse_ink(ink), wl_nm, default_materials().with_local_field(DISSOLVED_FIELD)))
    return airy_slab(1.0, n, 1.0, thickness_nm, wl_nm, 0.0)[3]


def test_fig9_molecular_curves_are_the_film_transmittance(tmp_path):
    rows, columns = parse_rows("G15,G30,R15", "fig9"), parse_columns("molecular", "fig9")
    opts = BuildOptions(workers=1, progress=False, cache=TableCache(tmp_path / "cache"))
    plans = plan_cells(rows, columns, FigureSettings("preview"))
    panels = spectra_panels(rows, columns, build_cells(plans, opts, [0.0] * len(plans), progress=False))
    assert [p.title for p in panels] == ["Fig. 9.1. green pigment", "Fig. 9.2. red pigment"]
    assert [len(p.curves) for p in panels] == [2, 1]
    for curve, ink in zip(panels[0].curves + panels[1].curves, ("G15", "G30", "R15")):
        assert curve.label == f"{ink}%, molecular"
        np.testing.assert_allclose(curve.value, film_transmittance(ink, curve.wavelengths_nm), atol=1e-9)
        np.testing.assert_array_equal(curve.se, 0.0)       # exact film
    g15, g30 = panels[0].curves[0].value, panels[0].curves[1].value
    assert np.all(g30 < g15)                               # more pigment, less light through
    out = tmp_path / "f9.png"
    assert main(["paper", "fig9", "--rows", "G15,R15", "--columns", "molecular", "--no-progress",
                 "--cache", str(tmp_path / "cache"), "-o", str(out)]) == 0
    assert read_png(out).shape[0] > 300 and len(read_rows(out.with_suffix(".csv"))) == 2
    # the plotted curves as numbers: one line per (curve, λ), the same values as the panels
    with open(tmp_path / "f9_spectra.csv", newline="") as fh:
        lines = list(csv.DictReader(fh))
    g15 = [r for r in lines if r["curve"] == "G15%, molecular"]
    assert len(lines) == 2 * len(g15) and len(g15) > 2 and {r["Tbar_se"] for r in g15} == {"0.000000"}
    wl = np.array([float(r["wavelength_nm"]) for r in g15])
    np.testing.assert_allclose([float(r["Tbar"]) for r in g15], film_transmittance("G15", wl), atol=1e-6)


@pytest.mark.parametrize("args, words", [
    (["--rows", "Q5"], "unknown pigment 'Q'"),
    (["--columns", "sphere:-3"], "negative particle size"),
    (["--columns", "sphere:100,sphere:100.0"], "given twice"),
    (["--grid", "2", "2", "2"], "--grid"),
    (["--grid", "4096", "4096", "2048"], "cannot fit this machine, refused before starting"),
    (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "exclude each other"),
])
def test_bad_input_is_one_line_before_any_work(tmp_path, capsys, args, words):
    status, _, err = run_main(main, ["paper", "fig8", "--cache", tmp_path / "c", "-o", tmp_path / "x.png", *args],
                              capsys)
    assert status == 2, err
    assert words in err and err.count("\n") == 1, err
    assert not (tmp_path / "c" / "tables").exists() or not any((tmp_path / "c" / "tables").iterdir())


def test_output_must_be_a_png(tmp_path):
    """As the installed command: exit 2, one line."""
    res = subprocess.run([sys.executable, "-m", "solver.apps.cli", "paper", "fig9", "-o", str(tmp_path / "x.jpg")],
                         capture_output=True, text=True)
    assert res.returncode == 2 and ".png" in res.stderr and res.stderr.count("\n") == 1, res.stderr


def test_unreachable_across_cell_says_why():
    """300-nm cylinders across a 1000-nm layer stand one per column (545 nm long): hexagonal
    packing caps them below 50 %, so the R50 cell is planned as failed, with the numbers."""
    column = parse_columns("cylinder:300:vertical", "fig7")[0]
    plans = plan_cells(parse_rows("R50,R30", "fig7"), (column,), FigureSettings("preview"))
    assert plans[0].request is None and "49.4 %" in plans[0].error and "packer reaches" in plans[0].error
    assert plans[1].request is not None


def test_a_cell_that_fails_to_build_makes_the_run_fail(tmp_path, particle_tables_fail, capsys):
    """Cells that cannot exist are part of a complete figure (exit 0); a table that failed to
    build is a failed run (exit 1), after drawing what it could."""
    out = tmp_path / "f9.png"
    status, _, _ = run_main(main, ["paper", "fig9", "--rows", "G15", "--columns", "molecular,sphere:300",
                                   "--no-progress", "--cache", tmp_path / "cache", "-o", out], capsys)
    assert status == 1 and out.exists()


def test_every_cell_of_a_figure_is_sampled_alike():
    """The molecular column is computed on the particle preset's wavelengths and angles, so a
    molecular-vs-grain step is never a step in spectral sampling (a 30-nm effective-medium cell
    of a single pigment is then the molecular film itself)."""
    for accuracy in ("preview", "default"):
        settings = FigureSettings(accuracy)
        mol, grains = settings.request("Y15", "molecular"), settings.request("Y15", "sphere:100")
        assert mol.molecular and mol.grids.wavelengths_nm == grains.grids.wavelengths_nm
        assert mol.grids.sigma_rad == grains.grids.sigma_rad
    drafted = FigureSettings("preview", (("wavelengths_nm", (400.0, 550.0, 700.0)),))
    assert drafted.request("Y15", "molecular").grids.wavelengths_nm == (400.0, 550.0, 700.0)


def test_a_figures_tables_stop_where_its_colour_does(tmp_path):
    """A figure's tables are only measured as colours (400–700 nm): they stop at 700 nm, so the
    solves past it (740, 780 nm at `default`) are not computed — and what is computed is the
    rendering table's own: identical values at the shared wavelengths, the same colour (E308
    extends the 700-nm value; the weights beyond it are ≈ 1e-3 of the total)."""
    from solver.colour.cie import REQUIRED_RANGE_NM
    from solver.colour.table_colour import table_colour
    from solver.paper import PAPER_ALBEDO
    from solver.table.builder import BuildOptions, build_table
    from solver.table.cache import TableCache
    from solver.table.request import default_grids, table_request

    for accuracy in ("preview", "default", "fine"):
        figure = FigureSettings(accuracy).request("R15", "sphere:200")
        full = default_grids(accuracy, molecular=False)[0]
        assert figure.grids.wavelengths_nm == tuple(w for w in full if w <= REQUIRED_RANGE_NM[1])
        assert figure.grids.wavelengths_nm[-1] == REQUIRED_RANGE_NM[1]
        solved = [figure.grids.wavelengths_nm[i] for i in figure.solved_wavelength_indices]
        assert solved[-1] == REQUIRED_RANGE_NM[1] and len(solved) < len(table_request(
            "R15", "sphere:200", accuracy=accuracy).solved_wavelength_indices)
    wave = (("grid", (12, 12, 6)), ("realizations", 2), ("tier", "full"))
    settings = FigureSettings("preview", wave)
    figure = settings.request("R15", "sphere:200")
    rendering = table_request("R15", "sphere:200", accuracy="preview", sigma_rad=figure.grids.sigma_rad, **dict(wave))
    assert rendering.grids.wavelengths_nm[-1] == 780.0
    opts = BuildOptions(workers=1, progress=False, cache=TableCache(tmp_path))
    a, b = build_table(rendering, opts), build_table(figure, opts)
    n = b.wavelengths.size
    for name in ("R", "R_spec", "Rbar", "Tbar", "Rbar_below"):
        assert np.allclose(getattr(a, name)[:n], getattr(b, name), rtol=0, atol=1e-12), name   # rounding only
    lab_a = table_colour(a, PAPER_ALBEDO, settings.colour_measurement).lab
    lab_b = table_colour(b, PAPER_ALBEDO, settings.colour_measurement).lab
    assert np.max(np.abs(lab_a - lab_b)) < 0.05
