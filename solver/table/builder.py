"""Build a table for a request: pick the tier, run the work units (cached, resumable), reduce.

    table, path, built = get_or_build(table_request("Y7.5+B7.5", "sphere:300"))

Nothing is computed twice: finished tables come from the content-addressed cache; the units of
an interrupted build (geometry per realization, solves per realization × λ, the tier probe)
are stored as they finish and reused; the probe's full solves are ordinary units of the full
tier, so they count toward the table when the full tier is chosen.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import host
from . import jackknife, preflight, spectral, tier_choice
from .cache import TableCache
from .executor import check_scheduler, default_workers, local_pool, run_units, usable_workers
from .meta import table_meta
from .request import RequestError, TableRequest
from .schema import InkTable
from .thinfilm_tier import request_film

log = logging.getLogger("inkbsdf.tables")
#: a build's first and last line ("computing table …", "table ready …"): what a command that builds
#: tables on the way (render, print) shows without -v (solver/apps/cli/logs.py)
BUILDS_LOGGER = "inkbsdf.tables.builds"
builds = logging.getLogger(BUILDS_LOGGER)
#: a build estimated under this many seconds (a molecular film: instant) logs its first and last
#: line with the other INFO lines, shown only with -v: a quiet command stays quiet
QUIET_BUILD_S = 1.0


@dataclass(frozen=True)
class BuildOptions:
    """How (not what) to build: execution only, never part of the cache key."""

    workers: int = field(default_factory=default_workers)   # local processes (1 = in this process)
    scheduler: str | None = None         # Dask scheduler address: run the units there instead
    progress: bool = True
    cache: TableCache = field(default_factory=TableCache.default)
    pool: object = field(default=None, compare=False)   # a running executor.local_pool to reuse
    force: bool = False                  # build even what the preflight estimate says cannot fit

    def __post_init__(self):
        if not isinstance(self.workers, (int, np.integer)) or isinstance(self.workers, bool) or self.workers < 1:
            raise RequestError(f"--workers must be an integer ≥ 1, got {self.workers!r}")

    @property
    def threads(self) -> int | None:
        """FFT threads per unit: the cores shared among the local workers (None: the default)."""
        return max(1, host.cpu_count() // self.workers) if self.workers > 1 else None


@dataclass
class _Timer:
    stages: dict = field(default_factory=dict)

    def add(self, stage: str, seconds: float) -> None:
        self.stages[stage] = self.stages.get(stage, 0.0) + seconds


def _voxels_to_arrays(vox) -> dict:
    return {"fractions": vox.fractions, "materials": np.array(vox.materials),
            "period_nm": np.asarray(vox.period_nm, float), "z_range_nm": np.asarray(vox.z_range_nm, float)}


def _voxels_from_arrays(a: dict):
    from ..geometry import VoxelFractions

    return VoxelFractions(materials=tuple(str(m) for m in a["materials"]), fractions=a["fractions"],
                          period_nm=tuple(a["period_nm"]), z_range_nm=tuple(a["z_range_nm"]))


def _cached_units(opts, count, load, store, make_unit, fn, desc):
    """Results of `count` units: load(i) → a stored result or None; the rest are computed (in
    parallel) and store(i, result) keeps each as it ends."""
    results = [load(i) for i in range(count)]
    todo = [i for i, r in enumerate(results) if r is None]
    if todo:
        log.info("%s: %d of %d units to compute (%d reused)", desc, len(todo), count, count - len(todo))
        fresh = run_units(fn, [make_unit(i) for i in todo], workers=opts.workers, scheduler=opts.scheduler,
                          desc=desc, on_result=lambda k, res: store(todo[k], res), progress=opts.progress,
                          pool=opts.pool)
        for k, i in enumerate(todo):
            results[i] = fresh[k]
    return results


def _geometry(request, opts, timer, realizations=None):
    """Voxel fractions of the realizations (all by default), shared through the cache with every
    table on the same grains (geometry_store.py)."""
    from . import geometry_store
    from .wave_tier import GeometryUnit, geometry_unit

    rs = list(range(request.wave.realizations) if realizations is None else realizations)
    keys = [geometry_store.key(request, r) for r in rs]

    read = []

    def load(i):
        arrays = opts.cache.load_geometry(keys[i])
        if arrays is None:
            return None
        read.append(i)
        return geometry_store.relabel(_voxels_from_arrays(arrays), request)

    t0 = time.perf_counter()
    out = _cached_units(opts, len(rs), load, lambda i, vox: opts.cache.store_geometry(keys[i], _voxels_to_arrays(vox)),
                        lambda i: GeometryUnit(request, rs[i]), geometry_unit, "geometry")
    if read:
        log.info("shared grains: %d of %d realizations read from the cache (drawn for another ink on the "
                 "same grains, or by an earlier build)", len(read), len(rs))
    timer.add("geometry", time.perf_counter() - t0)
    return out


def _solves(request, opts, timer, method, voxels, pairs, stage="solve"):
    """Solve units for (realization, λ index) pairs with the given method (timed as `stage`)."""
    from .wave_tier import SolveUnit, solve_unit

    names = [f"{method}_r{r}_l{li}" for r, li in pairs]
    t0 = time.perf_counter()
    out = _cached_units(opts, len(pairs), lambda i: opts.cache.load_part(request, names[i]),
                        lambda i, res: opts.cache.store_part(request, names[i], res),
                        lambda i: SolveUnit(request, pairs[i][0], pairs[i][1], voxels[pairs[i][0]], method,
                                            opts.threads),
                        solve_unit, f"solve ({method})")
    timer.add(stage, time.perf_counter() - t0)
    return out


def _film_table(request: TableRequest, tier: str, reason: str, timer: _Timer, extra=None) -> InkTable:
    film = request_film(request)
    errors = {"model": 0.0 if tier == "thin-film" else (extra or {}).get("tier_probe", {}).get(
        "deviation", {}).get("effective-medium"), "energy_sum_tol": 1e-9}
    return dataclasses.replace(film, meta=table_meta(request, tier, reason, timings_s=timer.stages,
                                                     extra={**(extra or {}), "errors": errors,
                                                            "mixing_rule": film.meta.get("mixing_rule")}))


@contextlib.contextmanager
def pooled(opts: BuildOptions):
    """`opts` with a process pool that lives for the whole block (one spawn for all the
    stages of a build, or for all the tables of a figure); unchanged when no local pool is
    wanted (one worker, Dask) or one is running already."""
    if opts.pool is not None or opts.scheduler or usable_workers(opts.workers) <= 1:
        yield dataclasses.replace(opts, workers=1) if opts.pool is None and not opts.scheduler else opts
        return
    with local_pool(opts.workers) as pool:
        yield dataclasses.replace(opts, pool=pool)


def build_table(request: TableRequest, opts: BuildOptions | None = None) -> InkTable:
    """Compute the table of a request (no lookup of the finished table; parts are reused)."""
    opts = opts or BuildOptions()
    if request.molecular:
        return _film_table(request, "thin-film", "homogeneous layer: exact Airy (transfer-matrix) solution",
                           _Timer())
    with pooled(opts) as opts:
        return _build_wave(request, opts)


def _build_wave(request: TableRequest, opts: BuildOptions) -> InkTable:
    timer = _Timer()
    voxels = None
    tier, report = request.wave.tier, {}
    if tier == "auto":
        # the probe solves realization 0 (and 1 where 0 solves one polarisation); the other
        # workers draw the next realizations meanwhile (the rest only once a wave tier is
        # chosen: an effective-medium table needs none)
        from .wave_tier import probe_realizations
        probe_real = probe_realizations(request)
        voxels = _geometry(request, opts, timer, range(min(request.wave.realizations,
                                                           max(len(probe_real), usable_workers(opts.workers)))))
        pairs = [(r, li) for r in probe_real for li in tier_choice.probe_wavelength_indices(request)]
        full = _solves(request, opts, timer, "full", voxels, pairs, "tier_probe")
        born = _solves(request, opts, timer, "born", voxels, pairs, "tier_probe")
        tier, report = tier_choice.choose(request, full, born, [li for _, li in pairs],
                                          request.grids.solved_sigma_rad)
        log.info("tier for %s: %s (deviations from full solve: %s)", request.describe(), tier,
                 {k: round(v, 5) for k, v in report["deviation"].items()})
    reason = (f"measured: cheapest tier within tolerance {request.wave.tolerance:g}" if report
              else "requested explicitly")
    if tier == "effective-medium":
        return _film_table(request, tier, reason, timer, {"tier_probe": report})
    if voxels is None:
        voxels = _geometry(request, opts, timer)
    method = "born" if tier == "born" else "full"
    solved, nr = list(request.solved_wavelength_indices), request.wave.realizations
    units: dict[tuple[int, int], object] = {}            # (realization, wavelength index) → unit
    while True:
        voxels = voxels + _geometry(request, opts, timer, range(len(voxels), nr))
        todo = [(r, li) for r in range(nr) for li in solved if (r, li) not in units]
        units.update(zip(todo, _solves(request, opts, timer, method, voxels, todo)))
        t0 = time.perf_counter()
        table, broken = _reduce(request, tier, reason, report, units, solved, nr, timer)
        timer.add("reduce", time.perf_counter() - t0)
        if broken:
            # the guide film's bands are sharper than the solved wavelengths resolve: what the
            # interpolation cannot give is solved, never passed off (docs/tables.md, "Wavelength stride")
            log.info("film-guided wavelengths break energy at %s nm: solving them",
                     [round(float(request.grids.wavelengths_nm[i])) for i in broken])
            solved = sorted(set(solved) | set(broken))
            continue
        more = _more_realizations(request, table, nr)
        if more == nr:
            break
        log.info("standard error %s above --target-se %g with %d realizations: going on to %d",
                 _worst_se(table), request.wave.target_se, nr, more)
        nr = more
    table.meta["timings_s"] = dict(timer.stages)
    return table


def _reduce(request, tier, reason, report, units, solved, nr, timer):
    """(table, broken): the ensemble of the solved wavelengths, film-guided in between, holding
    the same of each leave-one-out ensemble (jackknife.py; N ≥ 2); broken: the unsolved
    wavelengths whose guided values break energy (spectral.py)."""
    from .wave_ensemble import reduce_units
    from .wave_tier import realization_seed, samples

    # the solved wavelengths' own request (grids only: units index the full request's wavelengths)
    coarse_request = request.with_grids(wavelengths_nm=tuple(request.grids.wavelengths_nm[i] for i in solved))
    extra = {"tier_probe": report, "realizations_used": nr}
    refined = len(solved) < len(request.grids.wavelengths_nm)
    if refined:
        extra["solved_wavelengths_nm"] = list(coarse_request.grids.wavelengths_nm)
    groups = [sorted({p for _, p in samples(request, r)}) for r in range(nr)]
    if len({tuple(g) for g in groups}) > 1:             # TE and TM cells: the jackknife's strata
        extra["jackknife_groups"] = [int(g[0]) for g in groups]
    meta = table_meta(request, tier, reason, seeds=[realization_seed(request, r) for r in range(nr)],
                      timings_s=timer.stages, extra=extra)
    film = spectral.guide_film(request) if refined else None

    def reduce(realizations: list) -> InkTable:
        table = reduce_units(coarse_request, realizations, copy.deepcopy(meta))
        return spectral.refine(table, film, tuple(solved)) if refined else table

    table = jackknife.reduce_with_replicas(reduce, [[units[r, li] for li in solved] for r in range(nr)])
    return table, spectral.unsolved_breaking_energy(table, solved) if refined else []


def _worst_se(table: InkTable) -> float | None:
    values = [table.meta["errors"].get(f"{k}_se_max") for k in ("Rbar", "Tbar")]
    return None if None in values else max(values)


def _more_realizations(request: TableRequest, table: InkTable, done: int) -> int:
    """How many realizations the table needs for --target-se (`done` when it is met, not
    asked, or the cap is reached): N·(SE/target)², at least one more."""
    target = request.wave.target_se
    if target is None or done >= request.wave.max_realizations:
        return done
    se = _worst_se(table)
    if se is not None and se <= target:
        return done
    wanted = done + 1 if se is None else math.ceil(done * (se / target) ** 2)
    return min(request.wave.max_realizations, max(done + 1, wanted))


def get_or_build(request: TableRequest, opts: BuildOptions | None = None) -> tuple[InkTable, str, bool]:
    """The cached table for the request, building (and caching) it when missing.

    Returns (table, path, built) — built is False on a cache hit (nothing computed)."""
    opts = opts or BuildOptions()
    if opts.cache.root.is_dir():
        table = opts.cache.load(request)        # a read-only cache serves what it holds
    else:
        table = None
    if table is None:
        opts.cache.check()                      # building: the cache must be writable
        est = preflight.check(request, opts.workers, opts.cache.root, force=opts.force).seconds
        if opts.scheduler and not request.molecular:
            check_scheduler(opts.scheduler)
        opts.cache.sweep()
        with opts.cache.lock(request):          # one builder per table, across threads and processes
            table = opts.cache.load(request)    # built meanwhile by whoever held the lock?
            if table is None:
                say = builds.info if est >= QUIET_BUILD_S else log.info
                say("computing table: %s%s", request.describe(), "" if est < QUIET_BUILD_S else
                    f" (estimated {preflight.duration(est)} for a quiet machine)")
                t0 = time.perf_counter()
                table = build_table(request, opts)
                path = opts.cache.store(request, table)
                say("table ready in %.1f s: %s", time.perf_counter() - t0, path)
                return table, str(path), True
    log.info("cache hit for %s", request.describe())
    return table, str(opts.cache.table_path(request)), False
