"""Before any work: estimate what a table build needs, refuse what cannot fit this machine.

A build that cannot finish must say so in one line before it starts, not die of a MemoryError
after minutes: the estimate covers the table's size (disk, and the memory of assembling it),
the peak memory of one worker (geometry, or one wave solve), the grains per realization and
the wall time.  What does not fit is refused with the estimate and the limit in the message
(`force=True`, `--force` at the CLI, for those who know better); what will take long is logged
as a warning with the estimate.  The models are simple fits to measurements
(`python -m benchmarks.bench_tables` prints the measured values beside these estimates).
"""

from __future__ import annotations

import logging
import math
import shutil
from dataclasses import dataclass
from pathlib import Path

from .. import host
from .request import TableRequest

log = logging.getLogger("inkbsdf.tables")

#: wave solve: fixed interpreter + libraries, and bytes per voxel (operator, Krylov basis, FFT
#: buffers) — fitted to 160 MB at 64×64×32 and 735 MB at 128×128×64 (docs/tables.md)
SOLVE_BASE_BYTES = 80e6
SOLVE_BYTES_PER_VOXEL = 620.0
#: wave solve CPU time per operator application per voxel·log2(voxels), everything of a table
#: unit included (preparation, orders, energy), and applications per solve: measured per unit
#: (solve_unit, one FFT thread, Y7.5+B7.5 300-nm spheres at 580 nm, 14 solves of 13.4
#: applications): 12.2 ms per application at 64×64×32, 4.7 ms at 48×48×24 (5.5e-9 s per
#: voxel·log2 voxel on this project's 2-core VM, under load, yardstick 1.6 s; docs/tables.md)
SECONDS_PER_VOXEL_LOG = 5.5e-9
APPLICATIONS_PER_SOLVE = 14
#: … at the solver tolerance REFERENCE_TOL; per decade of looser tolerance 27 % fewer: R15 with
#: 300-nm spheres, default grid, 616 solves: 13.9 / 12.0 / 10.1 applications at 1e-3 / 3e-3 /
#: 1e-2 (0.87, 0.73 of 1e-3); four cells' units at 3e-3: 0.85–0.91 (docs/tables.md, "The
#: default preset")
REFERENCE_TOL = 1e-3
APPLICATIONS_TOL_SLOPE = 0.27
#: a rough top's solve (above and below: both counted) against the flat layer's, in CPU time:
#: with the layered preconditioner (solver/wave/layered.py) 35–40 applications per solve pair
#: against 2 × 12.8–18.1 for the flat twin, plus the preconditioner's set-up and one more
#: lateral FFT per application (R15, 300-nm spheres, 500 and 740 nm, 48×48×24 and 64×64×32:
#: unit CPU 3.0–3.2× the flat twin's, i.e. 1.5–1.6 per solve); a whole rough-top cell (R15,
#: default preset, 11 wavelengths) took 1.4× more relative to its flat twin than that
#: (`bench_figures sample-quick`, docs/figures.md): 2.2.  Kept when a rough top's TM got its mean
#: profile (wave_tier.tm_faces; its cells 1.52× slower: the `default` Fig. 7's rough cells, CSV
#: seconds, 578 → 878 s, 2026-12-03): the whole figure then took 53.7 min against this
#: estimate's 56.4 (0.95; 0.90 before), where 3.3 would have estimated 66 min
ROUGH_TOP_SOLVE_FACTOR = 2.2
#: measured/modelled wall time of the preview Fig. 7's particle cells (326 tables built in one
#: pool, default model, empty cache, 2 workers) on this project's quiet 2-core VM, yardstick
#: 0.38–0.43 s, 2026-12-02: 1795 s against the model's 2235 s (per column 0.58–1.27; the
#: constants above were fitted under load).  Applied to every time estimate: they are for a
#: quiet machine (`python -m benchmarks.bench_figures sample` prints measured/estimate per column)
QUIET_MACHINE_FACTOR = 0.80
#: starting a local pool (spawned workers importing the solver), seconds
POOL_START_S = 2.0
#: tier auto: the probe solves realization 0 at this many wavelengths fully and by Born
#: (tier_choice.probe_wavelength_indices); a Born solve costs one application plus the solve's
#: fixed work (preparation, orders, energy: ≈ 2 applications' worth in the unit profile)
PROBE_WAVELENGTHS = 3
BORN_SOLVE_APPLICATIONS = 3.0
#: the share of tier-auto cells that end with the full solve, by the grains' (volume-equivalent)
#: diameter: none up to FULL_FROM_NM, all from FULL_ALL_NM, linear between; rough tops always.
#: Measured on the preview Fig. 7 (docs/data/fig7_preview.csv, column `tier`, 21 rows each):
#: 30 nm 0/21, 100 nm 1–4/21, 200 nm 6–12/21, 300 nm 17–20/21, 450 nm and rough tops 21/21
FULL_FROM_NM, FULL_ALL_NM = 100.0, 300.0
#: thin-film tier: seconds per (wavelength × angle), measured 0.2 s for 41 × 1000
MOLECULAR_SECONDS_PER_SAMPLE = 5e-6
#: grains smaller than this share of a voxel are only an average of the voxels they touch
UNRESOLVED_GRAIN_SHARE = 0.5
#: a realization's geometry expected to take longer than this (s) is announced with its
#: estimate: the geometry bar moves only when a whole realization is done
GEOMETRY_NOTE_S = 20.0
#: a build warns when it is expected to take longer than this
LONG_BUILD_S = 600.0
#: share of the available memory / free disk a build may plan to use
MEMORY_SHARE, DISK_SHARE = 0.8, 0.9


