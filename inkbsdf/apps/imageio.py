"""Images of renders: EXR (linear RGB, written with Mitsuba's Bitmap, read with OpenEXR) and an
8-bit sRGB PNG for people to look at."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np


class NonFiniteWarning(UserWarning):
    """An image written to PNG has NaN or infinite pixels (they cannot be shown as colours)."""


def check_suffix(path, suffix: str, what: str) -> Path:
    """`path` as a Path if it ends in `suffix` (any case), else ValueError naming the fix."""
    path = Path(path)
    if path.suffix.lower() != suffix:
        raise ValueError(f"{what} '{path}' must end in {suffix} (it is written as {suffix[1:].upper()})")
    return path


def check_exposure(exposure_stops: float) -> float:
    """The exposure in stops if finite, else ValueError."""
    if not math.isfinite(exposure_stops):
        raise ValueError(f"exposure must be a finite number of stops, got {exposure_stops}")
    return float(exposure_stops)


def non_finite_pixels(image) -> int:
    """Pixels of an [H, W, C] image with a NaN or infinite channel."""
    return int(np.count_nonzero(~np.isfinite(np.asarray(image)).all(axis=-1)))


def to_rgb_array(image) -> np.ndarray:
    """A render (Mitsuba TensorXf or array [H, W, ≥3], or [H, W, 1] luminance from a mono
    variant, written as grey) as float32 [H, W, 3] linear RGB."""
    arr = np.asarray(image, dtype=np.float32)
    if arr.ndim == 3 and arr.shape[2] == 1:
        arr = np.repeat(arr, 3, axis=2)
    if arr.ndim != 3 or arr.shape[2] < 3:
        raise ValueError(f"expected an RGB image [H, W, 3] or a luminance one [H, W, 1], got shape {arr.shape}")
    return np.ascontiguousarray(arr[:, :, :3])


def write_exr(path, image) -> Path:
    """Write linear RGB as a float32 OpenEXR file (channels R, G, B)."""
    import mitsuba as mi

    path = check_suffix(path, ".exr", "EXR file")
    path.parent.mkdir(parents=True, exist_ok=True)
    bitmap = mi.Bitmap(to_rgb_array(image), mi.Bitmap.PixelFormat.RGB)
    bitmap.write(str(path))
    return path


def srgb_encode(linear: np.ndarray, exposure_stops: float = 0.0) -> np.ndarray:
    """Linear RGB → 8-bit sRGB (IEC 61966-2-1 curve), clipped; NaN becomes 0 (write_png warns).
    A non-finite exposure is refused (ValueError)."""
    from solver.colour import srgb

    scale = 2.0 ** check_exposure(exposure_stops)
    return srgb.to_8bit(srgb.encode(np.asarray(linear, dtype=np.float64) * scale))


def write_png(path, image, exposure_stops: float = 0.0) -> Path:
    """Write a linear RGB render as an sRGB PNG; warns (NonFiniteWarning, with the count) when
    pixels are NaN (written black) or infinite (clipped)."""
    import matplotlib.image

    path = check_suffix(path, ".png", "PNG file")
    rgb = to_rgb_array(image)
    encoded = srgb_encode(rgb, exposure_stops)
    bad = non_finite_pixels(rgb)
    if bad:
        warnings.warn(f"{path}: {bad} of {rgb.shape[0] * rgb.shape[1]} pixels are NaN or infinite "
                      "(NaN written black, ±inf clipped): the render has a problem", NonFiniteWarning,
                      stacklevel=2)
    path.parent.mkdir(parents=True, exist_ok=True)
    matplotlib.image.imsave(path, encoded)
    return path


def read_exr(path) -> np.ndarray:
    """Read an EXR's R, G, B channels with OpenEXR as float32 [H, W, 3]."""
    import OpenEXR

    with OpenEXR.File(str(path)) as exr:
        channels = exr.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)[:, :, :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=-1)
