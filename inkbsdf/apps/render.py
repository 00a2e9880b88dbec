"""Render a scene that uses the `ink` BSDF: EXR + sRGB PNG, and the render time.

    python -m inkbsdf.render scenes/printed_page.xml --tables out/tables --spp 64 \\
        -o out/printed_page.exr --png out/printed_page.png [--width 640 --height 400]

The table folder reaches the scene as the parameter `$tables` (file names `<ink>.npz`, as
`make tables` writes them); `--width/--height/--spp` as `$width/$height/$spp` when the scene
declares them. Without `--spp` the scene's own sample count is used (its sensor's sampler, e.g.
`<default name="spp">`). Bad input: one line on stderr, exit status 2, before any work;
Ctrl-C: exit status 130, promptly.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from solver.apps.cli import package_version
from solver.apps.cli.logs import add_verbose, configure_logging
from solver.apps.cli.parsing import DefaultsFormatter, OneLineParser, interrupted_word, run_guarded, writable_output
from solver.interrupts import exit_status, raising
from solver.seeds import checked_seed

from inkbsdf.errors import loader_problem


#: the program as its usage and error lines name it
PROG = "python -m inkbsdf.render"
#: Samples (pixels × spp) one `mi.render` can take: above it Mitsuba 3.9 splits the render into
#: passes, and that segfaults (probed: 2×2 px × 1.1e9 spp).
MAX_SAMPLES = 2**32
#: memory of a rendered image per pixel, bytes: Mitsuba's film, the developed image and its NumPy
#: copy (peak RSS growth of a 1024×1024, 4-spp path render in llvm_ad_spectral: 52 B per pixel;
#: the samples are traced in chunks, so spp adds little)
IMAGE_BYTES_PER_PIXEL = 64


@dataclass(frozen=True)
class RenderResult:
    image: object            # linear RGB, numpy [H, W, 3]
    load_s: float            # scene loading (tables read, textures loaded)
    render_s: float          # mi.render including kernel compilation, synchronised
    spp: int                 # samples per pixel used


class SceneLoadError(ValueError):
    """A scene failed to load; the message is the underlying problem, without the traceback."""


class UsageError(ValueError):
    """Bad command-line input; the message names the option and the fix."""


def scene_parameters(tables=None, width=None, height=None, spp=None) -> dict:
    """Mitsuba `load_file` parameters; None values are left to the scene's defaults."""
    params = {"tables": str(Path(tables).resolve()) if tables is not None else None,
              "width": width, "height": height, "spp": spp}
    return {k: str(v) for k, v in params.items() if v is not None}


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
        raise SceneLoadError(loader_problem(exc) if str(scene_path) in str(exc)
                             else f"{scene_path}: {loader_problem(exc)}") from None


def scene_defaults(xml_text: str) -> dict:
    """{name: value} of a scene file's `<default name=… value=…/>`."""
    return dict(re.findall(r'<default\s+name="(\w+)"\s+value="([^"]*)"', xml_text))


def planned_image(scene_path, width=None, height=None, spp=None) -> tuple[int, int, int | None] | None:
    """(width, height, spp or None) a render of the scene file will have, as far as the file and
    the options tell before it loads (None: its size is not a parameter with a default)."""
    text = Path(scene_path).read_text(errors="replace")
    taken, defaults = scene_parameter_names(text), scene_defaults(text)

    def value(name, given):
        if given is not None and name in taken:
            return int(given)
        try:
            return int(defaults[name])
        except (KeyError, ValueError):
            return None

    w, h = value("width", width), value("height", height)
    return None if w is None or h is None else (w, h, spp if spp is not None else value("spp", None))