class PreflightError(ValueError):
    """A build refused before it starts: the estimate and the limit are in the message."""


@dataclass(frozen=True)
class Estimate:
    table_bytes: int          # the finished table (uncompressed)
    worker_bytes: int         # peak memory of one worker process
    grains: int               # grains per realization (0 for a molecular ink)
    solves: int               # wave solves of the whole build
    seconds: float            # rough wall time with the given workers
    geometry_seconds: float = 0.0   # one realization's geometry (generate + voxelize)

    def describe(self) -> str:
        parts = [f"table {_size(self.table_bytes)}", f"{_size(self.worker_bytes)} per worker"]
        if self.grains:
            parts.append(f"{self.grains:,} grains per cell")
        if self.solves:
            parts.append(f"{self.solves:,} wave solves")
        parts.append(f"≈ {duration(self.seconds)}")
        return ", ".join(parts)


def _size(n: float) -> str:
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.1f} {unit}"
    return f"{int(n)} B"


def duration(s: float) -> str:
    """'12 s', '4.5 min', '1.1 h': a time in seconds as the estimates and the figures say it."""
    if s >= 3600:
        return f"{s / 3600:.1f} h"
    return f"{s / 60:.1f} min" if s >= 60 else f"{s:.0f} s"


def estimate(request: TableRequest, workers: int = 1, geometry_drawn: bool = False,
             pool_running: bool = False) -> Estimate:
    """What building the request needs (pure arithmetic: no geometry, no solve).
    geometry_drawn: its realizations are in the cache already (another ink on the same grains
    drew them, geometry_store.py), so their time is not counted.  pool_running: the workers
    are started already (a figure's cells share one pool), so their start is not counted."""
    g = request.grids
    nl, ns = len(g.wavelengths_nm), len(g.sigma_rad)
    columns = 5 * nl * ns * 8
    if request.molecular:
        table = nl * ns * 2 * 2 * 8 + columns
        work = 40e6 + 6 * table
        return Estimate(int(table), int(work), 0, 0, MOLECULAR_SECONDS_PER_SAMPLE * nl * ns)
    from ..geometry import geometry_cost
    from .wave_tier import layer_spec, probe_realizations, solves_per_incidence

    w = request.wave
    table = 2 * nl * ns * ns * g.dphi_count * 8 + 2 * columns          # R and its errors
    voxels = math.prod(w.grid)
    geoms = [geometry_cost(layer_spec(request, i), w.grid)
             for i, layer in enumerate(request.layers) if layer.particles is not None]
    grains = sum(c.grains for c in geoms)
    geometry_s = sum(c.seconds for c in geoms)
    geometry_bytes = max((c.peak_bytes for c in geoms), default=0)
    solve_bytes = SOLVE_BASE_BYTES + SOLVE_BYTES_PER_VOXEL * voxels
    solved_wl = len(request.solved_wavelength_indices)          # the rest are film-guided (spectral.py)
    per_incidence = int(g.solved_mask.sum()) * solved_wl
    solves = per_incidence * solves_per_incidence(request)
    per_solve = solve_seconds(w.grid, w.solver_tol) * (ROUGH_TOP_SOLVE_FACTOR if request.has_rough_top else 1.0)
    solve_s = solves * per_solve
    if w.tier in ("auto", "born"):
        born = solves * solve_seconds(w.grid) * BORN_SOLVE_APPLICATIONS / APPLICATIONS_PER_SOLVE
        probe = (per_incidence * min(PROBE_WAVELENGTHS, solved_wl) / solved_wl       # probe solves
                 * solves_per_incidence(request, len(probe_realizations(request))))
        if w.tier == "born":
            solve_s = born
        else:
            p = full_tier_share(request)
            solve_s = p * solve_s + (1 - p) * (born + probe * per_solve) + probe * per_solve * (
                BORN_SOLVE_APPLICATIONS / APPLICATIONS_PER_SOLVE)
    seconds = QUIET_MACHINE_FACTOR * ((0.0 if geometry_drawn else geometry_s * w.realizations) + solve_s) / max(1, workers) \
        + (POOL_START_S if workers > 1 and not pool_running else 0.0)
    return Estimate(int(table), int(max(solve_bytes, geometry_bytes) + 3 * table), int(grains),
                    int(solves), float(seconds), float(QUIET_MACHINE_FACTOR * geometry_s))


