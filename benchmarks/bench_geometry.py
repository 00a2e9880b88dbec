"""Speed, memory, reach and cost model of the geometry generator (2-core machine).

    python -m benchmarks.bench_geometry                    # the speed cases (targets: ≤ 10 s each)
    python -m benchmarks.bench_geometry --baseline REV     # also the same cases with git revision REV
                                                           # (e.g. 98de97b), side by side, with ratios
    python -m benchmarks.bench_geometry --cost             # geometry_cost's estimates against measurements
    python -m benchmarks.bench_geometry --limits           # search the reachable concentrations (slow)
    python -m benchmarks.bench_geometry --variants         # the packer's alternatives tried and dropped
    python -m benchmarks.bench_geometry --skip-speed --limits --only spheroid   # cases whose spec contains TEXT
    python -m benchmarks.bench_geometry --skip-speed --shapes  # placement of spheroids beside cylinders

Per speed case: seconds for placement (`generate`) and voxelisation separately (wall clock and
process CPU), particle count, achieved fractions, relative error of the grid's pigment volume,
packer statistics, overlap count, orientation statistic, and the peak traced memory (tracemalloc,
numpy buffers included) of generate + voxelize, measured in a second, separate run so that
tracing does not slow the timed one.  A baseline revision is exported with `git archive` into a
temporary folder and run in a subprocess with that folder first on PYTHONPATH, through the
public API only (`generate`, `voxelize`), on the same machine in the same command.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from solver.geometry import (LayerSpec, draw_grains, find_overlaps, generate, geometry_cost, parse_particles, place,
                             reachable_limit, voxelize)
from solver.geometry.packing import PackOptions
from solver.inks import parse_ink

from .baseline import extract, run_python

GRID = (128, 128, 64)
SPEED_CASES = [
    # (ink, particles, cell nm, thickness nm, grid, budget s (placement + voxelisation))
    ("Y25+B25", "sphere:30", 2000.0, 1000.0, GRID, 10.0),
    ("Y25+B25", "sphere:100", 2000.0, 1000.0, GRID, 10.0),
    ("Y25+B25", "cylinder:100:isotropic", 2000.0, 1000.0, GRID, None),
    ("Y25+B25", "cylinder:100:inplane", 2000.0, 1000.0, GRID, None),
    ("Y25+B25", "cylinder:100:vertical", 2000.0, 1000.0, GRID, None),
]
#: Budget of the placement alone for the cylinder cases (s).
CYLINDER_BUDGET_S = 10.0

COST_CASES = [
    # (ink, particles, cell nm) at H = 1000 nm, grids 64×64×32 and 128×128×64
    ("B15", "sphere:30", 1000.0), ("B50", "sphere:30", 1000.0), ("B30", "sphere:30", 2000.0),
    ("B15", "sphere:100", 2000.0), ("B50", "sphere:100", 2000.0), ("B30", "sphere:300", 2000.0),
    ("B15", "cylinder:100:isotropic", 2000.0), ("B30", "cylinder:100:isotropic", 2000.0),
    ("B50", "cylinder:100:isotropic", 1000.0), ("B30", "cylinder:100:inplane", 2000.0),
    ("B50", "cylinder:100:inplane", 1000.0), ("B30", "cylinder:100:vertical", 2000.0),
    ("B50", "cylinder:100:vertical", 1000.0), ("B30", "cylinder:200:isotropic", 2000.0),
    ("B30", "cylinder:300:inplane", 2000.0), ("Y7.5+B7.5", "sphere:100:agglutinated", 1000.0),
    ("B15", "spheroid:100:aspect=3", 2000.0), ("B30", "spheroid:100:aspect=3", 2000.0),
    ("B50", "spheroid:100:aspect=3", 1000.0), ("B30", "spheroid:100:aspect=3:inplane", 2000.0),
    ("B50", "spheroid:100:aspect=3:inplane", 1000.0), ("B30", "spheroid:100:aspect=3:vertical", 2000.0),
    ("B50", "spheroid:100:aspect=3:vertical", 1000.0), ("B30", "spheroid:200:aspect=0.25:vertical", 2000.0),
    ("Y7.5+B7.5", "spheroid:100:aspect=3:agglutinated", 1000.0),
]

LIMIT_CASES = [
    # (particles, cell nm, ladder of total fractions; the search stops at the first failure)
    ("sphere:100", 1000.0, (0.50, 0.54, 0.58, 0.60)),
    ("cylinder:100:isotropic", 1000.0, (0.50, 0.52, 0.53, 0.55)),
    ("cylinder:100:inplane", 1000.0, (0.50, 0.55, 0.58)),
    ("cylinder:100:vertical", 1000.0, (0.50, 0.55)),
    ("cylinder:200:isotropic", 2000.0, (0.50, 0.52, 0.55)),
    ("cylinder:200:inplane", 2000.0, (0.50, 0.55)),
    ("cylinder:200:vertical", 2000.0, (0.45, 0.50, 0.55)),
    ("cylinder:300:isotropic", 2000.0, (0.50, 0.52)),
    ("cylinder:300:inplane", 2000.0, (0.50, 0.55)),
    ("cylinder:300:vertical", 2000.0, (0.40, 0.44, 0.46, 0.48)),
    ("cylinder:100:inplane:tilt=15", 1000.0, (0.50, 0.55)),
    ("cylinder:100:vertical:tilt=15", 1000.0, (0.45, 0.50)),
    ("cylinder:300:vertical:tilt=15", 2000.0, (0.38, 0.40, 0.42, 0.44)),
    ("spheroid:100:aspect=4", 1000.0, (0.50, 0.55, 0.58)),
    ("spheroid:100:aspect=4:inplane", 1000.0, (0.50, 0.55, 0.58)),
    ("spheroid:100:aspect=4:vertical", 1000.0, (0.50, 0.55, 0.58)),
    ("spheroid:100:aspect=0.25", 1000.0, (0.50, 0.55, 0.58)),
    ("spheroid:100:aspect=0.25:inplane", 1000.0, (0.50, 0.55, 0.58)),
    ("spheroid:100:aspect=0.25:vertical", 1000.0, (0.50, 0.55, 0.58)),
    ("spheroid:300:aspect=4", 2000.0, (0.45, 0.50, 0.55)),
    ("spheroid:300:aspect=4:vertical", 2000.0, (0.40, 0.45, 0.50)),
    ("spheroid:300:aspect=0.25:vertical", 2000.0, (0.45, 0.50, 0.55)),
    ("spheroid:100:aspect=4:vertical:tilt=30", 1000.0, (0.45, 0.50, 0.55)),
    ("spheroid:100:aspect=0.25:vertical:tilt=30", 1000.0, (0.50, 0.55)),
]

#: Runs one speed case with whatever `solver.geometry` is first on the path (public API only).
_CASE_SCRIPT = r"""
import json, sys, time, tracemalloc
import numpy as np
from solver.geometry import LayerSpec, generate, parse_particles, voxelize
from solver.inks import parse_ink
ink, particles, cell, thickness, grid, trace = json.loads(sys.argv[1])
layer = LayerSpec(parse_ink(ink), parse_particles(particles), thickness, (cell, cell))
if trace:
    tracemalloc.start()
