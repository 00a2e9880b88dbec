"""The figures' costs and the honesty of their standard errors.

    python -m benchmarks.bench_figures            # ~50 min on 2 cores (presets ~25 min the first time, fig7 ~25 min)
    python -m benchmarks.bench_figures draw       # some sections: plan, se, draw, presets
    python -m benchmarks.bench_figures presets    # preset errors vs fine (~35 min the first time)

1. plan: cells and estimated build time of Fig. 7, 8 and 9 at each accuracy preset (the table
   preflight's model; with 2 workers and 16), nothing built;
2. standard error: one small particle cell built with K seeds; the spread of its CIELAB across
   seeds against the standard error of one table: the jackknife over its realizations (what the
   CSV reports) and the propagated bounds (independent, per-column correlated, and the larger —
   what it reported before); se-cylinders: the same for B30 with in-plane 200-nm cylinders at
   preview (16 seeds, ~2 min), se-cylinders-default: at `default` (36 seeds, 4 realizations; ~5 min),
   se-rotated: the same with each seed's incidence azimuths turned (~2 min); se-singles: each
   realization of 12 default tables reduced alone (linearity; azimuths by index; ~2 min); none
   of the se-* sections in the default run;
3. drawing: one Fig. 6 cell and one colour + SE for a particle and a molecular table on the
   default grids, and composing and writing a full 21 × 17 Fig. 7 (one table in every cell,
   so only drawing is timed);
4. presets: each accuracy preset's colour error (ΔE2000) against `fine` and its build time on
   a few cells (tables kept in out/bench/presets_cache); presets-quick: the two cells whose
   fine tables take about a minute; presets-span: six cells across the columns (~45 min
   the first time); candidates: the default beside the former default and cheaper settings on the
   six cells against their fine tables (after presets-span; candidates-quick: the first four,
   whose fine tables take ~20 min); none of them in the default run;
5. fig7: the whole Fig. 7 at `preview` from an empty cache, timed, with the yardstick (~20 min);
   fig7-default: the same at `default` (~1 h; not part of the default run);
6. steps: the map's colour steps between columns in the committed Fig. 7 CSV (the scale of 4);
7. compare: the committed `default` row of Fig. 7 against the same cells at `preview`;
8. sample / sample-quick: the `default` Fig. 7's build time extrapolated from a stratified
   sample of its cells (3 rows × 17 columns, each column's measured/estimate ratio applied to
   the column's estimates, validated row by row; ~1/5 of the figure's time) or, quick, one row ×
   four columns (~3 min on 2 cores).  Not part of the default run.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from solver.colour.table_colour import SE_MODES, lab_jacobian, node_errors, propagate_se, table_colour
from solver.paper import PAPER_ALBEDO
from solver.apps.figures.cells import CellResult, FigureSettings, estimates, plan_cells
from solver.apps.figures.fig6 import DPHI_SAMPLES, azimuth_averaged, figure6, pixel_angles_rad
from solver.apps.figures.layout import CellGeometry
from solver.apps.figures.make import draw_grid_figure, evaluate_cells
from solver.table.preflight import duration
from solver.apps.figures.paper_grid import FIG7_COLUMNS, FIG7_ROWS, FIGURES, Column
from solver.table import preflight
from solver.table.builder import BuildOptions, build_table
from solver.table.cache import TableCache
from solver.table.evaluate import diffuse_brdf
from solver.table.request import ACCURACY, table_request

OUT = Path("out/bench")
SE_CELL = ("Y7.5+B7.5", "sphere:300")
#: 5 λ across 380–780 nm (a colour needs 400–700 nm: the 420–660 nm of earlier rounds is refused now)
SE_SETTINGS = dict(wavelengths_nm=(380.0, 480.0, 580.0, 680.0, 780.0), sigma_rad=tuple(np.radians([0, 40, 90])),
                   grid=(24, 24, 12), realizations=3, azimuths=1, tier="full")
SE_SEEDS = 24
SE_CYLINDER_CELL = ("B30", "cylinder:200:inplane")
SE_CYLINDER_SEEDS = 16


def _figure_estimate(plans, workers: int) -> float:
    """Seconds a figure's planned cells are estimated at from an empty cache (shared grains, one pool)."""
    empty = TableCache(Path(tempfile.gettempdir()) / "bench_figures_plan_no_cache")   # never created
    return sum(e.seconds for e in estimates(plans, BuildOptions(workers=workers, progress=False, cache=empty))
               if e is not None)


