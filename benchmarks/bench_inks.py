"""Cost of several overlapping inks in one `ink` BSDF against one ink (docs/plugin.md,
"Performance"): a 48×32, 4-spp render of a patch under a constant sky (first render: kernel
compilation included, then the median of timed renders), the BSDF alone (eval + sample on 2¹⁸
random lanes, median), and the process's resident memory added by the first render.

    python -m benchmarks inks
    python -m benchmarks.bench_inks [--inks 1 4] [--repeats 5]

Each configuration runs in its own process with an empty kernel cache (in memory and on disk)
and a clean memory figure.
Inks R30, Y30, B30, G30 (molecular: their overprints are exact multilayer films built through
the table cache), coverages 0.5 each: every one of the 2^k − 1 printed primaries occurs.
Targets (issue 24): 4 inks ≤ 1.5× one ink per sample, ≤ +100 MiB at render.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INKS = ("R30", "Y30", "B30", "G30")
TARGET_RATIO, TARGET_MIB = 1.5, 100.0

WORKER = r'''
import json, resource, statistics, sys, time
import numpy as np
import drjit as dr
import mitsuba as mi
cfg = json.loads(sys.argv[1])
mi.set_variant(cfg["variant"])
import inkbsdf

def rss_mib():
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * resource.getpagesize() / 2**20

k = cfg["n_inks"]
rng = np.random.default_rng(7)

def coverage(i):
    if cfg["coverage"] == "number":
        return 0.5
    if cfg["coverage"] == "halftone":       # 0 or 1 per texel, half of them inked
        data, filt = (rng.random((64, 64, 1)) < 0.5).astype(np.float32), "nearest"
    else:                                   # contone: any value, filtered
        data, filt = rng.random((64, 64, 1)).astype(np.float32), "bilinear"
    return {"type": "bitmap", "data": mi.TensorXf(data), "raw": True, "filter_type": filt}

if k == 1:
    bsdf = {"type": "ink", "ink": cfg["inks"][0], "coverage": coverage(0), "paper": 0.9}
else:
    bsdf = {"type": "ink", "paper": 0.9}
    for i in range(k):
        bsdf[f"ink{i + 1}"] = cfg["inks"][i]
        bsdf[f"coverage{i + 1}"] = coverage(i)
T = mi.ScalarTransform4f
scene = mi.load_dict({"type": "scene", "integrator": {"type": "path", "max_depth": 3},
    "sensor": {"type": "perspective", "fov": 40,
               "to_world": T().look_at(origin=[0, -2.5, 2.5], target=[0, 0, 0], up=[0, 0, 1]),
               "film": {"type": "hdrfilm", "width": 48, "height": 32}},
    "sky": {"type": "constant", "radiance": 1.0},
    "patch": {"type": "rectangle", "bsdf": bsdf}})
dr.sync_thread()
before = rss_mib()

def render(seed):
    dr.sync_thread(); t0 = time.perf_counter()
    img = mi.render(scene, spp=4, seed=seed); dr.eval(img); dr.sync_thread()
    return time.perf_counter() - t0

first = render(0)
after = rss_mib()
renders = [render(s + 1) for s in range(cfg["repeats"])]

n = 1 << 18
rng = np.random.default_rng(0)
v = rng.normal(size=(2, 3, n)); v /= np.linalg.norm(v, axis=1, keepdims=True); v[:, 2] = np.abs(v[:, 2])
si = dr.zeros(mi.SurfaceInteraction3f, n)
si.wi = mi.Vector3f(*[mi.Float(c) for c in v[0]])
si.wavelengths = mi.Spectrum(*[mi.Float(c) for c in rng.uniform(360, 830, size=(4, n))])
si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
si.uv = mi.Point2f(mi.Float(rng.random(n)), mi.Float(rng.random(n)))
wo = mi.Vector3f(*[mi.Float(c) for c in v[1]])
u = [mi.Float(rng.random(n)) for _ in range(3)]
b = scene.shapes()[0].bsdf()
def lanes():
    dr.sync_thread(); t0 = time.perf_counter()
    f = b.eval(mi.BSDFContext(), si, wo)
    bs, w = b.sample(mi.BSDFContext(), si, u[0], mi.Point2f(u[1], u[2]))
    dr.eval(f, bs, w); dr.sync_thread()
    return time.perf_counter() - t0
lanes()
alone = [lanes() for _ in range(cfg["repeats"])]
print(json.dumps({"first_s": first, "render_s": statistics.median(renders), "lanes_s": statistics.median(alone),
                  "added_mib": after - before}))
'''


def run(n_inks: int, repeats: int, variant: str, cache: str, coverage: str = "number") -> dict:
    cfg = {"n_inks": n_inks, "inks": INKS, "repeats": repeats, "variant": variant, "coverage": coverage}
    # a fresh HOME: Dr.Jit's on-disk kernel cache (~/.drjit) empty, so the first render compiles
    env = dict(os.environ, INKBSDF_CACHE=cache, HOME=tempfile.mkdtemp(prefix="inkbsdf_bench_home_"))
    out = subprocess.run([sys.executable, "-c", WORKER, json.dumps(cfg)], capture_output=True, text=True,
                         cwd=ROOT, env=env, timeout=1800)
    if out.returncode != 0:
        raise RuntimeError(out.stderr[-2000:])
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--inks", type=int, nargs="+", default=[1, 4])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--variant", default="llvm_ad_spectral")
    parser.add_argument("--coverage", nargs="+", default=["number", "halftone", "contone"],
                        choices=("number", "halftone", "contone"),
                        help="coverages: 0.5 everywhere; 64×64 bitmaps of 0 or 1 (half inked, nearest); "
                             "of uniform random values (bilinear)")
    args = parser.parse_args(argv)
    from benchmarks.yardstick import yardstick_s

    cache = tempfile.mkdtemp(prefix="inkbsdf_bench_inks_")
    run(max(args.inks), 1, args.variant, cache)          # build the stack tables (not timed)
    print(f"{args.variant}; yardstick {yardstick_s():.3f} s; 48×32 px, 4 spp, path; BSDF alone: 2^18 lanes")
    print(f"{'coverage':>8s} {'inks':>4s} {'first render s':>15s} {'render s':>9s} {'BSDF alone s':>13s} "
          f"{'+MiB at render':>15s}")
    for mode in args.coverage:
        got = {}
        for k in args.inks:
            got[k] = r = run(k, args.repeats, args.variant, cache, mode)
            print(f"{mode:>8s} {k:4d} {r['first_s']:15.2f} {r['render_s']:9.3f} {r['lanes_s']:13.4f} "
                  f"{r['added_mib']:15.1f}", flush=True)
        if 1 in got:
            for k in (k for k in got if k != 1):
                print(f"{mode:>8s} {k} inks / 1 ink: first render {got[k]['first_s'] / got[1]['first_s']:.2f}×, render "
                      f"{got[k]['render_s'] / got[1]['render_s']:.2f}×, BSDF alone "
                      f"{got[k]['lanes_s'] / got[1]['lanes_s']:.2f}× (target ≤ {TARGET_RATIO}×); "
                      f"+{got[k]['added_mib']:.0f} MiB (target ≤ {TARGET_MIB:.0f})")


if __name__ == "__main__":
    main(sys.argv[1:])