def full_tier_share(request: TableRequest) -> float:
    """The expected share of tier auto ending with the full solve (FULL_FROM_NM, FULL_ALL_NM):
    the largest over the request's particle layers; 1 with a rough top."""
    if request.has_rough_top:
        return 1.0
    sizes = [layer.particles.diameter_nm for layer in request.layers if layer.particles is not None]
    d = max(sizes, default=0.0)
    return float(min(1.0, max(0.0, (d - FULL_FROM_NM) / (FULL_ALL_NM - FULL_FROM_NM))))


def solve_seconds(grid: tuple[int, int, int], solver_tol: float = REFERENCE_TOL) -> float:
    """Rough CPU seconds of one wave solve on this grid at this solver tolerance (applications
    × cost of one)."""
    voxels = math.prod(grid)
    return applications(solver_tol) * SECONDS_PER_VOXEL_LOG * voxels * math.log2(max(voxels, 2))


def applications(solver_tol: float) -> float:
    """Operator applications per solve at the solver tolerance (APPLICATIONS_TOL_SLOPE)."""
    return APPLICATIONS_PER_SOLVE * max(0.3, 1.0 - APPLICATIONS_TOL_SLOPE * math.log10(solver_tol / REFERENCE_TOL))


def _warn_unresolved(request: TableRequest) -> None:
    """Grains much smaller than a voxel cost geometry time and give the voxel average only."""
    if request.molecular:
        return
    w = request.wave
    voxel_nm = min(w.cell_nm / w.grid[0], w.cell_nm / w.grid[1], request.thickness_nm / w.grid[2])
    for layer in request.layers:
        if layer.particles is not None:
            warn_unresolved(request.describe(), layer.particles.diameter_nm, voxel_nm,
                            "the wave tier sees only their average (a smooth mix, as --particles molecular "
                            "gives at no cost)")


def warn_unresolved(what: str, diameter_nm: float, voxel_nm: float, consequence: str) -> None:
    """Warn when grains of `diameter_nm` are much smaller than the voxels (UNRESOLVED_GRAIN_SHARE)."""
    if diameter_nm < UNRESOLVED_GRAIN_SHARE * voxel_nm:
        log.warning("%s: grains of %g nm are much smaller than the %.0f-nm voxels: %s",
                    what, diameter_nm, voxel_nm, consequence)


