"""Make one of the paper's figures: plan the cells, build their tables (cached), draw, write the
CSV and, on request, the findings report.

    records = make_figure("fig7", rows, columns, FigureSettings("preview"), BuildOptions(), "fig7.png")
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass
from pathlib import Path

from solver.colour.table_colour import node_errors, table_colour
from solver.paper import PAPER_ALBEDO
from solver.table.builder import BuildOptions, pooled
from solver.table.preflight import duration
from . import findings
from .cells import (CellResult, FigureSettings, build_cells, estimates, failure_reason, plan_cells,
                    refuse_what_cannot_fit)
from .draw import Curve, Panel, compose, draw_grid, draw_spectra
from .fig6 import crossed_out, figure6
from .layout import CellGeometry, GridLayout, grid_labels, header_rules
from .paper_grid import TITLES
from .records import CellRecord, plural, record_of, run_counts, write_csv

log = logging.getLogger("inkbsdf.figures")

GRID_FIGURES = ("fig7", "fig8")


@dataclass(frozen=True)
class FigureOutput:
    png: Path
    csv: Path
    report: Path | None
    records: list[CellRecord]
    spectra: Path | None = None          # Fig. 9: the plotted curves, one line per (curve, λ)


def grid_caption(settings: FigureSettings) -> str:
    mirror = "with" if settings.model.mirror_in_strip else "without"
    return (f"Ink layer on paper (white Lambertian, albedo {PAPER_ALBEDO:g}); {settings.caption}. Each cell: strip = "
            f"diffuse light, view 0° (top) to 60° (bottom), {mirror} the layer's mirror; square = parallel beam, "
            "light 0–60° (x) × view 0–60° (y). Crossed out: failed (reason in the CSV).")


def evaluate_cells(results: list[CellResult], geometry: CellGeometry | None, settings: FigureSettings):
    """Each cell's colour (the CSV) and, for a grid, its Fig. 6 picture; a table that cannot be
    evaluated makes its cell failed (crossed out, with the reason), never a crash after the builds.

    Returns (results, colours, pictures), keyed by (i, j) where dicts."""
    out, colours, pictures = [], {}, {}
    for res in results:
        key = (res.plan.i, res.plan.j)
        if res.ok:
            try:
                colours[key] = table_colour(res.table, PAPER_ALBEDO, settings.colour_measurement)
                if geometry is not None:
                    pictures[key] = figure6(res.table, PAPER_ALBEDO, size=geometry.square, strip=geometry.strip,
                                            mirror=settings.model.mirror_in_strip)
            except Exception as exc:           # noqa: BLE001 — recorded and drawn, never dropped
                colours.pop(key, None)
                res = dataclasses.replace(res, table=None, error=f"evaluating the table: {failure_reason(exc)}")
        if not res.ok and geometry is not None:
            pictures[key] = crossed_out(geometry.square, geometry.width)
        out.append(res)
    return out, colours, pictures


def draw_grid_figure(figure: str, rows, columns, pictures: dict, settings: FigureSettings, path,
                     geometry: CellGeometry | None = None) -> GridLayout:
    """Fig. 7 / Fig. 8: each cell the Fig. 6 picture of its table, laid out as in the paper."""
    caption = grid_caption(settings)
    layout = GridLayout(len(rows), len(columns), geometry or CellGeometry(), has_sub=any(c.sub for c in columns),
                        caption_text=caption)
    labels = grid_labels(layout, [r.label for r in rows], [c.group for c in columns], [c.sub for c in columns],
                         TITLES.get(figure, figure), caption)
    draw_grid(compose(layout, pictures, header_rules(layout, [c.group for c in columns])), labels, path)
    return layout


def _pigment_key(row) -> str:
    return "+".join(code for code, _ in row.ink.components)


_PIGMENT_NAMES = {"G": "green", "B": "blue", "Y": "yellow", "R": "red"}
_LINESTYLES = ("-", "--", ":", "-.")


def _normal_se(table, name: str):
    """Standard error of a column at normal incidence (σ = 0 is the first node); None: unknown."""
    errors, _, _ = node_errors(table)
    return None if errors is None else errors[name][:, 0]


def spectra_panels(rows, columns, results: list[CellResult]) -> list[Panel]:
    """Fig. 9: one panel per pigment (rows grouped by their pigments), Tbar at σ = 0 of each cell."""
    import matplotlib

    groups: dict[str, list[int]] = {}
    for i, row in enumerate(rows):
        groups.setdefault(_pigment_key(row), []).append(i)
    by_cell = {(r.plan.i, r.plan.j): r for r in results}
    cmap = matplotlib.colormaps["viridis"]
    panels = []
    for n, (key, members) in enumerate(groups.items(), start=1):
        curves, failed = [], []
        for k, i in enumerate(members):
            colour = matplotlib.colors.to_hex(cmap(0.85 * k / max(len(members) - 1, 1)))
            for j, column in enumerate(columns):
                res = by_cell[(i, j)]
                name = f"{rows[i].label}, {column.label}"
                if not res.ok:
                    failed.append(f"{name}: {res.error}")
                    continue
                t = res.table
                curves.append(Curve(name, t.wavelengths, t.Tbar[:, 0], _normal_se(t, "Tbar"), colour,
                                    _LINESTYLES[j % len(_LINESTYLES)]))
        name = _PIGMENT_NAMES.get(key, key)
        panels.append(Panel(f"Fig. 9.{n}. {name} pigment" if name != key else f"Fig. 9.{n}. {key}", tuple(curves),
                            tuple(failed)))
    return panels


def draw_spectra_figure(rows, columns, results, settings: FigureSettings, path) -> list[Panel]:
    caption = (f"Total transmittance Tbar (coherent + diffuse) of the layer at normal incidence; model "
               f"{settings.model.name} ({settings.model.description}); accuracy {settings.label}; "
               "bands: ±2 standard errors across random cells (none for one realization).")
    panels = spectra_panels(rows, columns, results)
    draw_spectra(panels, TITLES["fig9"], caption, path, "transmittance Tbar(0°)")
    return panels


def write_spectra_csv(panels: list[Panel], path) -> Path:
    """The curves a spectra figure plots: panel, curve, wavelength_nm, Tbar, Tbar_se (empty when
    unknown), one line per point."""
    import csv

    path = Path(path)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        out = csv.writer(fh)
        out.writerow(["panel", "curve", "wavelength_nm", "Tbar", "Tbar_se"])
        for panel in panels:
            for c in panel.curves:
                for k, wl in enumerate(c.wavelengths_nm):
                    se = "" if c.se is None else f"{c.se[k]:.6f}"
                    out.writerow([panel.title, c.label, f"{wl:g}", f"{c.value[k]:.6f}", se])
    return path


def make_figure(figure: str, rows, columns, settings: FigureSettings, opts: BuildOptions, out_png,
                report_path=None, echo=print) -> FigureOutput:
    """Build every cell (cached, resumable), draw the figure, write OUT.csv (and the report)."""
    out_png = Path(out_png)
    started = time.perf_counter()
    plans = plan_cells(rows, columns, settings)          # bad settings are refused here, before any work
    ests = estimates(plans, opts)
    refuse_what_cannot_fit(figure, plans, ests, opts)
    seconds = [0.0 if e is None else e.seconds for e in ests]
    cached = sum(p.request is not None and e is None for p, e in zip(plans, ests))   # None: in the cache
    unplanned = sum(p.request is None for p in plans)
    if cached < len(plans) - unplanned:
        opts.cache.check()                         # something to build: the cache must be writable
    where = f"on {opts.scheduler}" if opts.scheduler else f"with {opts.workers} worker(s)"
    echo(f"{figure}: {len(rows)} × {len(columns)} = {plural(len(plans), 'cell')}, {cached} in the cache, "
         f"{len(plans) - cached - unplanned} to build (estimated {duration(sum(seconds))} {where})"
         + (f", {unplanned} cannot be planned (drawn crossed out)" if unplanned else ""))
    geometry = CellGeometry() if figure in GRID_FIGURES else None
    with pooled(opts) as running:                  # one pool of workers for every table of the figure
        built = build_cells(plans, running, seconds, progress=opts.progress)
    results, colours, pictures = evaluate_cells(built, geometry, settings)
    spectra = None
    if geometry is not None:
        draw_grid_figure(figure, rows, columns, pictures, settings, out_png, geometry)
    else:
        panels = draw_spectra_figure(rows, columns, results, settings, out_png)
        spectra = write_spectra_csv(panels, out_png.with_name(out_png.stem + "_spectra.csv"))
    records = [record_of(figure, r, settings, colours.get((r.plan.i, r.plan.j))) for r in results]
    csv_path = write_csv(records, out_png.with_suffix(".csv"))
    report = None
    if report_path is not None:
        report = Path(report_path)
        report.write_text(findings.report(records, TITLES.get(figure, figure)), encoding="utf-8")
    echo(f"wrote {out_png} and {csv_path}" + (f" and {spectra}" if spectra else "")
         + (f" and {report}" if report else "")
         + f" in {duration(time.perf_counter() - started)}; {run_counts(records)}")
    for r in records:
        if not r.ok:
            echo(f"  failed: {r.ink} × {r.grains}: {r.reason}")
    return FigureOutput(out_png, csv_path, report, records, spectra)