t0, c0 = time.perf_counter(), time.process_time()
real = generate(layer, 1)
t1, c1 = time.perf_counter(), time.process_time()
gen_peak = tracemalloc.get_traced_memory()[1] if trace else 0
if trace:
    tracemalloc.reset_peak()
vox = voxelize(real, tuple(grid))
t2, c2 = time.perf_counter(), time.process_time()
peak = tracemalloc.get_traced_memory()[1] if trace else 0
grid_error = sum(vox.volume_nm3(c) for c in real.population_codes) / float(np.sum(real.volumes_nm3)) - 1
print(json.dumps(dict(n=int(len(real.radii_nm)), place_s=t1 - t0, place_cpu_s=c1 - c0, vox_s=t2 - t1,
                      vox_cpu_s=c2 - c1, gen_peak_bytes=int(gen_peak), peak_bytes=int(max(gen_peak, peak)),
                      az=float(np.mean(np.abs(real.axes[:, 2]))), grid_error=float(grid_error))))
"""


def run_case(path: str, case, trace: bool) -> dict:
    """One speed case in a fresh interpreter with `path` first on PYTHONPATH."""
    ink, particles, cell, thickness, grid, _ = case
    out = run_python(Path(path), ["-c", _CASE_SCRIPT, json.dumps([ink, particles, cell, thickness, list(grid), trace])],
                     capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def speed_case(case, seed=1):
    """Details of one case in this process (statistics the timing subprocess does not print)."""
    ink, particles, cell, thickness, grid, budget = case
    layer = LayerSpec(parse_ink(ink), parse_particles(particles), thickness, (cell, cell))
    t0 = time.perf_counter()
    real = generate(layer, seed)
    t1 = time.perf_counter()
    vox = voxelize(real, grid)
    t2 = time.perf_counter()
    exact = float(np.sum(real.volumes_nm3))
    grid_volume = sum(vox.volume_nm3(c) for c in real.population_codes)
    fractions = ", ".join(f"{c} {100 * f:.4f}%" for c, f in real.achieved_fractions.items())
    total = t2 - t0
    limit = budget if budget is not None else CYLINDER_BUDGET_S
    spent = total if budget is not None else t1 - t0
    what = "placement + voxelisation" if budget is not None else "placement"
    print(f"{ink} {particles} in {cell:g}x{cell:g}x{thickness:g} nm -> grid {grid}:")
    print(f"  particles {len(real.radii_nm)}, achieved {fractions}")
    print(f"  placement {t1 - t0:.2f} s ({real.stats.method}), voxelisation {t2 - t1:.2f} s "
          f"({vox.lines_per_voxel}x{vox.lines_per_voxel} lines/column), total {total:.2f} s  "
          f"[{what} {'within' if spent <= limit else 'OVER'} {limit:g} s]")
    if real.stats.pack is not None:
        p = real.stats.pack
        print(f"  packer: {p.iterations} iterations, {p.rebuilds} list builds, escapes {p.escapes}, "
              f"{p.seconds:.2f} s; RSA {real.stats.rsa_tries} tries at size x{real.stats.rsa_scale:.3f}")
    if real.shape.oriented:
        print(f"  <|a_z|> = {np.mean(np.abs(real.axes[:, 2])):.3f}")
    print(f"  grid pigment volume / particle volume - 1 = {grid_volume / exact - 1:+.2e}; "
          f"overlapping pairs {len(find_overlaps(real))}")


def compare(baseline_rev: str | None):
    """Timings of this tree (and the baseline) in fresh processes, side by side."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    trees = [("new", here)]
    with tempfile.TemporaryDirectory(prefix="geom_baseline_") as tmp:
        if baseline_rev:
            tree = extract(baseline_rev, Path(tmp))
            if tree is None:
                baseline_rev = None
            else:
                trees.append((baseline_rev, str(tree)))
        print(f"{'case':40s} " + "  ".join(f"{name + ': place / cpu / voxelise / peak (generate) / grid err':65s}"
                                           for name, _ in trees)
              + ("  ratio old/new (place, total)" if baseline_rev else ""))
        for case in selected(SPEED_CASES, 1):
            rows = []
            for _, path in trees:
                timed = run_case(path, case, trace=False)
                traced = run_case(path, case, trace=True)
                timed["peak_bytes"], timed["gen_peak_bytes"] = traced["peak_bytes"], traced["gen_peak_bytes"]
                rows.append(timed)
            text = "  ".join(f"{r['place_s']:7.2f} s / {r['place_cpu_s']:6.2f} s / {r['vox_s']:5.2f} s / "
                             f"{r['peak_bytes'] / 2**20:4.0f} MiB ({r['gen_peak_bytes'] / 2**20:4.0f} MiB) "
                             f"{r['grid_error']:+.0e}   " for r in rows)
            if baseline_rev:
                new, old = rows
                text += (f"  x{old['place_s'] / new['place_s']:.1f}, "
                         f"x{(old['place_s'] + old['vox_s']) / (new['place_s'] + new['vox_s']):.1f}")
            print(f"{case[0] + ' ' + case[1]:40s} {text}", flush=True)


