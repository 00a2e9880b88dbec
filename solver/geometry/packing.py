"""Dense packing by growth with collective rearrangement (force-biased, Lubachevsky–Stillinger-like).

Start: every particle at its position (RSA result, or random where RSA left it) with all lengths
multiplied by a scale s0 < 1 chosen so that the shrunk particles fill about the RSA fraction.
Each iteration:

1. for every pair closer than the cut-off (Verlet list with a skin, rebuilt when a particle has
   moved too far), take the separation normal n and gap g (`contacts.separation`);
2. each overlapping pair (g < margin) is pushed apart by (margin − g) along n as a position-based
   rigid-body contact: with contact point p (midway between the closest points of the two
   axes), masses m = V and transverse moments I = V·(r²/4 + L²/12), the push λ = δ / Σ(1/m +
   |(p − c)×n|²/I) moves the centres by ∓λn/m and turns the axes by ∓λ(p − c)×n/I.  Rotation is
   free for isotropic cylinders (but each axis stays within max_tilt of the one drawn for it, so
   the orientation statistics stay isotropic), about z only for in-plane ones, none for vertical
   cylinders and spheres.  The pushes on a particle add up (Jacobi sweep, over-relaxed);
3. centres are clamped to their allowed z range (`walls`); x, y are periodic;
4. while s < 1 and the largest remaining overlap is below `grow_tolerance` of the contact
   distance, s grows by the factor (1 + growth_rate);
5. walls can block a push: a column of particles taller than the layer has its overlaps along
   z and the clamp undoes every vertical push.  When neither s nor the largest overlap has
   improved for `patience` iterations, overlapping pairs with a near-vertical normal are pushed
   along their best horizontal separating axis instead (`contacts.horizontal_separation`) for
   `escape_iterations` iterations.

It stops when s = 1 and no pair has a negative gap — every pair certified apart, so the result
has no overlaps — or gives up after `max_iterations` (the caller reports the concentration as
unreachable).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .contacts import horizontal_separation, neighbour_pairs, segment_closest_params, separation, sphere_gaps
from .shapes import Bodies
from .walls import Walls

#: Which rotations the packer may use, per orientation mode.
ROTATION = {"isotropic": "free", "inplane": "z", "vertical": "none", None: "none"}


@dataclass(frozen=True)
class PackOptions:
    margin: float = 0.02            # push pairs this far apart (fraction of the mean radius)
    skin: float = 0.8               # Verlet skin (fraction of the mean radius)
    growth_rate: float = 0.01       # relative growth per iteration
    grow_tolerance: float = 0.1     # grow only while max overlap < this × contact distance
    max_iterations: int = 4000
    relaxation: float = 1.2         # over-relaxation of the summed push per sweep
    search_iterations: int = 6      # cylinder separating-axis refinement per iteration
    full_search_every: int = 8      # full axis search every k-th iteration (else warm local search)
    max_tilt: float = 0.35          # free rotation: largest angle (rad) from the drawn axis
    patience: int = 60              # iterations without progress before the horizontal escape
    escape_iterations: int = 30     # iterations of horizontal pushes for near-vertical contacts
    wall_torque: bool = True        # walls push rods at their deepest point (they turn flat)


@dataclass(frozen=True)
class PackStats:
    iterations: int
    rebuilds: int
    converged: bool
    final_scale: float
    max_overlap_nm: float           # largest remaining penetration (0 when converged)
    seconds: float
    escapes: int = 0                # times the horizontal escape was used


def _apply_walls(xyz, bodies, walls):
    lo, hi = walls.centre_bounds(bodies)
    np.clip(xyz[2], lo, hi, out=xyz[2])


def _turn(axes, turn, rotation):
    """Axes turned by small rotation vectors (rows of turn), kept unit with a_z >= 0."""
    if rotation == "z":
        turn = turn * np.array([0.0, 0.0, 1.0])
    new = axes + np.cross(turn, axes)
    new /= np.linalg.norm(new, axis=1)[:, None]
    new *= np.where(new[:, 2] < 0, -1.0, 1.0)[:, None]
    if rotation == "z":
        new[:, 2] = 0.0
        new /= np.linalg.norm(new, axis=1)[:, None]
    return new


def wall_contacts(xyz, bodies: Bodies, walls: Walls, rotation="none"):
    """Push particles that cross the top or bottom wall back in, as rigid-body contacts with
    an immovable plane at the particle's deepest point (a rod pressed on one end turns flat),
    then clamp.  xyz (3, N) in place; returns the axes."""
    axes = bodies.axes
    if rotation != "none" and walls.protrusion.max(initial=0.0) == 0.0:
        lo, hi = walls.centre_bounds(bodies)
        depth = np.maximum(xyz[2] + 0.0 - hi, lo - xyz[2])
        hit = np.flatnonzero(depth > 0)
        if hit.size:
            a = axes[hit]
            down = np.where(xyz[2][hit] - hi[hit] > lo[hit] - xyz[2][hit], 1.0, -1.0)   # wall side
            ez = np.zeros_like(a)
            ez[:, 2] = down
            side = ez - np.sum(ez * a, axis=1)[:, None] * a
            norm = np.linalg.norm(side, axis=1)
            side = np.where(norm[:, None] > 1e-9, side / np.where(norm > 1e-9, norm, 1.0)[:, None], 0.0)
            h, r = bodies.half_lengths_nm[hit], bodies.radii_nm[hit]
            p = np.sign(np.sum(ez * a, axis=1))[:, None] * h[:, None] * a + r[:, None] * side
            n = -ez                                                    # push away from the wall
            vol = bodies.volumes_nm3[hit]
            inertia = vol * (r**2 / 4.0 + (2.0 * h) ** 2 / 12.0)
            rxn = np.cross(p, n)
            if rotation == "z":
                rxn[:, :2] = 0.0
            lam = depth[hit] / (1.0 / vol + np.sum(rxn**2, axis=1) / inertia)
            xyz[2][hit] += lam / vol * n[:, 2]
            axes = axes.copy()
            axes[hit] = _turn(a, lam[:, None] * rxn / inertia[:, None], rotation)
            bodies = Bodies(bodies.shape, bodies.radii_nm, bodies.half_lengths_nm, axes)
    _apply_walls(xyz, bodies, walls)
    return axes


def spatial_order(centres: np.ndarray, cell_nm: float) -> np.ndarray:
    """Permutation that sorts particles by coarse grid cell (memory locality of pair gathers)."""
    cell = np.floor(centres / max(cell_nm, 1e-9)).astype(np.int64)
    cell -= cell.min(axis=0)
    span = cell.max(axis=0) + 1
    return np.argsort((cell[:, 2] * span[1] + cell[:, 1]) * span[0] + cell[:, 0], kind="stable")


class _Verlet:
    """Pair list with a skin: valid while reach + 2·(largest move since the build) <= cut-off."""

    def __init__(self, period_nm, skin_nm):
        self.period, self.skin = period_nm, skin_nm
        self.ref = None
        self.cutoff = -1.0
        self.rebuilds = 0
        self.hint = None

    def pairs(self, xyz, reach_nm, reach_max_nm):
        stale = self.ref is None
        if not stale:
            moved = np.sqrt(np.max(np.sum((xyz - self.ref) ** 2, axis=0)))
            stale = reach_nm + 2.0 * moved > self.cutoff
        if stale:
            self.cutoff = min(reach_max_nm, 1.05 * reach_nm) + self.skin
            i, j = neighbour_pairs(xyz.T, self.cutoff, self.period)
            order = np.lexsort((j, i))
            self.i, self.j = i[order], j[order]
            self.hint = None
            self.ref = xyz.copy()
            self.rebuilds += 1
        return self.i, self.j


def pair_normals_gaps(bodies: Bodies, xyz: np.ndarray, i, j, period_nm, hint=None, margin_nm=0.0,
                      search_iterations=12, full_search=True):
    """(normals (3, P), gaps (P,)) for pairs; xyz is (3, N)."""
    if bodies.shape == "sphere":
        r = bodies.radii_nm
        nx, ny, nz, gap = sphere_gaps(xyz, xyz, i, j, r[i] + r[j], period_nm)
        return np.stack([nx, ny, nz]), gap
    sep = separation(bodies, xyz.T, i, j, period_nm, hint=hint, margin_nm=margin_nm,
                     search_iterations=search_iterations, full_search=full_search)
    return sep.normal.T, sep.gap_nm


def limit_tilt(axes: np.ndarray, reference: np.ndarray, max_angle: float) -> np.ndarray:
    """Axes turned back onto the cone of half-angle max_angle about the reference axes."""
    dot = np.einsum("pc,pc->p", axes, reference)
    ref = reference * np.where(dot < 0, -1.0, 1.0)[:, None]      # a and −a are the same axis
    cos_t = np.abs(dot)
    far = cos_t < np.cos(max_angle)
    if not far.any():
        return axes
    perp = axes[far] - cos_t[far, None] * ref[far]
    perp /= np.linalg.norm(perp, axis=1)[:, None]
    out = axes.copy()
    out[far] = np.cos(max_angle) * ref[far] + np.sin(max_angle) * perp
    return out * np.where(out[:, 2] < 0, -1.0, 1.0)[:, None]


def push_apart(xyz, bodies: Bodies, i, j, normal, gap, margin_nm, period_nm, rotation="none",
               relaxation=1.0, reference_axes=None, max_tilt=np.pi):
    """One Jacobi sweep of rigid-body contact pushes (module doc, step 2).

    xyz (3, N) is moved in place; returns the new axes (N, 3) (unchanged without rotation),
    kept within max_tilt of reference_axes when given."""
    over = margin_nm - gap
    act = np.flatnonzero(over > 0)
    axes = bodies.axes
    if act.size == 0:
        return axes
    ia, ja = i[act], j[act]
    n = normal[:, act].T
    vol = bodies.volumes_nm3
    inv_m_i, inv_m_j = 1.0 / vol[ia], 1.0 / vol[ja]
    k_sum = inv_m_i + inv_m_j
    if rotation != "none":
        d = np.stack([xyz[k][ja] - xyz[k][ia] for k in range(3)], axis=1)
        for k in (0, 1):
            d[:, k] -= period_nm[k] * np.round(d[:, k] / period_nm[k])
        h, r = bodies.half_lengths_nm, bodies.radii_nm
        s, t = segment_closest_params(d, axes[ia], axes[ja], h[ia], h[ja])
        p = 0.5 * (s[:, None] * axes[ia] + d + t[:, None] * axes[ja])    # contact, from c_i
        inertia = vol * (r**2 / 4.0 + (2.0 * h) ** 2 / 12.0)
        rxn_i, rxn_j = np.cross(p, n), np.cross(p - d, n)
        if rotation == "z":
            rxn_i[:, :2] = 0.0
            rxn_j[:, :2] = 0.0
        k_sum = k_sum + np.sum(rxn_i**2, axis=1) / inertia[ia] + np.sum(rxn_j**2, axis=1) / inertia[ja]
    lam = over[act] * relaxation / k_sum
    npart = xyz.shape[1]
    for k in range(3):
        xyz[k] -= np.bincount(ia, weights=lam * inv_m_i * n[:, k], minlength=npart)
        xyz[k] += np.bincount(ja, weights=lam * inv_m_j * n[:, k], minlength=npart)
    if rotation == "none":
        return axes
    turn = np.zeros((npart, 3))
    for k in range(3):
        turn[:, k] -= np.bincount(ia, weights=lam * rxn_i[:, k] / inertia[ia], minlength=npart)
        turn[:, k] += np.bincount(ja, weights=lam * rxn_j[:, k] / inertia[ja], minlength=npart)
    new = _turn(axes, turn, rotation)
    if reference_axes is not None and max_tilt < np.pi:
        new = limit_tilt(new, reference_axes, max_tilt)
    return new


def _escape_walls(bodies, xyz, i, j, normal, gap, margin_nm, period_nm):
    """Near-vertical pushes of overlapping pairs replaced by their best horizontal ones."""
    steep = np.flatnonzero((gap < margin_nm) & (np.abs(normal[2]) > 0.5))
    if steep.size == 0:
        return normal, gap
    sep = horizontal_separation(bodies, xyz.T, i[steep], j[steep], period_nm)
    normal, gap = normal.copy(), gap.copy()
    normal[:, steep] = sep.normal.T
    gap[steep] = sep.gap_nm
    return normal, gap


def pack(bodies: Bodies, walls: Walls, centres: np.ndarray, period_nm, scale0: float = 1.0,
         options: PackOptions = PackOptions(), rotation: str = "none", reference_axes=None):
    """Grow from scale0 to 1 and relax until no pair overlaps; free rotations stay within
    options.max_tilt of reference_axes (default: the axes given).

    Returns (centres (N, 3), axes (N, 3), stats)."""
    t0 = time.perf_counter()
    mean_r = float(np.mean(bodies.radii_nm)) if len(bodies) else 1.0
    perm = spatial_order(np.asarray(centres, dtype=float), 4.0 * mean_r)
    bodies, walls = bodies.take(perm), walls.take(perm)
    drawn_axes = bodies.axes if reference_axes is None else np.asarray(reference_axes)[perm]
    xyz = np.ascontiguousarray(np.asarray(centres, dtype=float)[perm].T)
    margin = options.margin * mean_r
    verlet = _Verlet(period_nm, options.skin * mean_r)
    reach_max = 2.0 * float(bodies.bounding_radii_nm.max()) if len(bodies) else 0.0
    contact = 2.0 * mean_r
    s = min(1.0, scale0)
    worst = -np.inf
    converged = len(bodies) < 2
    it = 0
    best_scale, best_worst, since, escape, escapes = s, np.inf, 0, 0, 0
    while not converged and it < options.max_iterations:
        it += 1
        body_s = bodies.scaled(s)
        if options.wall_torque:
            axes = wall_contacts(xyz, body_s, walls, rotation)
            if axes is not body_s.axes:
                bodies = Bodies(bodies.shape, bodies.radii_nm, bodies.half_lengths_nm, axes)
                body_s = bodies.scaled(s)
        else:
            _apply_walls(xyz, body_s, walls)
        i, j = verlet.pairs(xyz, reach_max * s, reach_max)
        normal, gap = pair_normals_gaps(body_s, xyz, i, j, period_nm, verlet.hint, margin * s,
                                        options.search_iterations, it % options.full_search_every == 0)
        if body_s.shape == "cylinder":
            verlet.hint = normal.T
        worst = float(-gap.min()) if gap.size else -np.inf
        if s >= 1.0 and worst <= 0.0:
            converged = True
            break
        if s > best_scale or worst < best_worst * 0.98:
            best_scale, best_worst, since = s, worst, 0
        else:
            since += 1
        if since > options.patience:
            escape, since, escapes = options.escape_iterations, 0, escapes + 1
            best_worst = np.inf
        if escape > 0:
            escape -= 1
            normal, gap = _escape_walls(body_s, xyz, i, j, normal, gap, margin * s, period_nm)
        axes = push_apart(xyz, body_s, i, j, normal, gap, margin * s, period_nm, rotation,
                          options.relaxation, drawn_axes, options.max_tilt if rotation == "free" else np.pi)
        if axes is not bodies.axes:
            bodies = Bodies(bodies.shape, bodies.radii_nm, bodies.half_lengths_nm, axes)
        if s < 1.0 and worst < options.grow_tolerance * contact * s:
            s = min(1.0, s * (1.0 + options.growth_rate))
    _apply_walls(xyz, bodies.scaled(s), walls)
    out = np.empty((len(perm), 3))
    out[perm] = xyz.T
    out_axes = np.empty((len(perm), 3))
    out_axes[perm] = bodies.axes
    stats = PackStats(iterations=it, rebuilds=verlet.rebuilds, converged=converged, final_scale=s,
                      max_overlap_nm=max(0.0, worst), seconds=time.perf_counter() - t0, escapes=escapes)
    return out, out_axes, stats
