"""Rigid-body moves of particles: pair normals and gaps, contact levers, turns, wall contacts.

Conventions shared by the packer (`packing`) and the Brownian dynamics (`agglutination`):
positions are xyz (3, N) in nm; a particle's mass is its volume and its transverse moment of
inertia its shape's (`Bodies.inertia`: a solid cylinder's V·(r²/4 + L²/12) for rods).  `rotation`
says which turns are allowed (`orientation.ROTATION`): "free" (about any axis perpendicular to the
particle's own), "z" (about the vertical only: in-plane grains keep their elevation), "none"
(spheres; vertical grains).  Where a turn acts — support points, wall points, contact points —
the shape says (`Shape.support_candidates`, `wall_point`, `contact_point`).
"""

from __future__ import annotations

import numpy as np

from .bodies import Bodies
from .contact_solve import BodyRows, Contacts
from .contacts import horizontal_separation, separation
from .neighbours import min_image
from .walls import Walls


def turn_axes(axes: np.ndarray, turn: np.ndarray, rotation: str) -> np.ndarray:
    """Axes turned by small rotation vectors (rows of turn), kept unit with a_z ≥ 0; rotation
    "z" turns about the vertical only and keeps each axis's elevation exactly."""
    if rotation == "z":
        angle = turn[:, 2]
        c, s = np.cos(angle), np.sin(angle)
        new = np.stack([c * axes[:, 0] - s * axes[:, 1], s * axes[:, 0] + c * axes[:, 1], axes[:, 2]], axis=1)
        return new
    new = axes + np.cross(turn, axes)
    new /= np.linalg.norm(new, axis=1)[:, None]
    new *= np.where(new[:, 2] < 0, -1.0, 1.0)[:, None]
    return new


def project_levers(lever: np.ndarray, axes: np.ndarray, rotation: str) -> np.ndarray:
    """Rotation levers restricted to the allowed turns (see module doc)."""
    if rotation == "z":
        out = np.zeros_like(lever)
        out[:, 2] = lever[:, 2]
        return out
    return lever - np.einsum("pc,pc->p", lever, axes)[:, None] * axes


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


def wall_contacts(xyz, bodies: Bodies, walls: Walls, rotation="none"):
    """Push particles that cross the top or bottom wall back in, as rigid-body contacts with
    an immovable plane at the particle's deepest point (a rod pressed on one end turns flat),
    then clamp.  xyz (3, N) in place; returns the axes."""
    axes = bodies.axes
    if rotation != "none" and walls.protrusion.max(initial=0.0) == 0.0:
        lo, hi = walls.centre_bounds(bodies)
        depth = np.maximum(xyz[2] - hi, lo - xyz[2])
        hit = np.flatnonzero(depth > 0)
        if hit.size:
            a = axes[hit]
            down = np.where(xyz[2][hit] - hi[hit] > lo[hit] - xyz[2][hit], 1.0, -1.0)   # wall side
            ez = np.zeros_like(a)
            ez[:, 2] = down
            p = bodies.shape.wall_point(a, bodies.half_lengths_nm[hit], bodies.radii_nm[hit], ez)
            n = -ez                                                    # push away from the wall
            vol = bodies.volumes_nm3[hit]
            moment = bodies.take(hit).inertia
            rxn = np.cross(p, n)
            if rotation == "z":
                rxn[:, :2] = 0.0
            lam = depth[hit] / (1.0 / vol + np.sum(rxn**2, axis=1) / moment)
            xyz[2][hit] += lam / vol * n[:, 2]
            axes = axes.copy()
            axes[hit] = turn_axes(a, lam[:, None] * rxn / moment[:, None], rotation)
            bodies = bodies.turned(axes)
    walls.clamp(xyz, bodies)
    return axes


def pair_normals_gaps(bodies: Bodies, xyz: np.ndarray, i, j, period_nm, hint=None, margin_nm=0.0,
                      search_iterations=12, full_search=True):
    """(normals (3, P), gaps (P,)) for pairs; xyz is (3, N).  Pairs whose gap comes from a
    search stop once certified apart by margin_nm (their gap is then only a lower bound ≥ margin_nm)."""
    sep = separation(bodies, xyz.T, i, j, period_nm, hint=hint, margin_nm=margin_nm,
                     search_iterations=search_iterations, full_search=full_search)
    return sep.normal.T, sep.gap_nm


def pair_separations(bodies: Bodies, xyz: np.ndarray, i, j, period_nm) -> np.ndarray:
    """Minimum-image separation vectors c_j − c_i, (P, 3)."""
    d = np.stack([xyz[k][j] - xyz[k][i] for k in range(3)], axis=1)
    return min_image(d, period_nm)


