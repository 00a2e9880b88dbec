"""Render time of the demo scene in `llvm_ad_spectral_polarized` against `llvm_ad_spectral`
(docs/plugin.md, "Polarized variants"), with unpolarised tables (they carry r_s, r_p).

    python -m benchmarks polarized
    python -m benchmarks.bench_polarized --spp 32 --rounds 2 --repeats 3

Each (variant, scene) runs in its own process, processes alternating between the variants: one
warm-up render (kernel compilation, reported apart), then `repeats` timed renders; medians of
wall and CPU time over all rounds. Scenes: the demo with the `ink` BSDF, and the same with
Mitsuba's `roughplastic` in place of every ink (what polarisation costs Mitsuba's own
pipeline); and the BSDF alone (Y30 at coverage 0.8: `sample` + `eval` on 2^20 lanes). Also printed: how far the polarized render's intensity is from the spectral one
(same seed; they differ only through light that meets two polarising surfaces in a row).

Picture: out/bench/polarized.png, the demo seen through Mitsuba's `stokes` integrator
(intensity, degree and angle of linear polarisation), rendered in its own process.
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
OUT = Path("out/bench")
_PATH_INTEGRATOR = '<integrator type="path"><integer name="max_depth" value="$max_depth"/></integrator>'
SCENES = ("ink", "roughplastic")
KINDS = SCENES + ("bsdf",)
BSDF_LANES = 1 << 20


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


def bsdf_alone(tables: str, repeats: int) -> dict:
    """(wall s, CPU s) of `sample` + `eval` of one ink BSDF on BSDF_LANES lanes, after a warm-up."""
    import drjit as dr
    import mitsuba as mi

    bsdf = mi.load_dict({"type": "ink", "filename": str(Path(tables) / "Y30.npz"), "paper": 0.9, "coverage": 0.8})
    rng = np.random.default_rng(0)
    wi = rng.normal(size=(3, BSDF_LANES))
    wi /= np.linalg.norm(wi, axis=0)
    wi[2] = np.abs(wi[2])
    si = dr.zeros(mi.SurfaceInteraction3f, BSDF_LANES)
    si.wi = mi.Vector3f(*[mi.Float(c) for c in wi])
    si.wavelengths = mi.UnpolarizedSpectrum(*[mi.Float(c) for c in rng.uniform(360.0, 830.0, (4, BSDF_LANES))])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    u = rng.random((3, BSDF_LANES))
    u1, u2 = mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2]))
    wo = mi.Vector3f(*[mi.Float(c) for c in wi[[1, 0, 2]]])
    dr.eval(si, u1, u2, wo)
    runs = []
    for _ in range(repeats + 1):
        dr.sync_thread()
        t0, c0 = time.perf_counter(), time.process_time()
        bs, w = bsdf.sample(mi.BSDFContext(), si, u1, u2)
        f = bsdf.eval(mi.BSDFContext(), si, wo)
        dr.eval(bs, w, f)
        dr.sync_thread()
        runs.append((time.perf_counter() - t0, time.process_time() - c0))
    return {"first": runs[0][0], "runs": runs[1:]}


def worker(variant: str, which: str, tables: str, spp: int, width: int, height: int, repeats: int,
           image_out: str | None) -> dict:
    """One process: load the scene in `variant`, warm up, time `repeats` renders (or the BSDF
    alone)."""
    import mitsuba as mi

    import inkbsdf
    from inkbsdf.apps.render import load_scene, scene_parameters

    from .bench_render import roughplastic_scene

    mi.set_variant(variant)
    inkbsdf.register()
    if which == "bsdf":
        return bsdf_alone(tables, repeats)
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


def stokes_picture(tables: str, spp: int, width: int, height: int, path: Path) -> None:
    """Render the demo in llvm_ad_spectral_polarized through the `stokes` integrator and plot
    intensity, degree of linear polarisation (DoLP) and angle of polarisation (AoLP)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import mitsuba as mi
    from matplotlib.colors import hsv_to_rgb

    import inkbsdf
    from inkbsdf.apps.render import scene_parameters

    mi.set_variant(VARIANTS[1])
    inkbsdf.register()
    xml = SCENE.read_text()
    if _PATH_INTEGRATOR not in xml:
        raise ValueError(f"{SCENE}: its integrator is not '{_PATH_INTEGRATOR}'")
    xml = xml.replace(_PATH_INTEGRATOR, f'<integrator type="stokes">{_PATH_INTEGRATOR}</integrator>')
    resolver = mi.file_resolver()
    resolver.prepend(str(SCENE.parent))
    try:
        scene = mi.load_string(xml, **scene_parameters(tables=tables, width=width, height=height, spp=spp))
    finally:
        del resolver[0]
    img = np.array(mi.render(scene, spp=spp))          # RGB, then S0, S1, S2, S3 (RGB each)
    s0, s1, s2 = (img[..., 3 + 3 * k: 6 + 3 * k].mean(axis=-1) for k in range(3))
    dolp = np.hypot(s1, s2) / np.maximum(s0, 1e-6)
    aolp = 0.5 * np.arctan2(s2, s1)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    rgb = np.clip(img[..., :3], 0.0, None) ** (1 / 2.2)
    ax[0].imshow(np.clip(rgb / np.percentile(rgb, 99), 0, 1))
    ax[0].set_title(f"intensity ({VARIANTS[1]})")
    shown = ax[1].imshow(dolp, vmin=0, vmax=0.6, cmap="magma")
    ax[1].set_title("degree of linear polarisation")
    fig.colorbar(shown, ax=ax[1])
    ax[2].imshow(hsv_to_rgb(np.stack([(aolp / np.pi) % 1.0, np.ones_like(dolp), np.clip(dolp / 0.6, 0, 1)], -1)))
    ax[2].set_title("angle of polarisation (hue), DoLP (brightness)")
    for a in ax:
        a.axis("off")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=80)
    print(f"wrote {path} (DoLP: max {dolp.max():.2f}, 99th percentile {np.percentile(dolp, 99):.2f})")


