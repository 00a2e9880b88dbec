"""What a layer's geometry will cost, before any work: `geometry_cost(layer, grid) -> GeometryCost`.

* grains: Σ over pigments of round(φ_k·V_cell / v) — exactly the count `generate` draws for
  particles without a size spread; with a log-normal spread σ, the expected count
  φ_k·V / (v·e^{4.5σ²}) (the generator draws until the volume is reached: a few % either way);
* seconds = placement + voxelisation, a model fitted to `python -m benchmarks.bench_geometry --cost`
  on the 2-core development machine (docs/geometry.md gives its accuracy):
  - placement: a fixed part (the packer's per-iteration overhead) plus grains × a cost per
    grain, both depending on the shape, the orientation mode and the total fraction φ (piecewise
    linear in φ between measured points, `Shape.place_cost`; growing geometrically beyond the
    last point, where the packer nears its limit), plus the Brownian steps of agglutination
    (`Shape.agglutination_cost`);
  - voxelisation (the shape enters through its extents and its thinnest part): VOXEL_S_PER_LINE_STEP × (grains × sample lines in a grain's window × voxel
    layers it spans) + VOXEL_S_PER_GRAIN × grains + VOXEL_S_PER_VOXEL × voxels + VOXEL_S (+ the
    rough-top surface, per sample line);
* peak_bytes: the larger of the generator's peak (GEN_BYTES + `Shape.gen_bytes_per_grain` per
  grain) and the
  voxeliser's (its chunk buffers plus the grid arrays), as traced by tracemalloc.

Cheap: no particle is drawn or placed; orientation-dependent window sizes are averaged over a
fixed set of axes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .bodies import Bodies
from .orientation import sample_orientations
from .populations import grain_count
from .spec import LayerSpec
from .voxelize import lines_per_voxel

#: Relative growth of the placement cost per 0.01 of fraction beyond the last tabulated point.
PLACE_GROWTH_BEYOND = 0.25
#: A tilt spread makes aligned cylinders' contacts general (no parallel-axis shortcut).
TILT_PLACE_FACTOR = 2.0
#: Voxelisation: seconds per (grain × window line × voxel layer), per voxel, and per surface line.
VOXEL_S = 0.03
VOXEL_S_PER_GRAIN = 1.7e-6
VOXEL_S_PER_LINE_STEP = 1.33e-8
VOXEL_S_PER_VOXEL = 1.1e-7
SURFACE_S_PER_LINE = 2.0e-6
#: Memory: the generator's fixed part and bytes per grain; the voxeliser's chunk buffers
#: (`lattice.chunks` budget) while it deposits into one float64 grid per pigment, then the
#: grid arrays of the mixing step (six float64 work grids and the float32 fractions).
GEN_BYTES = 20 * 2**20
VOXEL_CHUNK_BYTES = 150 * 2**20
VOXEL_BYTES_PER_VOXEL = 48.0

#: Axes averaged over for the window sizes of grains with an axis.
_AXES_SAMPLE = 256


@dataclass(frozen=True)
class GeometryCost:
    grains: int          # particles generate() draws (exact without size spread)
    peak_bytes: int      # estimated peak of traced memory (generate + voxelize)
    seconds: float       # estimated wall time of generate + voxelize on the 2-core reference machine


def expected_grains(layer: LayerSpec) -> int:
    """Grains `generate` draws for this layer (exact without size spread, else the mean)."""
    spec = layer.particles
    volume = layer.cell_nm[0] * layer.cell_nm[1] * layer.thickness_nm
    total = 0
    for _, fraction in layer.ink.components:
        if spec.size_spread == 0:
            total += grain_count(spec, fraction, volume)
        else:
            mean_v = math.pi / 6.0 * spec.diameter_nm**3 * math.exp(4.5 * spec.size_spread**2)
            total += max(1, int(round(fraction * volume / mean_v)))
    return total


def _interpolate(points, phi: float) -> tuple[float, float]:
    """(fixed s, µs per grain) at φ: linear between the points, growing geometrically beyond."""
    xs, fixed, per_grain = zip(*points)
    if phi <= xs[-1]:
        return float(np.interp(phi, xs, fixed)), float(np.interp(phi, xs, per_grain))
    factor = (1.0 + PLACE_GROWTH_BEYOND) ** ((phi - xs[-1]) / 0.01)
    return fixed[-1] * factor, per_grain[-1] * factor


def placement_seconds(layer: LayerSpec, grains: int) -> float:
    spec = layer.particles
    phi = layer.ink.total_fraction
    fixed, per_grain = _interpolate(spec.shape.place_cost[spec.orientation], phi)
    if spec.tilt_rad > 0 and phi > spec.shape.rsa_fraction:
        fixed, per_grain = TILT_PLACE_FACTOR * fixed, TILT_PLACE_FACTOR * per_grain
    if spec.agglutination_kT > 0:
        agg_fixed, agg_per_grain = spec.shape.agglutination_cost
        fixed, per_grain = fixed + agg_fixed, per_grain + agg_per_grain
    return fixed + 1e-6 * per_grain * grains


def _typical_bodies(layer: LayerSpec) -> Bodies:
    """A fixed sample of grains of the median size in the spec's orientation mode."""
    spec = layer.particles
    if not spec.shape.oriented:
        return Bodies.of(spec.shape, np.array([spec.diameter_nm]), np.array([[0.0, 0.0, 1.0]]))
    axes = sample_orientations(spec.orientation, _AXES_SAMPLE, np.random.default_rng(0), spec.tilt_rad)
    return Bodies.of(spec.shape, np.full(_AXES_SAMPLE, spec.diameter_nm), axes)


