"""Drawing the figures: the Fig. 7 / Fig. 8 grid (cells composed as pixels, labels by matplotlib
within the layout's boxes) and the Fig. 9 transmission spectra."""

from __future__ import annotations

import textwrap
from dataclasses import dataclass

import numpy as np

from .layout import GridLayout, Label

DPI = 100
MAX_FONT_PX, MIN_FONT_PX = 14.0, 6.0


RULE_GREY = 150


def compose(layout: GridLayout, pictures: dict, rules=()) -> np.ndarray:
    """The grid's pixels: white, with each cell's (strip, square) pair or crossed-out image,
    and grey rules (boxes) under the group headers.

    pictures[(i, j)] is (strip, square) arrays of the layout's sizes, or one array of the whole
    cell's size (a failed cell)."""
    width, height = layout.size
    canvas = np.full((height, width, 3), 255, dtype=np.uint8)
    for x0, y0, x1, y1 in rules:
        canvas[y0:y1, x0:x1] = RULE_GREY
    for (i, j), picture in pictures.items():
        if isinstance(picture, tuple):
            for image, (x0, y0, x1, y1) in zip(picture, (layout.strip_box(i, j), layout.square_box(i, j))):
                canvas[y0:y1, x0:x1] = image
        else:
            x0, y0, x1, y1 = layout.cell_box(i, j)
            canvas[y0:y1, x0:x1] = picture
    return canvas


def _mathtext(text: str) -> str:
    return text.replace("D_eff", "$D_{eff}$")


def _fit_text(fig, renderer, label: Label, height_px: int):
    """Place a label inside its box: wrapped, at the largest font size (px) that fits."""
    x0, y0, x1, y1 = label.box
    w, h = x1 - x0, y1 - y0
    x = (x0 + x1) / 2 if label.align == "center" else x1
    y = height_px - (y0 + y1) / 2
    font = MAX_FONT_PX
    while True:
        chars = max(4, int(w / (0.55 * font)))
        text = "\n".join(textwrap.wrap(label.text, chars, break_long_words=False)) or label.text
        artist = fig.text(x / fig.bbox.width, y / fig.bbox.height, _mathtext(text), ha=label.align,
                          va="center", fontsize=font * 72.0 / DPI, multialignment=label.align)
        ext = artist.get_window_extent(renderer)
        if (ext.width <= w and ext.height <= h) or font <= MIN_FONT_PX:
            return artist
        artist.remove()
        font -= 0.5


def draw_grid(canvas: np.ndarray, labels: list[Label], path) -> None:
    """Write the grid PNG: the canvas pixel for pixel, the labels on top."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    height, width = canvas.shape[:2]
    fig = plt.figure(figsize=(width / DPI, height / DPI), dpi=DPI)
    fig.figimage(canvas, 0, 0, origin="upper")
    renderer = fig.canvas.get_renderer()
    for label in labels:
        _fit_text(fig, renderer, label, height)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


@dataclass(frozen=True)
class Curve:
    label: str
    wavelengths_nm: np.ndarray
    value: np.ndarray
    se: np.ndarray | None      # None: unknown
    colour: str
    linestyle: str = "-"


@dataclass(frozen=True)
class Panel:
    title: str
    curves: tuple[Curve, ...]
    failed: tuple[str, ...] = ()        # 'ink grains: reason' of cells that failed


def draw_spectra(panels: list[Panel], title: str, caption: str, path, ylabel: str) -> None:
    """Fig. 9: one panel per pigment, transmission against wavelength, ±2 SE bands."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(panels)
    cols = 2 if n > 1 else 1
    nrows = (n + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(6.0 * cols, 3.9 * nrows + 0.9), squeeze=False)
    for ax, panel in zip(axes.flat, panels):
        for c in panel.curves:
            ax.plot(c.wavelengths_nm, c.value, color=c.colour, ls=c.linestyle, label=c.label, lw=1.6)
            if c.se is not None and np.any(c.se > 0):
                ax.fill_between(c.wavelengths_nm, c.value - 2 * c.se, c.value + 2 * c.se, color=c.colour, alpha=0.2, lw=0)
        for k, text in enumerate(panel.failed):
            ax.text(0.02, 0.04 + 0.07 * k, "failed: " + textwrap.shorten(text, 70), transform=ax.transAxes,
                    color="firebrick", fontsize=7)
        ax.set_title(panel.title, fontsize=10)
        ax.set_xlabel("wavelength (nm)")
        ax.set_ylabel(ylabel)
        ax.set_ylim(0.0, 1.0)
        ax.grid(alpha=0.3)
        if panel.curves:
            ax.legend(fontsize=7, ncol=2)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle(title)
    # ~ 15 characters of 7.5-pt text per inch of figure width: wrap to fit one panel or several
    fig.text(0.5, 0.01, "\n".join(textwrap.wrap(caption, int(15 * 6.0 * cols))), ha="center", va="bottom",
             fontsize=7.5)
    fig.tight_layout(rect=(0, 0.06, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)