def plan_costs() -> None:
    print("1. estimated build time of every cell (table preflight model; nothing built)")
    print(f"   {'figure':6s} {'cells':>5s}  " + "  ".join(f"{a + ' (2 / 16 workers)':>28s}" for a in ACCURACY))
    for name, (rows, columns) in FIGURES.items():
        line = f"   {name:6s} {len(rows) * len(columns):5d}  "
        for accuracy in ACCURACY:
            plans = plan_cells(rows, columns, FigureSettings(accuracy))
            t2, t16 = (_figure_estimate(plans, w) for w in (2, 16))
            line += f"{duration(t2) + ' / ' + duration(t16):>28s}  "
        print(line)
    print("   the default Fig. 7 beside other settings (`candidates` measures their colour against fine):")
    for name, overrides in DEFAULT_CANDIDATES.items():
        seconds = _figure_estimate(plan_cells(*FIGURES["fig7"], FigureSettings("default", tuple(overrides.items()))), 2)
        print(f"     {name:34s} {duration(seconds)}")


def se_check(cache: TableCache) -> None:
    ink, particles = SE_CELL
    title = (f"\n2. standard error of the colour: {ink} {particles}, {SE_SETTINGS['realizations']} realizations, "
             f"grid {SE_SETTINGS['grid']}, {len(SE_SETTINGS['wavelengths_nm'])} λ, {SE_SEEDS} seeds")
    _se_against_seeds(title, [table_request(ink, particles, seed=seed, **SE_SETTINGS)
                              for seed in range(1, SE_SEEDS + 1)], cache)


def se_check_cylinders(cache: TableCache, accuracy: str = "preview", seeds: int = SE_CYLINDER_SEEDS) -> None:
    """The cell whose propagated bounds disagree most (2.08 against 0.38 in a* at preview): B30,
    in-plane 200-nm cylinders, as Fig. 7 builds it at `accuracy`, over `seeds` seeds."""
    ink, particles = SE_CYLINDER_CELL
    settings = lambda seed: FigureSettings(accuracy, (("seed", seed),))
    title = f"\n2b. standard error of the colour: {ink} {particles} at {accuracy} (Fig. 7's request), {seeds} seeds"
    _se_against_seeds(title, [settings(seed).request(ink, particles) for seed in range(1, seeds + 1)], cache)


def se_check_rotated_azimuths(cache: TableCache, accuracy: str = "default", seeds: int = 12) -> None:
    """se-cylinders with the seed spread widened to the incidence azimuths too: each seed's
    golden-ratio azimuth sequence (wave_tier.azimuths, the same for every seed) turned by an
    offset drawn from the seed — does the azimuth sampling explain a jackknife above the seed
    spread?  In this process only (1 worker) and in a cache of its own."""
    import contextlib
    import solver.table.wave_tier as wave_tier

    def rotated(request, realization):
        s = realization * request.wave.azimuths + np.arange(request.wave.azimuths)
        offset = np.random.default_rng([request.wave.seed, 99]).uniform()
        return 0.5 * np.pi * np.mod(s * wave_tier.GOLDEN + offset, 1.0)

    ink, particles = SE_CYLINDER_CELL
    own = TableCache(Path(tempfile.mkdtemp(prefix="figures_rotated_")))
    with contextlib.ExitStack() as stack:
        original = wave_tier.azimuths
        stack.callback(setattr, wave_tier, "azimuths", original)
        wave_tier.azimuths = rotated
        _se_against_seeds(f"\n2c. as 2b at {accuracy}, each seed's azimuths turned by its own offset, {seeds} seeds",
                          [FigureSettings(accuracy, (("seed", seed),)).request(ink, particles)
                           for seed in range(1, seeds + 1)], own, workers=1)