def check_image(width: int, height: int, spp: int | None) -> None:
    """Refuse (UsageError) an image this machine cannot hold, or more samples than one render
    takes (MAX_SAMPLES; spp None: at least one per pixel)."""
    from solver.table.preflight import memory_exceeded

    problem = memory_exceeded(width * height * IMAGE_BYTES_PER_PIXEL, f"{IMAGE_BYTES_PER_PIXEL} B per pixel")
    if problem:
        raise UsageError(f"a {width}×{height} image {problem}: lower --width/--height")
    samples = width * height * (spp or 1)
    if samples > MAX_SAMPLES:
        raise UsageError(f"{width}×{height} pixels × {spp or 1} spp = {samples:,} samples, over Mitsuba's limit "
                         f"of 2^32 per render (its multi-pass fallback crashes in 3.9): lower --spp or the size")


def scene_spp(scene) -> int:
    """Samples per pixel the scene's first sensor asks for (its sampler's sample count)."""
    return int(scene.sensors()[0].sampler().sample_count())


def render_loaded(scene, spp=None, seed=0) -> tuple:
    """(image as numpy [H, W, 3], seconds) of `mi.render`, synchronised; spp None: the scene's."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    t0 = time.perf_counter()
    try:
        image = mi.render(scene, spp=spp or 0, seed=seed)
        dr.eval(image)
        dr.sync_thread()
    except Exception as exc:     # e.g. a scene without an integrator
        raise SceneLoadError(f"cannot render: {loader_problem(exc)}") from None
    return np.asarray(image, dtype=np.float32), time.perf_counter() - t0


def render_scene(scene_path, tables=None, spp=None, width=None, height=None, seed=0) -> RenderResult:
    """Load and render with the active variant (the `ink` BSDF must be registered); spp None:
    the scene's own sample count."""
    t0 = time.perf_counter()
    scene = load_scene(scene_path, tables=tables, width=width, height=height, spp=spp)
    load_s = time.perf_counter() - t0
    image, render_s = render_loaded(scene, spp, seed)
    return RenderResult(image=image, load_s=load_s, render_s=render_s, spp=spp or scene_spp(scene))


# ------------------------------------------------------------------------- command line
def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number ≥ 1, got '{text}'") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be ≥ 1, got {value}")
    return value


def _finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got '{text}'") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got '{text}'")
    return value


class _Parser(OneLineParser):
    usage_error = UsageError


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, description=__doc__.split("\n\n")[0],
                formatter_class=DefaultsFormatter)
    p.add_argument("--version", action="version", version=f"inkbsdf.render {package_version()}")
    add_verbose(p)
    p.add_argument("scene", help="Mitsuba scene file (.xml)")
    p.add_argument("--tables", default=None, help="folder of ink tables, passed as $tables")
    p.add_argument("--spp", type=_positive_int, default=None,
                   help="samples per pixel (default: the scene's own, e.g. its <default name=\"spp\">)")
    p.add_argument("-o", "--output", default=None, help="EXR file (linear RGB); at least one of -o and --png")
    p.add_argument("--png", default=None, help="an sRGB PNG (with -o: also)")
    p.add_argument("--width", type=_positive_int, default=None, help="image width (scene default if unset)")
    p.add_argument("--height", type=_positive_int, default=None, help="image height (scene default if unset)")
    p.add_argument("--exposure", type=_finite_float, default=0.0, help="PNG exposure, stops")
    p.add_argument("--seed", type=int, default=0, help="sampler seed, an integer in [0, 2^32)")
    p.add_argument("--workers", type=_positive_int, default=None,
                   help="processes for tables a scene load builds (in-scene inks; default one per core)")
    p.add_argument("--variant", default=None,
                   help="Mitsuba variant (default: cuda_ad_spectral with a GPU, else llvm_ad_spectral)")
    return p


def main(argv=None) -> int:
    """The command; returns the exit status (2: bad input, told in one line on stderr).
    Warnings are said as one `warning: …` line each on stderr."""
    return run_guarded(lambda: _main(argv), PROG)      # interrupts: `run` (the main thread) handles them


