"""Separation of an image: unique colours → CIELAB targets → coverages per pixel, with a report.

    result = separate_image(model, rgb8, SolverSettings(), progress=bar.update)
    result.coverages                 # float32 [rows, columns, k]
    result.report.lines()            # what to tell the user

Images repeat colours: only the distinct 8-bit colours are separated (`image.unique_colours`),
then scattered back to the pixels.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .colour_space import delta_e2000, srgb8_to_lab
from .image import unique_colours
from .printmodel import PrintColourModel
from .solve import Separation, SolverSettings, separate_lab


@dataclass(frozen=True)
class SeparationReport:
    """Pixel statistics of a separation (ΔE between each pixel's colour and its print)."""

    pixels: int
    unique_colours: int
    clipped_pixels: int                  # out of gamut: ΔE76 > gamut_de
    gamut_de: float
    mean_de76: float                     # over all pixels
    clipped_mean_de76: float             # over the clipped pixels (0 when none)
    clipped_max_de76: float
    clipped_mean_de2000: float
    clipped_max_de2000: float
    seconds: float

    def lines(self) -> list[str]:
        share = self.clipped_pixels / max(self.pixels, 1)
        out = [f"separated {self.pixels:,} pixels ({self.unique_colours:,} distinct colours) in "
               f"{self.seconds:.1f} s; mean ΔE76 {self.mean_de76:.2f}"]
        if self.clipped_pixels:
            out.append(f"out of gamut (ΔE76 > {self.gamut_de:g}), clipped to the closest printable colour: "
                       f"{self.clipped_pixels:,} pixels ({share:.1%}); ΔE76 mean {self.clipped_mean_de76:.2f}, "
                       f"max {self.clipped_max_de76:.2f}; ΔE2000 mean {self.clipped_mean_de2000:.2f}, "
                       f"max {self.clipped_max_de2000:.2f}")
        else:
            out.append(f"every pixel in gamut (ΔE76 ≤ {self.gamut_de:g})")
        return out


@dataclass(frozen=True)
class ImageSeparation:
    coverages: np.ndarray                # float32 [rows, columns, k]
    printed_lab: np.ndarray              # float32 [rows, columns, 3]: the model's colour
    report: SeparationReport


def separate_image(model: PrintColourModel, rgb8: np.ndarray, settings: SolverSettings = SolverSettings(),
                   progress=None) -> ImageSeparation:
    """Separate an 8-bit sRGB image [rows, columns, 3]; `progress(done, total)` is called with
    the number of distinct colours separated so far and their total."""
    t0 = time.perf_counter()
    rows, cols = rgb8.shape[:2]
    colours, index = unique_colours(rgb8)
    done = [0]

    def chunk_done(n: int) -> None:
        done[0] += n
        progress(done[0], colours.shape[0])

    if progress is not None:
        progress(0, colours.shape[0])
    sep: Separation = separate_lab(model, srgb8_to_lab(colours), settings,
                                   progress=chunk_done if progress is not None else None)
    counts = np.bincount(index, minlength=colours.shape[0])
    de = sep.delta_e76
    clipped = sep.out_of_gamut
    n_clipped = int(counts[clipped].sum())
    if n_clipped:
        de00 = delta_e2000(sep.printed_lab[clipped], sep.target_lab[clipped])
        w = counts[clipped]
        stats = (float(np.average(de[clipped], weights=w)), float(de[clipped].max()),
                 float(np.average(de00, weights=w)), float(de00.max()))
    else:
        stats = (0.0, 0.0, 0.0, 0.0)
    report = SeparationReport(rows * cols, colours.shape[0], n_clipped, sep.gamut_de,
                              float(np.average(de, weights=counts)), *stats, time.perf_counter() - t0)
    k = model.n_inks
    coverages = sep.coverages.astype(np.float32)[index].reshape(rows, cols, k)
    printed = sep.printed_lab.astype(np.float32)[index].reshape(rows, cols, 3)
    return ImageSeparation(coverages, printed, report)
