"""Inverse rendering with the `ink` BSDF: recover the coverage map of a printed patch from a
rendered image of it (docs/plugin.md, "Differentiable rendering").

    python scenes/inverse_coverage.py [--size 64] [--iterations 60] [--spp 16] [--integrator prb]

A square patch of ink (R30 by default, paper 0.9) under a constant sky, seen from straight above
by an orthographic camera whose pixels are the coverage texels. The target image is rendered from
a known coverage map (`true_coverage`: a disc, a ramp and a dot); the optimisation starts from a
uniform 0.5 and minimises the mean squared difference of the images with Adam (its step halved
every HALVING iterations), clamping the map to [0, 1] after each step. Prints the recovered map's RMS error per iteration. `recover` is what
benchmarks/bench_gradients.py times.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

import numpy as np

SIZE = 64                   # texels per side of the coverage map = pixels per side of the image
ITERATIONS = 80
SPP = 16                    # samples per pixel of each optimisation step
TARGET_SPP = 256            # samples per pixel of the target image
LEARNING_RATE = 0.03         # Adam's step, halved every HALVING iterations (the gradients' noise
HALVING = 30                 # sets the floor a fixed step reaches)
INK = "R30"
PAPER = 0.9
KEY = "patch.bsdf.coverage.data"


def true_coverage(size: int = SIZE) -> np.ndarray:
    """The map to recover, [size, size] in [0, 1]: a ramp from 0.1 to 0.9 left to right, a disc
    of full coverage, and a small dot of none."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    c = 0.1 + 0.8 * x
    c[(x - 0.35) ** 2 + (y - 0.4) ** 2 < 0.2**2] = 1.0
    c[(x - 0.75) ** 2 + (y - 0.7) ** 2 < 0.08**2] = 0.0
    return c


def scene_dict(coverage: np.ndarray, integrator: str = "prb", ink: str = INK, paper: float = PAPER) -> dict:
    import mitsuba as mi

    size = coverage.shape[0]
    return {
        "type": "scene",
        "integrator": {"type": integrator, "max_depth": 2},
        "sensor": {"type": "orthographic",
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 3], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"},
                            "pixel_format": "rgb"},
                   "sampler": {"type": "independent"}},
        "sky": {"type": "constant", "radiance": 1.0},
        "patch": {"type": "rectangle",
                  "bsdf": {"type": "ink", "ink": ink, "paper": paper,
                           "coverage": {"type": "bitmap", "data": mi.TensorXf(coverage[..., None].astype(np.float32)),
                                        "raw": True, "filter_type": "nearest"}}}}


@dataclass(frozen=True)
class Recovery:
    coverage: np.ndarray        # [size, size], the recovered map
    rms_error: list             # RMS error of the map after each iteration (index 0: the start)
    loss: list                  # image loss at each iteration
    seconds: float              # optimisation wall time (the target's render excluded)
    first_step_seconds: float   # the first iteration alone (kernel compilation)


def recover(size: int = SIZE, iterations: int = ITERATIONS, spp: int = SPP, integrator: str = "prb",
            learning_rate: float = LEARNING_RATE, log=None) -> Recovery:
    """Render the target from `true_coverage(size)`, then recover the map from a uniform 0.5."""
    import drjit as dr
    import mitsuba as mi

    import inkbsdf

    inkbsdf.register()
    truth = true_coverage(size)
    scene = mi.load_dict(scene_dict(truth, integrator))
    params = mi.traverse(scene)
    target = mi.render(scene, params, spp=TARGET_SPP, seed=12345)
    dr.eval(target)

    params[KEY] = mi.TensorXf(np.full((size, size, 1), 0.5, dtype=np.float32))
    params.update()
    opt = mi.ad.Adam(lr=learning_rate)
    opt[KEY] = params[KEY]
    params.update(opt)

    def rms() -> float:
        got = np.asarray(params[KEY]).reshape(size, size)
        return float(np.sqrt(np.mean((got - truth) ** 2)))

    errors, losses = [rms()], []
    t0 = time.perf_counter()
    first = None
    for it in range(iterations):
        opt.set_learning_rate(learning_rate * 0.5 ** (it // HALVING))
        image = mi.render(scene, params, spp=spp, seed=it)
        loss = dr.mean(dr.square(image - target), axis=None)
        dr.backward(loss)
        opt.step()
        opt[KEY] = dr.clip(opt[KEY], 0.0, 1.0)
        params.update(opt)
        losses.append(float(np.ravel(np.asarray(loss))[0]))
        errors.append(rms())
        if first is None:
            first = time.perf_counter() - t0
        if log is not None:
            log(f"iteration {it + 1:3d}: image loss {losses[-1]:.3e}, coverage RMS error {errors[-1]:.4f}")
    seconds = time.perf_counter() - t0
    return Recovery(np.asarray(params[KEY]).reshape(size, size), errors, losses, seconds, first)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=SIZE)
    parser.add_argument("--iterations", type=int, default=ITERATIONS)
    parser.add_argument("--spp", type=int, default=SPP)
    parser.add_argument("--integrator", default="prb", choices=("prb", "direct_projective", "path"))
    args = parser.parse_args(argv)
    import mitsuba as mi

    from inkbsdf.variant import ensure_variant

    ensure_variant()
    print(f"variant {mi.variant()}; {args.size}×{args.size} map, {args.iterations} iterations, {args.spp} spp")
    got = recover(args.size, args.iterations, args.spp, args.integrator, log=print)
    print(f"RMS error of the coverage map: {got.rms_error[0]:.4f} at the start, {got.rms_error[-1]:.4f} "
          f"after {args.iterations} iterations ({got.seconds:.1f} s, first iteration {got.first_step_seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