def se_singles(cache: TableCache, accuracy: str = "default", seeds: int = 12) -> None:
    """Is the reduction linear enough for the jackknife, and does a realization's index (its
    incidence azimuths) matter?  For each seed's table of SE_CYLINDER_CELL, each realization
    reduced alone by the builder's own `_reduce` (its units, refined the same way): the mean of
    their a* against the table's, SD/√N against the jackknife; then a one-way ANOVA of all
    realizations' a* by realization index."""
    from solver.table.builder import _reduce, _Timer

    ink, particles = SE_CYLINDER_CELL
    print(f"\n2d. {ink} {particles} at {accuracy}: each realization alone, {seeds} seeds")
    singles_all = []
    for seed in range(1, seeds + 1):
        request = FigureSettings(accuracy, (("seed", seed),)).request(ink, particles)
        table = build_table(request, BuildOptions(progress=False, cache=cache))
        wl = list(request.grids.wavelengths_nm)
        solved = [wl.index(w) for w in table.meta.get("solved_wavelengths_nm", wl)]
        method, n = ("born" if table.meta["tier"] == "born" else "full"), table.meta["realizations_used"]
        a = []
        for r in range(n):
            units = {(0, li): cache.load_part(request, f"{method}_r{r}_l{li}") for li in solved}
            alone, _ = _reduce(request, table.meta["tier"], "", {}, units, solved, 1, _Timer())
            a.append(table_colour(alone, PAPER_ALBEDO).lab[1])
        colour = table_colour(table, PAPER_ALBEDO)
        singles_all.append(a)
        print(f"   seed {seed:2d}: a* {colour.lab[1]:7.2f}, mean of its realizations' {np.mean(a):7.2f}; "
              f"SD/√N {np.std(a, ddof=1) / np.sqrt(n):.2f}, jackknife {colour.se[1]:.2f}")
    x = np.array(singles_all)                       # [seed, realization]
    k, m = x.shape[1], x.size
    between = x.shape[0] * np.var(x.mean(axis=0), ddof=1)
    within = np.mean(np.var(x, axis=0, ddof=1))
    print(f"   a* by realization index: means {' '.join(f'{v:.2f}' for v in x.mean(axis=0))}; "
          f"F = {between / within:.2f} at {k - 1} and {m - k} degrees of freedom")


def _se_against_seeds(title: str, requests, cache: TableCache, workers: int | None = None) -> None:
    """One table per request (the same cell, other seeds): the spread of the colour across them
    (the truth) against each table's own standard error — the jackknife over its realizations
    (what the CSV reports now; root mean square over the tables) and the two propagated bounds
    and their larger (what it reported before)."""
    print(title)
    labs, se = [], {m: [] for m in ("jackknife", "independent", "correlated", "larger")}
    t0 = time.perf_counter()
    for request in requests:
        opts = BuildOptions(progress=False, cache=cache) if workers is None else \
            BuildOptions(progress=False, cache=cache, workers=workers)
        table = build_table(request, opts)
        colour = table_colour(table, PAPER_ALBEDO)
        labs.append(colour.lab)
        se["jackknife"].append(colour.se if colour.method == "jackknife" else np.full(3, np.nan))
        errors, _, _ = node_errors(table)
        jac = lab_jacobian(table, PAPER_ALBEDO)
        for mode in SE_MODES:
            se[mode].append(propagate_se(jac, errors, mode))
    k = len(requests)
    spread = np.std(labs, axis=0, ddof=1)
    dof = k * (table.meta["realizations_used"] - 1)
    print(f"   built in {time.perf_counter() - t0:.0f} s; the spread across {k} seeds has ±{100 / np.sqrt(2 * (k - 1)):.0f} % "
          f"sampling error, the jackknife's root mean square (over {dof} degrees of freedom) ±{100 / np.sqrt(2 * dof):.0f} %")
    print(f"   {'':34s} {'L*':>7s} {'a*':>7s} {'b*':>7s}")
    print(f"   {'observed spread (seeds)':34s} " + " ".join(f"{v:7.3f}" for v in spread))
    for mode, values in se.items():
        rms = np.sqrt(np.mean(np.square(values), axis=0))
        label = ("jackknife SE (the CSV), rms" if mode == "jackknife" else
                 f"propagated SE, {mode}" + (" (before)" if mode == "larger" else ""))
        print(f"   {label:34s} " + " ".join(f"{v:7.3f}" for v in rms) + "   ratio to observed "
              + " ".join(f"{r:4.2f}" for r in rms / spread))
    print(f"   per table, jackknife a* SE: " + " ".join(f"{v[1]:.2f}" for v in se["jackknife"])
          + "; larger bound: " + " ".join(f"{v[1]:.2f}" for v in se["larger"]))


