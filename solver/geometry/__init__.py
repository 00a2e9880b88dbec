"""Ink-layer geometry: random periodic cells of pigment particles in binder, and their voxel grids.

    layer = LayerSpec(parse_ink("Y7.5+B7.5"), parse_particles("sphere:100:agglutinated"))
    real = generate(layer, seed=1)             # particles (nm), reproducible from the seed
    vox = voxelize(real, (128, 128, 64))       # sub-voxel volume fractions, once per realization
    eps = eps_grid(vox, 550.0)                 # complex ε per voxel at λ = 550 nm

See docs/geometry.md for the algorithms and measured numbers.
"""

from .generate import GeneratorStats, Realization, generate
from .limits import reachable_limit
from .spec import (AGGLUTINATED_DEFAULT_KT, GeometryError, LayerSpec, ParticleSpec, ParticleSpecError,
                   UnreachableConcentrationError, cylinder_radius_length, parse_particles)
from .statistics import ClusterStats, cluster_statistic, find_overlaps, pair_correlation
from .voxelize import VoxelFractions, eps_grid, voxelize

__all__ = [
    "AGGLUTINATED_DEFAULT_KT", "ClusterStats", "GeneratorStats", "GeometryError", "LayerSpec",
    "ParticleSpec", "ParticleSpecError", "Realization", "UnreachableConcentrationError",
    "VoxelFractions", "cluster_statistic", "cylinder_radius_length", "eps_grid", "find_overlaps",
    "generate", "pair_correlation", "parse_particles", "reachable_limit", "voxelize",
]