def _main(argv) -> int:
    from inkbsdf.variant import VariantError, select_variant

    args = build_parser().parse_args(argv)
    configure_logging(args.verbose, builds=True)
    checked_seed(args.seed, "--seed", UsageError)
    if not (args.output or args.png):
        raise UsageError("give -o OUT.exr (linear), --png OUT.png (sRGB), or both")
    exr = writable_output(args.output, ".exr", "-o/--output") if args.output else None
    png = writable_output(args.png, ".png", "--png") if args.png else None
    outputs = [p for p in (exr, png) if p is not None]
    if len(set(p.absolute() for p in outputs)) < len(outputs):
        raise UsageError("-o/--output and --png name the same file")
    if not Path(args.scene).is_file():
        raise UsageError(f"{args.scene}: scene file not found")
    planned = planned_image(args.scene, args.width, args.height, args.spp)
    if planned:
        check_image(*planned)                  # before any table is built or read
    import inkbsdf
    from inkbsdf.apps.imageio import write_exr, write_png
    from solver.table.executor import default_workers

    # this entry point is guarded, so spawned table workers are safe here (inkbsdf/source.py)
    from inkbsdf.source import set_build_workers

    set_build_workers(args.workers or default_workers())
    try:
        variant = select_variant(args.variant)
    except VariantError as exc:
        raise UsageError(f"--variant: {exc}") from None
    inkbsdf.register()
    t0 = time.perf_counter()
    try:
        scene = load_scene(args.scene, tables=args.tables, width=args.width, height=args.height, spp=args.spp)
    finally:
        set_build_workers(None)                # process-wide: for this command's scene load only
    load_s = time.perf_counter() - t0
    spp = args.spp or scene_spp(scene)
    w, h = scene.sensors()[0].film().crop_size()
    check_image(w, h, spp)
    print(f"{args.scene}: {w}×{h}, {spp} spp" + (" (the scene's default)" if args.spp is None else "")
          + f", {variant}: rendering…", flush=True)
    image, render_s = render_loaded(scene, args.spp, args.seed)
    try:
        if exr:
            write_exr(exr, image)
        if png:
            write_png(png, image, args.exposure)
    except OSError as exc:
        raise UsageError(f"cannot write {exc.filename or outputs[0]}: {exc.strerror or exc}") from None
    print(f"render {render_s:.1f} s (scene load {load_s:.1f} s) → " + ", ".join(map(str, outputs)))
    return 0


def run(argv=None) -> int:
    """`python -m inkbsdf.render`: `main` in a worker thread while this (main) thread waits, so
    that Ctrl-C stops a render or a table build within ~0.1 s (the render's kernel runs without
    returning to Python), stops the table workers and exits 130 without a traceback."""
    import threading

    outcome: dict = {}

    def work():
        try:
            outcome["status"] = main(argv)
        except BaseException as exc:      # a bug: re-raised in the main thread, with its traceback
            outcome["error"] = exc

    # after os._exit below, multiprocessing's resource tracker unlinks the semaphores left (tqdm's
    # lock of its progress bars) as it should, and would warn that it had to: expected, not shown
    sys.warnoptions.append("ignore:resource_tracker:UserWarning")
    worker = threading.Thread(target=work, name="inkbsdf-render", daemon=True)
    try:
        with raising():             # SIGTERM: the same, "terminated", exit 143
            worker.start()
            while worker.is_alive():
                worker.join(0.05)
    except KeyboardInterrupt as exc:
        _stop_children()
        print(f"\n{PROG}: {interrupted_word(exc)}: stopped", file=sys.stderr, flush=True)
        sys.stdout.flush()
        os._exit(exit_status(exc))         # the render kernel cannot be cancelled: leave now
    if "error" in outcome:
        raise outcome["error"]
    return outcome["status"]


def _stop_children(timeout_s: float = 2.0) -> None:
    """Terminate the worker processes this process started (a table build's pool), by their
    handles (they also die with this process: solver/table/executor.py)."""
    import multiprocessing

    children = multiprocessing.active_children()
    for child in children:
        child.terminate()
    deadline = time.monotonic() + timeout_s
    for child in children:
        child.join(max(0.0, deadline - time.monotonic()))
        if child.is_alive():
            child.kill()


if __name__ == "__main__":
    sys.exit(run())