def drawing(cache: TableCache) -> None:
    print("\n3. drawing (tables on the default λ, σ, Δφ grids; a 16×16×8 voxel grid keeps the build short)")
    opts = BuildOptions(progress=False, cache=cache)
    particle = build_table(table_request(*SE_CELL, grid=(16, 16, 8), realizations=2, azimuths=1, tier="full"), opts)
    molecular = build_table(table_request(SE_CELL[0]), opts)
    g = CellGeometry()
    figure6(molecular, 0.9, size=8, strip=2)              # warm-up: imports, colour tables
    for name, table in (("particle", particle), ("molecular", molecular)):
        t0 = time.perf_counter()
        for _ in range(5):
            figure6(table, 0.9, size=g.square, strip=g.strip)
        per_cell = (time.perf_counter() - t0) / 5
        t0 = time.perf_counter()
        for _ in range(5):
            table_colour(table, PAPER_ALBEDO)
        print(f"   {name:9s} ({table.wavelengths.size} λ × {table.sigma.size} σ × {table.dphi.size} Δφ): Fig. 6 cell "
              f"{1000 * per_cell:.0f} ms, colour + SE {1000 * (time.perf_counter() - t0) / 5:.0f} ms")
    view, dphi = pixel_angles_rad(g.square), np.linspace(0.0, np.pi, DPHI_SAMPLES)
    loop = lambda: np.mean([diffuse_brdf(particle, 0.9, view[None, :], view[:, None], p) for p in dphi], axis=0)
    once = lambda: diffuse_brdf(azimuth_averaged(particle, dphi), 0.9, view[None, :], view[:, None], 0.0)
    times = {}
    for name, fn in (("loop", loop), ("once", once)) * 2:          # interleaved, the second pair kept
        t0 = time.perf_counter()
        for _ in range(10):
            fn()
        times[name] = (time.perf_counter() - t0) / 10
    print(f"   Fig. 6 square, mean over {DPHI_SAMPLES} Δφ: one evaluation per Δφ {1000 * times['loop']:.0f} ms, "
          f"one of the Δφ-averaged table {1000 * times['once']:.1f} ms (max difference "
          f"{np.max(np.abs(loop() - once())):.1e})")
    rows, columns = FIG7_ROWS, FIG7_COLUMNS
    results = [CellResult(p, particle) for p in plan_cells(rows, tuple(
        Column("molecular", c.group, c.sub) for c in columns), FigureSettings("default"))]
    OUT.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    _, _, pictures = evaluate_cells(results, g, FigureSettings())
    layout = draw_grid_figure("fig7", rows, columns, pictures, FigureSettings(), OUT / "fig7_layout.png", g)
    print(f"   a full Fig. 7 (21 × 17 cells, the particle table in each; with each cell's colour + SE): {time.perf_counter() - t0:.1f} s, "
          f"{layout.size[0]} × {layout.size[1]} px: {OUT / 'fig7_layout.png'}")


