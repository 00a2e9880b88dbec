"""Pictures of a realization: horizontal and vertical sections like the paper's Figs. 3–5.

Binder grey, air white, pigments in their display colours (`PIGMENT_DISPLAY_RGB`).  The top row
cuts the particles exactly (point-in-particle per pixel); the bottom row shows the same planes
through the voxel grid the wave solver sees (colours mixed by the sub-voxel fractions).
"""

from __future__ import annotations

import numpy as np

from solver.materials import PIGMENT_DISPLAY_RGB

from .lattice import windows
from .bodies import contains
from .surface import binder_surface_nm

BINDER_RGB = (0.62, 0.62, 0.62)
AIR_RGB = (1.0, 1.0, 1.0)


def _palette(codes):
    return np.array([BINDER_RGB, AIR_RGB] + [PIGMENT_DISPLAY_RGB[c] for c in codes])


def _min_image(d, period):
    return d - period * np.round(d / period)


def horizontal_labels(real, z_nm: float, pixel_nm: float) -> np.ndarray:
    """Material label per pixel of the plane z = z_nm: 0 binder, 1 air, 2 + population."""
    lx, ly = real.period_nm
    nx, ny = int(round(lx / pixel_nm)), int(round(ly / pixel_nm))
    hx, hy = lx / nx, ly / ny
    labels = np.zeros((nx, ny), dtype=np.int16)
    if real.z_range_nm[0] < 0:
        gx, gy = np.meshgrid((np.arange(nx) + 0.5) * hx, (np.arange(ny) + 0.5) * hy, indexing="ij")
        labels[binder_surface_nm(real.bodies, real.centres_nm, real.period_nm, gx, gy) > z_nm] = 1
    bodies = real.bodies
    c = real.centres_nm
    cut = np.flatnonzero(np.abs(c[:, 2] - z_nm) < bodies.half_extent_nm(2))
    if cut.size == 0:
        return labels
    sub = bodies.take(cut)
    kx, vx, ox = windows(c[cut, 0], sub.half_extent_nm(0), hx)
    ky, vy, oy = windows(c[cut, 1], sub.half_extent_nm(1), hy)
    mx, my = kx.shape[1], ky.shape[1]
    dx = np.repeat(ox, my, axis=1)
    dy = np.tile(oy, (1, mx))
    inside = contains(sub, dx, dy, np.broadcast_to((z_nm - c[cut, 2])[:, None], dx.shape))
    inside &= np.repeat(vx, my, axis=1) & np.tile(vy, (1, mx))
    ix = np.mod(np.repeat(kx, my, axis=1), nx)[inside]
    iy = np.mod(np.tile(ky, (1, mx)), ny)[inside]
    labels[ix, iy] = 2 + np.broadcast_to(real.population[cut][:, None], inside.shape)[inside]
    return labels


def vertical_labels(real, y_nm: float, pixel_nm: float) -> np.ndarray:
    """Material labels on the plane y = y_nm, shape (nx, nz) with z from z_top down."""
    lx, _ = real.period_nm
    z_top, z_bottom = real.z_range_nm
    nx = int(round(lx / pixel_nm))
    nz = int(round((z_bottom - z_top) / pixel_nm))
    hx, hz = lx / nx, (z_bottom - z_top) / nz
    xs = (np.arange(nx) + 0.5) * hx
    zs = z_top + (np.arange(nz) + 0.5) * hz
    labels = np.zeros((nx, nz), dtype=np.int16)
    if z_top < 0:
        surf = binder_surface_nm(real.bodies, real.centres_nm, real.period_nm, xs, np.full(nx, y_nm))
        labels[zs[None, :] < surf[:, None]] = 1
    bodies = real.bodies
    c = real.centres_nm
    dy_all = _min_image(y_nm - c[:, 1], real.period_nm[1])
    cut = np.flatnonzero(np.abs(dy_all) < bodies.half_extent_nm(1))
    if cut.size == 0:
        return labels
    sub = bodies.take(cut)
    kx, vx, ox = windows(c[cut, 0], sub.half_extent_nm(0), hx)
    kz, vz, oz = windows(c[cut, 2] - z_top, sub.half_extent_nm(2), hz)
    mx, mz = kx.shape[1], kz.shape[1]
    dx = np.repeat(ox, mz, axis=1)
    dz = np.tile(oz, (1, mx))
    inside = contains(sub, dx, np.broadcast_to(dy_all[cut][:, None], dx.shape), dz)
    kzz = np.tile(kz, (1, mx))
    inside &= np.repeat(vx, mz, axis=1) & np.tile(vz, (1, mx)) & (kzz >= 0) & (kzz < nz)
    ix = np.mod(np.repeat(kx, mz, axis=1), nx)[inside]
    labels[ix, kzz[inside]] = 2 + np.broadcast_to(real.population[cut][:, None], inside.shape)[inside]
    return labels


