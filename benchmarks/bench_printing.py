"""Render time of the `ink` BSDF's coverage models and of several overlapping inks.

    python -m benchmarks.bench_printing [--baseline /path/to/previous/checkout] [--spp 32 ...]

Scenes (the demo page, `scenes/printed_page.xml`, tables built into a temp folder):
  1ink-cy   the demo as it is: one ink per BSDF, Clapper–Yule (the default)
  1ink-md   the same with coverage_model = murray-davies (the former formula)
  3ink-cy   the page printed with R30, Y30 (two crossing coverage ramps) and B30 (the text):
            all eight printed primaries are evaluated on the page; overprint tables are the
            exact multilayer films (solver.table.thinfilm_tier.build_stack_table)
  1ink-base the demo with the code of `--baseline` (the BSDF before coverage models)

Each scene (and each BSDF-alone timing: eval + sample on `--lanes` random lanes) runs in a
process of its own (one warm-up, then `--repeats` timed runs; a process that also held the other
scenes measured its 1-ink scene 10 % slower); the processes alternate for `--rounds`. Medians of
wall and CPU time (all threads) are printed, and the ratios the comparisons need; CPU time is the
steadier measure on a shared machine.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "printed_page.xml"

WORKER = r'''
import json, re, statistics, sys, time
from pathlib import Path
import numpy as np
import drjit as dr, mitsuba as mi
import inkbsdf

cfg = json.loads(sys.argv[1])
mi.set_variant(inkbsdf.default_variant())
inkbsdf.register()
scene_path = Path(cfg["scene"])
params = {"tables": cfg["tables"], "width": str(cfg["width"]), "height": str(cfg["height"]),
          "spp": str(cfg["spp"])}

def exact_stack(members):
    """The exact multilayer film of the members (molecular demo inks), top first."""
    from solver.inks import parse_ink
    from solver.table import read_table
    from solver.table.thinfilm_tier import build_stack_table
    from inkbsdf.lut import lut_from_table
    layers = []
    for m in members:
        meta = read_table(m.lut.source).meta
        layers.append((parse_ink(meta["ink"]), float(meta["thickness_nm"])))
    lut0 = members[0].lut
    return lut_from_table(build_stack_table(layers, lut0.wavelengths_nm, lut0.sigma_rad),
                          source="stack:" + "/".join(m.label for m in members))

if any("3ink" in n for n in list(cfg["scenes"]) + list(cfg["bsdfs"])):
    from inkbsdf.inks import set_stack_provider
    set_stack_provider(exact_stack)
scenes = {}
for name, xml in cfg["scenes"].items():
    resolver = mi.file_resolver()
    resolver.prepend(str(scene_path.parent))
    try:
        scenes[name] = mi.load_string(xml, **{k: v for k, v in params.items() if "$" + k in xml})
    finally:
        del resolver[0]

def timed(scene, seed):
    dr.sync_thread()
    t0, c0 = time.perf_counter(), time.process_time()
    img = mi.render(scene, spp=cfg["spp"], seed=seed)
    dr.eval(img); dr.sync_thread()
    return time.perf_counter() - t0, time.process_time() - c0

def lanes_bsdf(d, n):
    """Time of eval + sample of one BSDF on n random lanes (after a warm-up)."""
    rng = np.random.default_rng(0)
    v = rng.normal(size=(2, 3, n)); v /= np.linalg.norm(v, axis=1, keepdims=True); v[:, 2] = np.abs(v[:, 2])
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(*[mi.Float(c) for c in v[0]])
    si.wavelengths = mi.Spectrum(*[mi.Float(c) for c in rng.uniform(360, 830, size=(4, n))])
    si.uv = mi.Point2f(mi.Float(rng.random(n)), mi.Float(rng.random(n)))
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    wo = mi.Vector3f(*[mi.Float(c) for c in v[1]])
    u = [mi.Float(rng.random(n)) for _ in range(3)]
    bsdf = mi.load_dict(d)
    def once():
        dr.sync_thread(); t0 = time.perf_counter(); c0 = time.process_time()
        f = bsdf.eval(mi.BSDFContext(), si, wo)
        bs, w = bsdf.sample(mi.BSDFContext(), si, u[0], mi.Point2f(u[1], u[2]))
        dr.eval(f, bs, w); dr.sync_thread()
        return time.perf_counter() - t0, time.process_time() - c0
    once()
    return once

lane_fns = {n: lanes_bsdf(dict(d, **{k: cfg["tables"] + "/" + v for k, v in d.items() if k.startswith("filename")}),
                          cfg["lanes"])
            for n, d in cfg["bsdfs"].items()}

first = {n: timed(s, 0) for n, s in scenes.items()}
times = {n: [] for n in scenes}
names = list(scenes)
for k in range(cfg["repeats"]):
    for n in (names if k % 2 == 0 else names[::-1]):
        times[n].append(timed(scenes[n], k + 1))
for n, fn in lane_fns.items():
    times[n] = [fn() for _ in range(cfg["repeats"])]
print(json.dumps({"variant": mi.variant(), "first": first, "times": times}))
'''


def md_scene(xml: str) -> str:
    """Every ink BSDF with coverage_model = murray-davies."""
    return xml.replace('<bsdf type="ink">',
                       '<bsdf type="ink"><string name="coverage_model" value="murray-davies"/>')


def three_ink_scene(xml: str, folder: Path) -> str:
    """The page's BSDF as three inks: R30 and Y30 ramps crossing, B30 the text on top."""
    import numpy as np

    n = 256
    ramp = (np.arange(n) + 0.5) / n
    textures = {"ramp_u": np.tile(ramp, (n, 1)), "ramp_v": np.tile(ramp[:, None], (1, n))}
    import mitsuba as mi

    mi.set_variant("scalar_spectral")
    for name, img in textures.items():
        mi.Bitmap(img.astype(np.float32)[..., None], mi.Bitmap.PixelFormat.Y).write(str(folder / f"{name}.exr"))
    start = xml.index('<shape type="rectangle" id="page">')
    b0 = xml.index('<bsdf type="ink">', start)
    b1 = xml.index("</bsdf>", b0) + len("</bsdf>")
    text = xml[b0:b1]
    cov = text[text.index('<texture type="bitmap" name="coverage">'):text.index("</texture>") + len("</texture>")]
    ramp_tex = lambda name, n_: (f'<texture type="bitmap" name="coverage{n_}"><string name="filename" '   # noqa: E731
                                 f'value="{folder / name}.exr"/><boolean name="raw" value="true"/></texture>')
    bsdf = ('<bsdf type="ink"><string name="filename1" value="$tables/R30.npz"/>'
            '<string name="filename2" value="$tables/Y30.npz"/><string name="filename3" value="$tables/B30.npz"/>'
            '<float name="paper" value="$paper"/>' + ramp_tex("ramp_u", 1) + ramp_tex("ramp_v", 2)
            + cov.replace('name="coverage"', 'name="coverage3"') + "</bsdf>")
    return xml[:b0] + bsdf + xml[b1:]