def memory_exceeded(need_bytes: float, how: str = "") -> str | None:
    """The problem when `need_bytes` exceed the share of this machine's available memory a
    command may plan to use (MEMORY_SHARE), else None; `how`: how the need adds up."""
    memory = host.available_memory_bytes() * MEMORY_SHARE
    if need_bytes <= memory:
        return None
    return f"needs ≈ {_size(need_bytes)} of memory{f' ({how})' if how else ''}, this machine has {_size(memory)} available"


def limits_exceeded(est: Estimate, request: TableRequest, workers: int, cache_root: Path) -> list[str]:
    """What of this machine the estimated build would exceed (memory, the cache's disk); empty
    when it fits."""
    count = max(1, workers if not request.molecular else 1)
    memory = memory_exceeded(est.worker_bytes * count, f"{count} worker(s) × {_size(est.worker_bytes)}")
    problems = [memory] if memory else []
    try:
        free = shutil.disk_usage(cache_root if cache_root.exists() else cache_root.parent).free * DISK_SHARE
    except OSError:
        free = math.inf
    if est.table_bytes > free:
        problems.append(f"the table is ≈ {_size(est.table_bytes)}, the cache's disk has {_size(free)} free")
    return problems


def check(request: TableRequest, workers: int, cache_root: Path, *, force: bool = False) -> Estimate:
    """Refuse what cannot fit (unless forced), warn about what will take long; return the estimate."""
    est = estimate(request, workers)
    problems = limits_exceeded(est, request, workers, cache_root)
    if problems and not force:
        raise PreflightError(f"{request.describe()}: refused before starting: " + "; ".join(problems)
                             + " (estimate: " + est.describe() + "; use coarser settings, or --force to try anyway)")
    _warn_unresolved(request)
    if est.geometry_seconds > GEOMETRY_NOTE_S:
        log.info("geometry: ≈ %.0f s per realization (estimate: %s grains), %d realization(s) on %d worker(s)",
                 est.geometry_seconds, f"{est.grains:,}", request.wave.realizations, workers)
    if est.seconds > LONG_BUILD_S:
        log.warning("%s will take long: %s", request.describe(), est.describe())
    return est


#: how `ink-tables geometry` makes a cell cheaper (its own options)
GEOMETRY_FIX = "use a coarser --grid, a smaller --cell or --thickness or larger grains (--particles)"


def check_geometry(layer, grid: tuple[int, int, int], *, force: bool = False):
    """`ink-tables geometry`'s preflight, the build's limits for one cell (geometry.cost): refuse
    what cannot fit the memory (unless forced), warn about grains the voxels do not resolve and
    a long generation, announce one that takes a while; return the GeometryCost."""
    from ..geometry import geometry_cost

    nx, ny, nz = grid
    what = (f"{layer.ink.label} {layer.particles.label} H={layer.thickness_nm:g} nm, cell "
            f"{layer.cell_nm[0]:g}×{layer.cell_nm[1]:g} nm, grid {nx}×{ny}×{nz}")
    cost = geometry_cost(layer, grid)
    estimate_text = f"{cost.grains:,} grains, ≈ {duration(cost.seconds)}"
    problem = memory_exceeded(cost.peak_bytes)
    if problem and not force:
        raise PreflightError(f"{what}: refused before starting: {problem} (estimate: {estimate_text}; "
                             f"{GEOMETRY_FIX}, or --force to try anyway)")
    voxel_nm = min(layer.cell_nm[0] / nx, layer.cell_nm[1] / ny, layer.thickness_nm / nz)
    warn_unresolved(what, layer.particles.diameter_nm, voxel_nm,
                    "the voxels hold only their average (a finer --grid resolves them)")
    if cost.seconds > LONG_BUILD_S:
        log.warning("%s will take long: %s (%s)", what, estimate_text, GEOMETRY_FIX)
    elif cost.seconds > GEOMETRY_NOTE_S:
        log.info("geometry: ≈ %s (estimate: %s grains)", duration(cost.seconds), f"{cost.grains:,}")
    return cost
