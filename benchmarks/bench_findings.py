"""The paper's findings tested under both models, and what the project's own choices change
(issue 20; docs/findings.md, docs/figures.md).

    python -m benchmarks.bench_findings                      # Fig. 7, 8, 9 at preview, both models
    python -m benchmarks.bench_findings --figures fig8,fig9  # a part
    python -m benchmarks.bench_findings --rows R15,G15 --columns molecular,sphere:100   # a quick look

For each model (figures.models: `paper` = TE, bulk ε, the paper's strip colour; `default` =
unpolarised, local field, 45:0/D50) and each figure, the figure is drawn through the table cache
(timed; from an empty cache when --cache is a new folder), its CSV and findings report written,
and then:
  1. the findings of every figure under both models side by side (agree / undecided /
     contradict / not testable), with the molecular rows of finding 1 counted apart (exact films:
     the paper model must show no contradiction there);
  2. the difference between the models per Fig. 7 cell: ΔE2000 of each model's own colour
     (its tables, its measurement) and of the tables alone (both measured 45:0/D50/2°), drawn as
     a grid picture;
  3. every contradiction that survives, with the numbers a reader needs to explain it: the cells'
     saturation under both models and under d:0 (mirror included: the glare of a surround).
Outputs go to --out (default out/bench/findings): PNG, CSV, reports, summary.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from solver.apps.figures import FigureSettings, make_figure, parse_columns, parse_rows
from solver.apps.figures.findings import VERDICTS, evaluate, summary_table
from solver.table.preflight import duration
from solver.apps.figures.models import MODELS
from solver.apps.figures.paper_grid import TITLES
from solver.colour import measurement as M
from solver.colour.cie import delta_e2000, saturation
from solver.paper import PAPER_ALBEDO
from solver.table.builder import BuildOptions
from solver.table.cache import TableCache
from solver.table.schema import read_table


def run_model(model: str, figures, args, cache: TableCache, out: Path) -> dict:
    """{figure: (records, seconds)} of one model."""
    runs = {}
    for figure in figures:
        rows, columns = parse_rows(args.rows, figure), parse_columns(args.columns, figure)
        settings = FigureSettings(args.accuracy, (), MODELS[model])
        t0 = time.perf_counter()
        output = make_figure(figure, rows, columns, settings, BuildOptions(cache=cache, progress=False),
                             out / f"{figure}_{args.accuracy}_{model}.png",
                             out / f"{figure}_{args.accuracy}_{model}_report.md", echo=lambda s: print("  " + s))
        runs[figure] = (output.records, time.perf_counter() - t0)
    return runs


def molecular_finding1(checks) -> tuple[int, int]:
    """(checks, contradictions) of finding 1 in the molecular column."""
    mine = [c for c in checks if c.finding == 1 and c.where.startswith("mol:")]
    return len(mine), sum(c.verdict == "contradicts" for c in mine)


def colour_of(cache: TableCache, record, measurement) -> np.ndarray:
    return measurement.lab(read_table(cache.root / "tables" / f"{record.cache_key}.npz"), PAPER_ALBEDO)


def model_difference(runs: dict, cache: TableCache, out: Path, accuracy: str) -> list[str]:
    """ΔE2000 per Fig. 7 cell between the models (own colours; tables alone at 45:0/D50)."""
    if "fig7" not in runs.get("paper", {}) or "fig7" not in runs.get("default", {}):   # one model run
        return []
    paper = {(r.ink, r.column): r for r in runs["paper"]["fig7"][0] if r.ok}
    default = {(r.ink, r.column): r for r in runs["default"]["fig7"][0] if r.ok}
    keys = [k for k in default if k in paper]
    own = np.array([float(delta_e2000(paper[k].lab, default[k].lab)) for k in keys])
    tables = np.array([float(delta_e2000(colour_of(cache, paper[k], M.DEFAULT), default[k].lab)) for k in keys])
    _draw_difference(keys, own, out / f"fig7_{accuracy}_model_difference.png", runs["default"]["fig7"][0])
    q = lambda a: f"median {np.median(a):.2f}, 90 % {np.percentile(a, 90):.2f}, max {a.max():.2f}"
    return [f"Fig. 7, {len(keys)} cells, ΔE2000 paper ↔ default model:",
            f"- each model's own colour (paper: TE, bulk ε, strip geometry; default: unpolarised, local field, "
            f"45:0): {q(own)}",
            f"- the tables alone (both measured 45:0/D50/2°): {q(tables)}",
            f"- picture: {out / f'fig7_{accuracy}_model_difference.png'}"]


def _draw_difference(keys, values, path: Path, records) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    inks = list(dict.fromkeys(r.ink for r in records))
    cols = list(dict.fromkeys(r.column for r in records))
    grid = np.full((len(inks), len(cols)), np.nan)
    for (ink, col), v in zip(keys, values):
        grid[inks.index(ink), cols.index(col)] = v
    fig, ax = plt.subplots(figsize=(1.0 + 0.62 * len(cols), 1.2 + 0.36 * len(inks)))
    im = ax.imshow(grid, cmap="magma_r", vmin=0.0, vmax=max(1.0, float(np.nanmax(grid))))
    for i in range(len(inks)):
        for j in range(len(cols)):
            if np.isfinite(grid[i, j]):
                ax.text(j, i, f"{grid[i, j]:.1f}", ha="center", va="center", fontsize=6,
                        color="white" if grid[i, j] > 0.6 * np.nanmax(grid) else "black")
    ax.set_xticks(range(len(cols)), [c.replace("cylinder:", "cyl ").replace("sphere:", "ball ")
                                     .replace(":agglutinated", " aggl").replace(":rough", " rough")
                                     for c in cols], rotation=70, fontsize=7)
    ax.set_yticks(range(len(inks)), inks, fontsize=7)
    ax.set_title("ΔE2000 between the paper's model and this project's, per Fig. 7 cell", fontsize=9)
    fig.colorbar(im, ax=ax, fraction=0.03, label="ΔE2000")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def contradictions(runs: dict, cache: TableCache) -> list[str]:
    """Each contradiction that survives, with the cells' saturations under both models and d:0."""
    glare = replace(M.DEFAULT, geometry=M.GEOMETRIES["d:0"])
    lines = []
    for model, figs in runs.items():
        for figure, (records, _) in figs.items():
            by_cell = {(r.ink, r.column): r for r in records}
            for c in evaluate(records):
                if c.verdict != "contradicts":
                    continue
                lines.append(f"- {model} {figure} finding {c.finding}: {c.where}: {c.value:+.3f} ± {c.se:.3f}")
                ink = c.where.split(":")[0].split(" ")[0]
                cells = [k for k in by_cell if k[0] == ink and (k[1] in c.where or k[1].replace("molecular", "mol")
                                                                in c.where)]
                for k in cells[:4]:
                    r = by_cell[k]
                    if not r.ok:
                        continue
                    d0 = colour_of(cache, r, glare)
                    lines.append(f"    {k[0]} × {k[1]}: s = {float(saturation(r.lab)):.3f} ({r.measurement}), "
                                 f"L* {r.lab[0]:.1f}; under d:0 (glare) s = {float(saturation(d0)):.3f}, L* {d0[0]:.1f}")
    return lines


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_findings", description=__doc__.split("\n\n")[0])
    p.add_argument("--figures", default="fig7,fig8,fig9")
    p.add_argument("--accuracy", default="preview")
    p.add_argument("--rows", default=None)
    p.add_argument("--columns", default=None)
    p.add_argument("--models", default="paper,default")
    p.add_argument("--cache", default=None, help="table cache (default: the user's cache)")
    p.add_argument("--out", default="out/bench/findings")
    args = p.parse_args(argv)
    figures = [f.strip() for f in args.figures.split(",")]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cache = TableCache(Path(args.cache)) if args.cache else TableCache.default()
    runs, lines = {}, []
    for model in [m.strip() for m in args.models.split(",")]:
        print(f"model {model}: {MODELS[model].description}", flush=True)
        runs[model] = run_model(model, figures, args, cache, out)
        for figure, (records, seconds) in runs[model].items():
            computed = sum(r.computed for r in records)
            lines.append(f"- {model} {figure}: {len(records)} cells, {computed} computed, {duration(seconds)}")
    summary = ["# The paper's findings under both models", "", f"accuracy {args.accuracy}; figures {', '.join(figures)}",
               "", "## Runs", "", *lines]
    for figure in figures:
        summary += ["", f"## {TITLES.get(figure, figure)}"]
        for model in runs:
            checks = evaluate(runs[model][figure][0])
            n, bad = molecular_finding1(checks)
            summary += ["", f"### model {model} ({MODELS[model].measurement.label})", "", *summary_table(checks),
                        "", f"finding 1 on the molecular column (exact films): {n} checks, {bad} contradict"]
    summary += ["", "## The two models per cell", "", *model_difference(runs, cache, out, args.accuracy)]
    summary += ["", "## Contradictions that survive", "", *contradictions(runs, cache)]
    text = "\n".join(summary) + "\n"
    (out / "summary.md").write_text(text, encoding="utf-8")
    print(text)
    print(f"verdicts: {', '.join(VERDICTS)}; wrote {out / 'summary.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
