"""Render time of the demo scene with the `ink` BSDF against the same scene with Mitsuba's
built-in `roughplastic` in place of every ink (same geometry, lights, textures, spp).

    python -m benchmarks render        # via the runner (make bench)
    python -m benchmarks.bench_render --spp 64 --repeats 5

One warm-up render each (kernel compilation, reported apart), then timed renders alternating
ink / roughplastic; the ratio of the medians is printed. Target: ≤ 1.5×.
"""

from __future__ import annotations

import argparse
import re
import statistics
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "printed_page.xml"
TARGET_RATIO = 1.5

_INK_BSDF = re.compile(r'<bsdf type="ink">(.*?)</bsdf>', re.S)
_COVERAGE = re.compile(r'<texture type="bitmap" name="coverage">.*?</texture>', re.S)


def roughplastic_scene(xml: str) -> str:
    """The scene with each `ink` BSDF replaced by roughplastic (a textured one where the ink
    had a coverage texture, so both scenes do the same texture lookups)."""
    def swap(match: re.Match) -> str:
        tex = _COVERAGE.search(match.group(1))
        diffuse = (tex.group(0).replace('name="coverage"', 'name="diffuse_reflectance"') if tex
                   else '<rgb name="diffuse_reflectance" value="0.4, 0.3, 0.2"/>')
        return f'<bsdf type="roughplastic"><float name="alpha" value="0.1"/>{diffuse}</bsdf>'
    out, n = _INK_BSDF.subn(swap, xml)
    if n == 0:
        raise ValueError(f"{SCENE}: no ink BSDF to replace")
    return out


def _time_render(scene, spp: int, seed: int) -> tuple[float, float]:
    """(wall seconds, CPU seconds of this process's threads) of one synchronised render.

    CPU time is the steadier measure on a shared machine: other jobs stretch wall time."""
    import drjit as dr
    import mitsuba as mi

    dr.sync_thread()
    t0, c0 = time.perf_counter(), time.process_time()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    dr.sync_thread()
    return time.perf_counter() - t0, time.process_time() - c0


def run(spp=64, width=640, height=512, repeats=3, tables=None) -> dict:
    import mitsuba as mi

    import inkbsdf
    from inkbsdf.apps.demo_tables import build_tables
    from inkbsdf.apps.render import load_scene, scene_parameters

    mi.set_variant(inkbsdf.default_variant())
    inkbsdf.register()
    with tempfile.TemporaryDirectory() as tmp:
        if tables is None:
            build_tables(tmp)
        tables = Path(tables or tmp)
        scenes = {"ink": load_scene(SCENE, tables=tables, width=width, height=height, spp=spp)}
        resolver = mi.file_resolver()
        resolver.prepend(str(SCENE.parent))       # the copy's textures resolve as the scene's
        try:
            scenes["roughplastic"] = mi.load_string(roughplastic_scene(SCENE.read_text()),
                                                    **scene_parameters(width=width, height=height, spp=spp))
        finally:
            del resolver[0]
    first = {name: _time_render(scene, spp, seed=0) for name, scene in scenes.items()}
    times = {name: [] for name in scenes}
    for k in range(repeats):
        order = ("ink", "roughplastic") if k % 2 == 0 else ("roughplastic", "ink")
        for name in order:
            times[name].append(_time_render(scenes[name], spp, seed=k + 1))
    med = {name: statistics.median(t[0] for t in ts) for name, ts in times.items()}
    med_cpu = {name: statistics.median(t[1] for t in ts) for name, ts in times.items()}
    return {"variant": mi.variant(), "spp": spp, "size": (width, height), "first": first,
            "times": times, "median": med, "median_cpu": med_cpu,
            "ratio": med["ink"] / med["roughplastic"],
            "ratio_cpu": med_cpu["ink"] / med_cpu["roughplastic"]}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_render", description=__doc__.split("\n\n")[0])
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--width", type=int, default=640)
    p.add_argument("--height", type=int, default=512)
    p.add_argument("--repeats", type=int, default=3, help="timed renders per scene")
    p.add_argument("--tables", default=None, help="folder of demo tables (default: build into a temp dir)")
    args = p.parse_args(argv if argv is not None else [])
    r = run(args.spp, args.width, args.height, args.repeats, args.tables)
    w, h = r["size"]
    print(f"scene {SCENE.name}, {w}×{h}, {r['spp']} spp, {r['variant']}")
    for name in ("ink", "roughplastic"):
        runs = ", ".join(f"{t[0]:.2f}" for t in r["times"][name])
        print(f"  {name:12s} first (incl. compile) {r['first'][name][0]:6.2f} s; timed wall [{runs}] s, "
              f"median {r['median'][name]:.2f} s wall, {r['median_cpu'][name]:.2f} s CPU")
    verdict = "within" if r["ratio"] <= TARGET_RATIO else "ABOVE"
    print(f"  ratio ink / roughplastic (medians): {r['ratio']:.2f}× wall, {r['ratio_cpu']:.2f}× CPU  "
          f"({verdict} target {TARGET_RATIO}×)")
    return 0


if __name__ == "__main__":
    import sys

    sys.exit(main(sys.argv[1:]))
