"""Coverage textures at scene load: checked (`check_coverage_texture`), and where each can be
> 0 (`coverage_support`, `solver.printing.overlap`).

A coverage is linear data (the inked fraction of the area), so a bitmap must be read as stored:
`raw` true. Without it Mitsuba decodes 8-bit files through the sRGB curve (a 50 % grey becomes
0.21 coverage) and, in spectral variants, upsamples colours as reflectance spectra; such a bitmap
is refused with the fix. NaN or infinite texels (an EXR's holes) are refused too: they would
render as NaN or as an arbitrary colour.

    uniform value        → the number (clamped to [0, 1])
    bitmap               → a TexelMask of its texels > 0; with bilinear filtering grown by one
                           texel (a lookup between texels mixes them), framed by resolution and
                           uv transform
    any other texture    → None (could be > 0 anywhere)
"""

from __future__ import annotations

import re

import drjit as dr
import mitsuba as mi
import numpy as np

from solver.printing import TexelMask

_PROBE_SHIFT = 0.25         # texel widths off a texel centre where the filter is probed
_RAW = re.compile(r"\braw = (\d)")
_NAME = re.compile(r'\bname = "([^"]*)"')


def check_coverage_texture(texture, parameter: str) -> None:
    """InkParameterError (naming `parameter` and the fix) for a bitmap coverage read without
    `raw` or with non-finite texels (module docstring)."""
    from .errors import InkParameterError

    text = str(texture)
    if not text.startswith("BitmapTexture"):
        return
    m = _NAME.search(text)
    name = f"'{m.group(1)}'" if m else "bitmap"
    raw = _RAW.search(text)
    if raw is not None and raw.group(1) != "1":
        raise InkParameterError(
            f"ink BSDF: '{parameter}': the bitmap {name} is read as sRGB colour (raw missing or false), but a "
            f"coverage is linear data: add <boolean name=\"raw\" value=\"true\"/> to the bitmap (raw=True in a dict)")
    params = mi.traverse(texture)
    if "data" in params:
        data = np.asarray(params["data"], dtype=np.float64)
        bad = int(np.count_nonzero(~np.isfinite(data)))
        if bad:
            raise InkParameterError(f"ink BSDF: '{parameter}': the bitmap {name} has {bad} NaN or infinite "
                                    f"texel values of {data.size}: fill them (0 = no ink) and save it again")


def _grow(mask: np.ndarray) -> np.ndarray:
    """Mask grown by one texel in each direction, wrapping (a superset for every wrap mode)."""
    out = mask.copy()
    for axis in (0, 1):
        for shift in (-1, 1):
            out |= np.roll(mask, shift, axis=axis)
    for sy in (-1, 1):
        for sx in (-1, 1):
            out |= np.roll(np.roll(mask, sy, axis=0), sx, axis=1)
    return out


def _filters_between_texels(texture, values: np.ndarray, to_uv) -> bool:
    """True unless a lookup a quarter texel off a centre, toward a neighbour of another value,
    returns that texel's value exactly (nearest filtering)."""
    h, w = values.shape
    for di, dj in ((0, 1), (1, 0)):
        rows, cols = np.nonzero(values[: h - di, : w - dj] != values[di:, dj:])
        if rows.size == 0:
            continue
        i, j = int(rows[0]), int(cols[0])
        target = np.array([(j + 0.5 + _PROBE_SHIFT * dj) / w, (i + 0.5 + _PROBE_SHIFT * di) / h, 1.0])
        uv = np.linalg.solve(np.array(to_uv.matrix, dtype=np.float64), target)
        si = dr.zeros(mi.SurfaceInteraction3f, 1)
        si.uv = mi.Point2f(float(uv[0]), float(uv[1]))
        got = float(np.asarray(texture.eval_1(si)).ravel()[0])
        return abs(got - float(values[i, j])) > 1e-6 * (1.0 + abs(float(values[i, j])))
    return False                                      # a constant texture: nothing to mix


def coverage_support(texture):
    """The support (number, TexelMask or None) of a coverage texture."""
    if not texture.is_spatially_varying():
        return float(np.clip(np.asarray(texture.mean(), dtype=np.float64).ravel()[0], 0.0, 1.0))
    params = mi.traverse(texture)
    if "data" not in params or "to_uv" not in params:
        return None
    data = np.asarray(params["data"], dtype=np.float64)
    if data.ndim != 3:
        return None
    positive = np.any(data > 0.0, axis=-1)
    to_uv = params["to_uv"]
    values = data.max(axis=-1)
    if _filters_between_texels(texture, values, to_uv):
        positive = _grow(positive)
    frame = (positive.shape, np.array(to_uv.matrix, dtype=np.float64).tobytes())
    return TexelMask(positive, frame)
