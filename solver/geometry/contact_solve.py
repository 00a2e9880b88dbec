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
    """Sparse Jacobian (rows: pairs, then one-particle rows) with 3N (or 6N) columns, built
    directly in CSR form (float32, filled in place: no temporaries of the full size): each pair
    row holds its two particles' shift columns and, when rotating, their turn columns (only z
    when every lever is vertical: in-plane rods)."""
    c, r = len(contacts), len(body)
    blocks = [(contacts.i, 0, -contacts.normal), (contacts.j, 0, contacts.normal)]
    if rotating:
        z_only = not (np.any(contacts.lever_i[:, :2]) or np.any(contacts.lever_j[:, :2]))
        span = slice(2, 3) if z_only else slice(0, 3)
        blocks += [(contacts.i, 3 * n, -contacts.lever_i[:, span]), (contacts.j, 3 * n, contacts.lever_j[:, span])]
    width = sum(v.shape[1] for _, _, v in blocks)
    body_width = 6 if rotating else 3
    data = np.empty(c * width + r * body_width, dtype=np.float32)
    indices = np.empty(data.size, dtype=np.int32)
    pair_data, pair_indices = data[:c * width].reshape(c, width), indices[:c * width].reshape(c, width)
    col = 0
    for owner, offset, values in blocks:
        k = values.shape[1]
        first = 3 - k if k < 3 else 0                     # z only: column 3k + 2
        pair_data[:, col:col + k] = values
        for m in range(k):
            np.multiply(owner, 3, out=pair_indices[:, col + m], casting="unsafe")
            pair_indices[:, col + m] += offset + first + m
        col += k
    body_data, body_indices = data[c * width:].reshape(r, body_width), indices[c * width:].reshape(r, body_width)
    body_data[:, :3] = body.shift
    body_indices[:, :3] = 3 * body.k[:, None] + np.arange(3)
    if rotating:
        body_data[:, 3:] = body.turn if body.turn is not None else 0.0
        body_indices[:, 3:] = 3 * n + 3 * body.k[:, None] + np.arange(3)
    indptr = np.concatenate([width * np.arange(c + 1), width * c + body_width * np.arange(1, r + 1)])
    return csr_matrix((data, indices, indptr), shape=(c + r, (6 if rotating else 3) * n))


def _row_owners(contacts: Contacts, body: BodyRows, rows: np.ndarray):
    """(first particle, second particle or −1) of the given rows (pairs first, then one-particle rows)."""
    c = len(contacts)
    pair = rows < c
    first = np.empty(rows.size, dtype=np.int64)
    second = np.full(rows.size, -1, dtype=np.int64)
    first[pair] = contacts.i[rows[pair]]
    first[~pair] = body.k[rows[~pair] - c]          # (no gather from an empty array: no pair or no body row)
    second[pair] = contacts.j[rows[pair]]
    return first, second


def _stiffness(contacts: Contacts, body: BodyRows, rows, inv_mass, inv_inertia, count):
    """Diagonal of J (M/count)⁻¹ Jᵀ for the given rows (mass splitting, module doc)."""
    c = len(contacts)
    pair = rows < c
    pr, br = rows[pair], rows[~pair] - c
    out = np.empty(rows.size)
    i, j = contacts.i[pr], contacts.j[pr]
    wi, wj = inv_mass[i] * count[i], inv_mass[j] * count[j]
    if contacts.lever_i is not None:
        wi = wi + np.einsum("pc,pc->p", contacts.lever_i[pr], contacts.lever_i[pr]) * inv_inertia[i] * count[i]
        wj = wj + np.einsum("pc,pc->p", contacts.lever_j[pr], contacts.lever_j[pr]) * inv_inertia[j] * count[j]
    out[pair] = wi + wj
    k = body.k[br]
    wk = np.einsum("pc,pc->p", body.shift[br], body.shift[br]) * inv_mass[k] * count[k]
    if body.turn is not None and inv_inertia is not None:
        wk = wk + np.einsum("pc,pc->p", body.turn[br], body.turn[br]) * inv_inertia[k] * count[k]
    out[~pair] = wk
    return out


def _fista(jac, gap, target, minv, stiffness, lam, sweeps, tolerance):
    """Accelerated projected gradient on the dual; returns (λ, sweeps done).  Single precision
    (the sweeps are memory bound; nm-scale gaps need no more)."""
    step = (1.0 / np.where(stiffness > 0, stiffness, np.inf)).astype(np.float32)
    jac_t = jac.T                                   # a CSC view: no copy
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
        if rows.size == active.size:
            jac = jac_all
            owners = np.concatenate([contacts.i, contacts.j, body_rows.k])
        else:
            jac = jac_all[rows]
            first, second = _row_owners(contacts, body_rows, rows)
            owners = np.concatenate([first, second[second >= 0]])
        count = np.maximum(np.bincount(owners, minlength=n), 1).astype(float)
        del owners
        stiffness = _stiffness(contacts, body_rows, rows, inv_mass, inv_inertia, count)
        lam, done = _fista(jac, gap_all[rows], target_all[rows], minv, stiffness, lam_all[rows], sweeps, tolerance_nm)
        lam = lam.astype(float)
        total += done
        lam_all[rows] = lam
        x = minv * (jac.T @ lam.astype(np.float32))
        short = target_all - (gap_all + jac_all @ x.astype(np.float32))
        add = ~active & (short > tolerance_nm)
        if not add.any():
            break
        active |= add
    short = target_all[:c] - (gap_all[:c] + (jac_all @ x.astype(np.float32))[:c])
    residual = float(short.max(initial=0.0))
    shift = x[:3 * n].reshape(n, 3)
    turn = x[3 * n:].reshape(n, 3) if rotating else None
    return Moves(shift, turn, residual, total)