def cost_cases():
    """geometry_cost's estimates against measured time and traced peak memory."""
    print(f"{'case':50s} {'grains (est/made)':>18s} {'seconds (est/meas)':>20s} {'peak MiB (est/meas)':>20s}")
    worst_t, worst_m = 1.0, 1.0
    for ink, particles, cell in selected(COST_CASES, 1):
        layer = LayerSpec(parse_ink(ink), parse_particles(particles), 1000.0, (cell, cell))
        for grid in ((64, 64, 32), GRID):
            est = geometry_cost(layer, grid)
            t0 = time.perf_counter()
            real = generate(layer, 1)
            voxelize(real, grid)
            seconds = time.perf_counter() - t0
            tracemalloc.start()                      # a second, traced run (tracing slows numpy)
            voxelize(generate(layer, 1), grid)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            n = len(real.radii_nm)
            worst_t = max(worst_t, est.seconds / seconds, seconds / est.seconds)
            worst_m = max(worst_m, est.peak_bytes / peak, peak / est.peak_bytes)
            print(f"{ink + ' ' + particles + f' {cell:g} {grid}':50s} {est.grains:8d}/{n:<9d} "
                  f"{est.seconds:8.2f}/{seconds:<8.2f}   {est.peak_bytes / 2**20:8.0f}/{peak / 2**20:<8.0f}", flush=True)
    print(f"  worst ratio (either way): time x{worst_t:.2f}, memory x{worst_m:.2f}")


