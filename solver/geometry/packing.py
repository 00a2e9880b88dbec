"""Dense packing by growth with collective rearrangement, as a sequence of contact solves.

Start: every particle at its position (RSA result, or random where RSA left it) with all lengths
multiplied by a scale s0 < 1 chosen so that the shrunk particles fill the starting fraction.
Each iteration:

1. the size grows to s' = s·(1 + rate) (while growing is allowed, up to 1); the walls push
   particles that cross them back in (`motion.wall_contacts`: a rod pressed at one end turns flat);
2. for every pair closer than the cut-off (Verlet list with a skin, `neighbours.PairList`), the
   separation normal n and gap g at size s' (`contacts.separation`: exact for spheres and for
   parallel cylinders, a separating-axis lower bound for the others, warm-started from each
   pair's previous axis);
3. if s' = 1 and no pair has g < 0, every pair is certified apart: stop, without moving;
4. the pairs with g < margin + band form a linearised contact problem — every pair's gap to reach
   `margin`, every centre to stay within its walls, rigid bodies of mass V and moment of inertia
   of its shape (`Bodies.inertia`) — solved for the smallest moves by accelerated projected gradient on its dual
   (`contact_solve`; translations are exact at fixed n, so the prediction is a lower bound).
   Rotation ("coupled" mode, in-plane rods: about z only, keeping the elevation exactly) enters the
   same problem, with extra rows at the kinks of the support function; isotropic rods ("push"
   mode) turn by one rigid-body push sweep of the overlapping pairs instead, each axis kept within
   max_tilt of the one drawn for it so the orientation statistics stay as drawn; vertical
   cylinders and spheres do not turn.  Each particle's move and turn are capped (trust region);
5. the growth rate adapts: it rises (×1.5, up to max_growth_rate) while the largest overlap found
   in step 2 is below grow_tolerance × the contact distance, else growth pauses and the rate
   halves (down to min_growth_rate);
6. walls can block a push: a column of particles taller than the layer has its overlaps along z
   and the wall rows make the contact problem infeasible.  When neither s nor the largest overlap
   has improved for `patience` iterations, overlapping pairs with a near-vertical normal use their
   best horizontal separating axis instead (`motion.horizontal_escape`) for `escape_iterations`
   iterations (not for freely turning rods, which turn flat at the walls).

It gives up after `max_iterations` (the caller reports the concentration as unreachable).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .contact_solve import BodyRows, solve_contacts, wall_rows
from .bodies import Bodies
from .motion import (contact_rows, horizontal_escape, limit_tilt, pair_normals_gaps, push_apart, tilt_rows, turn_axes,
                     wall_contacts)
from .neighbours import PairList, spatial_order
from .walls import Walls

__all__ = ["PackOptions", "PackStats", "pack"]


@dataclass(frozen=True)
class PackOptions:
    margin: float = 0.02            # target gap of every pair (fraction of the mean radius)
    band: float = 0.1               # pairs closer than margin + band join the contact solve
    skin: float = 0.8               # Verlet skin (fraction of the mean radius)
    growth_rate: float = 0.01       # initial relative growth per iteration
    max_growth_rate: float = 0.04
    min_growth_rate: float = 0.0025
    grow_tolerance: float = 0.1     # grow only while max overlap < this × contact distance
    sweeps: int = 50                # most sweeps of the contact solve per round
    rounds: int = 2                 # active-set rounds (candidate rows of turning rods)
    tolerance: float = 0.5          # a solve stops when every row is within this × margin of its target
    max_iterations: int = 2000
    search_iterations: int = 1      # separating-axis refinement per iteration (cylinders)
    full_search_every: int = 8      # full axis search every k-th iteration (else warm local search)
    max_tilt: float = 0.35          # free rotation: largest angle (rad) from the drawn axis
    patience: int = 15              # iterations without progress before the horizontal escape
    escape_iterations: int = 10     # iterations of horizontal pushes for near-vertical contacts
    wall_torque: bool = True        # walls push rods at their deepest point (they turn flat)
    max_shift: float = 0.2          # trust region: largest move per iteration (× mean radius)
    max_turn: float = 0.05          # trust region: largest turn per iteration (rad)
    rotation_mode: str = "auto"     # "coupled": turns in the contact solve; "push": turns by one
    #                                 rigid-body push sweep; auto: push for free rotation, else coupled
    turn_relaxation: float = 1.2    # of the push sweep's turns


@dataclass(frozen=True)
class PackStats:
    iterations: int
    rebuilds: int
    converged: bool
    final_scale: float
    max_overlap_nm: float           # largest remaining penetration (0 when converged)
    seconds: float
    escapes: int = 0                # times the horizontal escape was used


class _Progress:
    """Fraction done: growth from s0 to 1 counts 0..0.8, shrinking the overlaps at s = 1 the rest."""

    def __init__(self, report: Callable[[float], None] | None, scale0: float):
        self.report, self.log_s0 = report, math.log(min(scale0, 1.0 - 1e-9))
        self.done, self.worst_at_one = 0.0, None

    def __call__(self, s: float, worst: float, margin: float):
        if self.report is None:
            return
        frac = 0.8 * (1.0 - math.log(s) / self.log_s0)
        if s >= 1.0:
            self.worst_at_one = self.worst_at_one or max(worst, 2.0 * margin)
            ratio = max(worst, margin) / self.worst_at_one
            frac = 0.8 + 0.2 * min(1.0, max(0.0, -math.log(ratio) / math.log(self.worst_at_one / margin)))
        if frac > self.done + 0.005:
            self.done = frac
            self.report(min(frac, 0.999))


def _clip_rows(v: np.ndarray, limit: float) -> np.ndarray:
    """Rows of v scaled down to length ≤ limit (trust region of one iteration's moves)."""
    size = np.linalg.norm(v, axis=1)
    return v * np.minimum(1.0, limit / np.maximum(size, 1e-300))[:, None]


def pack(bodies: Bodies, walls: Walls, centres: np.ndarray, period_nm, scale0: float = 1.0,
         options: PackOptions = PackOptions(), rotation: str = "none", reference_axes=None,
         progress: Callable[[float], None] | None = None):
    """Grow from scale0 to 1 and relax until no pair overlaps; free rotations stay within
    options.max_tilt of reference_axes (default: the axes given).  progress(fraction) is called
    now and then when given.

    Returns (centres (N, 3), axes (N, 3), stats)."""
    t0 = time.perf_counter()
    mean_r = float(np.mean(bodies.radii_nm)) if len(bodies) else 1.0
    perm = spatial_order(np.asarray(centres, dtype=float), 4.0 * mean_r)
    bodies, walls = bodies.take(perm), walls.take(perm)
    drawn_axes = bodies.axes if reference_axes is None else np.asarray(reference_axes)[perm]
    xyz = np.ascontiguousarray(np.asarray(centres, dtype=float)[perm].T)
    margin, band = options.margin * mean_r, options.band * mean_r
    pairs = PairList(period_nm, options.skin * mean_r + band)
    reach_max = 2.0 * float(bodies.bounding_radii_nm.max()) if len(bodies) else 0.0
    contact = 2.0 * mean_r
    inv_mass = 1.0 / bodies.volumes_nm3 if len(bodies) else np.zeros(0)
    inv_inertia = 1.0 / bodies.inertia if rotation != "none" else None
    tilt = options.max_tilt if rotation == "free" else np.pi
    report = _Progress(progress, scale0)
    s = min(1.0, scale0)
    rate, grow = options.growth_rate, True
    worst = -np.inf
    converged = len(bodies) < 2
    it, escape, escapes, since = 0, 0, 0, 0
    best_scale, best_worst = s, np.inf
    mode = options.rotation_mode if options.rotation_mode != "auto" else ("push" if rotation == "free" else "coupled")
    solve_rotation = rotation if mode == "coupled" else "none"
    while not converged and it < options.max_iterations:
        it += 1
        s_new = min(1.0, s * (1.0 + rate)) if grow else s
        body_s = bodies.scaled(s_new)
        if options.wall_torque:
            axes = wall_contacts(xyz, body_s, walls, rotation)
            if axes is not body_s.axes:
                bodies = bodies.turned(axes)
                body_s = bodies.scaled(s_new)
        else:
            walls.clamp(xyz, body_s)
        i, j = pairs.pairs(xyz, reach_max * s_new, reach_max)
        normal, gap = pair_normals_gaps(body_s, xyz, i, j, period_nm, pairs.hint, margin * s_new,
                                        options.search_iterations, it % options.full_search_every == 0)
        if body_s.shape.uses_axis_hint:
            pairs.hint = normal.T
        worst = float(-gap.min()) if gap.size else -np.inf
        s = s_new
        report(s, worst, margin * s)
        if s >= 1.0 and worst <= 0.0:            # every pair certified apart at full size
            converged = True
            break
        if s > best_scale or worst < best_worst * 0.98:
            best_scale, best_worst, since = s, worst, 0
        else:
            since += 1
        if since > options.patience and rotation != "free":
            escape, since, escapes, best_worst = options.escape_iterations, 0, escapes + 1, np.inf
        if escape > 0:
            escape -= 1
            normal, gap = horizontal_escape(body_s, xyz, i, j, normal, gap, margin * s, period_nm)
        near = np.flatnonzero(gap < (margin + band) * s)
        rows = contact_rows(body_s, xyz, i[near], j[near], normal[:, near].T, gap[near], period_nm, solve_rotation)
        turned = None
        if rotation != "none" and solve_rotation == "none":
            turned = push_apart(xyz.copy(), body_s, i[near], j[near], normal[:, near], gap[near], margin * s,
                                period_nm, rotation, options.turn_relaxation, drawn_axes, tilt)
        del normal, gap, near                            # the all-pairs arrays, before the solve
        lo, hi = walls.centre_bounds(body_s)
        body_rows = wall_rows(xyz[2], lo, hi, band * s)
        if solve_rotation != "none" and tilt < np.pi:
            body_rows = BodyRows.concat([body_rows, tilt_rows(bodies.axes, drawn_axes, tilt, 0.05)])
        moves = solve_contacts(rows, body_rows, inv_mass, None if inv_inertia is None else inv_inertia / s**2,
                               margin * s, options.sweeps, options.tolerance * margin * s, options.rounds)
        xyz += _clip_rows(moves.shift_nm, options.max_shift * mean_r * s).T
        if turned is not None:
            bodies = bodies.turned(turned)
        if moves.turn is not None:
            axes = turn_axes(bodies.axes, _clip_rows(moves.turn, options.max_turn), rotation)
            if tilt < np.pi:
                axes = limit_tilt(axes, drawn_axes, tilt)
            bodies = bodies.turned(axes)
        if s < 1.0 and worst < options.grow_tolerance * contact * s:
            grow, rate = True, min(options.max_growth_rate, 1.5 * rate)
        else:
            grow, rate = False, max(options.min_growth_rate, 0.5 * rate)
    walls.clamp(xyz, bodies.scaled(s))
    out = np.empty((len(perm), 3))
    out[perm] = xyz.T
    out_axes = np.empty((len(perm), 3))
    out_axes[perm] = bodies.axes
    stats = PackStats(iterations=it, rebuilds=pairs.rebuilds, converged=converged, final_scale=s,
                      max_overlap_nm=max(0.0, worst), seconds=time.perf_counter() - t0, escapes=escapes)
    return out, out_axes, stats