def voxel_colours(vox, axis: int, index: int) -> np.ndarray:
    """RGB image of one voxel plane (axis 2: horizontal (nx, ny); axis 1: vertical (nx, nz))."""
    frac = np.take(vox.fractions, index, axis=axis + 1)
    return np.einsum("m...,mc->...c", frac, _palette(vox.materials[2:]))


def draw_sections(real, vox, path: str, title: str = "", pixel_nm: float | None = None,
                  z_nm: float | None = None, y_nm: float | None = None) -> dict:
    """Write a 2×2 figure (exact / voxel × horizontal / vertical) to path; returns the planes.

    The horizontal plane is at depth z_nm, the vertical one at y_nm (default: mid-cell), both
    moved to the centre of the nearest voxel plane so that the two rows show the same cut."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lx, ly = real.period_nm
    z_top, z_bottom = real.z_range_nm
    pixel = pixel_nm or max(lx, ly) / 600.0
    dz = (z_bottom - z_top) / vox.shape[2]
    dy = ly / vox.shape[1]
    k_mid = vox.shape[2] // 2 if z_nm is None else int(np.clip((z_nm - z_top) // dz, 0, vox.shape[2] - 1))
    j_mid = vox.shape[1] // 2 if y_nm is None else int(np.mod(y_nm, ly) // dy) % vox.shape[1]
    z_cut = z_top + (k_mid + 0.5) * dz                   # the voxel plane's centre, for both rows
    y_cut = (j_mid + 0.5) * dy
    pal = _palette(real.population_codes)
    h_exact = pal[horizontal_labels(real, z_cut, pixel)]
    v_exact = pal[vertical_labels(real, y_cut, pixel)]
    aspect = (z_bottom - z_top) / lx
    fig, ax = plt.subplots(2, 2, figsize=(11, 5.5 + 5.5 * aspect), dpi=110,
                           gridspec_kw=dict(height_ratios=[1, 1], width_ratios=[1, 1]))
    ext_h = (0, lx, 0, ly)
    ext_v = (0, lx, z_bottom, z_top)
    ax[0, 0].imshow(np.transpose(h_exact, (1, 0, 2)), origin="lower", extent=ext_h, interpolation="nearest")
    ax[0, 0].set_title(f"horizontal section z = {z_cut:.0f} nm (exact)")
    ax[0, 1].imshow(np.transpose(v_exact, (1, 0, 2)), extent=ext_v, interpolation="nearest", aspect="equal")
    ax[0, 1].set_title(f"vertical section y = {y_cut:.0f} nm (exact)")
    ax[1, 0].imshow(np.transpose(voxel_colours(vox, 2, k_mid), (1, 0, 2)), origin="lower", extent=ext_h,
                    interpolation="nearest")
    ax[1, 0].set_title(f"voxel grid {vox.shape[0]}×{vox.shape[1]}×{vox.shape[2]}, same plane")
    ax[1, 1].imshow(np.transpose(voxel_colours(vox, 1, j_mid), (1, 0, 2)), extent=ext_v,
                    interpolation="nearest", aspect="equal")
    ax[1, 1].set_title("voxel grid, same plane")
    for a in ax[:, 0]:
        a.set_xlabel("x, nm")
        a.set_ylabel("y, nm")
    for a in ax[:, 1]:
        a.set_xlabel("x, nm")
        a.set_ylabel("z, nm (down)")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return {"z_nm": z_cut, "y_nm": y_cut}
