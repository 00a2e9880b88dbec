"""One seeded random realization of an ink layer: `generate(layer, seed) -> Realization`.

Steps (every random stream is a child of SeedSequence(seed), one per step, so e.g. changing the
agglutination strength leaves sizes and orientations as they were):
1. sizes — per pigment population, N = round(φ·V_cell / v) grains (log-normal diameters when
   size_spread > 0, drawn until the population's volume is reached); all sizes of a population
   are then scaled by a common factor (recorded, |factor − 1| ≲ 1/(6N)) so the achieved volume
   fraction equals the target;
2. orientations (cylinders: isotropic, in-plane, vertical), rough-top allowances, random order;
3. placement: RSA (`rsa`) up to RSA_FRACTION, beyond it RSA at reduced size then growth and
   relaxation (`packing`);
4. agglutination (`agglutination`) when its strength is > 0;
5. a final overlap check of all pairs (`statistics.find_overlaps_of`).
The concentration is checked first against `limits.reachable_limit`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .agglutination import AgglutinationStats, agglutinate
from .limits import PACK_START_FRACTION, RSA_FRACTION, reachable_limit
from .motion import ROTATION
from .packing import PackStats, pack
from .rsa import random_positions, rsa
from .shapes import Bodies, sample_orientations
from .statistics import find_overlaps_of
from .spec import (SPREAD_TRUNCATION_SIGMA, GeometryError, LayerSpec, UnreachableConcentrationError,
                   bounding_diameter_nm, cylinder_radius_length)
from .walls import Walls, draw_protrusion


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
    lengths_nm: np.ndarray           # (N,) cylinder length; 0 for spheres
    population: np.ndarray           # (N,) index into population_codes
    population_codes: tuple[str, ...]
    protrusion: np.ndarray           # (N,) allowed fraction of the height above z = 0
    z_range_nm: tuple[float, float]
    stats: GeneratorStats = field(repr=False)

    @property
    def shape(self) -> str:
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


def _population_diameters(spec, fraction, cell_volume, rng):
    """Diameters (effective) of one population and the factor that makes its volume exact."""
    target = fraction * cell_volume
    d0 = spec.diameter_nm
    if spec.size_spread == 0:
        n = max(1, int(round(target / (math.pi / 6.0 * d0**3))))
        diam = np.full(n, d0)
    else:
        sigma = spec.size_spread
        mean_v = math.pi / 6.0 * d0**3 * math.exp(4.5 * sigma**2)
        draw = []
        total = 0.0
        while total < target:
            z = rng.standard_normal(int(2 * target / mean_v) + 16)
            z = z[np.abs(z) <= SPREAD_TRUNCATION_SIGMA]
            draw.append(d0 * np.exp(sigma * z))
            total += float(np.sum(math.pi / 6.0 * draw[-1] ** 3))
        diam = np.concatenate(draw)
        cum = np.cumsum(math.pi / 6.0 * diam**3)
        n = max(1, int(np.searchsorted(cum, target)))
        if n < len(cum) and abs(cum[n] - target) < abs(cum[n - 1] - target):
            n += 1
        diam = diam[:n]
    factor = (target / float(np.sum(math.pi / 6.0 * diam**3))) ** (1.0 / 3.0)
    return diam * factor, factor


def _particles(layer: LayerSpec, seeds):
    spec = layer.particles
    cell_volume = layer.cell_nm[0] * layer.cell_nm[1] * layer.thickness_nm
    diams, pops, factors = [], [], []
    size_rng = np.random.default_rng(seeds[0])
    for k, (code, fraction) in enumerate(layer.ink.components):
        d, factor = _population_diameters(spec, fraction, cell_volume, size_rng)
        diams.append(d)
        pops.append(np.full(len(d), k))
        factors.append((code, float(factor)))
    diam = np.concatenate(diams) if diams else np.zeros(0)
    pop = np.concatenate(pops) if pops else np.zeros(0, dtype=int)
    order = np.random.default_rng(seeds[1]).permutation(len(diam))
    diam, pop = diam[order], pop[order]
    if len(diam) and bounding_diameter_nm(spec, float(diam.max())) >= 0.5 * min(layer.cell_nm):
        raise GeometryError(f"particles of {spec.label} are too large for the cell at this concentration")
    orient_rng = np.random.default_rng(seeds[2])
    n = len(diam)
    if spec.shape == "sphere":
        bodies = Bodies("sphere", 0.5 * diam, np.zeros(n), np.tile([0.0, 0.0, 1.0], (n, 1)))
    else:
        r, length = cylinder_radius_length(diam)
        bodies = Bodies("cylinder", r, 0.5 * length, sample_orientations(spec.orientation, n, orient_rng))
    walls = Walls(layer.thickness_nm, draw_protrusion(spec.rough_top, n, orient_rng))
    return bodies, walls, pop, tuple(factors)


def _place(layer, bodies, walls, rng):
    """RSA, then growth + relaxation when needed. Returns (centres, axes, partial stats)."""
    spec = layer.particles
    target = layer.ink.total_fraction
    rsa_max = RSA_FRACTION[spec.shape]
    import os
    start = float(os.environ.get("GEOM_START", PACK_START_FRACTION[spec.shape]))
    scale0 = 1.0 if target <= rsa_max else (start / target) ** (1.0 / 3.0)
    if os.environ.get("GEOM_NORSA") and scale0 < 1.0:
        from .rsa import RsaResult
        res = RsaResult(random_positions(bodies.scaled(scale0), walls, layer.cell_nm, rng), np.ones(len(bodies), bool), 0)
    else:
        res = rsa(bodies.scaled(scale0), walls, layer.cell_nm, rng)
    centres = res.centres
    axes = bodies.axes
    stats = dict(rsa_tries=res.tries, rsa_placed=int(res.placed.sum()), rsa_scale=scale0, pack=None,
                 method="rsa")
    if scale0 < 1.0 or not res.placed.all():
        left = np.flatnonzero(~res.placed)
        centres[left] = random_positions(bodies.scaled(scale0).take(left), walls.take(left), layer.cell_nm, rng)
        centres, axes, pstats = pack(bodies, walls, centres, layer.cell_nm, scale0,
                                     rotation=ROTATION[spec.orientation])
        stats.update(pack=pstats, method="rsa+packing")
        if not pstats.converged:
            reached = target * pstats.final_scale**3
            raise UnreachableConcentrationError(
                f"the packer did not reach {100 * target:.4g}% of {spec.label} in a "
                f"{layer.thickness_nm:.6g} nm layer (stopped near {100 * reached:.3g}% after "
                f"{pstats.iterations} iterations); reachable limit ~{100 * reachable_limit(layer):.3g}%",
                limit=reachable_limit(layer))
    return centres, axes, stats


def generate(layer: LayerSpec, seed: int) -> Realization:
    """A reproducible random realization of the layer (same seed → identical arrays)."""
    t0 = time.perf_counter()
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise GeometryError(f"seed must be a non-negative integer, got {seed!r}")
    spec = layer.particles
    target = layer.ink.total_fraction
    limit = reachable_limit(layer)
    if target > limit:
        raise UnreachableConcentrationError(
            f"total pigment concentration {100 * target:.4g}% is beyond what the packer reaches for "
            f"{spec.label} in a {layer.thickness_nm:.6g} nm layer: reachable limit {100 * limit:.3g}%",
            limit=limit)
    seeds = np.random.SeedSequence(int(seed)).spawn(5)
    bodies, walls, pop, factors = _particles(layer, seeds)
    drawn = bodies.axes
    centres, axes, stats = _place(layer, bodies, walls, np.random.default_rng(seeds[3]))
    bodies = Bodies(bodies.shape, bodies.radii_nm, bodies.half_lengths_nm, axes)
    agg = None
    if spec.agglutination_kT > 0 and len(bodies) > 1:
        centres, axes, agg = agglutinate(bodies, walls, centres, layer.cell_nm, spec.agglutination_kT,
                                         np.random.default_rng(seeds[4]), ROTATION[spec.orientation],
                                         reference_axes=drawn)
        bodies = Bodies(bodies.shape, bodies.radii_nm, bodies.half_lengths_nm, axes)
        if not agg.final_pack.converged:
            raise UnreachableConcentrationError(
                f"after agglutination the packer could not separate all grains of {spec.label} at "
                f"{100 * target:.4g}%; reachable limit ~{100 * limit:.3g}%", limit=limit)
    centres = centres.copy()
    for k in (0, 1):
        centres[:, k] = np.mod(centres[:, k], layer.cell_nm[k])
    overlaps = len(find_overlaps_of(bodies, centres, layer.cell_nm))
    if overlaps:                                     # the packer certifies every pair: never
        raise RuntimeError(f"internal error: {overlaps} overlapping pairs in {layer.label}, seed {seed}")
    z_top = 0.0
    if len(bodies) and spec.rough_top > 0:
        z_top = min(0.0, float(np.min(centres[:, 2] - bodies.half_extent_nm(2))))
    stats = GeneratorStats(method=stats["method"], rsa_tries=stats["rsa_tries"], rsa_placed=stats["rsa_placed"],
                           rsa_scale=stats["rsa_scale"], pack=stats["pack"], agglutination=agg,
                           size_scale=factors, seconds=time.perf_counter() - t0)
    return Realization(layer=layer, seed=int(seed), centres_nm=centres, axes=axes, radii_nm=bodies.radii_nm,
                       lengths_nm=2.0 * bodies.half_lengths_nm, population=pop,
                       population_codes=tuple(c for c, _ in layer.ink.components), protrusion=walls.protrusion,
                       z_range_nm=(z_top, float(layer.thickness_nm)), stats=stats)
