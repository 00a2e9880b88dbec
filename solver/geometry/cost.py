"""What a layer's geometry will cost, before any work: `geometry_cost(layer, grid) -> GeometryCost`.

* grains: Σ over pigments of round(φ_k·V_cell / v) — exactly the count `generate` draws for
  particles without a size spread; with a log-normal spread σ, the expected count
  φ_k·V / (v·e^{4.5σ²}) (the generator draws until the volume is reached: a few % either way);
* seconds = placement + voxelisation, a model fitted to `python -m benchmarks.bench_geometry --cost`
  on the 2-core development machine (docs/geometry.md gives its accuracy):
  - placement: a fixed part (the packer's per-iteration overhead) plus grains × a cost per
    grain, both depending on the shape, the orientation mode and the total fraction φ (piecewise
    linear in φ between measured points, `PLACE_COST`; growing geometrically beyond the last
    point, where the packer nears its limit), plus the Brownian steps of agglutination;
  - voxelisation: VOXEL_S_PER_LINE_STEP × (grains × sample lines in a grain's window × voxel
    layers it spans) + VOXEL_S_PER_GRAIN × grains + VOXEL_S_PER_VOXEL × voxels + VOXEL_S (+ the
    rough-top surface, per sample line);
* peak_bytes: the larger of the generator's peak (GEN_BYTES + bytes per grain) and the
  voxeliser's (its chunk buffers plus the grid arrays), as traced by tracemalloc.

Cheap: no particle is drawn or placed; orientation-dependent window sizes are averaged over a
fixed quasi-random set of axes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .limits import RSA_FRACTION
from .populations import grain_count
from .shapes import Bodies, sample_orientations
from .spec import LayerSpec, cylinder_radius_length
from .voxelize import lines_per_voxel

#: Placement cost against the total volume fraction φ, per (shape, orientation): points
#: (φ, fixed seconds, µs per grain) — the fixed part is the packer's per-iteration overhead.
PLACE_COST = {
    ("sphere", None): ((0.0, 0.0, 15.0), (0.15, 0.05, 18.0), (0.30, 0.2, 30.0), (0.50, 0.6, 36.0),
                       (0.58, 2.0, 100.0)),
    ("cylinder", "isotropic"): ((0.0, 0.0, 900.0), (0.15, 0.05, 1000.0), (0.30, 0.8, 900.0), (0.50, 3.9, 560.0)),
    ("cylinder", "inplane"): ((0.0, 0.0, 600.0), (0.15, 0.05, 700.0), (0.30, 0.8, 700.0), (0.50, 3.1, 1050.0),
                              (0.55, 10.0, 2000.0)),
    ("cylinder", "vertical"): ((0.0, 0.0, 120.0), (0.15, 0.02, 150.0), (0.30, 0.4, 250.0), (0.50, 0.9, 310.0)),
}
#: Relative growth of the placement cost per 0.01 of fraction beyond the last tabulated point.
PLACE_GROWTH_BEYOND = 0.25
#: A tilt spread makes aligned cylinders' contacts general (no parallel-axis shortcut).
TILT_PLACE_FACTOR = 2.0
#: Brownian steps of agglutination: fixed seconds and µs per grain.
AGGLUTINATION_COST = {"sphere": (0.1, 1200.0), "cylinder": (1.0, 10000.0)}
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
GEN_BYTES_PER_GRAIN = {"sphere": 1000.0, "cylinder": 7000.0}
VOXEL_CHUNK_BYTES = 150 * 2**20
VOXEL_BYTES_PER_VOXEL = 48.0

#: Axes averaged over for the window sizes of cylinders.
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
    fixed, per_grain = _interpolate(PLACE_COST[(spec.shape, spec.orientation)], phi)
    if spec.tilt_rad > 0 and phi > RSA_FRACTION[spec.shape]:
        fixed, per_grain = TILT_PLACE_FACTOR * fixed, TILT_PLACE_FACTOR * per_grain
    if spec.agglutination_kT > 0:
        agg_fixed, agg_per_grain = AGGLUTINATION_COST[spec.shape]
        fixed, per_grain = fixed + agg_fixed, per_grain + agg_per_grain
    return fixed + 1e-6 * per_grain * grains


def _typical_bodies(layer: LayerSpec) -> Bodies:
    """A fixed sample of grains of the median size in the spec's orientation mode."""
    spec = layer.particles
    if spec.shape == "sphere":
        return Bodies("sphere", np.array([0.5 * spec.diameter_nm]), np.zeros(1), np.array([[0.0, 0.0, 1.0]]))
    axes = sample_orientations(spec.orientation, _AXES_SAMPLE, np.random.default_rng(0), spec.tilt_rad)
    r, length = cylinder_radius_length(spec.diameter_nm)
    return Bodies("cylinder", np.full(_AXES_SAMPLE, r), np.full(_AXES_SAMPLE, 0.5 * length), axes)


def voxelisation_seconds(layer: LayerSpec, grid, grains: int) -> float:
    nx, ny, nz = (int(g) for g in grid)
    spec = layer.particles
    lx, ly = layer.cell_nm
    height = layer.thickness_nm * (1.0 + spec.rough_top * spec.diameter_nm / layer.thickness_nm)
    voxel_xy = max(lx / nx, ly / ny)
    r_min = 0.5 * spec.diameter_nm * math.exp(-3.0 * spec.size_spread)
    if spec.shape == "cylinder":
        r_min = cylinder_radius_length(2.0 * r_min)[0]
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
    gen = GEN_BYTES + GEN_BYTES_PER_GRAIN[spec.shape] * grains
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
