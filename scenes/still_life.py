"""The demo's photograph: a still life rendered with Mitsuba (RGB), made by the project.

    python scenes/still_life.py OUT.png [--width 360 --height 270 --spp 256]

Fruit on a gingham tablecloth before a two-tone wall, lit by a large window-like area light
from the upper left and a dim sky: smooth shading, highlights, saturated reds, oranges, yellows,
greens and blues (many outside the gamut of three inks), a neutral white egg and deep shadows —
a test image for colour separation and halftoning. Written as an 8-bit sRGB PNG; deterministic
for a given Mitsuba version (independent sampler, seed 0). `scenes/make_assets.py` calls it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

SIZE = (360, 270)          # width, height (pixels)
SPP = 256


def _fruit(center, radius, rgb, roughness=0.25):
    return {"type": "sphere", "center": list(center), "radius": radius,
            "bsdf": {"type": "roughplastic", "alpha": roughness,
                     "diffuse_reflectance": {"type": "rgb", "value": rgb}}}


def scene_dict(width: int, height: int, spp: int) -> dict:
    import mitsuba as mi

    T = mi.ScalarTransform4f
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 6},
        "sensor": {"type": "perspective", "fov": 38,
                   "to_world": T().look_at(origin=[0.0, 5.2, 13.5], target=[0.0, 1.2, 0.0], up=[0, 1, 0]),
                   "sampler": {"type": "independent", "sample_count": spp},
                   "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "gaussian"}}},
        "window": {"type": "rectangle",
                   "to_world": T().look_at(origin=[-9.0, 10.0, 7.0], target=[0.0, 0.5, 0.0], up=[0, 1, 0]).scale([4.0, 4.0, 1.0]),
                   "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [5.2, 5.0, 4.6]}}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.16, 0.18, 0.22]}},
        "cloth": {"type": "rectangle",
                  "to_world": T().rotate([1, 0, 0], -90).scale([14.0, 14.0, 1.0]),
                  "bsdf": {"type": "diffuse",
                           "reflectance": {"type": "checkerboard",
                                           "color0": {"type": "rgb", "value": [0.80, 0.78, 0.74]},
                                           "color1": {"type": "rgb", "value": [0.62, 0.06, 0.07]},
                                           "to_uv": T().scale([18.0, 18.0, 1.0])}}},
        "wall": {"type": "rectangle",
                 "to_world": T().translate([0.0, 6.0, -6.0]).scale([16.0, 8.0, 1.0]),
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.10, 0.32, 0.42]}}},
        "vase": {"type": "cylinder", "p0": [3.6, 0.0, -1.8], "p1": [3.6, 3.4, -1.8], "radius": 1.05,
                 "bsdf": {"type": "roughplastic", "alpha": 0.08,
                          "diffuse_reflectance": {"type": "rgb", "value": [0.05, 0.12, 0.55]}}},
        "vase_top": {"type": "disk", "to_world": T().translate([3.6, 3.4, -1.8]).rotate([1, 0, 0], -90).scale(1.05),
                     "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.02, 0.03, 0.08]}}},
        "stem": {"type": "cylinder", "p0": [-2.3, 2.3, 0.6], "p1": [-2.15, 2.85, 0.55], "radius": 0.07,
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.20, 0.12, 0.05]}}},
        "apple": _fruit([-2.3, 1.25, 0.6], 1.25, [0.55, 0.03, 0.03], 0.18),
        "orange": _fruit([0.4, 1.15, -0.4], 1.15, [0.85, 0.30, 0.02], 0.35),
        "lemon": _fruit([2.2, 0.8, 1.6], 0.8, [0.85, 0.72, 0.05], 0.3),
        "lime": _fruit([-0.4, 0.7, 2.2], 0.7, [0.18, 0.50, 0.05], 0.3),
        "plum1": _fruit([-4.4, 0.62, 2.0], 0.62, [0.20, 0.04, 0.28], 0.12),
        "plum2": _fruit([-3.5, 0.55, 3.1], 0.55, [0.24, 0.05, 0.32], 0.12),
        "egg": _fruit([1.0, 0.62, 3.3], 0.62, [0.86, 0.84, 0.80], 0.5),
    }


def render_still_life(width: int = SIZE[0], height: int = SIZE[1], spp: int = SPP) -> np.ndarray:
    """The photograph as 8-bit sRGB [height, width, 3] (rendered in llvm_ad_rgb, else
    scalar_rgb; the previous variant is restored)."""
    import mitsuba as mi

    from inkbsdf.apps.imageio import srgb_encode

    previous = mi.variant()
    mi.set_variant("llvm_ad_rgb" if "llvm_ad_rgb" in mi.variants() else "scalar_rgb")
    try:
        image = mi.render(mi.load_dict(scene_dict(width, height, spp)), seed=0)
        return srgb_encode(np.asarray(image, dtype=np.float64)[:, :, :3])
    finally:
        if previous is not None:
            mi.set_variant(previous)


def write_png8(path, rgb8: np.ndarray) -> Path:
    """An 8-bit sRGB PNG (Pillow)."""
    from PIL import Image

    Image.fromarray(np.ascontiguousarray(rgb8, dtype=np.uint8)).save(path)
    return Path(path)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("output")
    p.add_argument("--width", type=int, default=SIZE[0])
    p.add_argument("--height", type=int, default=SIZE[1])
    p.add_argument("--spp", type=int, default=SPP)
    args = p.parse_args(argv)
    write_png8(args.output, render_still_life(args.width, args.height, args.spp))
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
