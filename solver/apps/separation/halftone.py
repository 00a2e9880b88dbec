"""Coverage images → coverage textures (8-bit, 255 = full ink): continuous, AM or FM dots.

    dots = parse_dots("AM:150")                       # or "FM", "none"
    grid = TexelGrid.for_print(size_cm=(12.0, 9.0), image_shape=(270, 360), dots=dots)
    texture = halftone_ink(coverage[:, :, 0], grid, dots, angle_deg=15.0, seed=1)

The texture covers the print; each texel takes the ink's coverage at its centre (bilinear in
the coverage image, pixel centres aligned; area-averaged first when the texels are at least
twice as large as the pixels). `none` writes that coverage (rounded to 1/255); AM and FM ink a
texel (255) where its threshold (`screens`) is below the coverage, else 0.

Default texture resolution (`TexelGrid.for_print`): `none` one texel per image pixel; AM
`AM_TEXELS_PER_CELL` texels per screen period (1200 dpi at 150 lpi); FM `FM_DPI` (a dot of
42 µm). `dpi` overrides it, down to `min_dpi`: AM `AM_MIN_TEXELS_PER_CELL` texels per screen
period, FM `FM_MIN_DPI` (`check_dpi`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from .screens import am_threshold, fm_threshold

CM_PER_INCH = 2.54
AM_TEXELS_PER_CELL = 8
MIN_LPI, MAX_LPI = 0.5, 600.0       # AM screen rulings accepted, lines per inch
FM_DPI = 600.0
# The smallest AM cell that draws a dot: `am_threshold` samples the spot function once per
# texel, so below 2 texels per period the screen aliases (its period is lost), and at 2–3 a
# cell has 4–9 texels (5–10 tone steps): the dot is one texel, a cross or the whole cell. From
# 4 (a 4×4 cell, 17 tone steps) it grows from one texel through a cross and a disc to the 50 %
# checkerboard.
AM_MIN_TEXELS_PER_CELL = 4
# FM dots are single texels, so the resolution is the dot size: below 60 dpi a dot is over
# 0.42 mm (ten times the default FM_DPI's 42 µm), a coarse grain rather than a screen, and a
# 12-cm print has under 300 texels across.
FM_MIN_DPI = 60.0
ROWS_PER_CHUNK = 256
DOT_KINDS = ("none", "AM", "FM")


class DotsError(ValueError):
    """A dot specification or texture size that cannot be made; the message names the fix."""


@dataclass(frozen=True)
class Dots:
    """How coverages become textures: `none` (continuous), `AM` at `lpi`, or `FM`."""

    kind: str
    lpi: float | None = None

    @property
    def binary(self) -> bool:
        return self.kind != "none"

    def label(self) -> str:
        return f"AM {self.lpi:g} lpi" if self.kind == "AM" else ("FM" if self.kind == "FM" else "continuous")


def parse_dots(text: str) -> Dots:
    """'AM:150' (lines per inch), 'FM' or 'none' (any case) → Dots; DotsError otherwise."""
    t = str(text).strip()
    if t.lower() == "none":
        return Dots("none")
    if t.upper() == "FM":
        return Dots("FM")
    m = re.fullmatch(r"(?i:am):([0-9]*\.?[0-9]+)", t)
    if m:
        lpi = float(m.group(1))
        if not MIN_LPI <= lpi <= MAX_LPI:
            raise DotsError(f"dots: the screen ruling must lie in [{MIN_LPI:g}, {MAX_LPI:g}] lines per inch, "
                            f"got {lpi:g}")
        return Dots("AM", lpi)
    raise DotsError(f"dots: give AM:LPI (e.g. AM:150, lines per inch), FM or none; got {text!r}")


@dataclass(frozen=True)
class TexelGrid:
    """The texture's texels over a print of `size_cm` (width, height)."""

    shape: tuple[int, int]          # (rows, columns)
    size_cm: tuple[float, float]    # (width, height)

    @property
    def texel_in(self) -> float:
        """Texel width in inches (texels are square up to rounding of the counts)."""
        return self.size_cm[0] / CM_PER_INCH / self.shape[1]

    @property
    def dpi(self) -> float:
        return 1.0 / self.texel_in

    @classmethod
    def for_print(cls, size_cm, image_shape, dots: Dots, dpi: float | None = None,
                  max_texels: int = 2**26) -> "TexelGrid":
        """The grid for a print of `size_cm` from an image of `image_shape` (rows, columns)."""
        w_cm, h_cm = (float(v) for v in size_cm)
        if dpi is None and dots.kind == "none":
            rows, cols = int(image_shape[0]), int(image_shape[1])
        else:
            if dpi is not None:
                check_dpi(dots, dpi)
            dpi = default_dpi(dots) if dpi is None else float(dpi)
            cols = max(1, round(w_cm / CM_PER_INCH * dpi))
            rows = max(1, round(h_cm / CM_PER_INCH * dpi))
        if rows * cols > max_texels:
            raise DotsError(f"the coverage textures would have {cols}×{rows} texels per ink (over "
                            f"{max_texels:,}): lower --dpi, the screen ruling or --size")
        return cls((rows, cols), (w_cm, h_cm))


def default_dpi(dots: Dots) -> float:
    """Texels per inch when not given: AM_TEXELS_PER_CELL per screen period, FM_DPI for FM."""
    return AM_TEXELS_PER_CELL * dots.lpi if dots.kind == "AM" else FM_DPI


