"""Agglutination: pigment grains that attract each other gather into clusters (paper Fig. 4).

Model: overdamped Brownian dynamics of the hard particles with a short-range attraction of
strength ε (in kT; the spec's `agglutinated=ε`) between every pair, whatever their pigment:

    U(g) = −ε·exp(−g/λ),   g = surface gap,   λ = well_range × mean diameter.

Step (units kT = 1, mobility·Δt = δ²/2 with δ the rms random step per coordinate):
  x ← x + (δ²/2)·F + δ·ξ,  F = −∇U  (each pair pulls its two grains together along the normal,
  the pull capped at δ per step), ξ ~ N(0, 1); then one rigid-body overlap-removal sweep
  (`motion.push_apart`) and the wall clamp.  After `steps` steps `packing.pack` removes the
  last overlaps.  ε = 0 gives a hard-particle fluid (the placement is just stirred); growing ε
  gives more and bigger clusters — `statistics.cluster_statistic` measures it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .bodies import Bodies
from .motion import pair_normals_gaps, push_apart
from .neighbours import PairList, spatial_order
from .packing import PackOptions, PackStats, pack
from .walls import Walls


@dataclass(frozen=True)
class AgglutinationOptions:
    steps: int = 600
    step_rms: float = 0.05      # δ, × mean diameter
    well_range: float = 0.1     # λ, × mean diameter
    cutoff: float = 4.0         # attraction neglected beyond this many λ of gap


@dataclass(frozen=True)
class AgglutinationStats:
    strength_kT: float
    steps: int
    seconds: float
    final_pack: PackStats


def agglutinate(bodies: Bodies, walls: Walls, centres: np.ndarray, period_nm, strength_kT: float,
                rng: np.random.Generator, rotation: str = "none",
                options: AgglutinationOptions = AgglutinationOptions(),
                pack_options: PackOptions = PackOptions(), reference_axes=None, progress=None):
    """Brownian dynamics with attraction; returns (centres, axes, stats), overlap-free.
    progress(fraction) is called now and then when given (the steps count 0.8, the final pack 0.2)."""
    t0 = time.perf_counter()
    n = len(bodies)
    mean_d = 2.0 * float(np.mean(bodies.radii_nm)) if n else 1.0
    perm = spatial_order(np.asarray(centres, dtype=float), 2.0 * mean_d)
    body, wall = bodies.take(perm), walls.take(perm)
    drawn = (bodies.axes if reference_axes is None else np.asarray(reference_axes))[perm]
    xyz = np.ascontiguousarray(np.asarray(centres, dtype=float)[perm].T)
    delta = options.step_rms * mean_d
    lam = options.well_range * mean_d
    reach = 2.0 * float(body.bounding_radii_nm.max()) + options.cutoff * lam if n else 0.0
    margin = pack_options.margin * 0.5 * mean_d
    verlet = PairList(period_nm, pack_options.skin * 0.5 * mean_d + options.cutoff * lam)
    vol = body.volumes_nm3
    for step in range(options.steps if n > 1 else 0):
        if progress is not None and step % 50 == 0:
            progress(0.8 * step / options.steps)
        i, j = verlet.pairs(xyz, reach, reach)
        normal, gap = pair_normals_gaps(body, xyz, i, j, period_nm, verlet.hint, margin,
                                        pack_options.search_iterations)
        if body.shape.uses_axis_hint:
            verlet.hint = normal.T
        axes = push_apart(xyz, body, i, j, normal, gap, margin, period_nm, rotation, 1.0,
                          drawn, pack_options.max_tilt if rotation == "free" else np.pi)
        if axes is not body.axes:
            body = body.turned(axes)
        near = np.flatnonzero((gap >= 0) & (gap < options.cutoff * lam))
        if near.size and strength_kT > 0:
            ia, ja = i[near], j[near]
            pull = np.minimum(0.5 * delta**2 * strength_kT / lam * np.exp(-gap[near] / lam), delta)
            wi = vol[ja] / (vol[ia] + vol[ja])
            for k in range(3):
                move = pull * normal[k, near]
                xyz[k] += np.bincount(ia, weights=wi * move, minlength=n)
                xyz[k] -= np.bincount(ja, weights=(1.0 - wi) * move, minlength=n)
        xyz += rng.normal(0.0, delta, xyz.shape)
        wall.clamp(xyz, body)
    out = np.empty((n, 3))
    out[perm] = xyz.T
    out_axes = np.empty((n, 3))
    out_axes[perm] = body.axes
    final_centres, final_axes, stats = pack(bodies.turned(out_axes),
                                            walls, out, period_nm, 1.0, pack_options, rotation,
                                            reference_axes,
                                            None if progress is None else (lambda f: progress(0.8 + 0.2 * f)))
    return final_centres, final_axes, AgglutinationStats(strength_kT, options.steps,
                                                         time.perf_counter() - t0, stats)