def voxelisation_seconds(layer: LayerSpec, grid, grains: int) -> float:
    nx, ny, nz = (int(g) for g in grid)
    spec = layer.particles
    lx, ly = layer.cell_nm
    height = layer.thickness_nm * (1.0 + spec.rough_top * spec.diameter_nm / layer.thickness_nm)
    voxel_xy = max(lx / nx, ly / ny)
    r_min = float(spec.shape.smallest_half_width_nm(*spec.shape.dimensions(
        np.array([spec.diameter_nm * math.exp(-3.0 * spec.size_spread)])))[0])
    s = lines_per_voxel(voxel_xy, r_min)
    spacing_x, spacing_y, dz = lx / (nx * s), ly / (ny * s), height / nz
    body = _typical_bodies(layer)
    # Windows of a chunk are padded to the largest of its (similar-area) grains in x and y.
    side = np.maximum(body.half_extent_nm(0) / spacing_x, body.half_extent_nm(1) / spacing_y)
    lines = (2.0 * side + 2.0) ** 2
    steps = 2.0 * float(np.max(body.half_extent_nm(2))) / dz + 2.0
    work = grains * float(np.mean(lines)) * steps
    seconds = (VOXEL_S + VOXEL_S_PER_GRAIN * grains + VOXEL_S_PER_LINE_STEP * work
               + VOXEL_S_PER_VOXEL * nx * ny * nz)
    if spec.rough_top > 0:
        seconds += SURFACE_S_PER_LINE * nx * ny * s * s
    return seconds


def peak_bytes(layer: LayerSpec, grid, grains: int) -> int:
    nx, ny, nz = (int(g) for g in grid)
    spec = layer.particles
    pigments = len(layer.ink.components)
    voxels = nx * ny * nz
    gen = GEN_BYTES + spec.shape.gen_bytes_per_grain * grains
    deposit = VOXEL_CHUNK_BYTES + 8 * pigments * voxels
    mixing = voxels * (8 * pigments + VOXEL_BYTES_PER_VOXEL + 4 * (2 + pigments))
    return int(max(gen, deposit, mixing))


def geometry_cost(layer: LayerSpec, grid: tuple[int, int, int]) -> GeometryCost:
    """Estimated grains, peak memory (bytes) and time (s) of generate(layer) + voxelize(…, grid)."""
    if len(grid) != 3 or min(int(g) for g in grid) < 1:
        raise ValueError(f"voxel grid must be three positive counts (nx, ny, nz), got {grid!r}")
    grains = expected_grains(layer)
    seconds = placement_seconds(layer, grains) + voxelisation_seconds(layer, grid, grains)
    return GeometryCost(grains=grains, peak_bytes=peak_bytes(layer, grid, grains), seconds=seconds)
