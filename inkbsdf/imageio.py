"""Images of renders: EXR (linear RGB, written with Mitsuba's Bitmap, read with OpenEXR) and an
8-bit sRGB PNG for people to look at."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def to_rgb_array(image) -> np.ndarray:
    """A render (Mitsuba TensorXf or array [H, W, ≥3]) as float32 [H, W, 3] linear RGB."""
    arr = np.asarray(image, dtype=np.float32)
    if arr.ndim != 3 or arr.shape[2] < 3:
        raise ValueError(f"expected an RGB image [H, W, 3], got shape {arr.shape}")
    return np.ascontiguousarray(arr[:, :, :3])


def write_exr(path, image) -> Path:
    """Write linear RGB as a float32 OpenEXR file (channels R, G, B)."""
    import mitsuba as mi

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    bitmap = mi.Bitmap(to_rgb_array(image), mi.Bitmap.PixelFormat.RGB)
    bitmap.write(str(path))
    return path


def srgb_encode(linear: np.ndarray, exposure_stops: float = 0.0) -> np.ndarray:
    """Linear RGB → 8-bit sRGB (IEC 61966-2-1 curve), clipped; NaN becomes 0."""
    x = np.nan_to_num(np.asarray(linear, dtype=np.float64) * 2.0 ** exposure_stops, nan=0.0)
    x = np.clip(x, 0.0, 1.0)
    encoded = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(encoded * 255.0).astype(np.uint8)


def write_png(path, image, exposure_stops: float = 0.0) -> Path:
    """Write a linear RGB render as an sRGB PNG."""
    import matplotlib.image

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    matplotlib.image.imsave(path, srgb_encode(to_rgb_array(image), exposure_stops))
    return path


def read_exr(path) -> np.ndarray:
    """Read an EXR's R, G, B channels with OpenEXR as float32 [H, W, 3]."""
    import OpenEXR

    with OpenEXR.File(str(path)) as exr:
        channels = exr.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)[:, :, :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=-1)
