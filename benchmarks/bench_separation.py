"""Colour separation and halftoning (solver.apps.separation): speed, accuracy knobs, demo render.

    python -m benchmarks.bench_separation [--quick] [--no-render]

1. the demo photograph (scenes/textures/printed_page_photo.png, 360×270) separated into
   R30/Y30/B30 with each coverage model: time, distinct colours per second, gamut report;
2. accuracy vs time of the solver's knobs (LUT nodes, starts, Broyden updates): on 2000 random
   printable mixes (max ΔE76, targets left unmatched, max coverage error where the map is well
   conditioned) and on 3000 colours of the photograph (how much farther than a brute-force
   search of a 65³ coverage grid the solver's colour is);
3. the print model's throughput (mixes per second);
4. halftoning: texels per second (AM, FM), mean-coverage error;
5. the demo render (640×512, 32 spp) with and without the photograph, processes alternating:
   medians of render wall time and of the process's CPU time.
"""

from __future__ import annotations

import argparse
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PHOTO = ROOT / "scenes" / "textures" / "printed_page_photo.png"
SCENE = ROOT / "scenes" / "printed_page.xml"
INKS = ("R30", "Y30", "B30")


def _timed(fn, repeats=1):
    best = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t0
        best = dt if best is None else min(best, dt)
    return out, best


def photo_separation(printed) -> None:
    from solver.apps.separation import PrintColourModel, Separator, read_srgb8, separate_image

    rgb8 = read_srgb8(PHOTO)
    print(f"\n1. separation of the demo photograph ({rgb8.shape[1]}×{rgb8.shape[0]} px), R30/Y30/B30, paper 0.9, "
          "45:0 D50 (the print's gamut and start grid built first, not timed)")
    for model_name in ("clapper-yule", "murray-davies"):
        model = PrintColourModel.build(printed, 0.9, model_name)
        for mapping in ("clip", "perceptual"):
            separator = Separator.build(model, mapping=mapping)
            result, dt = _timed(lambda: separate_image(separator, rgb8), repeats=2)
            r = result.report
            print(f"  {model_name:14s} {mapping:10s} {dt:5.2f} s (best of 2), {r.unique_colours / dt:7.0f} colours/s; "
                  + " | ".join(r.lines()))


def knob_study(printed, quick: bool) -> None:
    from scipy.spatial import cKDTree

    from solver.apps.separation import PrintColourModel, SolverSettings, read_srgb8, separate_lab, srgb8_to_lab, unique_colours
    from solver.apps.separation.solve import jacobian

    model = PrintColourModel.build(printed, 0.9, "clapper-yule")
    rng = np.random.default_rng(7)
    mixes = rng.random((1000 if quick else 2000, 3))
    targets = model.lab(mixes)
    sigma_min = np.linalg.svd(jacobian(model, mixes, targets, 1e-6), compute_uv=False)[:, -1]
    good = sigma_min > 5.0
    colours, _ = unique_colours(read_srgb8(PHOTO))
    photo_lab = srgb8_to_lab(colours[rng.choice(len(colours), 1500 if quick else 3000, replace=False)])
    axis = np.linspace(0, 1, 65)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    brute, _ = cKDTree(model.lab(grid)).query(photo_lab)
    print(f"\n2. solver knobs (clapper-yule): {len(mixes)} printable mixes ({good.mean():.0%} well conditioned, "
          f"σ_min > 5 ΔE per unit coverage) | {len(photo_lab)} photograph colours vs a 65³ grid search")
    print("  setting                       | time s | max ΔE76 | unmatched | max Δc (cond.) || time s | "
          "worse than grid by > 0.05 | max excess ΔE")
    base = SolverSettings()
    knobs = [("default (25 nodes, 2 starts)", base), ("LUT 9 nodes", replace(base, grid_nodes=9)),
             ("LUT 17 nodes", replace(base, grid_nodes=17)), ("LUT 33 nodes", replace(base, grid_nodes=33)),
             ("1 start", replace(base, starts=1)), ("4 starts", replace(base, starts=4)),
             ("no near-miss restarts", replace(base, near_miss_starts=0)),
             ("Broyden updates", replace(base, broyden=True))]
    for label, settings in knobs:
        sep, t1 = _timed(lambda: separate_lab(model, targets, settings))
        err = np.abs(sep.coverages - mixes).max(axis=-1)
        ph, t2 = _timed(lambda: separate_lab(model, photo_lab, settings))
        excess = ph.delta_e76 - brute
        print(f"  {label:29s} | {t1:6.2f} | {sep.delta_e76.max():8.4f} | {int(np.sum(sep.delta_e76 > settings.tolerance_de)):9d} | "
              f"{err[good].max():14.2e} || {t2:6.2f} | {int(np.sum(excess > 0.05)):25d} | {excess.max():13.3f}")


def throughput(printed) -> None:
    from solver.apps.separation import PrintColourModel

    n = 65536
    c = np.random.default_rng(1).random((n, 3))
    print("\n3. print model throughput (R30/Y30/B30, 8 primaries, 41 λ)")
    for model_name in ("clapper-yule", "murray-davies"):
        model = PrintColourModel.build(printed, 0.9, model_name)
        model.lab(c[:10])
        _, dt = _timed(lambda: model.lab(c), repeats=3)
        print(f"  {model_name:14s} coverages → CIELAB: {n / dt / 1e3:6.0f} k mixes/s")