VARIANT_CASES = [
    # (ink, particles, cell nm, label, PackOptions overrides, start fraction or None)
    ("B50", "cylinder:100:isotropic", 1000.0, "default (turns by a push sweep)", {}, None),
    ("B50", "cylinder:100:isotropic", 1000.0, "turns in the contact solve", {"rotation_mode": "coupled"}, None),
    ("B50", "cylinder:100:isotropic", 1000.0, "1 sweep per iteration (like the old packer)", {"sweeps": 1}, None),
    ("B50", "cylinder:100:isotropic", 1000.0, "search refinement 6 steps", {"search_iterations": 6}, None),
    ("B50", "cylinder:100:isotropic", 1000.0, "grow only below 2 % overlap", {"grow_tolerance": 0.02}, None),
    ("B50", "cylinder:100:inplane", 1000.0, "default (turns in the contact solve)", {}, None),
    ("B50", "cylinder:100:inplane", 1000.0, "turns by a push sweep", {"rotation_mode": "push"}, None),
    ("B50", "cylinder:100:inplane", 1000.0, "no kink rows (1 active-set round)", {"rounds": 1}, None),
    ("B50", "cylinder:100:vertical", 1000.0, "default", {}, None),
    ("B50", "cylinder:100:vertical", 1000.0, "10 sweeps", {"sweeps": 10}, None),
    ("Y25+B25", "sphere:30", 2000.0, "default (RSA start at 15 %)", {}, None),
    ("Y25+B25", "sphere:30", 2000.0, "RSA start at 25 % (the old start)", {}, 0.25),
    ("Y25+B25", "sphere:30", 2000.0, "RSA start at 8 %", {}, 0.08),
    ("Y25+B25", "sphere:30", 2000.0, "10 sweeps", {"sweeps": 10}, None),
]


#: Placement of spheroids side by side with the cylinders whose cost model was fitted on the quiet
#: reference machine: (ink, cell nm) × orientation × (cylinder, needles, flakes), 100 nm, seed 1.
SHAPE_CASES = [(ink, cell, f"{shape}:{orientation}" if orientation else shape)
               for ink, cell in (("B15", 2000.0), ("B30", 2000.0), ("B50", 1000.0))
               for orientation in ("isotropic", "inplane", "vertical")
               for shape in ("cylinder:100", "spheroid:100:aspect=3", "spheroid:100:aspect=0.25")] + [
    ("Y7.5+B7.5", 1000.0, f"{shape}:agglutinated")
    for shape in ("cylinder:100", "spheroid:100:aspect=3", "spheroid:100:aspect=0.25")]


def shape_cases():
    """Placement (generate) of each shape in one run: wall and process CPU seconds, and the CPU
    ratio to the cylinders of the same ink and orientation (load-independent, side by side)."""
    print(f"{'case':58s} {'grains':>7s} {'wall s':>8s} {'CPU s':>8s} {'CPU / cylinder':>15s}")
    reference = {}
    for ink, cell, particles in SHAPE_CASES:
        layer = LayerSpec(parse_ink(ink), parse_particles(particles), 1000.0, (cell, cell))
        t0, c0 = time.perf_counter(), time.process_time()
        real = generate(layer, 1)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        key = (ink, layer.particles.orientation, layer.particles.agglutination_kT)
        if layer.particles.shape.name == "cylinder":
            reference[key] = cpu
        ratio = cpu / reference[key] if key in reference else float("nan")
        print(f"{ink + ' ' + particles + f' {cell:g}':58s} {len(real.radii_nm):7d} {wall:8.2f} {cpu:8.2f} "
              f"{ratio:15.2f}", flush=True)


