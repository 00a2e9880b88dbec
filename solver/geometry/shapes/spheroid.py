"""Spheroids (ellipsoids of revolution): prolate needles (aspect > 1) or oblate flakes (aspect < 1,
the platelets of effect inks), sized by their effective diameter D (the sphere of equal volume).

The symmetry axis a carries the polar semi-axis h = A·r, the equatorial one is r, and
(4/3)π r²h = (π/6) D³ ⇒ r = (D/2)/A^(1/3).  The orientation names the axis: a `vertical` flake
lies flat, an `inplane` one stands on its edge.  The body is {x: xᵀ M⁻¹ x ≤ 1} with
M = r² I + (h² − r²) a aᵀ; everything follows from M:

* half-width along a unit n (support function) w(n) = √(nᵀ M n), support point M n / w;
* a vertical line at lateral offset (x, y) crosses it where the quadratic in z of xᵀ M⁻¹ x = 1
  has its roots (exact chords for the voxeliser);
* depolarisation factors: exact, `depolarisation.spheroid_axial_factor(A)`;
* transverse moment of inertia V (r² + h²)/5.

Pair separations by the separating-axis theorem (`separating_axis`): the support function is
smooth, so after the best of a few candidate axes (the enclosing capsules' direction, the centre
line, both axes, the pair's previous axis) a safeguarded Newton iteration on the sphere of axes
climbs to the maximum of g(n) = |d·n| − w_i(n) − w_j(n): the distance of the two when apart (a
certificate once g ≥ 0), minus a penetration depth when not — a lower bound of the signed
distance either way.  The enclosing capsules (radius r, half length max(h − r, 0)) give the
early certificate for pairs far apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bodies import Bodies
from ..depolarisation import axial_field, spheroid_axial_factor
from ..grammar import ParticleSpecError, fmt, parse_number
from ..separating_axis import segment_closest, support_gap, tangent_basis, unit
from .base import Shape

#: Aspect ratio (polar / equatorial semi-axis) of `spheroid:D` (the length/diameter ratio of the
#: paper's cylinders, 6 radii over 2), and the range accepted (the packer limits were measured at
#: its ends, docs/geometry.md).
DEFAULT_ASPECT = 3.0
ASPECT_RANGE = (0.25, 4.0)
#: Packer limits beyond `packer_limits` (total fraction; `python -m benchmarks.bench_geometry --limits
#: --only spheroid`, docs/geometry.md): vertical grains too tall to stack two in the layer (flat
#: top) — 300-nm needles of aspect 4, 756 nm high in 1000 nm, reached 45 %, not 50 %; vertical
#: axes with a spread keep their drawn axes — 100-nm needles and flakes with 30° reached 50 %, not
#: 55 %; beyond 30° unmeasured: the cylinders' 40 %.
ONE_TIER_LIMIT = 0.45
TILTED_VERTICAL_LIMIT = ((30.0, 0.50), (90.0, 0.40))
#: Newton steps of the separating-axis search, and the step (rad) below which it has converged.
NEWTON_ITERATIONS = 30
NEWTON_TOLERANCE = 1e-10


def _support(axes, half, radius, n):
    """(w (P,), support points (P, 3), c = a·n (P,)) of spheroids along unit n (P, 3)."""
    c = np.einsum("pc,pc->p", axes, n)
    r2, h2 = radius * radius, half * half
    w = np.sqrt(np.clip(r2 + (h2 - r2) * c * c, 0.0, None))
    p = (r2[:, None] * n + ((h2 - r2) * c)[:, None] * axes) / w[:, None]
    return w, p, c


def _hessian_form(axes, half, radius, w, p, u, v):
    """uᵀ H v for the support function's Hessian H = (M − p pᵀ)/w (P,)."""
    r2, h2 = radius * radius, half * half
    au, av = np.einsum("pc,pc->p", axes, u), np.einsum("pc,pc->p", axes, v)
    pu, pv = np.einsum("pc,pc->p", p, u), np.einsum("pc,pc->p", p, v)
    return (r2 * np.einsum("pc,pc->p", u, v) + (h2 - r2) * au * av - pu * pv) / w


