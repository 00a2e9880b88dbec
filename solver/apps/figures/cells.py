"""The cells of a figure: one table request per ink × grains, estimated, then built through the
cache one after another (resumable: finished tables and work units are kept).

Cylinders 'across the layer' (docs/design.md §3): vertical cylinders longer than half the layer
cannot pack beyond a geometric bound (≈ 44.5 % for 300-nm cylinders in a 1000-nm layer), so such
a column uses, per row, the smallest orientation spread (`tilt=` in degrees, from TILTS_DEG)
whose layer reaches the row's concentration (`solver.geometry.smallest_tilt_reaching`).

No cell is skipped: a cell whose planning or build raises is kept as failed, with the reason.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

from tqdm import tqdm

from solver.colour.cie import REQUIRED_RANGE_NM
from solver.colour.measurement import Measurement
from solver.geometry.spec import MOLECULAR_WORDS
from solver.table.builder import BuildOptions, get_or_build
from solver.table.request import OPTION, TableRequest, default_grids, table_request
from solver.table.schema import InkTable
from .models import DEFAULT_MODEL, MODELS, Model
from .paper_grid import Column, Row

log = logging.getLogger("inkbsdf.figures")

#: orientation spreads (degrees from the layer normal) tried for cylinders across the layer
TILTS_DEG = (0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0)
GRID_OPTIONS = ("wavelengths_nm", "sigma_rad")


def figure_grids(accuracy: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """A figure's wavelengths (nm) and incidence angles (rad): the particle preset's, the
    wavelengths up to the first node at or past the colour's upper end (700 nm,
    cie.REQUIRED_RANGE_NM).  A figure's tables are only measured as colours (E308 extends the
    700-nm value beyond it), so the nodes past 700 nm — at `default` 740 and 780 nm, 2 of the 11
    solved wavelengths — are not computed; a table for rendering keeps 380–780 nm."""
    wavelengths, sigma = default_grids(accuracy, molecular=False)
    upto = next((i for i, w in enumerate(wavelengths) if w >= REQUIRED_RANGE_NM[1] - 1e-9), len(wavelengths) - 1)
    return wavelengths[:upto + 1], sigma


@dataclass(frozen=True)
class FigureSettings:
    """What every table of a figure is computed with: an accuracy preset and overrides
    (grids for every cell; wave settings, as `table_request` takes them, for particle cells)."""

    accuracy: str = "default"
    overrides: tuple[tuple[str, object], ...] = ()
    model: Model = MODELS[DEFAULT_MODEL]
    measurement: Measurement | None = None      # None: the model's own

    @property
    def colour_measurement(self) -> Measurement:
        """How the cells' colours are measured (the CSV, the findings)."""
        return self.measurement or self.model.measurement

    def request(self, ink, particles: str) -> TableRequest:
        """The cell's request.  Every cell of a figure is sampled on the same grids — the
        molecular column too, on the particle preset's wavelengths and angles — so that a
        column-to-column difference is never a difference of spectral or angular sampling
        (at `preview`, 40-nm steps alone move a saturated film's colour by several ΔE)."""
        molecular = particles.strip().lower() in MOLECULAR_WORDS
        wavelengths, sigma = figure_grids(self.accuracy)
        kw = {"wavelengths_nm": wavelengths, "sigma_rad": sigma,
              **{k: v for k, v in self.overrides if k in GRID_OPTIONS or not molecular}}
        kw.update(self.model.request_options())
        if molecular:           # the preset gives its grids only: the film has no wave settings
            return table_request(ink, particles, **kw)
        return table_request(ink, particles, accuracy=self.accuracy, **kw)

    def particle_only(self) -> list[str]:
        """The overrides (as CLI options) that only particle cells use: ignored by a figure whose
        every column is molecular."""
        return [OPTION.get(k, k) for k, _ in self.overrides if k not in GRID_OPTIONS]

    @property
    def label(self) -> str:
        """'preview' or 'preview (grid=16x16x8, 4 λ 400–700 nm, …)' for the CSV and captions."""
        if not self.overrides:
            return self.accuracy
        return f"{self.accuracy} ({', '.join(_describe(k, v) for k, v in self.overrides)})"

    @property
    def caption(self) -> str:
        """The model and the colour measurement, for captions and reports."""
        return (f"model {self.model.name} ({self.model.description}); accuracy {self.label}; "
                f"colour measured {self.colour_measurement.label} ({self.colour_measurement.geometry.description})")


def _describe(name: str, value) -> str:
    if name == "wavelengths_nm":
        return f"{len(value)} λ {value[0]:g}–{value[-1]:g} nm"
    if name == "sigma_rad":
        return f"{len(value)} incidence angles"
    if isinstance(value, tuple):
        return f"{name}={'x'.join(map(str, value))}"
    return f"{name}={value}"


@dataclass(frozen=True)
class CellPlan:
    row: Row
    column: Column
    i: int                               # row index in the figure
    j: int                               # column index
    request: TableRequest | None         # None: the cell could not be planned (error says why)
    tilt_deg: float | None = None        # across cylinders: the orientation spread used
    error: str | None = None

    @property
    def particles(self) -> str:
        return self.request.particles_label if self.request is not None else self.column.particles


@dataclass(frozen=True)
class CellResult:
    plan: CellPlan
    table: InkTable | None
    built: bool = False
    seconds: float = 0.0
    error: str | None = None
    estimate_s: float = field(default=0.0)

    @property
    def ok(self) -> bool:
        return self.table is not None


