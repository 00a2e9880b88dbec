"""One seeded random realization of an ink layer: `generate(layer, seed) -> Realization`.

Steps (every random stream is a child of SeedSequence(seed), one per step, `populations.STREAMS`,
so e.g. changing the agglutination strength leaves sizes and orientations as they were):
1. grains (`populations.draw_grains`): sizes per pigment population, scaled so the achieved
   volume fraction equals the target; orientations (shapes with an axis: isotropic, in-plane,
   vertical, with the spec's tilt spread), rough-top allowances, random order;
2. placement (`placement.place`): RSA (`rsa`) up to the shape's rsa_fraction, beyond it RSA of shrunk grains,
   then growth and relaxation (`packing`);
3. agglutination (`agglutination`) when its strength is > 0;
4. a final overlap check of all pairs (`statistics.find_overlaps_of`).
The concentration is checked first against `limits.reachable_limit`.

`progress(stage, fraction)`, when given, is called as the work goes on: stage is one of
GENERATE_STAGES ("grains", "rsa", "packing", "agglutination", "check"; stages a layer does not
need are skipped), fraction the share of that stage done, from 0 to 1.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .agglutination import AgglutinationStats, agglutinate
from .limits import reachable_limit
from .bodies import Bodies
from .orientation import ROTATION
from .packing import PackStats
from .placement import Progress, place
from .populations import draw_grains, seed_streams
from .spec import LayerSpec, UnreachableConcentrationError
from .statistics import find_overlaps_of

if TYPE_CHECKING:
    from .shapes import Shape

GENERATE_STAGES = ("grains", "rsa", "packing", "agglutination", "check")


@dataclass(frozen=True)
class GeneratorStats:
    method: str                              # "rsa" or "rsa+packing"
    rsa_tries: int
    rsa_placed: int
    rsa_scale: float                         # particle size factor during RSA (1 = final size)
    pack: PackStats | None
    agglutination: AgglutinationStats | None
    size_scale: tuple[tuple[str, float], ...]  # per population: factor applied to hit the target
    seconds: float


@dataclass(frozen=True, eq=False)
class Realization:
    """Particles of one random cell.  z grows downward; binder top at z = 0 where flat, bottom
    at z = thickness; z_range_nm = (z_top, thickness) with z_top < 0 when particles stand out."""

    layer: LayerSpec
    seed: int
    centres_nm: np.ndarray           # (N, 3)
    axes: np.ndarray                 # (N, 3) unit, a_z >= 0 ((0, 0, 1) for spheres)
    radii_nm: np.ndarray             # (N,)
    lengths_nm: np.ndarray           # (N,) length along the axis (twice the half length; 0 for spheres)
    population: np.ndarray           # (N,) index into population_codes
    population_codes: tuple[str, ...]
    protrusion: np.ndarray           # (N,) allowed fraction of the height above z = 0
    z_range_nm: tuple[float, float]
    stats: GeneratorStats = field(repr=False)

    @property
    def shape(self) -> Shape:
        return self.layer.particles.shape

    @property
    def period_nm(self) -> tuple[float, float]:
        return self.layer.cell_nm

    @property
    def bodies(self) -> Bodies:
        return Bodies(self.shape, self.radii_nm, 0.5 * self.lengths_nm, self.axes)

    @property
    def pigments(self) -> np.ndarray:
        """Pigment code per particle."""
        return np.asarray(self.population_codes, dtype="<U8")[self.population]

    @property
    def volumes_nm3(self) -> np.ndarray:
        return self.bodies.volumes_nm3

    @property
    def effective_diameters_nm(self) -> np.ndarray:
        """Diameter of the sphere of equal volume, per particle."""
        return np.cbrt(6.0 * self.volumes_nm3 / np.pi)

    @property
    def nominal_volume_nm3(self) -> float:
        return self.layer.cell_nm[0] * self.layer.cell_nm[1] * self.layer.thickness_nm

    @property
    def achieved_fractions(self) -> dict[str, float]:
        """Pigment volume / (cell area × thickness), per pigment code."""
        vol = np.bincount(self.population, weights=self.volumes_nm3, minlength=len(self.population_codes))
        return {code: float(v) / self.nominal_volume_nm3 for code, v in zip(self.population_codes, vol)}


def generate(layer: LayerSpec, seed: int, progress: Progress | None = None) -> Realization:
    """A reproducible random realization of the layer (same seed → identical arrays).

    progress(stage, fraction), when given, reports the work as it goes (module doc)."""
    t0 = time.perf_counter()
    streams = seed_streams(seed)
    spec = layer.particles
    target = layer.ink.total_fraction
    limit = reachable_limit(layer)
    if target > limit:
        raise UnreachableConcentrationError(
            f"total pigment concentration {100 * target:.4g}% is beyond what the packer reaches for "
            f"{spec.label} in a {layer.thickness_nm:.6g} nm layer: reachable limit {100 * limit:.3g}%",
            limit=limit)
    report = progress or (lambda stage, fraction: None)
    report("grains", 0.0)
    grains = draw_grains(layer, seed)
    report("grains", 1.0)
    placed = place(layer, grains, seed, progress)
    bodies = grains.bodies.turned(placed.axes)
    centres, axes = placed.centres_nm, placed.axes
    agg = None
    if spec.agglutination_kT > 0 and len(bodies) > 1:
        report("agglutination", 0.0)
        centres, axes, agg = agglutinate(bodies, grains.walls, centres, layer.cell_nm, spec.agglutination_kT,
                                         np.random.default_rng(streams["agglutination"]), ROTATION[spec.orientation],
                                         reference_axes=grains.bodies.axes,
                                         progress=None if progress is None else (lambda f: progress("agglutination", f)))
        bodies = bodies.turned(axes)
        if not agg.final_pack.converged:
            raise UnreachableConcentrationError(
                f"after agglutination the packer could not separate all grains of {spec.label} at "
                f"{100 * target:.4g}%; reachable limit ~{100 * limit:.3g}%", limit=limit)
        report("agglutination", 1.0)
    report("check", 0.0)
    centres = centres.copy()
    for k in (0, 1):
        centres[:, k] = np.mod(centres[:, k], layer.cell_nm[k])
    overlaps = len(find_overlaps_of(bodies, centres, layer.cell_nm))
    if overlaps:                                     # the packer certifies every pair: never
        raise RuntimeError(f"internal error: {overlaps} overlapping pairs in {layer.label}, seed {seed}")
    report("check", 1.0)
    z_top = 0.0
    if len(bodies) and spec.rough_top > 0:
        z_top = min(0.0, float(np.min(centres[:, 2] - bodies.half_extent_nm(2))))
    stats = GeneratorStats(method=placed.method, rsa_tries=placed.rsa_tries, rsa_placed=placed.rsa_placed,
                           rsa_scale=placed.rsa_scale, pack=placed.pack, agglutination=agg,
                           size_scale=grains.size_scale, seconds=time.perf_counter() - t0)
    return Realization(layer=layer, seed=int(seed), centres_nm=centres, axes=axes, radii_nm=bodies.radii_nm,
                       lengths_nm=2.0 * bodies.half_lengths_nm, population=grains.population,
                       population_codes=tuple(c for c, _ in layer.ink.components),
                       protrusion=grains.walls.protrusion, z_range_nm=(z_top, float(layer.thickness_nm)),
                       stats=stats)