def min_dpi(dots: Dots) -> float:
    """The coarsest texture resolution (texels per inch) that draws `dots`: AM
    AM_MIN_TEXELS_PER_CELL per screen period, FM FM_MIN_DPI; 0 for continuous textures."""
    if dots.kind == "AM":
        return AM_MIN_TEXELS_PER_CELL * dots.lpi
    return FM_MIN_DPI if dots.kind == "FM" else 0.0


def check_dpi(dots: Dots, dpi: float) -> None:
    """DotsError (naming --dpi and --dots, and the fix) when `dpi` texels per inch cannot draw
    `dots`."""
    lowest = min_dpi(dots)
    if float(dpi) >= lowest:
        return
    if dots.kind == "AM":
        coarser = _down(dpi / AM_MIN_TEXELS_PER_CELL)
        screen = f", or a coarser screen (--dots AM:{coarser:g} or less)" if coarser >= MIN_LPI else ""
        raise DotsError(f"dpi: {dpi:g} texels per inch is too coarse for --dots AM:{dots.lpi:g} "
                        f"({_down(dpi / dots.lpi):g} texels per screen period, a dot needs at least "
                        f"{AM_MIN_TEXELS_PER_CELL}): give --dpi {math.ceil(lowest):d} or more{screen}")
    raise DotsError(f"dpi: {dpi:g} texels per inch is too coarse for --dots FM (one-texel dots of "
                    f"{10 * CM_PER_INCH / dpi:.2g} mm): give --dpi {lowest:g} or more (default {FM_DPI:g})")


def _down(x: float) -> float:
    """`x` rounded down to 2 decimals (a bound quoted in a message stays on its side)."""
    return math.floor(100 * x) / 100


def _axis_weights(n_out: int, n_in: int):
    """Bilinear weights along one axis, centres aligned: (i0, i1, t) of each output sample."""
    x = np.clip((np.arange(n_out) + 0.5) * n_in / n_out - 0.5, 0.0, n_in - 1.0)
    i0 = np.minimum(np.floor(x).astype(np.int64), n_in - 1)
    i1 = np.minimum(i0 + 1, n_in - 1)
    return i0, i1, x - i0


def box_reduce(image: np.ndarray, factor: int) -> np.ndarray:
    """Mean over factor × factor blocks (edge blocks partial)."""
    h, w = image.shape
    ph, pw = -h % factor, -w % factor
    padded = np.pad(image, ((0, ph), (0, pw)), mode="edge")
    return padded.reshape(padded.shape[0] // factor, factor, padded.shape[1] // factor, factor).mean(axis=(1, 3))


def coverage_at_texels(coverage: np.ndarray, grid: TexelGrid, rows: slice) -> np.ndarray:
    """The coverage image [h, w] at the centres of the texel rows `rows` (bilinear), float32."""
    img = np.asarray(coverage, dtype=np.float32)
    factor = int(min(img.shape[0] / grid.shape[0], img.shape[1] / grid.shape[1]))
    if factor >= 2:
        img = box_reduce(img, factor)
    h, w = img.shape
    r0, r1, ty = _axis_weights(grid.shape[0], h)
    c0, c1, tx = _axis_weights(grid.shape[1], w)
    r0, r1, ty = r0[rows], r1[rows], ty[rows, None].astype(np.float32)
    tx = tx[None, :].astype(np.float32)
    top = img[r0][:, c0] * (1 - tx) + img[r0][:, c1] * tx
    bottom = img[r1][:, c0] * (1 - tx) + img[r1][:, c1] * tx
    return top * (1 - ty) + bottom * ty


def halftone_ink(coverage: np.ndarray, grid: TexelGrid, dots: Dots, angle_deg: float = 0.0,
                 seed: int = 0) -> np.ndarray:
    """One ink's texture, uint8 [rows, columns] (255 = full ink), from its coverage image in
    [0, 1]. AM uses `angle_deg`, FM the blue-noise tile of `seed`."""
    rows, cols = grid.shape
    out = np.empty((rows, cols), dtype=np.uint8)
    for start in range(0, rows, ROWS_PER_CHUNK):
        part = slice(start, min(start + ROWS_PER_CHUNK, rows))
        c = np.clip(coverage_at_texels(coverage, grid, part), 0.0, 1.0)
        if dots.kind == "none":
            out[part] = np.round(255.0 * c).astype(np.uint8)
            continue
        if dots.kind == "AM":
            t = am_threshold(part, cols, grid.texel_in, dots.lpi, angle_deg)
        else:
            t = fm_threshold(part, cols, seed)
        out[part] = np.where(t < c, 255, 0).astype(np.uint8)
    return out


def texture_mean(texture: np.ndarray) -> float:
    """Mean coverage of an 8-bit texture (255 = 1)."""
    return float(np.mean(texture, dtype=np.float64) / 255.0)


def print_size(size_cm, image_shape) -> tuple[float, float]:
    """(width, height) in cm from a (width, height) pair where height may be None (kept
    to the image's aspect ratio)."""
    w, h = size_cm
    if h is None:
        h = w * image_shape[0] / image_shape[1]
    if not (math.isfinite(w) and math.isfinite(h) and w > 0 and h > 0):
        raise DotsError(f"size: width and height must be positive numbers of cm, got {w}×{h}")
    return float(w), float(h)
