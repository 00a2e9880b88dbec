"""Linearised contact solve: how far each particle moves and turns in one packer iteration.

Contact c joins particles i and j with a unit normal n (from i towards j) and a gap g = g(n) on
that axis (separating-axis value: a lower bound of their signed distance, nm).  A displacement
u_k and a small rotation w_k of each particle change g(n), to first order, by

    Δg_c = n·(u_j − u_i) + ℓ_j·w_j − ℓ_i·w_i,      ℓ = (q − c) × n,

q the support points of the two bodies along ±n (`motion.contact_rows`).  For translations this
is exact at fixed n, and the true gap max_n g(n) can only be larger: the prediction is a lower
bound.  Near the kinks of the support function a contact has several rows (other candidate
support points); they join the problem only when the solution violates them (active set,
`rounds`).  Rows of one particle (`BodyRows`) keep it inside the walls (z_lo ≤ z + u_z ≤ z_hi)
and within its tilt cone.

We look for the smallest moves (in the metric of the masses m = V and moments of inertia I) with
every row's linearised gap ≥ its target — a quadratic programme whose dual is

    max_{λ ≥ 0}  λ·(t − g) − ½ λᵀ J M⁻¹ Jᵀ λ,      moves x = M⁻¹ Jᵀ λ,

solved by accelerated projected gradient (FISTA with adaptive restart) preconditioned by the
mass-splitting diagonal (each row sees its particles' inverse masses times their row counts,
Tonge et al. 2012: a step that never overshoots).  It stops when the largest violation is below
`tolerance_nm` or after `sweeps` sweeps; a sweep is two sparse products with the Jacobian.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix


@dataclass(frozen=True, eq=False)
class Contacts:
    """Pair rows: gap + n·(u_j − u_i) + ℓ_j·w_j − ℓ_i·w_i ≥ target."""

    i: np.ndarray            # (C,) first particle
    j: np.ndarray            # (C,) second particle
    normal: np.ndarray       # (C, 3) unit, from i towards j
    gap_nm: np.ndarray       # (C,) the row's gap at the current positions
    lever_i: np.ndarray | None = None   # (C, 3) projected on i's allowed rotations
    lever_j: np.ndarray | None = None   # (C, 3) projected on j's allowed rotations
    primary: np.ndarray | None = None   # (C,) rows always in the problem (default: all)

    def __len__(self) -> int:
        return len(self.i)


@dataclass(frozen=True, eq=False)
class BodyRows:
    """One-particle rows: gap + s·u_k + τ·w_k ≥ 0 (walls, tilt cones); always in the problem."""

    k: np.ndarray            # (R,) particle
    shift: np.ndarray        # (R, 3) s
    turn: np.ndarray | None  # (R, 3) τ (None: translation only)
    gap: np.ndarray          # (R,)

    def __len__(self) -> int:
        return len(self.k)

    @staticmethod
    def concat(parts: list["BodyRows"]) -> "BodyRows":
        turn = [p.turn if p.turn is not None else np.zeros((len(p), 3)) for p in parts]
        return BodyRows(np.concatenate([p.k for p in parts]), np.concatenate([p.shift for p in parts]),
                        np.concatenate(turn), np.concatenate([p.gap for p in parts]))


@dataclass(frozen=True, eq=False)
class Moves:
    shift_nm: np.ndarray     # (N, 3) centre displacements
    turn: np.ndarray | None  # (N, 3) small rotation vectors (rad), None without rotation
    residual_nm: float       # largest remaining violation of the linearised pair rows
    sweeps: int


def wall_rows(z_now, z_lo, z_hi, band_nm) -> BodyRows:
    """Wall rows of the particles whose centre is within band_nm of its allowed z range's ends."""
    top = np.flatnonzero(z_now - z_lo < band_nm)
    bottom = np.flatnonzero(z_hi - z_now < band_nm)
    k = np.concatenate([top, bottom])
    shift = np.zeros((k.size, 3))
    shift[:, 2] = np.concatenate([np.ones(top.size), -np.ones(bottom.size)])
    return BodyRows(k, shift, None, np.concatenate([z_now[top] - z_lo[top], z_hi[bottom] - z_now[bottom]]))