#: cells of the preset study: a small and a large sphere, in-plane cylinders (the fine tables
#: take ~10 min each on 2 cores; kept in out/bench/presets_cache, so a rerun recomputes nothing)
PRESET_CELLS = (("R30", "sphere:100"), ("Y7.5+B7.5", "sphere:300"), ("B30", "cylinder:200:inplane"))


#: `presets-quick`: the two cells whose fine tables take about a minute (no 300-nm spheres)
QUICK_PRESET_CELLS = (PRESET_CELLS[0], PRESET_CELLS[2])

#: `presets-span`: six cells across Fig. 7's columns (grain sizes 30–300 nm, balls,
#: agglutinated balls, vertical cylinders) and its three concentrations — the issue's "≥ 6
#: cells spanning the columns"; the fine tables take ~45 min on 2 quiet cores
SPAN_PRESET_CELLS = (("R50", "sphere:30"), ("R30", "sphere:100"), ("R15", "sphere:300"), ("R50", "cylinder:100:vertical"),
                     ("R15", "sphere:200"), ("R30", "sphere:100:agglutinated"))      # cheapest fine tables first


def preset_errors(cells=PRESET_CELLS) -> None:
    """Each accuracy preset's colour against `fine` (ΔE2000 of the figure's colour: the default
    measurement, 45:0/D50/2°, paper albedo) and its build time, on PRESET_CELLS (or `cells`);
    the median and the largest error of each preset over the cells at the end."""
    from solver.colour.cie import delta_e2000
    from solver.table.builder import get_or_build

    print("\n4. accuracy presets against fine (ΔE2000 of the cell colour; build seconds from an empty cache, "
          "2 workers; cached tables are reused and their time read from the table)")
    cache = TableCache(OUT / "presets_cache")
    print(f"   {'cell':32s} " + "  ".join(f"{a:>22s}" for a in ACCURACY) + "   fine SE (L*, a*, b*)")
    errors = {a: [] for a in ACCURACY}
    for ink, particles in cells:
        colours, times = {}, {}
        for accuracy in reversed(ACCURACY):
            t0 = time.perf_counter()
            table, _, built = get_or_build(table_request(ink, particles, accuracy=accuracy),
                                           BuildOptions(workers=2, progress=False, cache=cache))
            times[accuracy] = (time.perf_counter() - t0 if built
                               else sum(table.meta.get("timings_s", {}).values()))
            colours[accuracy] = table_colour(table, PAPER_ALBEDO)
        fine = colours["fine"]
        for a in ACCURACY:
            errors[a].append(float(delta_e2000(colours[a].lab, fine.lab)))
        cells = [f"ΔE {float(delta_e2000(colours[a].lab, fine.lab)):5.2f}, {times[a]:6.0f} s" for a in ACCURACY]
        print(f"   {ink + ' ' + particles:32s} " + "  ".join(f"{c:>22s}" for c in cells)
              + "   " + " ".join(f"{v:.2f}" for v in fine.se), flush=True)
    print(f"   {'median / max ΔE2000 vs fine':32s} "
          + "  ".join(f"{np.median(errors[a]):>14.2f} / {max(errors[a]):5.2f}" for a in ACCURACY))


#: `candidates`: the default preset beside the former one and cheaper settings, tried on
#: SPAN_PRESET_CELLS against the fine tables of `presets-span` (run that first: it builds them)
DEFAULT_CANDIDATES = {"default": {}, "former default (4 × 2, tol 1e-3)": {"realizations": 4, "azimuths": 2,
                                                                          "solver_tol": 1e-3},
                      "5 realizations": {"realizations": 5}, "tol 5e-3": {"solver_tol": 5e-3},
                      "stride 3": {"wavelength_stride": 3}}


