"""Images in: any file Pillow reads (PNG, JPEG, TIFF, …) as 8-bit sRGB; textures out as 8-bit
grey PNG.

Pixels are taken as sRGB whatever the file says (embedded ICC profiles are not applied). Grey
images become neutral RGB; 16-bit images are rounded to 8 bits (the separation's resolution);
transparency is composited over white (the bare paper). Pillow is imported only here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


class ImageError(ValueError):
    """An image that cannot be read; the message names the file and the problem."""


def read_srgb8(path) -> np.ndarray:
    """The image as uint8 [rows, columns, 3] sRGB; ImageError when it cannot be read."""
    from PIL import Image, UnidentifiedImageError

    path = Path(path)
    if not path.is_file():
        raise ImageError(f"{path}: image file not found")
    try:
        with Image.open(path) as im:
            im.load()
            return to_srgb8(im)
    except UnidentifiedImageError:
        raise ImageError(f"{path}: not an image Pillow can read (PNG, JPEG, TIFF, …)") from None
    except (OSError, SyntaxError, ValueError, Image.DecompressionBombError) as exc:
        raise ImageError(f"{path}: cannot read the image ({exc})") from None


def to_srgb8(im) -> np.ndarray:
    """A loaded PIL image as uint8 [rows, columns, 3] (see the module docstring)."""
    if im.mode in ("I;16", "I;16B", "I;16L", "I", "F"):
        a = np.asarray(im, dtype=np.float64)
        scale = 255.0 if im.mode == "F" else (65535.0 if a.max(initial=0) > 255 else 255.0)
        grey = np.round(np.clip(a / scale, 0.0, 1.0) * 255.0).astype(np.uint8)
        return np.repeat(grey[:, :, None], 3, axis=2)
    if im.mode in ("RGBA", "LA", "PA") or (im.mode == "P" and "transparency" in im.info) \
            or (im.mode in ("RGB", "L") and "transparency" in im.info):
        rgba = np.asarray(im.convert("RGBA"), dtype=np.float64)
        alpha = rgba[:, :, 3:4] / 255.0
        return np.round(rgba[:, :, :3] * alpha + 255.0 * (1.0 - alpha)).astype(np.uint8)
    return np.ascontiguousarray(np.asarray(im.convert("RGB"), dtype=np.uint8))


def unique_colours(rgb8: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(colours [U, 3] uint8, index [rows·columns] into them) of an image [rows, columns, 3]."""
    flat = np.asarray(rgb8, dtype=np.uint8).reshape(-1, 3).astype(np.uint32)
    packed = (flat[:, 0] << 16) | (flat[:, 1] << 8) | flat[:, 2]
    values, index = np.unique(packed, return_inverse=True)
    colours = np.stack([(values >> 16) & 255, (values >> 8) & 255, values & 255], axis=-1).astype(np.uint8)
    return colours, index.reshape(-1)


def write_grey_png(path, texture: np.ndarray) -> Path:
    """An 8-bit grey PNG of a uint8 [rows, columns] array."""
    from PIL import Image

    path = Path(path)
    Image.fromarray(np.ascontiguousarray(texture, dtype=np.uint8)).save(path)
    return path


def write_rgb_png(path, rgb8: np.ndarray) -> Path:
    """An 8-bit RGB PNG of a uint8 [rows, columns, 3] array."""
    from PIL import Image

    path = Path(path)
    Image.fromarray(np.ascontiguousarray(rgb8, dtype=np.uint8)).save(path)
    return path