def dot_gain_table() -> None:
    """CIELAB (D65) of one ink at 25/50/75 % under diffuse light seen at 8°, paper 0.9: Clapper–Yule
    against Murray–Davies (solver.printing; the demo inks' default tables: exact thin films)."""
    import numpy as np

    from solver.colour import lab_hue_chroma, spectra_to_lab
    from solver.printing import PrintedInks, ReflectancePredictor
    from solver.table.builder import build_table
    from solver.table.request import table_request

    print("dot gain: L*, C* at coverage c (paper 0.9, diffuse light, view 8°), Clapper–Yule | Murray–Davies")
    for ink in ("R30", "Y30", "B30"):
        table = build_table(table_request(ink))
        wl = table.wavelengths
        printed = PrintedInks((table,))
        cells = []
        for c in (0.25, 0.5, 0.75):
            lab = [spectra_to_lab(wl, ReflectancePredictor.build(
                printed, 0.9, np.radians(8.0), model)([c]), "D65", "2") for model in ("clapper-yule", "murray-davies")]
            cy, md = ((float(x[0]), float(lab_hue_chroma(x)[1])) for x in lab)
            cells.append(f"c={c:.2f}: {cy[0]:5.1f} {cy[1]:5.1f} | {md[0]:5.1f} {md[1]:5.1f}")
        print(f"  {ink:4s} " + ";  ".join(cells))


