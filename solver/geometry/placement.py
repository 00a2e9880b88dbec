"""Where the grains go: RSA alone up to the shape's rsa_fraction, beyond it RSA of shrunk grains
then packing.

`place(layer, grains, seed)` does not check the concentration against `limits.reachable_limit`
(the generator does that first); it raises UnreachableConcentrationError when the packer gives
up, so a search for the reachable limit can call it directly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .limits import reachable_limit
from .orientation import ROTATION
from .packing import PackOptions, PackStats, pack
from .populations import Grains, seed_streams
from .rsa import random_positions, rsa
from .spec import LayerSpec, UnreachableConcentrationError

#: progress(stage, fraction): stage names in the order they run, fraction of that stage in [0, 1].
Progress = Callable[[str, float], None]


@dataclass(frozen=True, eq=False)
class Placement:
    centres_nm: np.ndarray          # (N, 3)
    axes: np.ndarray                # (N, 3) after the packer's turns
    method: str                     # "rsa" or "rsa+packing"
    rsa_tries: int
    rsa_placed: int
    rsa_scale: float                # grain size factor during RSA (1 = final size)
    pack: PackStats | None


def place(layer: LayerSpec, grains: Grains, seed: int, progress: Progress | None = None,
          options: PackOptions = PackOptions(), start_fraction: float | None = None) -> Placement:
    """Positions of the grains (RSA, then growth + relaxation when the concentration needs it).

    start_fraction: volume fraction of the shrunk grains RSA places before packing (default
    the shape's pack_start_fraction); options: the packer's knobs."""
    spec = layer.particles
    rng = np.random.default_rng(seed_streams(seed)["placement"])
    bodies, walls = grains.bodies, grains.walls
    target = layer.ink.total_fraction
    packing = target > spec.shape.rsa_fraction
    start = spec.shape.pack_start_fraction if start_fraction is None else start_fraction
    scale0 = (min(target, start) / target) ** (1.0 / 3.0) if packing else 1.0
    report = None if progress is None else (lambda f: progress("rsa", f))
    res = rsa(bodies.scaled(scale0), walls, layer.cell_nm, rng, progress=report)
    centres, axes = res.centres, bodies.axes
    if not (packing or not res.placed.all()):
        return Placement(centres, axes, "rsa", res.tries, int(res.placed.sum()), scale0, None)
    left = np.flatnonzero(~res.placed)
    centres[left] = random_positions(bodies.scaled(scale0).take(left), walls.take(left), layer.cell_nm, rng)
    report = None if progress is None else (lambda f: progress("packing", f))
    centres, axes, stats = pack(bodies, walls, centres, layer.cell_nm, scale0, options,
                                rotation=ROTATION[spec.orientation], progress=report)
    if not stats.converged:
        reached = target * stats.final_scale**3
        limit = reachable_limit(layer)
        raise UnreachableConcentrationError(
            f"the packer did not reach {100 * target:.4g}% of {spec.label} in a "
            f"{layer.thickness_nm:.6g} nm layer (stopped near {100 * reached:.3g}% after "
            f"{stats.iterations} iterations); reachable limit ~{100 * limit:.3g}%", limit=limit)
    if progress is not None:
        progress("packing", 1.0)
    return Placement(centres, axes, "rsa+packing", res.tries, int(res.placed.sum()), scale0, stats)