def variant_cases():
    """Placement alone with one knob changed: iterations, seconds, converged."""
    for ink, particles, cell, label, overrides, start in selected(VARIANT_CASES, 1):
        layer = LayerSpec(parse_ink(ink), parse_particles(particles), 1000.0, (cell, cell))
        grains = draw_grains(layer, 1)
        options = PackOptions(**dict({"max_iterations": 1500}, **overrides))
        t0 = time.perf_counter()
        try:
            placed = place(layer, grains, 1, options=options, start_fraction=start)
            outcome = f"{placed.pack.iterations} iterations"
        except ValueError:
            outcome = f"NOT converged in {options.max_iterations} iterations"
        print(f"  {ink + ' ' + particles + f' {cell:g} nm':38s} {label:45s} {outcome:34s} "
              f"{time.perf_counter() - t0:6.2f} s", flush=True)


#: `--only TEXT`: run only the cases whose particle spec contains TEXT (None: all)
ONLY: list[str | None] = [None]


def selected(cases, column: int) -> list:
    """The cases whose particle spec (at `column`) contains the --only text."""
    return [c for c in cases if ONLY[0] is None or ONLY[0] in c[column]]


def limit_case(particles, cell, ladder, thickness=1000.0, seed=1):
    """Largest fraction on the ladder the packer reaches (the generator's own check bypassed)."""
    reached = None
    for phi in ladder:
        layer = LayerSpec(parse_ink(f"B{100 * phi:g}"), parse_particles(particles), thickness, (cell, cell))
        grains = draw_grains(layer, seed)
        t0 = time.perf_counter()
        try:
            placed = place(layer, grains, seed)
            ok = True
        except ValueError:
            ok = False
        extra = ""
        if ok and grains.bodies.shape.oriented:
            extra = (f", <|a_z|> {np.mean(np.abs(placed.axes[:, 2])):.3f} "
                     f"(drawn {np.mean(np.abs(grains.bodies.axes[:, 2])):.3f})")
        print(f"  {particles:30s} {100 * phi:5.1f}%: {'reached' if ok else 'NOT reached'} "
              f"({len(grains)} particles, {time.perf_counter() - t0:.1f} s{extra})", flush=True)
        if not ok:
            break
        reached = phi
    accepted = reachable_limit(LayerSpec(parse_ink("B10"), parse_particles(particles), thickness, (cell, cell)))
    print(f"  -> reached {100 * reached if reached else 0:.3g}% (generator accepts up to {100 * accepted:.3g}%)")


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark; argv are this module's options (none: the speed cases only)."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks.bench_geometry", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--baseline", metavar="REV", help="also time git revision REV, side by side")
    parser.add_argument("--cost", action="store_true", help="compare geometry_cost with measurements")
    parser.add_argument("--limits", action="store_true", help="also search the reachable concentrations")
    parser.add_argument("--variants", action="store_true", help="time the packer's dropped alternatives")
    parser.add_argument("--skip-speed", action="store_true", help="no speed cases")
    parser.add_argument("--only", metavar="TEXT", help="only the cases whose particle spec contains TEXT")
    parser.add_argument("--shapes", action="store_true", help="placement of spheroids beside cylinders")
    args = parser.parse_args([] if argv is None else argv)
    ONLY[0] = args.only
    if not args.skip_speed:
        print(f"== speed: generate + voxelize {GRID}, seed 1 (budgets: spheres placement + voxelisation "
              f"10 s, cylinders placement {CYLINDER_BUDGET_S:g} s)")
        for case in selected(SPEED_CASES, 1):
            speed_case(case)
        print("== timings in fresh processes (wall / CPU of placement, voxelisation, peak traced memory)")
        compare(args.baseline)
    if args.cost:
        print("== geometry_cost against measurements (seed 1, wall clock)")
        cost_cases()
    if args.shapes:
        print("== placement of each shape, side by side (seed 1, H = 1000 nm)")
        shape_cases()
    if args.variants:
        print("== packer variants (placement only, seed 1, H = 1000 nm)")
        variant_cases()
    if args.limits:
        print("== reachable concentrations (thickness 1000 nm)")
        for particles, cell, ladder in selected(LIMIT_CASES, 0):
            limit_case(particles, cell, ladder)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