def candidate_errors(cells=SPAN_PRESET_CELLS, candidates=DEFAULT_CANDIDATES) -> None:
    """Each candidate setting's colour against `fine` and its build seconds (cells as `presets`)."""
    from solver.colour.cie import delta_e2000
    from solver.table.builder import get_or_build

    cache = TableCache(OUT / "presets_cache")
    print("\n4b. candidate default settings against fine (ΔE2000, 45:0/D50/2°; build seconds, 2 workers)")
    print(f"   {'cell':32s} " + "  ".join(f"{c:>26s}" for c in candidates))
    errors, seconds = {c: [] for c in candidates}, {c: 0.0 for c in candidates}
    for ink, particles in cells:
        fine, _, _ = get_or_build(table_request(ink, particles, accuracy="fine"),
                                  BuildOptions(workers=2, progress=False, cache=cache))
        fine_lab = table_colour(fine, PAPER_ALBEDO).lab
        line = []
        for name, overrides in candidates.items():
            t0 = time.perf_counter()
            table, _, built = get_or_build(table_request(ink, particles, **overrides),
                                           BuildOptions(workers=2, progress=False, cache=cache))
            t = time.perf_counter() - t0 if built else sum(table.meta.get("timings_s", {}).values())
            errors[name].append(float(delta_e2000(table_colour(table, PAPER_ALBEDO).lab, fine_lab)))
            seconds[name] += t
            line.append(f"ΔE {errors[name][-1]:5.2f}, {t:6.0f} s")
        print(f"   {ink + ' ' + particles:32s} " + "  ".join(f"{c:>26s}" for c in line), flush=True)
    print(f"   {'median / max ΔE2000, total s':32s} "
          + "  ".join(f"{np.median(errors[c]):>9.2f} / {max(errors[c]):4.2f}, {seconds[c]:5.0f} s" for c in candidates))


def fig7_whole(accuracy: str = "preview") -> None:
    """The whole Fig. 7 at `accuracy` from an empty cache, as a user runs it (`ink-tables paper
    fig7`, 2 workers), with the machine's yardstick before and after; CSV, report and picture
    in out/bench/fig7_<accuracy>.{png,csv,md}."""
    import subprocess

    from .bench_fresh import YARDSTICK, yardstick

    OUT.mkdir(parents=True, exist_ok=True)
    before = yardstick(YARDSTICK)
    with tempfile.TemporaryDirectory(prefix="fig7_") as tmp:
        t0 = time.perf_counter()
        out = subprocess.run([sys.executable, "-m", "solver.apps.cli", "paper", "fig7", "--accuracy", accuracy,
                              "--cache", tmp, "--no-progress", "--report", str(OUT / f"fig7_{accuracy}.md"),
                              "-o", str(OUT / f"fig7_{accuracy}.png")], capture_output=True, text=True, check=True)
        wall = time.perf_counter() - t0
    after = yardstick(YARDSTICK)
    said = [line.strip() for line in (out.stdout + out.stderr).splitlines() if "estimate" in line or line.startswith("wrote")]
    print(f"\n5. Fig. 7 at {accuracy} from an empty cache, 2 workers: {duration(wall)} ({wall:.0f} s); "
          f"yardstick {before:.3f} s before, {after:.3f} s after ({wall / (0.5 * (before + after)):.0f} yardsticks)")
    for line in said:
        print(f"   {line}")


#: column pairs whose colour steps give the map's scale (`steps`)
STEP_PAIRS = (("molecular", "sphere:300"), ("sphere:100", "sphere:200"), ("molecular", "sphere:30"))


def map_steps(csv_path: Path = Path("docs/data/fig7_preview.csv")) -> None:
    """The map's own colour steps between columns (ΔE2000 over the rows of a figure CSV), the
    scale the presets' errors are judged against."""
    from solver.colour.cie import delta_e2000

    lab = _csv_lab(csv_path)
    print(f"\n6. the map's steps between columns, ΔE2000 over the rows ({csv_path}):")
    for a, b in STEP_PAIRS:
        de = [float(delta_e2000(lab[(ink, a)], lab[(ink, b)])) for ink, col in lab if col == a and (ink, b) in lab]
        print(f"   {a} → {b}: median {np.median(de):.1f} ({min(de):.1f}–{max(de):.1f}) over {len(de)} rows")


