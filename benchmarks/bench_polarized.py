"""Render time of the demo scene in `llvm_ad_spectral_polarized` against `llvm_ad_spectral`
(docs/plugin.md, "Polarized variants"), with unpolarised tables (they carry r_s, r_p).

    python -m benchmarks polarized
    python -m benchmarks.bench_polarized --spp 32 --rounds 2 --repeats 3

Each (variant, scene) runs in its own process, processes alternating between the variants: one
warm-up render (kernel compilation, reported apart), then `repeats` timed renders; medians of
wall and CPU time over all rounds. Scenes: the demo with the `ink` BSDF, and the same with
Mitsuba's `roughplastic` in place of every ink (what polarisation costs Mitsuba's own
pipeline). Also printed: how far the polarized render's intensity is from the spectral one
(same seed; they differ only through light that meets two polarising surfaces in a row).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "printed_page.xml"
VARIANTS = ("llvm_ad_spectral", "llvm_ad_spectral_polarized")
SCENES = ("ink", "roughplastic")


def _timed(scene, spp: int, seed: int) -> tuple[float, float, object]:
    """(wall s, CPU s, image) of one synchronised render."""
    import drjit as dr
    import mitsuba as mi

    dr.sync_thread()
    t0, c0 = time.perf_counter(), time.process_time()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    dr.sync_thread()
    return time.perf_counter() - t0, time.process_time() - c0, img


def worker(variant: str, which: str, tables: str, spp: int, width: int, height: int, repeats: int,
           image_out: str | None) -> dict:
    """One process: load the scene in `variant`, warm up, time `repeats` renders."""
    import mitsuba as mi

    import inkbsdf
    from inkbsdf.render import load_scene, scene_parameters

    from .bench_render import roughplastic_scene

    mi.set_variant(variant)
    inkbsdf.register()
    if which == "ink":
        scene = load_scene(SCENE, tables=Path(tables), width=width, height=height, spp=spp)
    else:
        resolver = mi.file_resolver()
        resolver.prepend(str(SCENE.parent))
        try:
            scene = mi.load_string(roughplastic_scene(SCENE.read_text()),
                                   **scene_parameters(width=width, height=height, spp=spp))
        finally:
            del resolver[0]
    first = _timed(scene, spp, seed=0)
    if image_out:
        np.save(image_out, np.asarray(first[2], dtype=np.float32))
    runs = [_timed(scene, spp, seed=k + 1)[:2] for k in range(repeats)]
    return {"first": first[0], "runs": runs}


def run(spp=32, width=320, height=256, rounds=2, repeats=3, tables=None) -> dict:
    from inkbsdf.demo_tables import build_tables

    times = {(v, s): [] for v in VARIANTS for s in SCENES}
    first = {key: [] for key in times}
    with tempfile.TemporaryDirectory() as tmp:
        if tables is None:
            build_tables(tmp, polarisation="unpolarised")
        tables = str(tables or tmp)
        for r in range(rounds):
            for which in SCENES:
                for variant in (VARIANTS if r % 2 == 0 else VARIANTS[::-1]):
                    image = str(Path(tmp) / f"{variant}_{which}.npy") if r == 0 else ""
                    cmd = [sys.executable, "-m", "benchmarks.bench_polarized", "--worker", variant, which,
                           "--tables", tables, "--spp", str(spp), "--width", str(width), "--height",
                           str(height), "--repeats", str(repeats), "--image", image]
                    out = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True).stdout
                    result = json.loads(out.strip().splitlines()[-1])
                    times[(variant, which)].extend(result["runs"])
                    first[(variant, which)].append(result["first"])
        images = {key: np.load(Path(tmp) / f"{key[0]}_{key[1]}.npy") for key in times}
    med = {key: (statistics.median(t[0] for t in ts), statistics.median(t[1] for t in ts))
           for key, ts in times.items()}
    diff = {}
    for which in SCENES:
        a, b = images[(VARIANTS[0], which)], images[(VARIANTS[1], which)]
        diff[which] = (float(np.abs(b - a).mean() / np.abs(a).mean()), float(b.mean() / a.mean() - 1.0))
    return {"spp": spp, "size": (width, height), "median": med, "first": first, "image_difference": diff}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_polarized", description=__doc__.split("\n\n")[0])
    p.add_argument("--spp", type=int, default=32)
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=256)
    p.add_argument("--rounds", type=int, default=2, help="alternating process rounds")
    p.add_argument("--repeats", type=int, default=3, help="timed renders per process")
    p.add_argument("--tables", default=None, help="folder of unpolarised demo tables (default: build them)")
    p.add_argument("--worker", nargs=2, metavar=("VARIANT", "SCENE"), help=argparse.SUPPRESS)
    p.add_argument("--image", default="", help=argparse.SUPPRESS)
    args = p.parse_args(argv if argv is not None else [])
    if args.worker:
        print(json.dumps(worker(*args.worker, args.tables, args.spp, args.width, args.height, args.repeats,
                                args.image or None)))
        return 0
    r = run(args.spp, args.width, args.height, args.rounds, args.repeats, args.tables)
    w, h = r["size"]
    print(f"scene {SCENE.name}, {w}×{h}, {r['spp']} spp, unpolarised demo tables; medians of "
          f"{args.rounds}×{args.repeats} timed renders, processes alternating")
    for which in SCENES:
        for variant in VARIANTS:
            wall, cpu = r["median"][(variant, which)]
            firsts = ", ".join(f"{t:.2f}" for t in r["first"][(variant, which)])
            print(f"  {which:12s} {variant:28s} {wall:6.2f} s wall {cpu:6.2f} s CPU   (first, incl. "
                  f"compile: {firsts} s)")
        (w0, c0), (w1, c1) = (r["median"][(v, which)] for v in VARIANTS)
        mad, bias = r["image_difference"][which]
        print(f"  {which:12s} polarized / spectral: {w1 / w0:.2f}× wall, {c1 / c0:.2f}× CPU; intensity "
              f"|Δ|/mean {mad:.2e}, mean ratio − 1 {bias:+.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
