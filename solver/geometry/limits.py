"""How far the placement goes: RSA thresholds and the reachable pigment concentrations.

RSA (random sequential addition) places particles directly up to RSA_FRACTION; above it the
particles are placed by RSA at a reduced size and grown by the packer (`packing`).

`reachable_limit(layer)` is the largest total pigment volume fraction accepted.  It is the
smaller of
* an empirical limit of the packer per shape and orientation, measured with
  `python -m benchmarks.bench_geometry --limits` (H = 1000 nm, 100-nm particles in
  1000-nm cells, larger ones in 2000-nm cells; see docs/geometry.md): the lowest fraction
  reached for every size, and
* a geometric bound: a vertical cylinder whose height exceeds half the layer crosses its
  mid-plane, where the sections of all such cylinders are disjoint.  Untilted, the sections are
  equal discs (area fraction ≤ π/√12 ≈ 0.9069), so φ ≤ 0.9069·L/H; the packer reached 0.93 of
  that bound (46 %, not 48 %, for 300-nm cylinders in a 1000-nm layer) and is allowed 0.90 of it.
  With a tilt spread (axes uniform on the cap θ ≤ t) a cylinder at angle θ is
  L cos θ + 2r sin θ high and its section an ellipse of area πr²/cos θ; if a share q of the
  cylinders (those with θ < θ_c, height > H/2) must cross, with mean 1/cos θ = m among them, then
  q·N·πr²·m ≤ 0.9069·A and φ ≤ 0.9069·L / (H·q·m) (an estimate: sections cut near a cylinder's end
  are smaller ellipses), times the packer's share (TILTED_DISC_SHARE).  A spread only helps once
  some cylinders can stay clear of the mid-plane (t > θ_c: θ_c ≈ 48° for 300-nm cylinders in
  1000 nm); below that it lowers the bound (m > 1).  Tilted vertical cylinders keep their drawn
  axes, which also lowers the packer's own limit (TILTED_VERTICAL_LIMIT).

`smallest_tilt_reaching(layer)` picks the smallest spread from a list for which the layer's
concentration is within `reachable_limit`.
"""

from __future__ import annotations

import dataclasses
import math

from .spec import GeometryError, LayerSpec, TILTED_ORIENTATIONS, cylinder_height_nm, cylinder_radius_length

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

#: Hexagonal packing of equal discs in a plane, and the share of it random packing reaches:
#: untilted 0.90 (reached 46 %, not 48 %, for 300-nm cylinders); with a tilt spread the axes
#: stay as drawn and the packer reaches less of the estimate: 0.82 (300-nm cylinders, tilt 15°:
#: 40 % reached, 42 % not, of an estimate of 48.6 %).
DISC_PACKING = math.pi / math.sqrt(12.0)
RANDOM_DISC_SHARE = 0.90
TILTED_DISC_SHARE = 0.82

#: Vertical cylinders with a spread keep their drawn axes (fixed orientations pack less densely
#: than turning ones): packer limit against the largest tilt (degrees), measured with the bench:
#: 100-nm cylinders reached 50 % with 15° and 30°, 45 % with 45°; 300-nm ones 40 % with 60°.
TILTED_VERTICAL_LIMIT = ((30.0, 0.50), (90.0, 0.40))

#: Orientation spreads (degrees) tried by `smallest_tilt_reaching`.
DEFAULT_TILTS_DEG = (0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0)


def _critical_angle(radius_nm: float, length_nm: float, half_height_nm: float) -> float:
    """Largest angle from the vertical below which a cylinder is higher than half_height_nm
    (π/2 when it always is), by bisection on the decreasing flank of L cos θ + 2r sin θ."""
    if cylinder_height_nm(radius_nm, length_nm, 0.5 * math.pi) > half_height_nm:
        return 0.5 * math.pi
    lo, hi = math.atan2(2.0 * radius_nm, length_nm), 0.5 * math.pi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cylinder_height_nm(radius_nm, length_nm, mid) > half_height_nm else (lo, mid)
    return lo


def _one_tier_cylinders(layer: LayerSpec) -> tuple[float, float] | None:
    """(radius, length) nm of vertical cylinders too long to stack two in the layer (flat top),
    None for any other layer."""
    spec = layer.particles
    if not (spec.shape == "cylinder" and spec.orientation == "vertical" and spec.rough_top == 0):
        return None
    r, length = cylinder_radius_length(spec.diameter_nm * math.exp(-3.0 * spec.size_spread))
    return None if length <= 0.5 * layer.thickness_nm else (r, length)


def geometric_limit(layer: LayerSpec) -> float:
    """Rigorous-geometry bound (times the packer's share of it) where one applies, else 1."""
    one_tier = _one_tier_cylinders(layer)
    if one_tier is None:
        return 1.0
    r, length = one_tier
    tilt = layer.particles.tilt_rad
    if tilt == 0:
        share, mean_sec = 1.0, 1.0
    else:
        crit = min(_critical_angle(r, length, 0.5 * layer.thickness_nm), tilt)
        share = (1.0 - math.cos(crit)) / (1.0 - math.cos(tilt))              # uniform on the cap
        mean_sec = -math.log(math.cos(crit)) / (1.0 - math.cos(crit)) if crit > 0 else 1.0
    packed = RANDOM_DISC_SHARE if tilt == 0 else TILTED_DISC_SHARE
    return packed * DISC_PACKING * length / (layer.thickness_nm * share * mean_sec)


def aligned_column_bound(layer: LayerSpec) -> float | None:
    """The fraction aligned vertical cylinders fill when hexagonally packed, one per column (a
    rigorous upper bound for them: too long to stack two in the layer), None where that does
    not apply (other shapes, or cylinders that stack)."""
    one_tier = _one_tier_cylinders(layer)
    return None if one_tier is None else DISC_PACKING * one_tier[1] / layer.thickness_nm


def reachable_limit(layer: LayerSpec) -> float:
    """Largest total pigment volume fraction the generator accepts for this layer."""
    spec = layer.particles
    packer = PACKER_LIMIT[(spec.shape, spec.orientation)]
    if spec.orientation == "vertical" and spec.tilt_rad > 0:
        packer = next(limit for tilt, limit in TILTED_VERTICAL_LIMIT if spec.tilt_deg <= tilt)
    return min(packer, geometric_limit(layer))


def smallest_tilt_reaching(layer: LayerSpec, tilts_deg=DEFAULT_TILTS_DEG) -> float | None:
    """Smallest orientation spread (degrees) from tilts_deg with which the layer's concentration
    is reachable (`reachable_limit`), None if none is; the layer's own tilt is replaced.

    Particles without a spread option (spheres, isotropic cylinders) give 0.0 when the layer is
    reachable as it is, else None.  Spreads that make a particle higher than the layer are
    skipped."""
    spec = layer.particles
    target = layer.ink.total_fraction
    if spec.orientation not in TILTED_ORIENTATIONS:
        return 0.0 if target <= reachable_limit(layer) else None
    for tilt in sorted(float(t) for t in tilts_deg):
        try:
            tilted = dataclasses.replace(layer, particles=dataclasses.replace(spec, tilt_rad=math.radians(tilt)))
        except GeometryError:
            continue
        if target <= reachable_limit(tilted):
            return tilt
    return None
