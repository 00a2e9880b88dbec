"""Sub-voxel volume fractions of binder, air and each pigment, and the permittivity grid.

Voxel [i, j, k] is centred at x = (i + ½)·Lx/nx, y = (j + ½)·Ly/ny,
z = z_top + (k + ½)·(z_bottom − z_top)/nz.

Method ("exact in z, supersampled in x and y"): every voxel column carries s×s vertical sample
lines (at x = (a + ½)·Lx/(nx·s), ...).  A line crosses a particle in one exact interval
(`Shape.z_chords`), whose overlap with each voxel's z-interval is exact; a voxel's fraction is
the mean over its lines.  The lateral spacing is at most a sixth of a voxel and a third of the
smallest half-width of a particle (a sphere's or a rod's radius), so every particle is hit by many lines.  Each particle's deposits are
then corrected so that they add up to its exact volume: segments that fill their voxel's
z-interval are exact and stay; the small quadrature error of the lateral sampling, which sits at
the particle's rim, is removed by scaling the partial segments.  Particles smaller than a voxel
count in full, and the pigment volume of the grid equals the particles' volume to rounding.
Where touching particles still add up to slightly more than 1 in a voxel, that voxel's pigment
fractions are scaled to sum to 1 (the volume lost is reported as `clipped_nm3`).  With a rough
top the binder surface height (`surface.binder_surface_nm`) is evaluated on the same lines; the
part of a line above it is air.

`eps_grid` mixes linearly: ε = Σ_m f_m ε_m(λ).  Voxelise once per realization, then call
eps_grid for each wavelength.  With material data that carry a local field
(`MaterialData.with_local_field`; a table request's default, docs/polarisation.md) every
pigment enters with the permittivity whose scalar contrast equals a small grain's dipole
response in the binder, for a sphere ε' = ε_h + 3ε_h(ε_p − ε_h)/(ε_p + 2ε_h), ε_h = the
binder's ε (docs/design.md §2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from solver.materials import AIR_EPS, MaterialData, default_materials

from .lattice import chunks, grid_windows
from .bodies import z_chords
from .surface import binder_surface_nm


@dataclass(frozen=True, eq=False)
class VoxelFractions:
    materials: tuple[str, ...]       # ("binder", "air", pigment codes...)
    fractions: np.ndarray            # float32 (n_materials, nx, ny, nz), sums to 1 per voxel
    period_nm: tuple[float, float]
    z_range_nm: tuple[float, float]  # (z_top, z_bottom)
    lines_per_voxel: int = 1         # s: s×s sample lines per voxel column
    clipped_nm3: float = 0.0         # pigment volume removed where touching particles overfilled

    @property
    def shape(self) -> tuple[int, int, int]:
        return tuple(self.fractions.shape[1:])

    @property
    def voxel_size_nm(self) -> tuple[float, float, float]:
        nx, ny, nz = self.shape
        return (self.period_nm[0] / nx, self.period_nm[1] / ny,
                (self.z_range_nm[1] - self.z_range_nm[0]) / nz)

    def volume_nm3(self, material: str) -> float:
        """Total volume of one material in the cell (nm³)."""
        dx, dy, dz = self.voxel_size_nm
        return float(self.fractions[self.materials.index(material)].sum(dtype=np.float64)) * dx * dy * dz


def lines_per_voxel(voxel_nm: float, min_radius_nm: float) -> int:
    """s such that the line spacing voxel/s is ≤ voxel/6 and ≤ a third of the smallest radius
    (largest error of one voxel's fraction ≈ 0.02 at the rims, see tests)."""
    return max(6, int(math.ceil(voxel_nm / (min_radius_nm / 3.0))))


def _deposit(real, shape, z_top, dz, spacing, s, per_population):
    """Add every particle's exactly normalised chord volumes into per_population (flat)."""
    nx, ny, nz = shape
    nvox = nx * ny * nz
    bodies = real.bodies
    c = real.centres_nm
    hx, hy = bodies.half_extent_nm(0), bodies.half_extent_nm(1)
    volumes = bodies.volumes_nm3
    line_area = spacing[0] * spacing[1]
    vox_vol = spacing[0] * s * spacing[1] * s * dz
    order = np.argsort(hx * hy)                      # similar window sizes per chunk
    per_item = int(np.ceil(2 * hx.max() / spacing[0] + 2) * np.ceil(2 * hy.max() / spacing[1] + 2) *
                   (np.ceil(2 * bodies.half_extent_nm(2).max() / dz) + 2)) if len(c) else 1
    for part in chunks(len(order), per_item):
        idx = order[part]
        sub = bodies.take(idx)
        kx, ky, valid, ox, oy = grid_windows(c[idx, 0], c[idx, 1], hx[idx], hy[idx], *spacing)
        zlo, zhi = z_chords(sub, ox, oy)
        zlo = zlo + c[idx, 2][:, None]
        zhi = zhi + c[idx, 2][:, None]
        hit = valid & (zhi > zlo)
        raw = np.sum(np.where(hit, zhi - zlo, 0.0), axis=1) * line_area
        col = ((np.mod(kx, nx * s) // s) * ny + np.mod(ky, ny * s) // s) * nz
        k0 = np.clip(np.floor((zlo - z_top) / dz).astype(np.int64), 0, nz - 1)
        k1 = np.clip(np.floor((zhi - z_top) / dz).astype(np.int64), 0, nz - 1)
        span = int(np.max(np.where(hit, k1 - k0, 0))) + 1 if hit.any() else 0
        pieces = []
        full_sum = np.zeros(len(idx))
        part_sum = np.zeros(len(idx))
        for step in range(span):
            k = k0 + step
            lo = np.maximum(zlo, z_top + k * dz)
            hi = np.minimum(zhi, z_top + (k + 1) * dz)
            w = np.where(hit & (k <= k1), np.clip(hi - lo, 0.0, None), 0.0)
            full = w >= dz * (1.0 - 1e-12)
            full_sum += np.sum(np.where(full, w, 0.0), axis=1)
            part_sum += np.sum(np.where(full, 0.0, w), axis=1)
            pieces.append((k, w, full))
        # Segments that fill their voxel's z-interval are exact; the quadrature error of the
        # lateral sampling sits at the rims, so the correction to the exact volume goes there.
        exact = volumes[idx] / line_area
        part_scale = np.where(part_sum > 0, (exact - full_sum) / np.where(part_sum > 0, part_sum, 1.0), 0.0)
        uniform = (part_sum <= 0) | (part_scale <= 0)
        all_scale = np.where(raw > 0, volumes[idx] / np.where(raw > 0, raw, 1.0), 0.0)
        pop = real.population[idx][:, None] * nvox
        for k, w, full in pieces:
            factor = np.where(uniform[:, None], all_scale[:, None], np.where(full, 1.0, part_scale[:, None]))
            w = w * factor * (line_area / vox_vol)
            sel = w > 0
            per_population += np.bincount((pop + col + k)[sel], weights=w[sel], minlength=per_population.size)
        missed = np.flatnonzero(raw <= 0)                # cannot happen with the spacing rule
        for p in missed:
            i = int(c[idx[p], 0] // (spacing[0] * s)) % nx
            j = int(c[idx[p], 1] // (spacing[1] * s)) % ny
            k = min(nz - 1, max(0, int((c[idx[p], 2] - z_top) // dz)))
            per_population[real.population[idx[p]] * nvox + (i * ny + j) * nz + k] += volumes[idx[p]] / vox_vol


def _below_surface(real, shape, z_top, z_bottom, dz, spacing, s):
    """Fraction of each voxel below the binder surface (binder or particle), (nx, ny, nz)."""
    nx, ny, nz = shape
    xs = (np.arange(nx * s) + 0.5) * spacing[0]
    ys = (np.arange(ny * s) + 0.5) * spacing[1]
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    zs = binder_surface_nm(real.bodies, real.centres_nm, real.period_nm, gx, gy)
    edges = z_top + dz * np.arange(nz + 1)
    below = np.clip(edges[None, None, 1:] - np.maximum(zs[:, :, None], edges[None, None, :-1]), 0.0, dz) / dz
    return below.reshape(nx, s, ny, s, nz).mean(axis=(1, 3))


def voxelize(realization, shape=(128, 128, 64), lines=None) -> VoxelFractions:
    """Volume fractions on an (nx, ny, nz) grid spanning the cell and its z range."""
    nx, ny, nz = (int(v) for v in shape)
    if min(nx, ny, nz) < 1:
        raise ValueError(f"voxel grid must be positive, got {shape}")
    real = realization
    period = real.period_nm
    z_top, z_bottom = real.z_range_nm
    dz = (z_bottom - z_top) / nz
    vox_xy = (period[0] / nx, period[1] / ny)
    r_min = float(real.bodies.smallest_half_width_nm.min()) if len(real.radii_nm) else max(vox_xy)
    s = int(lines) if lines else lines_per_voxel(max(vox_xy), r_min)
    spacing = (vox_xy[0] / s, vox_xy[1] / s)
    codes = real.population_codes
    nvox = nx * ny * nz
    flat = np.zeros(len(codes) * nvox)
    if len(real.radii_nm):
        _deposit(real, (nx, ny, nz), z_top, dz, spacing, s, flat)
    pig = flat.reshape(len(codes), nx, ny, nz)
    pig_sum = pig.sum(axis=0)
    over = pig_sum > 1.0
    dx, dy = vox_xy
    clipped = float(np.sum(pig_sum[over] - 1.0)) * dx * dy * dz
    if over.any():
        pig[:, over] /= pig_sum[over]
        pig_sum[over] = 1.0
    if z_top < 0:
        below = _below_surface(real, (nx, ny, nz), z_top, z_bottom, dz, spacing, s)
    else:
        below = np.ones((nx, ny, nz))
    binder = np.clip(below - pig_sum, 0.0, None)
    air = np.where(below >= pig_sum, 1.0 - below, 1.0 - pig_sum)
    fractions = np.concatenate([binder[None], air[None], pig], axis=0).astype(np.float32)
    return VoxelFractions(("binder", "air") + tuple(codes), fractions, tuple(period), (z_top, z_bottom), s,
                          clipped)


def eps_grid(vox: VoxelFractions, wavelength_nm: float, materials: MaterialData | None = None) -> np.ndarray:
    """Complex permittivity per voxel (nx, ny, nz) at one wavelength: Σ f_m ε_m(λ)
    (material data: the package's bulk constants unless given; data with a local field,
    `MaterialData.with_local_field`, give the pigments their local-field ε)."""
    data = materials or default_materials()
    eps = np.zeros(vox.shape, dtype=np.complex128)
    for name, frac in zip(vox.materials, vox.fractions):
        if name == "binder":
            value = complex(data.binder_eps(wavelength_nm))
        elif name == "air":
            value = complex(AIR_EPS)
        else:
            value = complex(data.pigment_eps(name, wavelength_nm))
        eps += value * frac
    return eps
