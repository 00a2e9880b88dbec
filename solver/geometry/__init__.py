"""Ink-layer geometry: random periodic cells of pigment particles in binder, and their voxel grids.

    layer = LayerSpec(parse_ink("Y7.5+B7.5"), parse_particles("sphere:100:agglutinated"))
    real = generate(layer, seed=1)             # particles (nm), reproducible from the seed
    vox = voxelize(real, (128, 128, 64))       # sub-voxel volume fractions, once per realization
    eps = eps_grid(vox, 550.0)                 # complex ε per voxel at λ = 550 nm

`geometry_cost(layer, grid)` estimates grains, time and memory before any work;
`smallest_tilt_reaching(layer)` picks an orientation spread that makes a concentration reachable.
See docs/geometry.md for the algorithms and measured numbers.
"""

from .bodies import Bodies
from .cost import GeometryCost, geometry_cost
from .generate import GENERATE_STAGES, GeneratorStats, Realization, generate
from .grammar import ParticleSpecError
from .limits import DEFAULT_TILTS_DEG, aligned_column_bound, reachable_limit, smallest_tilt_reaching
from .placement import Placement, place
from .populations import Grains, draw_grains
from .shapes import SHAPES, Shape
from .spec import (AGGLUTINATED_DEFAULT_KT, PARTICLE_GRAMMAR, PARTICLE_GRAMMAR_KEY, GeometryError, LayerSpec, ParticleSpec,
                   UnreachableConcentrationError, parse_particles)
from .statistics import ClusterStats, cluster_statistic, find_overlaps, pair_correlation
from .voxelize import VoxelFractions, eps_grid, voxelize

__all__ = [
    "AGGLUTINATED_DEFAULT_KT", "Bodies", "ClusterStats", "DEFAULT_TILTS_DEG", "GENERATE_STAGES", "GeneratorStats",
    "GeometryCost", "GeometryError", "Grains", "LayerSpec", "PARTICLE_GRAMMAR", "PARTICLE_GRAMMAR_KEY", "ParticleSpec", "ParticleSpecError",
    "Placement", "Realization", "SHAPES", "Shape", "UnreachableConcentrationError", "VoxelFractions",
    "cluster_statistic",
    "draw_grains", "eps_grid", "find_overlaps", "generate", "geometry_cost", "pair_correlation", "parse_particles",
    "place", "reachable_limit", "smallest_tilt_reaching", "aligned_column_bound", "voxelize",
]