def failure_reason(exc: BaseException) -> str:
    """Why a cell failed, in one line: the message of a refusal (bad input, a cell that cannot
    exist, a file problem), the exception's class too for anything else (a bug)."""
    text = " ".join(str(exc).split())
    if text and isinstance(exc, (ValueError, OSError)):
        return text
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def across_particles(row: Row, column: Column, settings: FigureSettings) -> tuple[str, float | None]:
    """The particle spec of a cylinders-across-the-layer cell, and the tilt it uses."""
    from solver.geometry import aligned_column_bound, reachable_limit, smallest_tilt_reaching
    from solver.table.wave_tier import layer_spec

    layer = layer_spec(settings.request(row.ink, column.particles))
    tilt = smallest_tilt_reaching(layer, TILTS_DEG)
    if tilt is None:
        bound = aligned_column_bound(layer)
        why = (f": one per column, even hexagonally packed they fill {100 * bound:.1f} %, the packer reaches "
               f"{100 * reachable_limit(layer):.1f} %, and every spread up to {TILTS_DEG[-1]:g}° lowers it"
               if bound is not None else "")
        raise ValueError(f"{column.particles} cannot hold {row.label} across a "
                         f"{layer.thickness_nm:g}-nm layer{why}")
    tilt = float(tilt)
    return (column.particles if tilt == 0 else f"{column.particles}:tilt={tilt:g}"), tilt


def plan_cells(rows, columns, settings: FigureSettings) -> list[CellPlan]:
    """One plan per cell, rows first.  Errors of the settings themselves are raised (bad input);
    a cell that cannot be planned (e.g. no tilt reaches its concentration) is kept as failed."""
    for probe in (settings.request("Y7.5+B7.5", "molecular"), settings.request("Y7.5+B7.5", "sphere:100")):
        # the settings are checked once, here, and the colour's needs against their grids
        settings.colour_measurement.check_grids(probe.grids.wavelengths_nm, probe.grids.sigma_rad,
                                                "the figure's tables")
    plans = []
    for i, row in enumerate(rows):
        for j, column in enumerate(columns):
            try:
                particles, tilt = (across_particles(row, column, settings) if column.across
                                   else (column.particles, None))
                plans.append(CellPlan(row, column, i, j, settings.request(row.ink, particles), tilt))
            except Exception as exc:               # noqa: BLE001 — recorded and drawn, never dropped
                plans.append(CellPlan(row, column, i, j, None, error=failure_reason(exc)))
    return plans


def estimates(plans, opts: BuildOptions) -> list:
    """What each cell's build needs (`preflight.Estimate`), None for a cached table or a failed
    plan; a cell whose grains an earlier cell (or the cache) has drawn is estimated without its
    geometry (solver/table/geometry_store.py).  The cells share one pool of workers
    (`make`), whose start the first particle cell carries."""
    from solver.table import geometry_store, preflight

    out, drawn, pool = [], set(), False
    for plan in plans:
        if plan.request is None or opts.cache.table_path(plan.request).exists():
            out.append(None)
            continue
        key = None if plan.request.molecular else geometry_store.key(plan.request, 0)
        out.append(preflight.estimate(plan.request, opts.workers, pool_running=pool,
                                      geometry_drawn=key is not None and (key in drawn or opts.cache.has_geometry(key))))
        drawn.add(key)
        pool = pool or not plan.request.molecular
    return out


def refuse_what_cannot_fit(figure: str, plans, ests, opts: BuildOptions) -> None:
    """Before any work: PreflightError when some cell's table cannot fit this machine (unless
    --force), naming how many and the first."""
    from solver.table import preflight

    if opts.force:
        return
    refused = []
    for plan, est in zip(plans, ests):
        problems = [] if est is None else preflight.limits_exceeded(est, plan.request, opts.workers, opts.cache.root)
        if problems:
            refused.append((plan, problems))
    if refused:
        plan, problems = refused[0]
        raise preflight.PreflightError(
            f"{figure}: {len(refused)} of {len(plans)} cells cannot fit this machine, refused before starting "
            f"(first: {plan.request.describe()}: {'; '.join(problems)}); use coarser settings, or --force to try anyway")


def build_cells(plans, opts: BuildOptions, seconds: list[float], progress: bool = True) -> list[CellResult]:
    """Build (or load) every planned table, in order; a failing cell is recorded and the run
    goes on.  The bar advances by each cell's estimate, so its ETA follows the estimate."""
    results = []
    bar = tqdm(total=max(sum(seconds), 1e-9), disable=None if progress else True, unit="s", unit_scale=True,
               desc="cells", bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}] {postfix}")
    try:
        for k, (plan, est) in enumerate(zip(plans, seconds)):
            bar.set_postfix_str(f"{k}/{len(plans)} cells, now {plan.row.spec} {plan.column.particles}")
            t0 = time.perf_counter()
            if plan.request is None:
                results.append(CellResult(plan, None, error=plan.error, estimate_s=est))
            else:
                try:
                    table, _, built = get_or_build(plan.request, opts)
                    results.append(CellResult(plan, table, built, time.perf_counter() - t0, estimate_s=est))
                except Exception as exc:           # noqa: BLE001 — a failed cell is drawn crossed out
                    log.warning("cell %s × %s failed: %s", plan.row.spec, plan.particles, failure_reason(exc))
                    results.append(CellResult(plan, None, False, time.perf_counter() - t0, failure_reason(exc), est))
            bar.update(est)
        bar.set_postfix_str(f"{len(plans)}/{len(plans)} cells")
    finally:
        bar.close()
    return results
