"""Derivatives of the `ink` BSDF under Mitsuba's differentiable integrators, and an inverse
rendering (docs/plugin.md, "Differentiable rendering").

    python -m benchmarks gradients
    python -m benchmarks.bench_gradients [--spp 256] [--iterations 80]

1. d(mean image)/d(coverage) and d/d(paper albedo) of an R30 patch (coverage 0.5, paper 0.9,
   constant sky, orthographic view 30° off the normal; the scene of tests/test_bsdf_gradients.py)
   by `prb`, `direct_projective` and `path` against central finite differences of the primal
   image rendered with the same seed; in `llvm_ad_spectral` and `llvm_ad_spectral_polarized`.
2. `scenes/inverse_coverage.py`: a 64×64 coverage map recovered from a rendered target image;
   the map's RMS error, iterations and wall time (with the yardstick measured in the same run).
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
STEP = 0.02


def _load_scene_module(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "scenes" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module            # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def patch_scene(mi, table, integrator):
    T = mi.ScalarTransform4f
    s = np.radians(30.0)
    return mi.load_dict({
        "type": "scene", "integrator": {"type": integrator, "max_depth": 2},
        "sensor": {"type": "orthographic",
                   "to_world": T().look_at(origin=[3 * np.sin(s), 0, 3 * np.cos(s)], target=[0, 0, 0],
                                           up=[0, 0, 1]) @ T().scale([0.2, 0.2, 1]),
                   "film": {"type": "hdrfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent"}},
        "sky": {"type": "constant", "radiance": 1.0},
        "patch": {"type": "rectangle",
                  "bsdf": {"type": "ink", "filename": str(table), "coverage": 0.5, "paper": 0.9}}})


def derivatives(spp: int, variant: str) -> None:
    import drjit as dr
    import mitsuba as mi

    from inkbsdf.apps.demo_tables import build_tables

    previous = mi.variant()
    mi.set_variant(variant)
    table = build_tables(Path(tempfile.mkdtemp()), inks=("R30",))["R30"]
    print(f"{variant}: R30 patch, coverage 0.5, paper 0.9, constant sky, 16×16 px, {spp} spp; "
          f"finite differences: central, step {STEP}, same seed")
    print(f"{'integrator':18s} {'parameter':10s} {'AD':>8s} {'FD':>8s} {'AD/FD−1':>8s} {'AD s':>6s}")
    integrators = ("prb", "direct_projective", "path")
    if mi.is_polarized:     # Mitsuba 3.9.1's prb fails there with any BSDF (dr.relative_grad of a Mueller matrix)
        print("(prb skipped: in polarized variants Mitsuba 3.9.1's prb fails with any BSDF)")
        integrators = integrators[1:]
    for integrator in integrators:
        scene = patch_scene(mi, table, integrator)
        params = mi.traverse(scene)
        for name in ("coverage", "paper"):
            key = f"patch.bsdf.{name}.value"
            x0 = float(np.ravel(params[key])[0])
            values = []
            for step in (STEP, -STEP):
                params[key] = x0 + step
                params.update()
                values.append(float(np.mean(np.asarray(mi.render(scene, params, spp=spp, seed=1)))))
            fd = (values[0] - values[1]) / (2 * STEP)
            x = mi.Float(x0)
            dr.enable_grad(x)
            params[key] = x
            params.update()
            t0 = time.perf_counter()
            dr.backward(dr.mean(mi.render(scene, params, spp=spp, seed=1), axis=None))
            ad = float(dr.grad(x)[0])
            seconds = time.perf_counter() - t0
            params[key] = x0
            params.update()
            print(f"{integrator:18s} {name:10s} {ad:+8.4f} {fd:+8.4f} {ad / fd - 1:+8.2%} {seconds:6.2f}", flush=True)
    mi.set_variant(previous)


def inverse(iterations: int) -> None:
    module = _load_scene_module("inverse_coverage")
    got = module.recover(iterations=iterations)
    size = got.coverage.shape[0]
    print(f"inverse rendering (scenes/inverse_coverage.py, prb): {size}×{size} coverage map, "
          f"{module.SPP} spp per step, target {module.TARGET_SPP} spp")
    for it in range(0, iterations + 1, max(1, iterations // 8)):
        print(f"  after {it:3d} iterations: coverage RMS error {got.rms_error[it]:.4f}")
    print(f"  final: RMS error {got.rms_error[-1]:.4f} after {iterations} iterations, {got.seconds:.1f} s "
          f"({got.seconds / iterations:.3f} s per iteration; first {got.first_step_seconds:.2f} s)")


def main(argv) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--iterations", type=int, default=80)
    args = parser.parse_args(argv)
    import mitsuba as mi

    from benchmarks.yardstick import yardstick_s
    from inkbsdf.variant import ensure_variant

    ensure_variant()
    import inkbsdf

    inkbsdf.register()
    print(f"variant {mi.variant()}; yardstick {yardstick_s():.3f} s")
    for variant in ("llvm_ad_spectral", "llvm_ad_spectral_polarized"):
        derivatives(args.spp, variant)
    inverse(args.iterations)


if __name__ == "__main__":
    main(sys.argv[1:])
