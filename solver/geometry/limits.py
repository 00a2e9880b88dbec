"""How far the placement goes: RSA thresholds and the reachable pigment concentrations.

RSA (random sequential addition) places particles directly up to RSA_FRACTION; above it the
particles are placed by RSA at a reduced size and grown by the packer (`packing`).

`reachable_limit(layer)` is the largest total pigment volume fraction accepted.  It is the
smaller of
* an empirical limit of the packer per shape and orientation, measured with
  `python -m benchmarks.bench_geometry --limits` (H = 1000 nm, 100-nm particles in
  1000-nm cells, larger ones in 2000-nm cells; see docs/geometry.md): the lowest fraction
  reached for every size, and
* a geometric bound: vertical cylinders longer than half the layer all cross its mid-plane,
  where their sections are disjoint equal discs (area fraction ≤ π/√12 ≈ 0.9069), so
  φ ≤ 0.9069·L/H; the packer reached 0.93 of that bound (46 %, not 48 %, for 300-nm
  cylinders in a 1000-nm layer) and is allowed 0.90 of it.
"""

from __future__ import annotations

import math

from .spec import LayerSpec, cylinder_radius_length

#: Largest fraction placed by RSA alone (RSA jams at ≈ 38 % for spheres, lower for rods).
RSA_FRACTION = {"sphere": 0.25, "cylinder": 0.15}

#: Above RSA_FRACTION, RSA places the particles shrunk to fill this fraction, then the packer
#: grows them (RSA slows down as it nears its jamming limit; growing is cheaper).
PACK_START_FRACTION = {"sphere": 0.15, "cylinder": 0.15}

#: Empirical limits of the packer (total volume fraction), see module doc.
PACKER_LIMIT = {
    ("sphere", None): 0.58,
    ("cylinder", "isotropic"): 0.50,
    ("cylinder", "inplane"): 0.55,
    ("cylinder", "vertical"): 0.50,
}

#: Hexagonal packing of equal discs in a plane, and the share of it random packing reaches.
DISC_PACKING = math.pi / math.sqrt(12.0)
RANDOM_DISC_SHARE = 0.90


def geometric_limit(layer: LayerSpec) -> float:
    """Rigorous-geometry bound (times the packer's share of it) where one applies, else 1."""
    spec = layer.particles
    if spec.shape == "cylinder" and spec.orientation == "vertical" and spec.rough_top == 0:
        _, length = cylinder_radius_length(spec.diameter_nm * math.exp(-3.0 * spec.size_spread))
        if length > 0.5 * layer.thickness_nm:
            return RANDOM_DISC_SHARE * DISC_PACKING * length / layer.thickness_nm
    return 1.0


def reachable_limit(layer: LayerSpec) -> float:
    """Largest total pigment volume fraction the generator accepts for this layer."""
    spec = layer.particles
    return min(PACKER_LIMIT[(spec.shape, spec.orientation)], geometric_limit(layer))
