"""Speed and reach of the geometry generator (issue: ≤ 10 s and ≤ 60 s cases, on 2 cores).

    python -m benchmarks.bench_geometry            # the speed cases
    python -m benchmarks.bench_geometry --limits   # also search the reachable concentrations (slow)

Prints, per case: seconds for placement (generate) and voxelisation separately, particle count,
achieved fractions, relative error of the grid's pigment volume, packer statistics and the peak
traced memory (tracemalloc, numpy buffers included).
"""

from __future__ import annotations

import argparse
import sys
import time
import tracemalloc

import numpy as np

from solver.geometry import LayerSpec, find_overlaps, generate, parse_particles, voxelize
from solver.geometry.generate import _particles, _place
from solver.geometry.limits import reachable_limit
from solver.inks import parse_ink

SPEED_CASES = [
    # (ink, particles, cell nm, thickness nm, grid, budget s)
    ("B50", "sphere:100", 2000.0, 1000.0, (128, 128, 64), 10.0),
    ("B50", "sphere:30", 2000.0, 1000.0, (128, 128, 64), 60.0),
    ("B50", "cylinder:100:isotropic", 2000.0, 1000.0, (128, 128, 64), None),
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
]


def speed_case(ink, particles, cell, thickness, grid, budget, seed=1):
    layer = LayerSpec(parse_ink(ink), parse_particles(particles), thickness, (cell, cell))
    tracemalloc.start()
    t0 = time.perf_counter()
    real = generate(layer, seed)
    t1 = time.perf_counter()
    vox = voxelize(real, grid)
    t2 = time.perf_counter()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    exact = float(np.sum(real.volumes_nm3))
    grid_volume = sum(vox.volume_nm3(c) for c in real.population_codes)
    fractions = ", ".join(f"{c} {100 * f:.4f}%" for c, f in real.achieved_fractions.items())
    total = t2 - t0
    verdict = "" if budget is None else f"  [{'within' if total <= budget else 'OVER'} {budget:g} s]"
    print(f"{ink} {particles} in {cell:g}x{cell:g}x{thickness:g} nm -> grid {grid}:")
    print(f"  particles {len(real.radii_nm)}, achieved {fractions}")
    print(f"  placement {t1 - t0:.2f} s ({real.stats.method}), voxelisation {t2 - t1:.2f} s "
          f"({vox.lines_per_voxel}x{vox.lines_per_voxel} lines/column), total {total:.2f} s{verdict}")
    if real.stats.pack is not None:
        p = real.stats.pack
        print(f"  packer: {p.iterations} iterations, {p.rebuilds} list builds, escapes {p.escapes}, "
              f"{p.seconds:.2f} s; RSA {real.stats.rsa_tries} tries at size x{real.stats.rsa_scale:.3f}")
    if real.shape == "cylinder":
        print(f"  <|a_z|> = {np.mean(np.abs(real.axes[:, 2])):.3f}")
    print(f"  grid pigment volume / particle volume - 1 = {grid_volume / exact - 1:+.2e}; "
          f"overlapping pairs {len(find_overlaps(real))}; peak traced memory {peak / 2**20:.0f} MiB")
    return total


def limit_case(particles, cell, ladder, thickness=1000.0, seed=1):
    """Largest fraction on the ladder the packer reaches (the generator's own check bypassed)."""
    reached = None
    for phi in ladder:
        layer = LayerSpec(parse_ink(f"B{100 * phi:g}"), parse_particles(particles), thickness, (cell, cell))
        seeds = np.random.SeedSequence(seed).spawn(5)
        bodies, walls, _, _ = _particles(layer, seeds)
        t0 = time.perf_counter()
        try:
            _, axes, stats = _place(layer, bodies, walls, np.random.default_rng(seeds[3]))
            ok = True
        except ValueError:
            ok = False
        extra = ""
        if ok and bodies.shape == "cylinder":
            extra = f", <|a_z|> {np.mean(np.abs(axes[:, 2])):.3f} (drawn {np.mean(np.abs(bodies.axes[:, 2])):.3f})"
        print(f"  {particles:24s} {100 * phi:5.1f}%: {'reached' if ok else 'NOT reached'} "
              f"({len(bodies)} particles, {time.perf_counter() - t0:.1f} s{extra})", flush=True)
        if not ok:
            break
        reached = phi
    accepted = reachable_limit(LayerSpec(parse_ink("B10"), parse_particles(particles), thickness, (cell, cell)))
    print(f"  -> reached {100 * reached if reached else 0:.3g}% (generator accepts up to {100 * accepted:.3g}%)")


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark; argv are this module's options (none: the speed cases only)."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks.bench_geometry", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--limits", action="store_true", help="also search the reachable concentrations")
    parser.add_argument("--skip-speed", action="store_true", help="only the limits")
    args = parser.parse_args([] if argv is None else argv)
    if not args.skip_speed:
        print("== speed (placement + voxelisation)")
        for case in SPEED_CASES:
            speed_case(*case)
    if args.limits:
        print("== reachable concentrations (thickness 1000 nm)")
        for particles, cell, ladder in LIMIT_CASES:
            limit_case(particles, cell, ladder)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
