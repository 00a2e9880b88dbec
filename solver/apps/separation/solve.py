"""Colour separation: the coverages whose printed colour is closest to a target in CIELAB.

For each target t (CIELAB), minimise ΔE76² = |Lab(c) − t|² over c ∈ [0, 1]^k, where Lab(c) is
the print model (`printmodel.PrintColourModel`):

1. **Initialisation** from a lookup table: the printed colour of every node of a regular
   coverage grid (`grid_nodes` per axis: 17³ = 4913 for three inks), the node nearest to t in
   CIELAB (k-d tree) is the start. For a target outside the gamut it is within a grid cell of
   the closest printable colour.
2. **Projected Levenberg–Marquardt** (a Gauss–Newton step damped per target, μ·diag(JᵀJ)),
   vectorised over all targets: Jacobian J = ∂Lab/∂c by one-sided finite differences (steps
   inward at the bounds), coverages at a bound whose gradient points outward held fixed (active
   set), steps clipped to [0, 1], a step kept only when it lowers ΔE (else μ × 10). A target
   stops when ΔE76 < `tolerance_de`, when the step is below `step_tol`, or after
   `max_iterations`.

A target whose final ΔE76 exceeds `gamut_de` is out of gamut: it is clipped to the closest
printable colour found and counted. ΔE76 is minimised because it is a sum of squares (so
Gauss–Newton applies as it is); inside the gamut the minimum is 0 for any colour difference.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from .printmodel import PrintColourModel

#: coverage-grid nodes per axis for k inks (LUT sizes 257, 4225, 15625, 28561)
DEFAULT_GRID_NODES = {1: 257, 2: 65, 3: 25, 4: 13}


@dataclass(frozen=True)
class SolverSettings:
    """Accuracy knobs of the separation (benchmarks/bench_separation.py measures them)."""

    grid_nodes: int | None = None     # LUT nodes per ink; None: DEFAULT_GRID_NODES[k]
    max_iterations: int = 30
    tolerance_de: float = 1e-3        # ΔE76 at which a target is matched
    step_tol: float = 1e-7            # coverage step below which a target has converged
    fd_step: float = 1e-6             # finite-difference step of the Jacobian (coverage)
    gamut_de: float = 0.5             # ΔE76 above which a target counts as out of gamut
    starts: int = 2                   # LUT nodes tried (nearest first) for unmatched targets
    near_miss_starts: int = 12        # nodes tried for unmatched targets within near_miss_de
    near_miss_de: float = 1.0
    polish_starts: int = 8            # … in the colour-first pass, for targets the black aim kept
    polish_near_miss_starts: int = 32  # from their colour (separate_lab)
    probe_iterations: int = 5         # LM steps from each start before the best is continued
    improvement_de: float = 1e-4      # a step improving ΔE76 by less than this: converged
    broyden: bool = False             # rank-one Jacobian updates between finite differences
    chunk: int = 16384                # targets solved together (memory ~ chunk·(k+1)·nλ·8 B·nP)

    def __post_init__(self):
        if self.grid_nodes is not None and self.grid_nodes < 2:
            raise ValueError(f"grid_nodes must be ≥ 2, got {self.grid_nodes}")
        if self.max_iterations < 0 or self.chunk < 1:
            raise ValueError("max_iterations must be ≥ 0 and chunk ≥ 1")

    def nodes(self, k: int) -> int:
        return self.grid_nodes if self.grid_nodes is not None else DEFAULT_GRID_NODES[k]


@dataclass(frozen=True)
class CoverageGrid:
    """Printed colours of a regular coverage grid, with a k-d tree on them (the initialiser)."""

    coverages: np.ndarray    # [M, k]
    lab: np.ndarray          # [M, 3]
    tree: object = field(repr=False)

    @classmethod
    def build(cls, model: PrintColourModel, nodes: int) -> "CoverageGrid":
        axis = np.linspace(0.0, 1.0, nodes)
        grids = np.meshgrid(*([axis] * model.n_inks), indexing="ij")
        return cls.of(np.stack([g.ravel() for g in grids], axis=-1), model)

    @classmethod
    def of(cls, coverages: np.ndarray, model) -> "CoverageGrid":
        """These coverage nodes under `model` (a PrintColourModel, or an objective's residuals)."""
        from scipy.spatial import cKDTree

        lab = model.lab(coverages)
        return cls(coverages, lab, cKDTree(lab))

    def on(self, objective) -> "CoverageGrid":
        """The same coverage nodes with another objective's residuals (e.g. the polishing pass's)."""
        return CoverageGrid.of(self.coverages, objective)

    def nearest(self, lab_targets, count: int = 1) -> np.ndarray:
        """Coverages [N, count, k] of the `count` nodes nearest to the targets [N, 3] in
        CIELAB, nearest first."""
        _, idx = self.tree.query(np.asarray(lab_targets, dtype=np.float64), k=[*range(1, count + 1)])
        return self.coverages[idx]


@dataclass(frozen=True)
class Separation:
    """Result for N target colours."""

    coverages: np.ndarray     # [N, k] in [0, 1]
    target_lab: np.ndarray    # [N, 3]
    printed_lab: np.ndarray   # [N, 3]: the model's colour of `coverages`
    iterations: np.ndarray    # [N] LM iterations used
    gamut_de: float           # threshold of `out_of_gamut`

    @property
    def delta_e76(self) -> np.ndarray:
        return np.linalg.norm(self.printed_lab - self.target_lab, axis=-1)

    @property
    def out_of_gamut(self) -> np.ndarray:
        return self.delta_e76 > self.gamut_de


def jacobian(model: PrintColourModel, c: np.ndarray, lab: np.ndarray, step: float) -> np.ndarray:
    """∂Lab/∂c [N, 3, k] by one-sided differences (a step of −`step` where c > 1 − step)."""
    n, k = c.shape
    h = np.where(c > 1.0 - step, -step, step)                     # [n, k]
    shifted = np.repeat(c[:, None, :], k, axis=1)                 # [n, k(perturbed), k]
    idx = np.arange(k)
    shifted[:, idx, idx] += h
    lab_shifted = model.lab(shifted.reshape(n * k, k)).reshape(n, k, -1)
    return np.moveaxis((lab_shifted - lab[:, None, :]) / h[:, :, None], 1, 2)


def project(c: np.ndarray, tac: float | None, bisections: int = 40) -> np.ndarray:
    """Coverages [N, k] in [0, 1] projected (Euclidean) onto Σc ≤ `tac` too: c ↦ clip(c − θ, 0, 1)
    with θ ≥ 0 found by bisection where the sum is over the limit (None: no limit)."""
    if tac is None:
        return c
    over = c.sum(axis=-1) > tac
    if not over.any():
        return c
    co = c[over]
    lo, hi = np.zeros(co.shape[0]), np.ones(co.shape[0])
    for _ in range(bisections):
        mid = 0.5 * (lo + hi)
        big = np.clip(co - mid[:, None], 0.0, 1.0).sum(axis=-1) > tac
        lo, hi = np.where(big, mid, lo), np.where(big, hi, mid)
    out = c.copy()
    out[over] = np.clip(co - hi[:, None], 0.0, 1.0)
    return out


def lm_solve(model: PrintColourModel, targets: np.ndarray, start: np.ndarray,
             settings: SolverSettings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Projected Levenberg–Marquardt from `start`: (coverages, printed Lab, iterations). Steps
    are projected onto [0, 1]^k and, for a model with a `tac_limit`, onto Σc ≤ tac_limit.

    With `settings.broyden` the Jacobian is computed by finite differences at the start and
    after a rejected step, and updated by Broyden's rank-one formula after an accepted one
    (J += (Δlab − J·Δc)·Δcᵀ/|Δc|²): one model evaluation per step instead of k + 1."""
    tac = getattr(model, "tac_limit", None)
    c = project(np.clip(np.array(start, dtype=np.float64), 0.0, 1.0), tac)
    n, k = c.shape
    lab = model.lab(c)
    cost = np.sum((lab - targets) ** 2, axis=-1)
    mu = np.full(n, 1e-3)
    iterations = np.zeros(n, dtype=np.int64)
    running = cost > settings.tolerance_de ** 2
    J = np.zeros((n, lab.shape[-1], k))
    stale = np.ones(n, dtype=bool)                  # J needs finite differences
    eye = np.eye(k)
    for _ in range(settings.max_iterations):
        idx = np.flatnonzero(running)
        if idx.size == 0:
            break
        refresh = idx[stale[idx]]
        if refresh.size:
            J[refresh] = jacobian(model, c[refresh], lab[refresh], settings.fd_step)
        fresh = stale[idx] | (not settings.broyden)
        stale[idx] = False
        ci, labi, ti, Ji = c[idx], lab[idx], targets[idx], J[idx]
        r = labi - ti
        g = np.einsum("nik,ni->nk", Ji, r)                         # ½ ∇cost
        A = np.einsum("nik,nil->nkl", Ji, Ji)
        held = ((ci <= 0.0) & (g > 0.0)) | ((ci >= 1.0) & (g < 0.0))
        free = ~held
        diag = np.einsum("nkk->nk", A)
        damp = mu[idx, None] * np.maximum(diag, 1e-9 * (diag.sum(-1, keepdims=True) + 1e-12))
        A = A + damp[:, :, None] * eye
        mask = free[:, :, None] & free[:, None, :]
        A = np.where(mask, A, eye)                                 # held coverages: δ = 0
        step = -np.linalg.solve(A, np.where(free, g, 0.0)[..., None])[..., 0]
        c_new = project(np.clip(ci + step, 0.0, 1.0), tac)
        lab_new = model.lab(c_new)
        cost_new = np.sum((lab_new - ti) ** 2, axis=-1)
        cost_before = cost[idx]
        better = cost_new < cost_before
        dc = c_new - ci
        moved = np.max(np.abs(dc), axis=-1)
        if settings.broyden:
            norm2 = np.sum(dc * dc, axis=-1)
            ok = better & (norm2 > 0.0)
            update = (lab_new - labi - np.einsum("nik,nk->ni", Ji, dc))[:, :, None] * dc[:, None, :]
            J[idx[ok]] = Ji[ok] + update[ok] / norm2[ok, None, None]
            stale[idx] = ~better & ~fresh                          # retry with a true Jacobian
        else:
            stale[idx] = True
        c[idx] = np.where(better[:, None], c_new, ci)
        lab[idx] = np.where(better[:, None], lab_new, labi)
        cost[idx] = np.where(better, cost_new, cost_before)
        # a rejected step on a Broyden Jacobian is retried with a fresh one before damping more
        mu[idx] = np.where(better, mu[idx] * 0.3, np.where(fresh, mu[idx] * 10.0, mu[idx]))
        iterations[idx] += 1
        gain = np.sqrt(cost_before) - np.sqrt(cost[idx])
        small = better & fresh & ((moved < settings.step_tol) | (gain < settings.improvement_de))
        done = (cost[idx] <= settings.tolerance_de ** 2) | small | (mu[idx] > 1e10)
        running[idx[done]] = False
    return c, lab, iterations


def _try_starts(model, targets, starts, todo, c, lab, cost, iterations, probe) -> None:
    """LM (`probe` settings) on targets `todo` from each of `starts[todo, j]`; keeps (in place)
    whichever result is closest to its target."""
    for j in range(starts.shape[1]):
        c2, lab2, it2 = lm_solve(model, targets[todo], starts[todo, j], probe)
        cost2 = np.sum((lab2 - targets[todo]) ** 2, axis=-1)
        better = cost2 < cost[todo]
        c[todo[better]], lab[todo[better]], cost[todo[better]] = c2[better], lab2[better], cost2[better]
        iterations[todo] += it2


def multistart(model: PrintColourModel, targets: np.ndarray, grid: CoverageGrid,
               settings: SolverSettings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """LM from the nearest LUT nodes, in phases (most in-gamut targets stop in the first):

    1. from the nearest node, `probe_iterations` steps;
    2. targets not yet matched (ΔE76 > tolerance) also from the next `starts − 1` nodes,
       `probe_iterations` steps each, keeping the closest result;
    3. near misses (still unmatched but within `near_miss_de`) from the nodes after those, up
       to `near_miss_starts` in all;
    4. the closest result continues to convergence (`max_iterations` in all).

    Several starts are needed where the map from coverages to colour is folded: in the dark
    corner of three inks (two of them near full coverage) a target can reach a local minimum at
    a bound from its nearest nodes while a farther node reaches the target itself. Targets far
    outside the gamut (most of the unmatched ones) do not pay for phase 3.
    """
    probe = replace(settings, max_iterations=min(settings.probe_iterations, settings.max_iterations))
    count = max(settings.starts, settings.near_miss_starts)
    starts = grid.nearest(targets, min(count, grid.coverages.shape[0]))
    c, lab, iterations = lm_solve(model, targets, starts[:, 0], probe)
    cost = np.sum((lab - targets) ** 2, axis=-1)
    todo = np.flatnonzero(cost > settings.tolerance_de ** 2)
    if todo.size == 0:
        return c, lab, iterations
    _try_starts(model, targets, starts[:, 1:settings.starts], todo, c, lab, cost, iterations, probe)
    near = todo[(cost[todo] > settings.tolerance_de ** 2) & (cost[todo] <= settings.near_miss_de ** 2)]
    if near.size:
        _try_starts(model, targets, starts[:, settings.starts:], near, c, lab, cost, iterations, probe)
    rest = replace(settings, max_iterations=max(settings.max_iterations - probe.max_iterations, 0))
    c[todo], lab[todo], it3 = lm_solve(model, targets[todo], c[todo], rest)
    iterations[todo] += it3
    return c, lab, iterations


def separate_lab(model: PrintColourModel, target_lab, settings: SolverSettings = SolverSettings(),
                 grid: CoverageGrid | None = None,
                 progress: Callable[[int], None] | None = None, objective=None) -> Separation:
    """Separate CIELAB targets [N, 3] (relative to the model's white) into coverages [N, k].

    `objective` (`black.InkingObjective` of `model`) adds the black aim and the total area
    coverage limit to the residuals (the grid, when given, must be built on it).
    `progress(n)` is called after each chunk of n targets (e.g. a tqdm bar's update)."""
    targets = np.asarray(target_lab, dtype=np.float64).reshape(-1, 3)
    if not np.all(np.isfinite(targets)):
        raise ValueError("target colours must be finite")
    solved = objective if objective is not None else model
    wanted = objective.targets(targets) if objective is not None else targets
    grid = grid or CoverageGrid.build(solved, settings.nodes(model.n_inks))
    k = model.n_inks
    coverages = np.empty((targets.shape[0], k))
    iterations = np.zeros(targets.shape[0], dtype=np.int64)
    polish_grid = None
    for start in range(0, targets.shape[0], settings.chunk):
        part = slice(start, start + settings.chunk)
        t = wanted[part]
        coverages[part], lab, iterations[part] = multistart(solved, t, grid, settings)
        if objective is not None and objective.black is not None:      # polish: the colour first
            miss = np.linalg.norm(lab[:, :3] - targets[part], axis=-1) > settings.tolerance_de
            rows = np.flatnonzero(miss) + part.start
            if rows.size:
                polish = objective.polished()
                if polish_grid is None:
                    polish_grid = grid.on(polish)
                coverages[rows], lab_rows, more = lm_solve(polish, polish.targets(targets[rows]), coverages[rows], settings)
                iterations[rows] += more
                # still missed: the black aim held the first pass where the colour needs another
                # black (dark reds: K ≈ 0.9 against an aim near 0), so start again from the nodes
                # nearest to the colour alone
                still = np.linalg.norm(lab_rows[:, :3] - targets[rows], axis=-1) > settings.tolerance_de
                if np.any(still):
                    again = rows[still]
                    c2, lab2, it2 = multistart(polish, polish.targets(targets[again]), polish_grid,
                                               replace(settings, starts=settings.polish_starts,
                                                       near_miss_starts=settings.polish_near_miss_starts))
                    better = (np.linalg.norm(lab2[:, :3] - targets[again], axis=-1)
                              < np.linalg.norm(lab_rows[still, :3] - targets[again], axis=-1))
                    coverages[again[better]] = c2[better]
                    iterations[again] += it2
        if progress is not None:
            progress(t.shape[0])
    if objective is not None:
        coverages = objective.enforce_tac(coverages)
    return Separation(coverages, targets, model.lab(coverages), iterations, settings.gamut_de)
