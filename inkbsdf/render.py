"""Render a scene that uses the `ink` BSDF: EXR + sRGB PNG, and the render time.

    python -m inkbsdf.render scenes/printed_page.xml --tables out/tables --spp 64 \\
        -o out/printed_page.exr --png out/printed_page.png [--width 640 --height 400]

The table folder reaches the scene as the parameter `$tables` (file names `<ink>.npz`, as
`make tables` writes them); `--width/--height/--spp` as `$width/$height/$spp` when the scene
declares them.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class RenderResult:
    image: object            # linear RGB, numpy [H, W, 3]
    load_s: float            # scene loading (tables read, textures loaded)
    render_s: float          # mi.render including kernel compilation, synchronised


class SceneLoadError(RuntimeError):
    """A scene failed to load; the message is the underlying problem, without the traceback."""


def scene_parameters(tables=None, width=None, height=None, spp=None) -> dict:
    """Mitsuba `load_file` parameters; None values are left to the scene's defaults."""
    params = {"tables": str(Path(tables).resolve()) if tables is not None else None,
              "width": width, "height": height, "spp": spp}
    return {k: str(v) for k, v in params.items() if v is not None}


def _problem(exc: Exception) -> str:
    """The line of a Mitsuba loader error that says what went wrong (it embeds a traceback)."""
    lines = [ln.strip() for ln in str(exc).splitlines() if ln.strip()]
    for ln in reversed(lines):
        if ln.startswith(("TableError:", "VariantError:", "ValueError:", "FileNotFoundError:")):
            return ln.split(":", 1)[1].strip()
    return lines[0] if lines else repr(exc)


def scene_parameter_names(xml_text: str) -> set:
    """Parameters a scene file takes: its `<default name=…>` and its `$name` references."""
    return set(re.findall(r'<default\s+name="(\w+)"', xml_text)) | set(re.findall(r"\$(\w+)", xml_text))


def load_scene(path, **params):
    """Load a scene file with those of `scene_parameters(**params)` it takes (Mitsuba refuses
    unused ones; the others are dropped with a warning); raise SceneLoadError on failure."""
    import mitsuba as mi

    scene_path = Path(path)
    if not scene_path.is_file():
        raise SceneLoadError(f"{scene_path}: scene file not found")
    wanted = scene_parameters(**params)
    taken = scene_parameter_names(scene_path.read_text(errors="replace"))
    dropped = sorted(set(wanted) - taken - {"spp"})      # spp also reaches mi.render directly
    if dropped:
        warnings.warn(f"{scene_path} takes no parameter {', '.join('$' + d for d in dropped)}; ignored",
                      stacklevel=2)
    try:
        return mi.load_file(str(scene_path), **{k: v for k, v in wanted.items() if k in taken})
    except Exception as exc:   # Mitsuba wraps plugin errors in RuntimeError with a traceback
        raise SceneLoadError(f"{scene_path}: {_problem(exc)}") from None


def render_scene(scene_path, tables=None, spp=64, width=None, height=None, seed=0) -> RenderResult:
    """Load and render with the active variant (the `ink` BSDF must be registered)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    t0 = time.perf_counter()
    scene = load_scene(scene_path, tables=tables, width=width, height=height, spp=spp)
    t1 = time.perf_counter()
    try:
        image = mi.render(scene, spp=spp, seed=seed)
    except Exception as exc:     # e.g. a scene without an integrator
        raise SceneLoadError(f"{scene_path}: cannot render: {_problem(exc)}") from None
    dr.eval(image)
    dr.sync_thread()
    t2 = time.perf_counter()
    return RenderResult(image=np.asarray(image, dtype=np.float32), load_s=t1 - t0, render_s=t2 - t1)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m inkbsdf.render", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("scene", help="Mitsuba scene file (.xml)")
    p.add_argument("--tables", default=None, help="folder of ink tables, passed as $tables")
    p.add_argument("--spp", type=int, default=64, help="samples per pixel")
    p.add_argument("-o", "--output", required=True, help="EXR file (linear RGB)")
    p.add_argument("--png", default=None, help="also write an sRGB PNG here")
    p.add_argument("--width", type=int, default=None, help="image width (scene default if unset)")
    p.add_argument("--height", type=int, default=None, help="image height (scene default if unset)")
    p.add_argument("--exposure", type=float, default=0.0, help="PNG exposure, stops")
    p.add_argument("--seed", type=int, default=0, help="sampler seed")
    p.add_argument("--workers", type=int, default=None,
                   help="processes for tables a scene load builds (in-scene inks; default one per core)")
    p.add_argument("--variant", default=None,
                   help="Mitsuba variant (default: cuda_ad_spectral with a GPU, else llvm_ad_spectral)")
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if args.spp < 1:
        print("error: --spp must be ≥ 1", file=sys.stderr)
        return 2
    import mitsuba as mi

    import inkbsdf
    from solver.table.executor import default_workers
    from inkbsdf.imageio import write_exr, write_png

    # this entry point is guarded, so spawned table workers are safe here (inkbsdf/source.py)
    from inkbsdf.source import set_build_workers

    set_build_workers(args.workers or default_workers())
    try:
        mi.set_variant(args.variant or inkbsdf.default_variant())
        inkbsdf.register()
        result = render_scene(args.scene, tables=args.tables, spp=args.spp, width=args.width,
                              height=args.height, seed=args.seed)
    except (SceneLoadError, inkbsdf.VariantError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    write_exr(args.output, result.image)
    if args.png:
        write_png(args.png, result.image, args.exposure)
    h, w = result.image.shape[:2]
    print(f"{args.scene}: {w}×{h}, {args.spp} spp, {mi.variant()}: render {result.render_s:.1f} s "
          f"(scene load {result.load_s:.1f} s) → {args.output}" + (f", {args.png}" if args.png else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