def _csv_lab(path: Path) -> dict:
    """{(ink, column): CIELAB} of a figure CSV's built cells."""
    from solver.apps.figures.records import read_csv

    return {(r.ink, r.column): r.lab for r in read_csv(path) if r.ok}


def preview_vs_default(preview: Path = Path("docs/data/fig7_preview.csv"),
                       default: Path = Path("docs/data/fig7_default_R15.csv")) -> None:
    """ΔE2000 between the cells a `default` CSV shares with the `preview` one."""
    from solver.colour.cie import delta_e2000

    a, b = _csv_lab(preview), _csv_lab(default)
    common = sorted(set(a) & set(b))
    de = np.array([float(delta_e2000(a[k], b[k])) for k in common])
    worst = common[int(np.argmax(de))]
    print(f"\n7. preview ({preview}) vs default ({default}): {len(common)} common cells, ΔE2000 median "
          f"{np.median(de):.2f}, max {de.max():.2f} ({worst[0]} {worst[1]})")


#: the stratified sample of `sample`: every 7th row (one per concentration block: R15, R30, R50)
#: × every column; `sample-quick`: the first row × four columns that span the costs
SAMPLE_ROWS, QUICK_COLUMNS = 7, ("molecular", "sphere:100", "sphere:300", "sphere:300:rough")


#: `sample-row-former`: the former default (4 realizations × 2 azimuths, tol 1e-3) on the first
#: sampled row, beside the same row of `sample` or `sample-row` (same code, one session);
#: `sample-row-5`: 5 realizations × 1 on that row
FORMER_DEFAULT = (("realizations", 4), ("azimuths", 2), ("solver_tol", 1e-3))


