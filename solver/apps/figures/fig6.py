"""The paper's Fig. 6 picture of one table (paper §3.2, docs/design.md §2).

Left, a vertical strip: the ink on paper under uniform diffuse light, view angle 0° (top) to
60° (bottom).  Right, a square: the diffuse BRDF under a parallel beam, light angle 0–60° along
x, view angle 0–60° along y (top to bottom).  sRGB under D65, scaled so that a white Lambertian
of albedo 1 is (255, 255, 255).  The square shows π·f without the mirror lobe, averaged over
the azimuth difference Δφ (or at one Δφ).

`figure6(table)` returns the two images as arrays (for composing Fig. 7 and Fig. 8);
`plot_figure6(table, path)` draws the standalone picture with axes, angle labels and a caption.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from solver.colour.srgb import spectra_to_srgb8
from solver.paper import PAPER_ALBEDO
from solver.table.evaluate import column_at, diffuse_brdf, directional_albedo
from solver.table.interpolation import lerp_weights
from solver.table.schema import InkTable

MAX_ANGLE_DEG = 60.0
#: Δφ nodes of the azimuth average of the square
DPHI_SAMPLES = 9


def pixel_angles_rad(size: int) -> np.ndarray:
    """Angles (rad) of the pixel centres along a side: 0 at the first, 60° at the last."""
    return np.radians(np.linspace(0.0, MAX_ANGLE_DEG, size))


def azimuth_averaged(table: InkTable, dphi_rad) -> InkTable:
    """The table with R replaced by its mean over the given Δφ values (as the multilinear
    interpolant gives them), on a Δφ grid of two equal nodes: evaluating it at any Δφ gives
    the mean of the original's values at dphi_rad, in one evaluation instead of one per Δφ."""
    if not table.has_diffuse:
        return table
    i, t = lerp_weights(table.dphi, np.asarray(dphi_rad, dtype=float))
    mean = np.mean(table.R[..., i] * (1 - t) + table.R[..., i + 1] * t, axis=-1)
    return dataclasses.replace(table, dphi=np.array([0.0, np.pi]), R=np.stack([mean, mean], axis=-1),
                               jackknife=None)       # a picture: its replicas are not needed


def strip_reflectance(table: InkTable, paper, view_rad, mirror: bool = True) -> np.ndarray:
    """[nλ, …]: the strip's reflectance under uniform diffuse light seen at `view_rad`, with the
    layer's coherent mirror (the surround's reflection) or without it (the paper's strip)."""
    albedo = directional_albedo(table, paper, view_rad)
    return albedo if mirror else albedo - column_at(table, "R_spec", view_rad)


def figure6(table: InkTable, paper=PAPER_ALBEDO, size: int = 256, strip: int = 64,
            dphi_deg: float | None = None, mirror: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The strip (size × strip × 3) and the square (size × size × 3), uint8 sRGB; `mirror`:
    whether the strip shows the layer's coherent mirror (the paper's model does not).

    Row i of both is the view angle 60°·i/(size − 1); column j of the square the light angle
    60°·j/(size − 1)."""
    view = pixel_angles_rad(size)
    strip_rgb = spectra_to_srgb8(table.wavelengths, strip_reflectance(table, paper, view, mirror), axis=0)
    light = view
    if dphi_deg is None:
        table = azimuth_averaged(table, np.linspace(0.0, np.pi, DPHI_SAMPLES))
    spec = diffuse_brdf(table, paper, light[None, :], view[:, None], np.radians(dphi_deg or 0.0))
    square = spectra_to_srgb8(table.wavelengths, spec, axis=0)            # [view, light, 3]
    return np.ascontiguousarray(np.broadcast_to(strip_rgb[:, None, :], (size, strip, 3))), square


def crossed_out(height: int, width: int, thickness: int = 3) -> np.ndarray:
    """A failed cell: light grey with a red X corner to corner (uint8 RGB)."""
    image = np.full((height, width, 3), 235, dtype=np.uint8)
    y, x = np.mgrid[0:height, 0:width]
    u, v = x / max(width - 1, 1), y / max(height - 1, 1)
    scale = np.hypot(width, height) / 2
    on = (np.abs(u - v) * scale < thickness) | (np.abs(u + v - 1) * scale < thickness)
    image[on] = (200, 30, 30)
    return image


def caption(table: InkTable, paper, dphi_deg: float | None) -> str:
    meta = table.meta
    azimuth = "averaged over the azimuth difference" if dphi_deg is None else f"at azimuth difference {dphi_deg:g}°"
    return (f"Fig. 6. {meta.get('ink')}, {meta.get('particles')} ({meta.get('tier')} tier), on paper of albedo "
            f"{paper:g}. Left: diffuse light, view angle 0° (top) to 60° (bottom). Right: diffuse BRDF under a "
            f"parallel beam (mirror lobe left out), light angle along x, view angle along y, {azimuth}. "
            "A white Lambertian of albedo 1 is (255, 255, 255).")


def plot_figure6(table: InkTable, path, paper=PAPER_ALBEDO, dphi_deg: float | None = None, size: int = 256) -> None:
    """The standalone Fig. 6 picture with axes, angle labels and a caption (PNG)."""
    import textwrap

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    strip, square = figure6(table, paper, size=size, strip=size // 4, dphi_deg=dphi_deg)
    fig = plt.figure(figsize=(6.4, 4.6))
    grid = fig.add_gridspec(1, 2, width_ratios=(1, 4), wspace=0.35, left=0.1, right=0.97, top=0.92, bottom=0.27)
    extent = (0.0, MAX_ANGLE_DEG, MAX_ANGLE_DEG, 0.0)
    ax_strip, ax_square = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
    ax_strip.imshow(strip, extent=(0, 1) + extent[2:], aspect="auto", interpolation="nearest")
    ax_strip.set_xticks([])
    ax_strip.set_ylabel("view angle (°)")
    ax_strip.set_title("diffuse light", fontsize=9)
    ax_square.imshow(square, extent=extent, interpolation="nearest")
    ax_square.set_xlabel("light angle (°)")
    ax_square.set_ylabel("view angle (°)")
    ax_square.set_title("parallel beam: diffuse BRDF", fontsize=9)
    for ax in (ax_strip, ax_square):
        ax.set_yticks(np.arange(0, MAX_ANGLE_DEG + 1, 15))
    ax_square.set_xticks(np.arange(0, MAX_ANGLE_DEG + 1, 15))
    fig.text(0.05, 0.15, "\n".join(textwrap.wrap(caption(table, paper, dphi_deg), 95)), fontsize=7.5, va="top")
    fig.savefig(path, dpi=110)
    plt.close(fig)
