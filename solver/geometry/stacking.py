"""Voxel grids of printed layers stacked in z (an overprint: ink A printed over ink B).

Each layer is voxelised on its own share of the grid's z cells — a particle layer from its
realization, a molecular layer as its uniform mix — and the grids are concatenated top first.
The wave solver needs one voxel height for the whole stack, so every layer must hold a whole
number of cells of height H/nz (H the total thickness); `split_cells` says how many, or refuses
with the grid that would fit.
"""

from __future__ import annotations

import math

import numpy as np

from ..inks import Ink
from .voxelize import VoxelFractions

#: largest relative change of a layer's thickness accepted when rounding it to whole cells
CELL_ROUNDING = 0.01


def split_cells(thicknesses_nm, nz: int) -> tuple[int, ...]:
    """Cells per layer for a stack of `thicknesses_nm` on `nz` cells of equal height."""
    total = float(sum(thicknesses_nm))
    cells = [max(1, round(nz * h / total)) for h in thicknesses_nm]
    dz = total / nz
    worst = max(abs(n * dz - h) / h for n, h in zip(cells, thicknesses_nm))
    if sum(cells) != nz or worst > CELL_ROUNDING:
        unit = math.gcd(*(int(round(h)) for h in thicknesses_nm))
        hint = next((k for k in range(nz, 4 * nz + 1) if all((k * h / total) % 1 < 1e-9 for h in thicknesses_nm)),
                    None)
        raise ValueError(f"--grid NZ {nz} does not split the layers {'/'.join(f'{h:g}' for h in thicknesses_nm)} nm "
                         f"into whole cells of one height"
                         + (f"; use NZ = {hint}" if hint else f"; choose layer thicknesses in steps of {unit} nm"))
    return tuple(cells)


def uniform_layer(ink: Ink, shape: tuple[int, int, int], period_nm, z_range_nm) -> VoxelFractions:
    """A molecular layer: binder and pigments mixed uniformly in every voxel."""
    materials = ("binder", "air") + tuple(code for code, _ in ink.components)
    fractions = np.zeros((len(materials),) + tuple(shape), np.float32)
    fractions[0] = 1.0 - ink.total_fraction
    for k, (_, f) in enumerate(ink.components):
        fractions[2 + k] = f
    return VoxelFractions(materials, fractions, tuple(period_nm), tuple(z_range_nm))


def stack_voxels(layers: list[VoxelFractions]) -> VoxelFractions:
    """Concatenate layers' grids along z (top first); materials are merged by name."""
    if not layers:
        raise ValueError("a stack needs at least one layer")
    materials = []
    for vox in layers:
        materials += [m for m in vox.materials if m not in materials]
    nx, ny = layers[0].shape[:2]
    if any(v.shape[:2] != (nx, ny) or tuple(v.period_nm) != tuple(layers[0].period_nm) for v in layers):
        raise ValueError("stacked layers need the same lateral grid and period")
    parts = []
    for vox in layers:
        full = np.zeros((len(materials),) + vox.shape, np.float32)
        for k, m in enumerate(vox.materials):
            full[materials.index(m)] = vox.fractions[k]
        parts.append(full)
    z_top, z_bottom = layers[0].z_range_nm[0], layers[-1].z_range_nm[1]
    return VoxelFractions(tuple(materials), np.concatenate(parts, axis=3), tuple(layers[0].period_nm),
                          (float(z_top), float(z_bottom)))