def _system(contacts: Contacts, body: BodyRows, n: int, rotating: bool):
    """Sparse Jacobian (rows: pairs, then one-particle rows) with 3N (or 6N) columns."""
    c, r = len(contacts), len(body)
    xyz = np.arange(3)
    rows = [np.repeat(np.arange(c), 3)] * 2 + [c + np.repeat(np.arange(r), 3)]
    cols = [(3 * contacts.i[:, None] + xyz).ravel(), (3 * contacts.j[:, None] + xyz).ravel(),
            (3 * body.k[:, None] + xyz).ravel()]
    vals = [-contacts.normal.ravel(), contacts.normal.ravel(), body.shift.ravel()]
    if rotating:
        rows += [np.repeat(np.arange(c), 3)] * 2 + [c + np.repeat(np.arange(r), 3)]
        cols += [3 * n + (3 * contacts.i[:, None] + xyz).ravel(), 3 * n + (3 * contacts.j[:, None] + xyz).ravel(),
                 3 * n + (3 * body.k[:, None] + xyz).ravel()]
        vals += [-contacts.lever_i.ravel(), contacts.lever_j.ravel(),
                 (body.turn if body.turn is not None else np.zeros((r, 3))).ravel()]
    jac = csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                     shape=(c + r, (6 if rotating else 3) * n))
    jac.eliminate_zeros()                      # e.g. the x, y turns of in-plane rods
    return jac


def _fista(jac, gap, target, minv, count, lam, sweeps, tolerance):
    """Accelerated projected gradient on the dual; returns (λ, sweeps done).  Single precision
    (the sweeps are memory bound; nm-scale gaps need no more)."""
    stiffness = jac.multiply(jac) @ (minv * count)
    step = (1.0 / np.where(stiffness > 0, stiffness, np.inf)).astype(np.float32)
    jac = jac.astype(np.float32)
    jac_t = jac.T.tocsr()
    minv = minv.astype(np.float32)
    gap, target, lam = gap.astype(np.float32), target.astype(np.float32), lam.astype(np.float32)
    lam_prev = lam
    momentum = 1.0
    done = 0
    for done in range(1, sweeps + 1):
        if done % 10 == 0:
            if float(np.max(target - (gap + jac @ (minv * (jac_t @ lam))))) <= tolerance:
                break
        nxt = 0.5 * (1.0 + math.sqrt(1.0 + 4.0 * momentum * momentum))
        y = lam + np.float32((momentum - 1.0) / nxt) * (lam - lam_prev)
        momentum = nxt
        new = np.maximum(0.0, y + (target - (gap + jac @ (minv * (jac_t @ y)))) * step)
        if float(np.sum((new - lam) * (y - new))) > 0.0:             # adaptive restart (no BLAS: its
            #                                                          threads spin on a busy machine)
            momentum = 1.0
        lam_prev, lam = lam, new
    return lam, done


def solve_contacts(contacts: Contacts, body_rows: BodyRows, inv_mass: np.ndarray, inv_inertia: np.ndarray | None,
                   target_nm: float, sweeps: int = 200, tolerance_nm: float = 0.0, rounds: int = 3) -> Moves:
    """Moves that bring every linearised pair gap to ≥ target_nm and every one-particle row to
    ≥ 0 (see module doc).  inv_mass (N,): 1/m; inv_inertia (N,): 1/I (transverse), needed when
    the contacts carry levers."""
    n = len(inv_mass)
    rotating = contacts.lever_i is not None
    jac_all = _system(contacts, body_rows, n, rotating)
    c = len(contacts)
    gap_all = np.concatenate([contacts.gap_nm, body_rows.gap])
    target_all = np.concatenate([np.full(c, float(target_nm)), np.zeros(len(body_rows))])
    minv = np.repeat(inv_mass, 3)
    if rotating:
        minv = np.concatenate([minv, np.repeat(inv_inertia, 3)])
    active = np.ones(len(gap_all), dtype=bool)
    if contacts.primary is not None:
        active[:c] = contacts.primary
    lam_all = np.zeros(len(gap_all))
    x = np.zeros(jac_all.shape[1])
    total = 0
    for _ in range(max(1, rounds)):
        rows = np.flatnonzero(active)
        if rows.size == 0:
            break
        jac = jac_all[rows]
        owners = np.concatenate([contacts.i[rows[rows < c]], contacts.j[rows[rows < c]],
                                 body_rows.k[rows[rows >= c] - c]])
        count = np.repeat(np.maximum(np.bincount(owners, minlength=n), 1).astype(float), 3)
        if rotating:
            count = np.concatenate([count, count])
        lam, done = _fista(jac, gap_all[rows], target_all[rows], minv, count, lam_all[rows], sweeps, tolerance_nm)
        lam = lam.astype(float)
        total += done
        lam_all[rows] = lam
        x = minv * (jac.T @ lam)
        short = target_all - (gap_all + jac_all @ x)
        add = ~active & (short > tolerance_nm)
        if not add.any():
            break
        active |= add
    short = target_all[:c] - (gap_all[:c] + jac_all[:c] @ x)
    residual = float(short.max(initial=0.0))
    shift = x[:3 * n].reshape(n, 3)
    turn = x[3 * n:].reshape(n, 3) if rotating else None
    return Moves(shift, turn, residual, total)