def predictor_timing(n_mixes: int = 100_000) -> None:
    """Time of ReflectancePredictor on random mixes of R30, Y30, B30 with every overprint (exact
    stacks from the table requests "B30/Y30", …), Clapper–Yule, view 8°."""
    import time

    import numpy as np

    from solver.printing import PrintedInks, ReflectancePredictor, stack_order
    from solver.table.builder import build_table
    from solver.table.request import LAYER_SEPARATOR, table_request

    inks = ("R30", "Y30", "B30")
    printed = PrintedInks.from_provider(
        [build_table(table_request(ink)) for ink in inks],
        lambda s: build_table(table_request(LAYER_SEPARATOR.join(inks[i] for i in stack_order(s)))))
    t0 = time.perf_counter()
    predict = ReflectancePredictor.build(printed, 0.9, np.radians(8.0))
    t1 = time.perf_counter()
    cov = np.random.default_rng(0).random((n_mixes, len(inks)))
    spectra = predict(cov)                                   # warm-up (BLAS threads start)
    runs = []
    for _ in range(5):
        t2 = time.perf_counter()
        predict(cov)
        runs.append(time.perf_counter() - t2)
    best, med = min(runs), sorted(runs)[len(runs) // 2]
    print(f"ReflectancePredictor, 3 inks + 4 overprints, {spectra.shape[-1]} λ: build {1e3 * (t1 - t0):.1f} ms; "
          f"{n_mixes} mixes: median {1e3 * med:.0f} ms ({1e9 * med / n_mixes:.0f} ns per mix), "
          f"best {1e3 * best:.0f} ms")


def run_process(root: Path, cfg: dict) -> dict:
    env = dict(os.environ, PYTHONPATH=str(root))
    out = subprocess.run([sys.executable, "-c", WORKER, json.dumps(cfg)], env=env, cwd=str(root),
                         capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"worker failed ({root}):\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_printing", description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", default=None, help="checkout of the previous code (adds 1ink-base)")
    p.add_argument("--spp", type=int, default=32)
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=256)
    p.add_argument("--repeats", type=int, default=4, help="timed renders per scene and process")
    p.add_argument("--rounds", type=int, default=2, help="alternations of the code versions' processes")
    p.add_argument("--lanes", type=int, default=1 << 20, help="lanes of the BSDF-only timing (eval + sample)")
    p.add_argument("--colour-only", action="store_true",
                   help="only the dot-gain table and the predictor timing (no renders)")
    args = p.parse_args(argv if argv is not None else [])
    dot_gain_table()
    predictor_timing()
    if args.colour_only:
        return 0
    from inkbsdf.apps.demo_tables import build_tables

    xml = SCENE.read_text()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        build_tables(tmp)
        base = {"scene": str(SCENE), "tables": str(tmp), "spp": args.spp, "width": args.width,
                "height": args.height, "repeats": args.repeats, "lanes": args.lanes}
        one = {"type": "ink", "filename": "R30.npz", "coverage": 0.7, "paper": 0.9}
        three = {"type": "ink", "paper": 0.9, "filename1": "R30.npz", "filename2": "Y30.npz",
                 "filename3": "B30.npz", "coverage1": 0.5, "coverage2": 0.4, "coverage3": 0.6}
        new_cfg = dict(base, scenes={"1ink-cy": xml, "1ink-md": md_scene(xml), "3ink-cy": three_ink_scene(xml, tmp)},
                       bsdfs={"lanes:1ink-cy": one, "lanes:1ink-md": dict(one, coverage_model="murray-davies"),
                              "lanes:3ink-cy": three, "lanes:3ink-md": dict(three, coverage_model="murray-davies")})
        runs = [(ROOT, dict(base, scenes={n: x}, bsdfs={})) for n, x in new_cfg["scenes"].items()]
        runs += [(ROOT, dict(base, scenes={}, bsdfs={n: d})) for n, d in new_cfg["bsdfs"].items()]
        if args.baseline:
            old = Path(args.baseline).resolve()
            runs += [(old, dict(base, scenes={"1ink-base": xml}, bsdfs={})),
                     (old, dict(base, scenes={}, bsdfs={"lanes:1ink-base": one}))]
        times: dict = {}
        variant = None
        for k in range(args.rounds):
            for root, cfg in (runs if k % 2 == 0 else runs[::-1]):
                r = run_process(root, cfg)
                variant = r["variant"]
                for name, ts in r["times"].items():
                    times.setdefault(name, []).extend(ts)
    print(f"scene {SCENE.name}, {args.width}×{args.height}, {args.spp} spp, {variant}, "
          f"{args.rounds} rounds × {args.repeats} renders")
    med = {n: (statistics.median(t[0] for t in ts), statistics.median(t[1] for t in ts)) for n, ts in times.items()}
    for name, (wall, cpu) in med.items():
        print(f"  {name:10s} median {wall:6.3f} s wall, {cpu:6.3f} s CPU  "
              f"[{', '.join(f'{t[0]:.2f}' for t in times[name])}]")

    def ratio(a, b, label):
        if a in med and b in med:
            print(f"  {label:34s} {med[a][0] / med[b][0]:.2f}× wall, {med[a][1] / med[b][1]:.2f}× CPU")

    ratio("1ink-cy", "1ink-base", "1 ink, Clapper–Yule / before:")
    ratio("1ink-md", "1ink-base", "1 ink, Murray–Davies / before:")
    ratio("1ink-cy", "1ink-md", "1 ink, Clapper–Yule / Murray–Davies:")
    ratio("3ink-cy", "1ink-cy", "3 overlapping inks / 1 ink:")
    ratio("lanes:1ink-cy", "lanes:1ink-base", "BSDF alone, 1 ink CY / before:")
    ratio("lanes:1ink-md", "lanes:1ink-base", "BSDF alone, 1 ink MD / before:")
    ratio("lanes:3ink-cy", "lanes:1ink-cy", "BSDF alone, 3 inks (8 primaries) / 1:")
    ratio("lanes:3ink-md", "lanes:1ink-md", "BSDF alone, 3 inks MD / 1 ink MD:")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