def run(spp=32, width=320, height=256, rounds=2, repeats=3, tables=None) -> dict:
    from inkbsdf.apps.demo_tables import build_tables

    times = {(v, s): [] for v in VARIANTS for s in KINDS}
    first = {key: [] for key in times}
    with tempfile.TemporaryDirectory() as tmp:
        if tables is None:
            build_tables(tmp, polarisation="unpolarised")
        tables = str(tables or tmp)
        for r in range(rounds):
            for which in KINDS:
                for variant in (VARIANTS if r % 2 == 0 else VARIANTS[::-1]):
                    image = str(Path(tmp) / f"{variant}_{which}.npy") if r == 0 and which in SCENES else ""
                    cmd = [sys.executable, "-m", "benchmarks.bench_polarized", "--worker", variant, which,
                           "--tables", tables, "--spp", str(spp), "--width", str(width), "--height",
                           str(height), "--repeats", str(repeats), "--image", image]
                    out = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True).stdout
                    result = json.loads(out.strip().splitlines()[-1])
                    times[(variant, which)].extend(result["runs"])
                    first[(variant, which)].append(result["first"])
        images = {(v, s): np.load(Path(tmp) / f"{v}_{s}.npy") for v in VARIANTS for s in SCENES}
        picture = subprocess.run([sys.executable, "-m", "benchmarks.bench_polarized", "--picture", tables,
                                  "--spp", str(spp), "--width", str(width), "--height", str(height)],
                                 cwd=ROOT, check=True, capture_output=True, text=True).stdout.strip()
    med = {key: (statistics.median(t[0] for t in ts), statistics.median(t[1] for t in ts))
           for key, ts in times.items()}
    diff = {}
    for which in SCENES:
        a, b = images[(VARIANTS[0], which)], images[(VARIANTS[1], which)]
        diff[which] = (float(np.abs(b - a).mean() / np.abs(a).mean()), float(b.mean() / a.mean() - 1.0))
    return {"spp": spp, "size": (width, height), "median": med, "first": first, "image_difference": diff,
            "picture": picture}


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
    p.add_argument("--picture", metavar="TABLES", help=argparse.SUPPRESS)
    args = p.parse_args(argv if argv is not None else [])
    if args.picture:
        stokes_picture(args.picture, args.spp, args.width, args.height, ROOT / OUT / "polarized.png")
        return 0
    if args.worker:
        print(json.dumps(worker(*args.worker, args.tables, args.spp, args.width, args.height, args.repeats,
                                args.image or None)))
        return 0
    r = run(args.spp, args.width, args.height, args.rounds, args.repeats, args.tables)
    w, h = r["size"]
    print(f"scene {SCENE.name}, {w}×{h}, {r['spp']} spp, unpolarised demo tables; medians of "
          f"{args.rounds}×{args.repeats} timed renders, processes alternating")
    for which in KINDS:
        for variant in VARIANTS:
            wall, cpu = r["median"][(variant, which)]
            firsts = ", ".join(f"{t:.2f}" for t in r["first"][(variant, which)])
            print(f"  {which:12s} {variant:28s} {wall:6.2f} s wall {cpu:6.2f} s CPU   (first, incl. "
                  f"compile: {firsts} s)")
        (w0, c0), (w1, c1) = (r["median"][(v, which)] for v in VARIANTS)
        line = f"  {which:12s} polarized / spectral: {w1 / w0:.2f}× wall, {c1 / c0:.2f}× CPU"
        if which in r["image_difference"]:
            mad, bias = r["image_difference"][which]
            line += f"; intensity |Δ|/mean {mad:.2e}, mean ratio − 1 {bias:+.2e}"
        print(line)
    print(f"  {r['picture']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