def contact_rows(bodies: Bodies, xyz, i, j, normal, gap, period_nm, rotation) -> Contacts:
    """Linearised constraint rows of contacts (i, j) with normals (P, 3) and gaps g(n) (P,).

    Without rotation one row per contact.  With rotation each row pairs a candidate support
    point q_i of body i along +n with one q_j of body j along −n (`Shape.support_candidates`:
    where the support function has kinks, a turn may make another point support); its gap is
    d·n + q_j·n − q_i·n (≥ g(n), = g(n) for the true support points) and its levers
    (q_i × n, q_j × n), projected on the allowed rotations."""
    if rotation == "none":
        return Contacts(i, j, normal, gap)
    axes, h, r = bodies.axes, bodies.half_lengths_nm, bodies.radii_nm
    q_i, m_i, w_i = bodies.shape.support_candidates(axes[i], h[i], r[i], normal)
    q_j, m_j, w_j = bodies.shape.support_candidates(axes[j], h[j], r[j], -normal)
    mask = m_i[:, :, None] & m_j[:, None, :]                              # (P, K, K)
    p, a, b = np.nonzero(mask)
    n = normal[p]
    qi, qj = q_i[p, a], q_j[p, b]
    row_gap = gap[p] + (w_i[p] - np.einsum("pc,pc->p", qi, n)) + (w_j[p] + np.einsum("pc,pc->p", qj, n))
    lever_i = project_levers(np.cross(qi, n), axes[i[p]], rotation)
    lever_j = project_levers(np.cross(qj, n), axes[j[p]], rotation)
    return Contacts(i[p], j[p], n, row_gap, lever_i, lever_j, primary=(a == 0) & (b == 0))


def tilt_rows(axes: np.ndarray, reference: np.ndarray, max_angle: float, band_rad: float) -> BodyRows:
    """Rows a·a_ref − cos(max_angle) + (a × a_ref)·w ≥ 0 of the particles whose axis is within
    band_rad of the edge of its tilt cone (a turn w changes a·a_ref by (a × a_ref)·w)."""
    dot = np.einsum("pc,pc->p", axes, reference)
    ref = reference * np.where(dot < 0, -1.0, 1.0)[:, None]
    near = np.flatnonzero(np.abs(dot) < np.cos(max(0.0, max_angle - band_rad)))
    return BodyRows(near, np.zeros((near.size, 3)), np.cross(axes[near], ref[near]),
                    np.abs(dot[near]) - np.cos(max_angle))


def midpoint_levers(bodies: Bodies, xyz, i, j, normal, period_nm, rotation):
    """(ℓ_i, ℓ_j): r × n for the pair's contact point (`Shape.contact_point`), projected on the
    allowed rotations; normal is (P, 3) (Brownian overlap removal)."""
    d = pair_separations(bodies, xyz, i, j, period_nm)
    axes, h, r = bodies.axes, bodies.half_lengths_nm, bodies.radii_nm
    p = bodies.shape.contact_point(d, axes[i], axes[j], h[i], h[j], r[i], r[j], normal)   # from c_i
    return (project_levers(np.cross(p, normal), axes[i], rotation),
            project_levers(np.cross(p - d, normal), axes[j], rotation))


def horizontal_escape(bodies, xyz, i, j, normal, gap, margin_nm, period_nm):
    """Near-vertical pushes of overlapping pairs replaced by their best horizontal ones (the way
    out when the walls block a vertical push: a column of particles taller than the layer)."""
    steep = np.flatnonzero((gap < margin_nm) & (np.abs(normal[2]) > 0.5))
    if steep.size == 0:
        return normal, gap
    sep = horizontal_separation(bodies, xyz.T, i[steep], j[steep], period_nm)
    normal, gap = normal.copy(), gap.copy()
    normal[:, steep] = sep.normal.T
    gap[steep] = sep.gap_nm
    return normal, gap


def push_apart(xyz, bodies: Bodies, i, j, normal, gap, margin_nm, period_nm, rotation="none",
               relaxation=1.0, reference_axes=None, max_tilt=np.pi):
    """One Jacobi sweep of rigid-body contact pushes: each pair with gap < margin is pushed
    apart by (margin − gap) along its normal, the pushes on a particle add up.

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
        moment = bodies.inertia
        rxn_i, rxn_j = midpoint_levers(bodies, xyz, ia, ja, n, period_nm, rotation)
        k_sum = k_sum + np.sum(rxn_i**2, axis=1) / moment[ia] + np.sum(rxn_j**2, axis=1) / moment[ja]
    lam = over[act] * relaxation / k_sum
    npart = xyz.shape[1]
    for k in range(3):
        xyz[k] -= np.bincount(ia, weights=lam * inv_m_i * n[:, k], minlength=npart)
        xyz[k] += np.bincount(ja, weights=lam * inv_m_j * n[:, k], minlength=npart)
    if rotation == "none":
        return axes
    turn = np.zeros((npart, 3))
    for k in range(3):
        turn[:, k] -= np.bincount(ia, weights=lam * rxn_i[:, k] / moment[ia], minlength=npart)
        turn[:, k] += np.bincount(ja, weights=lam * rxn_j[:, k] / moment[ja], minlength=npart)
    new = turn_axes(axes, turn, rotation)
    if reference_axes is not None and max_tilt < np.pi:
        new = limit_tilt(new, reference_axes, max_tilt)
    return new
