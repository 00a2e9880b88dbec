"""Images in: any file Pillow reads (PNG, JPEG, TIFF, …) as 8-bit sRGB; textures out as 8-bit
grey PNG.

    image = read_image("photo.png")        # LoadedImage: rgb8 [rows, columns, 3] and notes
    for note in image.notes: print(note)   # one line per thing done to the pixels

- an embedded ICC profile is honoured: the pixels are converted to sRGB with Pillow's ImageCms
  (LittleCMS, perceptual intent); a profile that cannot be applied is a warning and the pixels
  are taken as sRGB. Without a profile the pixels are taken as sRGB.
- transparency (RGBA, LA, a palette's transparent entry) is composited over paper white (255)
  with a note: the print has no transparency, the paper shows through.
- grey images become neutral RGB; 16-bit grey is rounded to 8 bits and 16-bit colour read at
  8 bits (Pillow keeps the high bytes: within one step), the separation's resolution, with a note; CMYK files without a profile are converted naively
  with a warning.
- a file that cannot be read: ImageError naming the file and why (exit 2 at the CLI).

Pillow is imported only here.
"""

from __future__ import annotations

import io
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np


class ImageError(ValueError):
    """An image that cannot be read; the message names the file and the problem."""


class ImageWarning(UserWarning):
    """Something about an image the print cannot honour (said in one line)."""


@dataclass(frozen=True)
class LoadedImage:
    rgb8: np.ndarray                 # uint8 [rows, columns, 3], sRGB
    notes: tuple[str, ...]           # what was done to the pixels (one line each)


def read_image(path) -> LoadedImage:
    """The image as 8-bit sRGB with notes (module docstring); ImageError when it cannot be read."""
    from PIL import Image, UnidentifiedImageError

    path = Path(path)
    if not path.is_file():
        raise ImageError(f"{path}: image file not found" if not path.exists() else f"{path}: not a file")
    try:
        with Image.open(path) as im:
            deep = im.mode in ("RGB", "RGBA") and any(";16" in str(getattr(t, "args", "")) for t in im.tile or ())
            im.load()
            loaded = _to_srgb8(im, str(path))
    except UnidentifiedImageError:
        raise ImageError(f"{path}: not an image Pillow can read (PNG, JPEG, TIFF, …)") from None
    except (OSError, SyntaxError, ValueError, Image.DecompressionBombError) as exc:
        raise ImageError(f"{path}: cannot read the image ({exc})") from None
    if deep:        # Pillow reads 16-bit colour as its high bytes: within one 8-bit step
        return LoadedImage(loaded.rgb8, ("16-bit colour, read at 8 bits (the separation's resolution)",)
                           + loaded.notes)
    return loaded


def read_srgb8(path) -> np.ndarray:
    """The image as uint8 [rows, columns, 3] sRGB (`read_image` without its notes)."""
    return read_image(path).rgb8


def to_srgb8(im) -> np.ndarray:
    """A loaded PIL image as uint8 [rows, columns, 3] (see the module docstring)."""
    return _to_srgb8(im, "image").rgb8


def _over_paper(rgb: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """RGB (float, 0–255) composited over paper white with alpha in [0, 1] (encoded values:
    the usual meaning of alpha in an sRGB file)."""
    return np.round(rgb * alpha[..., None] + 255.0 * (1.0 - alpha[..., None])).astype(np.uint8)


def _apply_profile(im, name: str, notes: list):
    """The image converted to sRGB through its embedded ICC profile (RGB mode out), or None when
    it has none; a profile that cannot be applied is warned about and None returned."""
    from PIL import ImageCms

    icc = im.info.get("icc_profile")
    if not icc:
        return None
    try:
        source = ImageCms.ImageCmsProfile(io.BytesIO(icc))
        described = (ImageCms.getProfileDescription(source) or "unnamed").strip()
        mode_in = im.mode if im.mode in ("RGB", "CMYK", "LAB", "L") else "RGB"
        src = im if im.mode == mode_in else im.convert(mode_in)
        out = ImageCms.profileToProfile(src, source, ImageCms.createProfile("sRGB"), outputMode="RGB")
    except Exception as exc:                                   # PyCMSError, OSError: a profile LittleCMS refuses
        warnings.warn(f"{name}: its embedded ICC profile cannot be applied ({str(exc).strip() or type(exc).__name__}); "
                      "the pixels are taken as sRGB", ImageWarning, stacklevel=3)
        return None
    if "srgb" not in described.lower():
        notes.append(f"converted from its embedded ICC profile ({described}) to sRGB")
    return out


def _to_srgb8(im, name: str) -> LoadedImage:
    notes: list[str] = []
    alpha = None
    if im.mode in ("RGBA", "LA", "PA", "RGBa", "La") or "transparency" in im.info:
        rgba = im.convert("RGBA")
        a = np.asarray(rgba, dtype=np.float64)[:, :, 3] / 255.0
        if np.any(a < 1.0):
            alpha = a
            notes.append(f"transparency composited over paper white ({np.mean(a < 1.0):.1%} of the pixels "
                         "not opaque)")
        im = rgba.convert("RGB") if im.mode != "LA" else im.convert("L")
    if im.mode in ("I;16", "I;16B", "I;16L", "I", "F"):
        a = np.asarray(im, dtype=np.float64)
        scale = 255.0 if im.mode == "F" else (65535.0 if a.max(initial=0) > 255 else 255.0)
        if scale == 65535.0:
            notes.append("16-bit grey, rounded to 8 bits (the separation's resolution)")
        grey = np.clip(a / scale, 0.0, 1.0) * 255.0
        rgb = np.repeat(grey[:, :, None], 3, axis=2)
    else:
        converted = _apply_profile(im, name, notes)
        if converted is None and im.mode == "CMYK":
            warnings.warn(f"{name}: a CMYK image without a usable ICC profile is converted naively to RGB; "
                          "give an RGB image for a faithful print", ImageWarning, stacklevel=3)
        rgb = np.asarray(converted if converted is not None else im.convert("RGB"), dtype=np.float64)
    if alpha is not None:
        return LoadedImage(_over_paper(rgb, alpha), tuple(notes))
    return LoadedImage(np.ascontiguousarray(np.round(rgb).astype(np.uint8)), tuple(notes))


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
