"""Finite circular cylinders of length 6 radii (the paper's rods, docs/design.md §3), sized by
their effective diameter D (the sphere of equal volume): π r²·6r = π D³/6 ⇒ r = D / 36^(1/3)
≈ 0.303 D, L ≈ 1.817 D.  Axis isotropic, in the layer plane or across it (with a tilt spread).

Pair separations (`contacts`), by the separating-axis theorem with the support function
w(n) = h|a·n| + r√(1 − (a·n)²): the enclosing capsules first (segment–segment distance: capsules
apart ⇒ cylinders apart), then g on the candidate axes of the contact types (face: a_i, a_j;
side–side: a_i×a_j and the capsule direction; side–rim: d ⟂ a_i, d ⟂ a_j; the centre line; the
pair's previous axis; parallel axes: the closed-form optimum), exact 1-D searches on the great
circles n ⟂ a_i, n ⟂ a_j (side contacts), and a pattern search for rim–rim contacts.  The result
is a lower bound: a pair we cannot certify counts as overlapping.

The support function has kinks where a side line or a face supports; near them a turn moves the
support point to the other end or round the rim, so contact rows carry those candidate points
too (`support_candidates`).  The binder over a protruding rod is sampled on its surface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..depolarisation import axial_field, spheroid_axial_factor
from ..separating_axis import (SEARCH_ITERATIONS, refine_axis, ridge_search, segment_closest, segment_closest_params,
                               support_gap, unit)
from .base import Shape

#: Cylinder length in radii (the paper's cylinders).
CYLINDER_LENGTH_RADII = 6.0
#: Below this |a·n| a cylinder's far end joins its contact rows (a turn may make it the
#: support point), and below this sin∠(a, n) its face's rim does (four points).
SIDE_TOLERANCE = 0.1
FACE_TOLERANCE = 0.1
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


def cylinder_radius_length(effective_diameter_nm):
    """Radius and length (nm) of a cylinder of length 6 radii with the volume of a sphere of
    the given diameter: π r²·6r = π D³/6  ⇒  r = D / 36^(1/3)."""
    radius = effective_diameter_nm / (6.0 * CYLINDER_LENGTH_RADII) ** (1.0 / 3.0)
    return radius, CYLINDER_LENGTH_RADII * radius


def cylinder_height_nm(radius_nm: float, length_nm: float, polar_rad: float) -> float:
    """Vertical extent (nm) of a cylinder whose axis makes the angle polar_rad with the vertical."""
    return length_nm * abs(math.cos(polar_rad)) + 2.0 * radius_nm * abs(math.sin(polar_rad))


def _parallel_axis(d, ai, aj, ri, rj, hi, hj):
    """Optimal separating axis of pairs with parallel axes (zero where not parallel).

    Two parallel cylinders differ by a cylinder of radius R = r_i + r_j and half length
    H = h_i + h_j about the common axis; with d split into axial z and radial ρ parts, the
    signed distance is ρ − R (beside), z − H (above), √((ρ−R)² + (z−H)²) (off the rim) or
    max(ρ − R, z − H) (overlapping), along the matching combination of the two directions."""
    parallel = np.abs(np.einsum("pc,pc->p", ai, aj)) > 1.0 - 1e-12
    z = np.einsum("pc,pc->p", d, ai)
    radial, rho = unit(d - z[:, None] * ai)
    along = np.abs(z) - hi - hj
    beside = rho - ri - rj
    off = (along > 0) & (beside > 0)
    wa = np.where(off, along, np.where(along > beside, 1.0, 0.0))
    wr = np.where(off, beside, np.where(along > beside, 0.0, 1.0))
    n = wa[:, None] * np.sign(z)[:, None] * ai + wr[:, None] * radial
    return np.where(parallel[:, None], unit(n)[0], 0.0), parallel


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


def _one_tier(layer) -> tuple[float, float] | None:
    """(radius, length) nm of vertical cylinders too long to stack two in the layer (flat top),
    None for any other layer."""
    spec = layer.particles
    if not (spec.orientation == "vertical" and spec.rough_top == 0):
        return None
    r, length = cylinder_radius_length(spec.diameter_nm * math.exp(-3.0 * spec.size_spread))
    return None if length <= 0.5 * layer.thickness_nm else (r, length)


@dataclass(frozen=True)
class Cylinder(Shape):
    name = "cylinder"
    plural = "cylinders"
    grammar = "cylinder:D[:isotropic|inplane|vertical][:tilt=DEG]"
    oriented = True
    uses_axis_hint = True
    rsa_fraction = 0.15
    packer_limits = {"isotropic": 0.50, "inplane": 0.55, "vertical": 0.50}
    place_cost = {
        "isotropic": ((0.0, 0.0, 900.0), (0.15, 0.05, 1000.0), (0.30, 0.8, 900.0), (0.50, 3.9, 560.0)),
        "inplane": ((0.0, 0.0, 600.0), (0.15, 0.05, 700.0), (0.30, 0.8, 700.0), (0.50, 3.1, 1050.0),
                    (0.55, 10.0, 2000.0)),
        "vertical": ((0.0, 0.0, 120.0), (0.15, 0.02, 150.0), (0.30, 0.4, 250.0), (0.50, 0.9, 310.0)),
    }
    agglutination_cost = (1.0, 10000.0)
    gen_bytes_per_grain = 7000.0

    # ------------------------------------------------------------------ one grain
    def dimensions(self, diameter_nm):
        r, length = cylinder_radius_length(diameter_nm)
        return r, 0.5 * length

    def max_height_nm(self, diameter_nm, polar_range):
        r, length = cylinder_radius_length(diameter_nm)
        lo, hi = polar_range
        peak = math.atan2(2.0 * r, length)                 # the extent L cos θ + 2r sin θ peaks here
        if lo <= peak <= hi:
            return math.hypot(length, 2.0 * r)
        return max(cylinder_height_nm(r, length, lo), cylinder_height_nm(r, length, hi))

    def span_nm(self, diameter_nm):
        r, length = cylinder_radius_length(diameter_nm)
        return math.hypot(length, 2 * r)

    # ------------------------------------------------------------------ N grains
    def volumes_nm3(self, radii_nm, half_lengths_nm):
        return np.pi * radii_nm**2 * (2.0 * half_lengths_nm)

    def width(self, c, radius, half_length):
        return half_length * np.abs(c) + radius * np.sqrt(np.clip(1.0 - c * c, 0.0, None))

    def support_point(self, axes, half_lengths, radii, n):
        return self.support_candidates(axes, half_lengths, radii, n)[0][:, 0]

    def bounding_radius_nm(self, radii_nm, half_lengths_nm):
        return np.hypot(radii_nm, half_lengths_nm)

    def smallest_half_width_nm(self, radii_nm, half_lengths_nm):
        return radii_nm                                 # the length is 6 radii

    def inertia_nm5(self, bodies):
        """That of a solid cylinder, V·(r²/4 + L²/12)."""
        r, h = bodies.radii_nm, bodies.half_lengths_nm
        return bodies.volumes_nm3 * (r**2 / 4.0 + (2.0 * h) ** 2 / 12.0)

    def z_chords(self, bodies, dx, dy):
        """Line ∩ infinite cylinder ∩ end slab, exact for any orientation."""
        r = bodies.radii_nm[:, None]
        rho2 = dx * dx + dy * dy
        ax, ay, az = (bodies.axes[:, k][:, None] for k in range(3))
        h = bodies.half_lengths_nm[:, None]
        ua = dx * ax + dy * ay                          # u·a for the lateral offset u
        # Infinite cylinder: A z² + B z + C <= 0.
        a_q = 1.0 - az * az
        b_q = -2.0 * az * ua
        c_q = rho2 - ua * ua - r * r
        steep = a_q <= 1e-12                            # (near-)vertical axis: all z or none
        disc = b_q * b_q - 4.0 * a_q * c_q
        sq = np.sqrt(np.clip(disc, 0.0, None))
        a_safe = np.where(steep, 1.0, a_q)
        lo_c = np.where(steep, -np.inf, (-b_q - sq) / (2.0 * a_safe))
        hi_c = np.where(steep, np.inf, (-b_q + sq) / (2.0 * a_safe))
        miss_c = np.where(steep, c_q > 0.0, disc < 0.0)
        # Slab |u·a + z a_z| <= h.
        flat = az <= 1e-9
        az_safe = np.where(flat, 1.0, az)
        lo_s = np.where(flat, -np.inf, (-h - ua) / az_safe)
        hi_s = np.where(flat, np.inf, (h - ua) / az_safe)
        miss_s = flat & (np.abs(ua) > h)
        lo = np.maximum(lo_c, lo_s)
        hi = np.minimum(hi_c, hi_s)
        miss = miss_c | miss_s | (lo >= hi)
        return np.where(miss, 0.0, lo), np.where(miss, 0.0, hi)

    def contains(self, bodies, dx, dy, dz):
        r = bodies.radii_nm[:, None]
        ax, ay, az = (bodies.axes[:, k][:, None] for k in range(3))
        t = dx * ax + dy * ay + dz * az
        radial2 = dx * dx + dy * dy + dz * dz - t * t
        return (np.abs(t) < bodies.half_lengths_nm[:, None]) & (radial2 < r * r)

    # ------------------------------------------------------------------ contacts
    def pair_axes(self, d, ai, aj, ri, rj, hi, hj, hint, margin, iterations=SEARCH_ITERATIONS, full_search=True):
        """Capsules, candidate axes, ridge and pattern searches (module doc); parallel axes
        (vertical cylinders) take their closed-form optimum, no search; between full searches
        (packing) a short local search from the best candidate and the pair's previous axis."""
        width = self.width
        caps = segment_closest(d, ai, aj, hi, hj)
        n_caps, dist = unit(caps)
        gap = dist - ri - rj                       # capsule gap: a lower bound of the cylinder gap
        normal = n_caps.copy()
        need = np.flatnonzero(gap < margin)
        if need.size == 0:
            return normal, gap
        dd, a1, a2 = d[need], ai[need], aj[need]
        sub = (dd, a1, a2, ri[need], rj[need], hi[need], hj[need])
        cands = [n_caps[need], unit(dd)[0], a1, a2, unit(np.cross(a1, a2))[0],
                 unit(dd - np.einsum("pc,pc->p", dd, a1)[:, None] * a1)[0],
                 unit(dd - np.einsum("pc,pc->p", dd, a2)[:, None] * a2)[0]]
        if hint is not None:
            cands.append(hint[need])
        n_par, parallel = _parallel_axis(*sub)
        cands.append(n_par)
        stack = np.stack(cands, axis=1)
        g_all = np.where(np.einsum("pkc,pkc->pk", stack, stack) > 0.25, support_gap(width, stack, *sub), -np.inf)
        best = np.argmax(g_all, axis=1)
        n_best = stack[np.arange(need.size), best].copy()
        g_best = g_all[np.arange(need.size), best].copy()
        warm = np.zeros(need.size, dtype=bool)
        if hint is not None and not full_search:
            warm = (g_best < margin) & ~parallel
            if warm.any():
                w = np.flatnonzero(warm)
                part = tuple(x[w] for x in sub)
                n_best[w], g_best[w] = refine_axis(width, n_best[w], g_best[w], *part, np.full(w.size, margin),
                                                   iterations, step0=0.05)
        # Side contacts: the optimum lies on a circle n ⟂ a_i or n ⟂ a_j (a coarser 1-D search when
        # the caller asked for a short search: packing iterations).
        ridge = {} if iterations >= SEARCH_ITERATIONS else {"samples": 16, "golden": 12}
        open_ = np.flatnonzero((g_best < margin) & ~warm & ~parallel)
        for which in (1, 2):
            if open_.size == 0:
                break
            part = tuple(x[open_] for x in sub)
            n_r, g_r = ridge_search(width, *part, axis=part[which], **ridge)
            better = g_r > g_best[open_]
            n_best[open_[better]] = n_r[better]
            g_best[open_[better]] = g_r[better]
            open_ = open_[g_best[open_] < margin]
        # Rim contacts: a smooth interior maximum; pattern search from the best so far.
        if open_.size:
            part = tuple(x[open_] for x in sub)
            n_o, g_o = refine_axis(width, n_best[open_], g_best[open_], *part, np.full(open_.size, margin), iterations)
            n_best[open_], g_best[open_] = n_o, g_o
        gap[need] = g_best
        normal[need] = n_best
        sign = np.where(np.einsum("pc,pc->p", normal, d) < 0, -1.0, 1.0)
        return normal * sign[:, None], gap

    def support_candidates(self, axes, half_lengths, radii, n):
        """Slot 0: the support point itself; 1: the other end (a side line supports: |a·n| small);
        2–5: four rim points of the face (a face supports: a ∥ n)."""
        c = np.einsum("pc,pc->p", axes, n)
        sign = np.where(c < 0, -1.0, 1.0)
        radial = n - c[:, None] * axes
        norm = np.linalg.norm(radial, axis=1)
        face = norm < FACE_TOLERANCE
        side = np.abs(c) < SIDE_TOLERANCE
        radial *= (radii / np.where(norm > 1e-12, norm, np.inf))[:, None]
        end = (half_lengths * sign)[:, None] * axes
        out = np.zeros((len(c), 6, 3))
        mask = np.zeros((len(c), 6), dtype=bool)
        out[:, 0] = end + radial
        mask[:, 0] = True
        out[:, 1] = radial - end
        mask[:, 1] = side
        if face.any():
            pick = np.eye(3)[np.argmin(np.abs(axes[face]), axis=1)]
            e1 = np.cross(axes[face], pick)
            e1 /= np.linalg.norm(e1, axis=1)[:, None]
            e2 = np.cross(axes[face], e1)
            rim = radii[face, None, None] * np.stack([e1, -e1, e2, -e2], axis=1)
            out[face, 2:] = end[face, None, :] + rim
            mask[face, 2:] = True
        return out, mask, half_lengths * np.abs(c) + radii * norm

    def wall_point(self, axes, half_lengths, radii, toward_wall):
        """The rim point of the end nearest the wall (the middle of the side line nearest it when
        the axis is parallel to the wall)."""
        side = toward_wall - np.sum(toward_wall * axes, axis=1)[:, None] * axes
        norm = np.linalg.norm(side, axis=1)
        side = np.where(norm[:, None] > 1e-9, side / np.where(norm > 1e-9, norm, 1.0)[:, None], 0.0)
        return (np.sign(np.sum(toward_wall * axes, axis=1))[:, None] * half_lengths[:, None] * axes
                + radii[:, None] * side)

    def contact_point(self, d, ai, aj, hi, hj, ri, rj, normal):
        """Midway between the closest points of the two axes (segments)."""
        s, t = segment_closest_params(d, ai, aj, hi, hj)
        return 0.5 * (s[:, None] * ai + d + t[:, None] * aj)

    # ------------------------------------------------------------------ rough top
    def surface_points(self, radius_nm, half_length_nm, axis, n_ring=48, n_len=13):
        """Rims, mantle and end discs."""
        axis = np.asarray(axis, dtype=float)
        e = np.eye(3)[np.argmin(np.abs(axis))]
        u = np.cross(axis, e)
        u /= np.linalg.norm(u)
        v = np.cross(axis, u)
        ang = 2 * np.pi * np.arange(n_ring) / n_ring
        ring = np.cos(ang)[:, None] * u + np.sin(ang)[:, None] * v
        pts = [t * half_length_nm * axis + radius_nm * ring for t in np.linspace(-1, 1, n_len)]
        for t in (-1.0, 1.0):
            for f in (0.25, 0.5, 0.75):
                pts.append(t * half_length_nm * axis + f * radius_nm * ring)
            pts.append((t * half_length_nm * axis)[None, :])
        return np.concatenate(pts, axis=0)

    # ------------------------------------------------------------------ placement limits
    def packer_limit(self, layer):
        """Tilted vertical cylinders keep their drawn axes: TILTED_VERTICAL_LIMIT."""
        spec = layer.particles
        if spec.orientation == "vertical" and spec.tilt_rad > 0:
            return next(limit for tilt, limit in TILTED_VERTICAL_LIMIT if spec.tilt_deg <= tilt)
        return self.packer_limits[spec.orientation]

    def geometric_limit(self, layer):
        """A vertical cylinder whose height exceeds half the layer crosses its mid-plane, where
        the sections of all such cylinders are disjoint.  Untilted, the sections are equal discs
        (area fraction ≤ π/√12 ≈ 0.9069), so φ ≤ 0.9069·L/H; the packer reached 0.93 of that bound
        (46 %, not 48 %, for 300-nm cylinders in a 1000-nm layer) and is allowed 0.90 of it.
        With a tilt spread (axes uniform on the cap θ ≤ t) a cylinder at angle θ is
        L cos θ + 2r sin θ high and its section an ellipse of area πr²/cos θ; if a share q of the
        cylinders (those with θ < θ_c, height > H/2) must cross, with mean 1/cos θ = m among them,
        then q·N·πr²·m ≤ 0.9069·A and φ ≤ 0.9069·L / (H·q·m) (an estimate: sections cut near a
        cylinder's end are smaller ellipses), times the packer's share (TILTED_DISC_SHARE).  A
        spread only helps once some cylinders can stay clear of the mid-plane (t > θ_c: θ_c ≈ 48°
        for 300-nm cylinders in 1000 nm); below that it lowers the bound (m > 1)."""
        one_tier = _one_tier(layer)
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

    def aligned_column_bound(self, layer):
        one_tier = _one_tier(layer)
        return None if one_tier is None else DISC_PACKING * one_tier[1] / layer.thickness_nm

    # ------------------------------------------------------------------ optics
    def local_field(self, spec):
        """The factors of the prolate spheroid of the same aspect ratio (length 6 r over diameter
        2 r: the standard stand-in for a finite cylinder)."""
        return axial_field(spheroid_axial_factor(CYLINDER_LENGTH_RADII / 2.0), spec)

    # ------------------------------------------------------------------ figures
    def column_group(self, diameter_nm):
        return f"cylinders D_eff = {diameter_nm:g} nm"