@dataclass(frozen=True)
class Spheroid(Shape):
    """aspect: polar over equatorial semi-axis (> 1 prolate, < 1 oblate, 1 a sphere)."""

    aspect: float = DEFAULT_ASPECT

    name = "spheroid"
    plural = "spheroids"
    grammar = "spheroid:D[:aspect=A][:isotropic|inplane|vertical][:tilt=DEG]"
    grammar_key = (f"A: spheroid axis ratio polar/equatorial, {fmt(ASPECT_RANGE[0])}–{fmt(ASPECT_RANGE[1])} "
                   f"(> 1 needles, < 1 flakes: vertical flakes lie flat; default {fmt(DEFAULT_ASPECT)})")
    option_keys = ("aspect",)
    oriented = True
    uses_axis_hint = True
    rsa_fraction = 0.15
    #: 100-nm grains of aspects 0.25 and 4 in 1000-nm cells: isotropic flakes reached 50 % (not 55 %),
    #: needles 55 % (300-nm ones 50 %, not 55 %); in-plane and vertical ones 58 % (300-nm vertical
    #: flakes 55 %; larger in-plane grains untried), accepted 55 %
    packer_limits = {"isotropic": 0.50, "inplane": 0.55, "vertical": 0.55}
    #: the cylinders' points (fitted on the reference machine) times the CPU ratio of spheroids to
    #: cylinders measured side by side (`bench_geometry --shapes`: 100-nm grains, the larger of
    #: aspects 0.25 and 3 at φ = 0.15, 0.30, 0.50; docs/geometry.md); memory as the cylinders'
    place_cost = {
        "isotropic": ((0.0, 0.0, 540.0), (0.15, 0.03, 600.0), (0.30, 0.44, 495.0), (0.50, 4.7, 680.0)),
        "inplane": ((0.0, 0.0, 330.0), (0.15, 0.03, 385.0), (0.30, 0.62, 540.0), (0.50, 1.1, 380.0),
                    (0.55, 3.6, 720.0)),
        "vertical": ((0.0, 0.0, 480.0), (0.15, 0.08, 600.0), (0.30, 0.82, 510.0), (0.50, 1.0, 345.0)),
    }
    agglutination_cost = (3.3, 33000.0)
    gen_bytes_per_grain = 7000.0

    def __post_init__(self):
        lo, hi = ASPECT_RANGE
        if not (isinstance(self.aspect, (int, float)) and lo <= self.aspect <= hi):
            raise ParticleSpecError(f"spheroid aspect must be in [{fmt(lo)}, {fmt(hi)}] (polar over equatorial "
                                    f"semi-axis), got {self.aspect!r}")

    # ------------------------------------------------------------------ grammar
    @classmethod
    def from_options(cls, options, spec):
        if "aspect" not in options:
            return cls()
        if not options["aspect"]:
            raise ParticleSpecError(f"'aspect' in {spec!r} needs a value, e.g. 'aspect=3' (needles) or "
                                    "'aspect=0.25' (flakes)")
        return cls(parse_number(options["aspect"], "spheroid aspect", spec))

    def label_parts(self):
        return (f"aspect={fmt(self.aspect)}",)

    # ------------------------------------------------------------------ one grain
    def dimensions(self, diameter_nm):
        r = 0.5 * np.asarray(diameter_nm, dtype=float) / self.aspect ** (1.0 / 3.0)
        return (r, self.aspect * r) if np.ndim(r) else (float(r), float(self.aspect * r))

    def max_height_nm(self, diameter_nm, polar_range):
        """2√(r² sin²θ + h² cos²θ) is monotone in θ: the larger of the range's ends."""
        r, h = self.dimensions(diameter_nm)
        return max(2.0 * math.hypot(r * math.sin(t), h * math.cos(t)) for t in polar_range)

    def span_nm(self, diameter_nm):
        return 2.0 * max(self.dimensions(diameter_nm))

    # ------------------------------------------------------------------ N grains
    def volumes_nm3(self, radii_nm, half_lengths_nm):
        return 4.0 / 3.0 * np.pi * radii_nm**2 * half_lengths_nm

    def width(self, c, radius, half_length):
        return np.sqrt(np.clip(radius * radius + (half_length * half_length - radius * radius) * c * c, 0.0, None))

    def support_point(self, axes, half_lengths, radii, n):
        return _support(axes, half_lengths, radii, n)[1]

    def bounding_radius_nm(self, radii_nm, half_lengths_nm):
        return np.maximum(radii_nm, half_lengths_nm)

    def smallest_half_width_nm(self, radii_nm, half_lengths_nm):
        return np.minimum(radii_nm, half_lengths_nm)

    def inertia_nm5(self, bodies):
        """A solid spheroid's, V·(r² + h²)/5, about an axis ⟂ its own."""
        return bodies.volumes_nm3 * (bodies.radii_nm**2 + bodies.half_lengths_nm**2) / 5.0

    def _inside_form(self, bodies, dx, dy):
        """xᵀ M⁻¹ x = α z² + β z + γ on the vertical lines (dx, dy) (N, M): (α, β, γ)."""
        r2 = (bodies.radii_nm**2)[:, None]
        k = 1.0 / (bodies.half_lengths_nm**2)[:, None] - 1.0 / r2          # 1/h² − 1/r²
        ax, ay, az = (bodies.axes[:, m][:, None] for m in range(3))
        u = dx * ax + dy * ay
        return 1.0 / r2 + k * az * az, 2.0 * k * az * u, (dx * dx + dy * dy) / r2 + k * u * u

    def z_chords(self, bodies, dx, dy):
        """The roots of α z² + β z + γ = 1 (α > 0): exact for any orientation."""
        alpha, beta, gamma = self._inside_form(bodies, dx, dy)
        disc = beta * beta - 4.0 * alpha * (gamma - 1.0)
        sq = np.sqrt(np.clip(disc, 0.0, None))
        miss = disc <= 0.0
        return (np.where(miss, 0.0, (-beta - sq) / (2.0 * alpha)), np.where(miss, 0.0, (-beta + sq) / (2.0 * alpha)))

    def contains(self, bodies, dx, dy, dz):
        alpha, beta, gamma = self._inside_form(bodies, dx, dy)
        return alpha * dz * dz + beta * dz + gamma < 1.0

    # ------------------------------------------------------------------ contacts
    def pair_axes(self, d, ai, aj, ri, rj, hi, hj, hint, margin, search_iterations=None, full_search=True):
        """Capsules, candidates, then Newton on the sphere of axes (module doc)."""
        ci, cj = np.maximum(hi - ri, 0.0), np.maximum(hj - rj, 0.0)
        normal, dist = unit(segment_closest(d, ai, aj, ci, cj))
        gap = dist - ri - rj                               # enclosing capsules: a lower bound
        need = np.flatnonzero(gap < margin)
        if need.size == 0:
            return normal, gap
        sub = (d[need], ai[need], aj[need], ri[need], rj[need], hi[need], hj[need])
        cands = [normal[need], unit(sub[0])[0], sub[1], sub[2]] + ([hint[need]] if hint is not None else [])
        stack = np.stack(cands, axis=1)
        g_all = np.where(np.einsum("pkc,pkc->pk", stack, stack) > 0.25, support_gap(self.width, stack, *sub), -np.inf)
        best = np.argmax(g_all, axis=1)
        n = stack[np.arange(need.size), best].copy()
        g = g_all[np.arange(need.size), best].copy()
        n, g = self._newton(n, g, *sub, np.full(need.size, float(margin)))
        sign = np.where(np.einsum("pc,pc->p", n, sub[0]) < 0, -1.0, 1.0)
        normal[need] = n * sign[:, None]
        gap[need] = g
        return normal, gap

    def _newton(self, n, g, d, ai, aj, ri, rj, hi, hj, target):
        """Safeguarded Newton ascent of g on the unit sphere from n (P, 3), g = g(n) (P,): the
        tangential gradient of g is P(d − p_i − p_j) (p the support points, d·n ≥ 0), its
        Hessian −P(H_i + H_j)P − g P; a step solves the 2×2 system with the shift g raised where
        needed to keep it positive definite (overlapping pairs far from their maximum), is kept
        only where g grows, shortened where it does not.  Stops per pair at g ≥ target,
        convergence, or NEWTON_ITERATIONS."""
        trust = np.ones(len(g))
        live = np.flatnonzero(g < target)
        for _ in range(NEWTON_ITERATIONS):
            if live.size == 0:
                break
            nl, dl = n[live], d[live]
            nl = nl * np.where(np.einsum("pc,pc->p", nl, dl) < 0, -1.0, 1.0)[:, None]
            args = (ai[live], hi[live], ri[live]), (aj[live], hj[live], rj[live])
            (wi, pi, _), (wj, pj, _) = (_support(a, h, r, nl) for a, h, r in args)
            v = dl - pi - pj
            u1, u2 = tangent_basis(nl)
            b1, b2 = np.einsum("pc,pc->p", v, u1), np.einsum("pc,pc->p", v, u2)
            h11, h12, h22 = (sum(_hessian_form(a, h, r, w, p, x, y) for (a, h, r), w, p in zip(args, (wi, wj), (pi, pj)))
                             for x, y in ((u1, u1), (u1, u2), (u2, u2)))
            lowest = 0.5 * (h11 + h22) - np.sqrt(0.25 * (h11 - h22) ** 2 + h12 * h12)
            lam = np.maximum(g[live], -0.9 * lowest)           # the Newton shift g, kept positive definite
            h11, h22 = h11 + lam, h22 + lam
            det = h11 * h22 - h12 * h12
            det = np.where(np.abs(det) > 1e-300, det, 1e-300)
            s1, s2 = (h22 * b1 - h12 * b2) / det, (h11 * b2 - h12 * b1) / det
            step = trust[live][:, None] * (s1[:, None] * u1 + s2[:, None] * u2)
            trial, _ = unit(nl + step)
            gt = support_gap(self.width, trial[:, None, :], dl, ai[live], aj[live], ri[live], rj[live], hi[live],
                             hj[live])[:, 0]
            better = gt > g[live]
            n[live[better]] = trial[better]
            g[live[better]] = gt[better]
            trust[live] = np.where(better, np.minimum(1.0, 2.0 * trust[live]), 0.5 * trust[live])
            size = np.linalg.norm(step, axis=1)
            live = live[(g[live] < target[live]) & (size > NEWTON_TOLERANCE) & (trust[live] > 1e-6)]
        return n, g

    # ------------------------------------------------------------------ rough top
    def surface_points(self, radius_nm, half_length_nm, axis, n_ring=48, n_polar=25):
        """A latitude–longitude net of the surface (poles included)."""
        axis = np.asarray(axis, dtype=float)
        e = np.eye(3)[np.argmin(np.abs(axis))]
        u = np.cross(axis, e)
        u /= np.linalg.norm(u)
        v = np.cross(axis, u)
        ang = 2 * np.pi * np.arange(n_ring) / n_ring
        ring = np.cos(ang)[:, None] * u + np.sin(ang)[:, None] * v
        polar = np.linspace(0.0, np.pi, n_polar)
        return np.concatenate([half_length_nm * np.cos(t) * axis + radius_nm * np.sin(t) * ring for t in polar])

    def meniscus_nm(self, radius_nm, half_length_nm, axis, z_centre_nm, dx, dy, angle_rad):
        """The sampled surface's envelope (`Shape.meniscus_nm`), and the grain's own top where a
        vertical line meets it: exact on the cap, where the binder wets the grain, and
        second-order in the sampling on the meniscus cone (its foot is stationary)."""
        f = super().meniscus_nm(radius_nm, half_length_nm, axis, z_centre_nm, dx, dy, angle_rad)
        if f is None:
            return None
        one = Bodies(self, np.array([radius_nm]), np.array([half_length_nm]), np.asarray(axis, dtype=float)[None])
        lo, hi = self.z_chords(one, dx[None], dy[None])
        return np.minimum(f, np.where(hi[0] > lo[0], z_centre_nm + lo[0], np.inf))

    # ------------------------------------------------------------------ placement limits
    def packer_limit(self, layer):
        """`packer_limits`, lower for vertical grains that cannot stack or keep a tilt spread."""
        spec = layer.particles
        limit = self.packer_limits[spec.orientation]
        if spec.orientation != "vertical":
            return limit
        if spec.tilt_rad > 0:
            limit = min(limit, next(v for tilt, v in TILTED_VERTICAL_LIMIT if spec.tilt_deg <= tilt))
        smallest = spec.diameter_nm * math.exp(-3.0 * spec.size_spread)
        if spec.rough_top == 0 and spec.max_height_nm(smallest) > 0.5 * layer.thickness_nm:
            limit = min(limit, ONE_TIER_LIMIT)
        return limit

    # ------------------------------------------------------------------ optics
    def local_field(self, spec):
        """Exact: L_∥ = spheroid_axial_factor(A), L_⊥ = (1 − L_∥)/2."""
        return axial_field(spheroid_axial_factor(self.aspect), spec)

    # ------------------------------------------------------------------ figures
    def column_group(self, diameter_nm):
        kind = "needles" if self.aspect > 1 else "flakes" if self.aspect < 1 else "spheroids"
        return f"{kind} D_eff = {diameter_nm:g} nm, aspect {self.aspect:g}"

    def orientation_label(self, orientation):
        if self.aspect < 1 and orientation != "isotropic":
            return {"vertical": "lying flat", "inplane": "on edge"}[orientation]
        return super().orientation_label(orientation)