def fig7_sample(quick: bool = False, accuracy: str = "default", overrides=(), one_row: bool = False) -> None:
    """The whole Fig. 7's build time from a stratified sample of its cells: each sampled cell
    built from an empty cache (2 workers, one pool), its time beside its preflight estimate;
    the figure = Σ over all cells of their estimates × the measured/estimate ratio of their
    column (the cost is set by the grains, far more than by the ink).  Validation: each sampled
    row's own total against the extrapolation from the other sampled rows (leave one row out).
    The full sample (3 rows × 17 columns) takes about a fifth of the figure; `quick` builds the
    first row's four representative cells only."""
    from solver.table.builder import pooled

    from .bench_fresh import YARDSTICK, yardstick

    settings = FigureSettings(accuracy, tuple(overrides))
    columns = [c for c in FIG7_COLUMNS if not quick or c.particles in QUICK_COLUMNS]
    rows = FIG7_ROWS[:1] if quick or one_row else FIG7_ROWS[::SAMPLE_ROWS]
    every = [p for p in plan_cells(FIG7_ROWS, FIG7_COLUMNS, settings) if p.request is not None]
    plans = [p for p in plan_cells(rows, columns, settings) if p.request is not None]
    print(f"\n8. Fig. 7 at `{accuracy}`{' with ' + str(dict(overrides)) if overrides else ''} from a stratified "
          f"sample: {len(plans)} cells ({len(rows)} row(s) × {len(columns)} columns) of {len(every)}, empty cache, "
          f"2 workers; yardstick {yardstick(YARDSTICK):.3f} s")
    measured = {}
    with tempfile.TemporaryDirectory(prefix="fig7_sample_") as tmp:
        opts = BuildOptions(workers=2, progress=False, cache=TableCache(Path(tmp)))
        # the whole figure's estimates, in its order: a cell whose grains an earlier row drew
        # (geometry_store.py) is estimated without its geometry; the sampled rows draw their own
        every_est = {(p.row.ink.label, p.column.particles): e.seconds
                     for p, e in zip(every, estimates(every, opts)) if e is not None}
        with pooled(opts) as running:
            for p in plans:
                est = every_est[(p.row.ink.label, p.column.particles)]
                t0 = time.perf_counter()
                build_table(p.request, running)
                measured[(p.row.ink.label, p.column.particles)] = (time.perf_counter() - t0, est)
                print(f"   {p.row.ink.label:10s} {p.column.particles:28s} {measured[(p.row.ink.label, p.column.particles)][0]:7.1f} s "
                      f"(estimate {est:6.1f} s)", flush=True)
    ratio = {c: np.mean([m / e for (r, col), (m, e) in measured.items() if col == c])
             for c in {col for (_, col), (_, e) in measured.items() if e > 0.5}}   # films: nothing to time
    known = [p for p in every if p.column.particles in ratio]
    measured = {k: v for k, v in measured.items() if k[1] in ratio}
    total_est = sum(every_est.values())
    extrapolated = sum(every_est[(p.row.ink.label, p.column.particles)] * ratio[p.column.particles]
                       for p in known if (p.row.ink.label, p.column.particles) in every_est)
    print(f"   the figure's preflight estimate {duration(total_est)}; measured/estimate per column "
          + ", ".join(f"{c} {v:.2f}" for c, v in sorted(ratio.items())))
    if quick:
        print(f"   (quick: {len(known)} of {len(every)} cells have a measured column; their extrapolated build "
              f"{duration(extrapolated)} — the full sample covers every column)")
    else:
        print(f"   extrapolated whole figure: {duration(extrapolated)} ({extrapolated:.0f} s) on 2 workers")
    labels = sorted({r for r, _ in measured})
    for held in labels if len(labels) > 1 else []:
        others = {c: np.mean([m / e for (r, col), (m, e) in measured.items() if col == c and r != held])
                  for c in ratio}
        row_cells = [(k, v) for k, v in measured.items() if k[0] == held]
        pred = sum(e * others[c] for (r, c), (m, e) in row_cells)
        real = sum(m for _, (m, e) in row_cells)
        print(f"   row {held}: measured {real:.0f} s, predicted from the other rows {pred:.0f} s ({pred / real - 1:+.0%})")
    print(f"   yardstick after: {yardstick(YARDSTICK):.3f} s")


def main(argv=None) -> int:
    cache = TableCache(Path(tempfile.mkdtemp(prefix="figures_")))
    sections = {"plan": plan_costs, "se": lambda: se_check(cache),
                "se-cylinders": lambda: se_check_cylinders(cache),
                "se-cylinders-default": lambda: se_check_cylinders(cache, "default", 36),
                "se-rotated": lambda: se_check_rotated_azimuths(cache),
                "se-singles": lambda: se_singles(cache), "draw": lambda: drawing(cache),
                "presets": preset_errors, "fig7": fig7_whole,
                "fig7-default": lambda: fig7_whole("default"), "steps": map_steps,
                "compare": preview_vs_default, "sample": fig7_sample,
                "sample-quick": lambda: fig7_sample(quick=True),
                "sample-row": lambda: fig7_sample(one_row=True),
                "sample-row-former": lambda: fig7_sample(overrides=FORMER_DEFAULT, one_row=True),
                "sample-row-5": lambda: fig7_sample(overrides=(("realizations", 5),), one_row=True),
                "presets-quick": lambda: preset_errors(QUICK_PRESET_CELLS),
                "presets-span": lambda: preset_errors(SPAN_PRESET_CELLS),
                "candidates": candidate_errors,
                "candidates-quick": lambda: candidate_errors(SPAN_PRESET_CELLS[:4])}
    for name in (argv or [n for n in sections if not n.startswith("sample") and not n.startswith("presets-")
                            and n != "fig7-default"
                            and not n.startswith("se-") and not n.startswith("candidates")]):
        sections[name]()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
