"""The grains of one realization before placement: sizes, pigment, orientations, rough-top allowances.

Per pigment population, N = round(φ·V_cell / v) grains (log-normal diameters when size_spread > 0,
drawn until the population's volume is reached); all sizes of a population are then scaled by a
common factor (recorded, |factor − 1| ≲ 1/(6N)) so that the achieved volume fraction equals the
target exactly.  The populations are mixed in a random order.  Every random stream is a child
of SeedSequence(seed) (`seed_streams`), one per step, so e.g. changing the agglutination
strength leaves sizes and orientations as they were.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .bodies import Bodies
from .orientation import sample_orientations
from .spec import SPREAD_TRUNCATION_SIGMA, GeometryError, LayerSpec
from .walls import Walls, draw_protrusion

#: Child streams of SeedSequence(seed), by step.
STREAMS = ("sizes", "order", "orientations", "placement", "agglutination")


def seed_streams(seed: int) -> dict[str, np.random.SeedSequence]:
    """The independent random streams of one realization, by step name (`STREAMS`)."""
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0:
        raise GeometryError(f"seed must be a non-negative integer, got {seed!r}")
    return dict(zip(STREAMS, np.random.SeedSequence(int(seed)).spawn(len(STREAMS))))


@dataclass(frozen=True, eq=False)
class Grains:
    """Grains drawn for a layer (`draw_grains`), not yet placed."""

    bodies: Bodies                       # sizes (nm) and drawn axes
    walls: Walls                         # allowed z range of each grain (rough top allowances)
    population: np.ndarray               # (N,) index into the ink's components
    size_scale: tuple[tuple[str, float], ...]   # per pigment: factor applied to hit the target

    def __len__(self) -> int:
        return len(self.bodies)


def grain_count(spec, fraction: float, cell_volume_nm3: float) -> int:
    """Grains of one population without size spread: round(φ V / v), at least 1."""
    return max(1, int(round(fraction * cell_volume_nm3 / (math.pi / 6.0 * spec.diameter_nm**3))))


def population_diameters(spec, fraction: float, cell_volume_nm3: float, rng: np.random.Generator):
    """(Effective) diameters (nm) of one population and the factor that makes its volume exact."""
    target = fraction * cell_volume_nm3
    d0 = spec.diameter_nm
    if spec.size_spread == 0:
        diam = np.full(grain_count(spec, fraction, cell_volume_nm3), d0)
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


def draw_grains(layer: LayerSpec, seed: int) -> Grains:
    """Sizes, pigments, orientations and rough-top allowances of one realization's grains."""
    streams = seed_streams(seed)
    spec = layer.particles
    cell_volume = layer.cell_nm[0] * layer.cell_nm[1] * layer.thickness_nm
    diams, pops, factors = [], [], []
    size_rng = np.random.default_rng(streams["sizes"])
    for k, (code, fraction) in enumerate(layer.ink.components):
        d, factor = population_diameters(spec, fraction, cell_volume, size_rng)
        diams.append(d)
        pops.append(np.full(len(d), k))
        factors.append((code, float(factor)))
    diam = np.concatenate(diams) if diams else np.zeros(0)
    pop = np.concatenate(pops) if pops else np.zeros(0, dtype=int)
    order = np.random.default_rng(streams["order"]).permutation(len(diam))
    diam, pop = diam[order], pop[order]
    if len(diam) and spec.span_nm(float(diam.max())) >= 0.5 * min(layer.cell_nm):
        raise GeometryError(f"particles of {spec.label} are too large for the cell at this concentration")
    orient_rng = np.random.default_rng(streams["orientations"])
    n = len(diam)
    axes = (sample_orientations(spec.orientation, n, orient_rng, spec.tilt_rad) if spec.shape.oriented
            else np.tile([0.0, 0.0, 1.0], (n, 1)))
    bodies = Bodies.of(spec.shape, diam, axes)
    walls = Walls(layer.thickness_nm, draw_protrusion(spec.rough_top, n, orient_rng))
    return Grains(bodies, walls, pop, tuple(factors))