def halftoning() -> None:
    from solver.apps.separation import TexelGrid, halftone_ink, parse_dots, texture_mean
    from solver.apps.separation.halftone import coverage_at_texels

    y, x = np.mgrid[0:270, 0:360]
    img = np.clip(0.5 + 0.45 * np.sin(x / 23.0) * np.cos(y / 17.0), 0, 1)
    print("\n4. halftoning a 360×270 coverage image, 12 cm wide")
    for dots in ("AM:150", "AM:20", "FM", "none"):
        d = parse_dots(dots)
        grid = TexelGrid.for_print((12.0, 9.0), img.shape, d)
        tex, dt = _timed(lambda: halftone_ink(img, grid, d, 15.0, seed=1))
        target = float(coverage_at_texels(img, grid, slice(0, grid.shape[0])).mean())
        n = grid.shape[0] * grid.shape[1]
        print(f"  {d.label():14s} {grid.shape[1]}×{grid.shape[0]} texels ({grid.dpi:.0f} dpi): {dt:5.2f} s, "
              f"{n / dt / 1e6:5.1f} Mtexel/s, mean coverage error {texture_mean(tex) - target:+.1e}")
    aligned_screen()


def aligned_screen() -> None:
    """A 0° screen of 8 × 8-texel cells: spot-area thresholds (equal between symmetric texels)
    against the cell's ranks (what am_threshold uses)."""
    from solver.apps.separation import am_threshold
    from solver.apps.separation.screens import spot_area

    n, lpi = 8, 25.0
    f = (np.arange(256) + 0.5) / n
    fu = f - np.floor(f) - 0.5
    spot = 0.5 * (np.cos(2 * np.pi * fu)[None, :] + np.cos(2 * np.pi * fu)[:, None])
    naive = spot_area(spot)
    ranked = am_threshold(slice(0, 256), 256, 1.0 / (n * lpi), lpi, 0.0)
    cs = np.linspace(0.01, 0.99, 99)
    err = lambda t: np.abs([np.mean(t < c) - c for c in cs])          # noqa: E731
    print(f"  0° screen, 8×8 texels per cell, coverages 0.01…0.99: max |mean − c| spot-area thresholds "
          f"{err(naive).max():.3f} (c = 0.3 inks {np.mean(naive < 0.3):.3f}), ranked thresholds {err(ranked).max():.4f}")


def _render_once(scene: Path, tables: Path) -> tuple[float, float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([sys.executable, "-m", "inkbsdf.render", str(scene), "--tables", str(tables),
                           "--spp", "32", "-o", str(tables / "bench.exr")], capture_output=True, text=True,
                          cwd=ROOT, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    m = re.search(r"render ([0-9.]+) s \(scene load ([0-9.]+) s\)", proc.stdout)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return float(m.group(1)), float(m.group(2)), cpu


def demo_render(rounds: int) -> None:
    from inkbsdf.apps.demo_tables import build_tables

    xml = SCENE.read_text()
    without = re.sub(r"\n    <!-- the photograph:.*?</shape>\n", "\n", xml, flags=re.S)
    assert without != xml, "no photograph in the demo scene"
    with tempfile.TemporaryDirectory() as tmp:
        tables = Path(tmp)
        build_tables(tables)
        scenes = {"with photo": SCENE, "without photo": SCENE.parent / ".bench_no_photo.xml"}
        scenes["without photo"].write_text(without)
        try:
            times = {k: [] for k in scenes}
            for r in range(rounds):
                for name in (list(scenes) if r % 2 == 0 else list(scenes)[::-1]):
                    times[name].append(_render_once(scenes[name], tables))
        finally:
            scenes["without photo"].unlink()
    print(f"\n5. demo render 640×512, 32 spp, llvm_ad_spectral ({rounds} runs each, alternating processes; "
          "medians; CPU = the whole process, load and JIT included)")
    med = {k: [statistics.median(v[i] for v in t) for i in range(3)] for k, t in times.items()}
    for name, (render, load, cpu) in med.items():
        print(f"  {name:14s} render {render:5.2f} s, scene load {load:4.2f} s, process CPU {cpu:5.1f} s")
    a, b = med["with photo"], med["without photo"]
    ratio = lambda x, y: f"{x / y:.2f}×" if y > 0 else "n/a (nothing to load without it)"   # noqa: E731
    print(f"  with / without: render {ratio(a[0], b[0])}, load {ratio(a[1], b[1])}, CPU {ratio(a[2], b[2])}")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="smaller knob study, 2 render rounds")
    p.add_argument("--no-render", action="store_true", help="skip the demo render timing")
    args = p.parse_args(argv if argv is not None else sys.argv[1:] if __name__ == "__main__" else [])
    from solver.apps.separation import printed_inks

    printed = printed_inks(INKS)
    photo_separation(printed)
    knob_study(printed, args.quick)
    throughput(printed)
    halftoning()
    if not args.no_render:
        demo_render(2 if args.quick else 4)


if __name__ == "__main__":
    main()
