"""Table pipeline: one particle-ink table at default accuracy, and what each knob costs.

    python -m benchmarks.bench_tables                    # everything (~8 min on 2 cores)
    python -m benchmarks.bench_tables --quick            # knob curves only (~1 min)
    python -m benchmarks.bench_tables --default-only     # the default table, old and new (~5 min)
    python -m benchmarks.bench_tables --control-variate  # the Born control-variate study (~1 min)
    python -m benchmarks.bench_tables --stride-curve     # film-guided wavelength stride (~3 min)
    python -m benchmarks.bench_tables --common-grains    # rows sharing grains: paired realizations (~1 min)
    python -m benchmarks.bench_tables --samples          # sample design: cells × azimuths (~5 min)
    python -m benchmarks.bench_tables --default-knobs    # the default's grid and solver tolerance (~25 min)

1. The default table (issue target: ≤ 60 s wall on this 2-core machine with max SE of Rbar and
   Tbar ≤ 0.011), old and new code side by side: Y7.5+B7.5, 300-nm spheres, seconds per stage
   (geometry, tier probe, solve, reduce), solves, applications, seconds per solve against its
   FFT floor, and the table's error estimates.
2. Accuracy-vs-time curves of the table knobs, each against a reference computed here:
   realizations (standard error of Rbar, Tbar, R_spec and the diffuse BRDF), grid resolution
   (deviation from a 128×128×64 reference), the wavelength step (CIELAB ΔE of the ink on paper
   vs 1-nm sampling, thin film) and the number of incidence angles (interpolation error of the
   directional albedo, thin film).  Numbers on stdout, plot in out/bench/tables_accuracy_time.png.
4. The wavelength stride (film-guided refinement, solver/table/spectral.py): the default ink on
   a 10-nm grid solved at every wavelength is the reference; strides k solve every k-th and
   interpolate the difference to the exact film — max |Δ| of the columns and ΔE2000 of the ink
   on paper (45:0/D50) against the reference, beside plain linear interpolation of the spectrum
   and today's 20-nm grid (docs/tables.md, "Wavelength stride").
3. The Born solves as a control variate (tried, not built): correlation with the full solves,
   cost, and the two-phase-sampling gain at equal cost (docs/tables.md).
5. The sample design (--samples): variance components of the ensemble (between cells, between
   azimuths of one cell, the TE–TM covariance of a cell) and the standard error of each design
   (realizations × azimuths; one azimuth alternates TE and TM over the cells) relative to the
   former default 4 × 2 (docs/tables.md, "Samples: one cell per solve").
6. The default's grid and solver tolerance (--default-knobs): ΔE2000 of each value against the
   finest on cells across Fig. 7's columns (same seeds), applications and retried solves.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from solver.table.builder import BuildOptions
from solver.table.executor import default_workers
from solver.table.cache import TableCache
from solver.table.evaluate import directional_albedo
from solver.table.request import TableRequest, table_request
from solver.table.thinfilm_tier import request_film
from solver.table.wave_tier import GeometryUnit, SolveUnit, geometry_unit, solve_unit

from .baseline import PREVIOUS_ROUND, ROOT, extract, run_python

OUT = Path("out/bench")


def colour(table) -> np.ndarray:
    """CIELAB of the ink on paper (the figures' default measurement, 45:0/D50/2°)."""
    from solver.colour.measurement import DEFAULT
    from solver.paper import PAPER_ALBEDO

    return DEFAULT.lab(table, PAPER_ALBEDO)
INK, PARTICLES = "Y7.5+B7.5", "sphere:300"


def _options(workers: int = 1) -> BuildOptions:
    return BuildOptions(workers=workers, progress=True, cache=TableCache(Path(tempfile.mkdtemp(prefix="bench_"))))


def _build_cli(tree: Path, cache: Path, out: Path, workers: int) -> float:
    """Wall seconds of `ink-tables build` of the default particle table from an empty cache,
    run with the sources of `tree`."""
    t0 = time.perf_counter()
    run_python(tree, ["-m", "solver.apps.cli", "build", "--ink", INK, "--particles", PARTICLES, "--workers",
                      str(workers), "--cache", str(cache), "--no-progress", "-o", str(out)],
               capture_output=True)
    return time.perf_counter() - t0


class _FFTOwner:
    """What fft_floor reads off an operator: its FFT backend."""

    def __init__(self, fft):
        self.fft = fft


def default_table(workers: int, baseline: str | None = PREVIOUS_ROUND) -> dict:
    """The issue's target: the default particle table in ≤ 60 s wall on 2 cores, timed side by
    side with the previous round's code, with its stages, solves and error bars."""
    from solver.table import read_table

    from solver.wave.fftback import DEFAULT_FFT, get_fft

    from .wave_reference import fft_floor

    req = table_request(INK, PARTICLES)
    print(f"default table: {req.describe()}, tier auto, {workers} worker(s)")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        old = None
        if baseline:
            tree = extract(baseline, tmp / "old")
            if tree is not None:
                old = _build_cli(tree, tmp / "old_cache", tmp / "old.npz", workers)
        new = _build_cli(ROOT, tmp / "new_cache", tmp / "new.npz", workers)
        table = read_table(tmp / "new.npz")
    meta = table.meta
    stats, errors = meta["solver_stats"], meta["errors"]
    if old is not None:
        print(f"  wall: previous round ({baseline}) {old:.0f} s, now {new:.0f} s: {old / new:.1f}× faster "
              f"(target ≤ 60 s)")
    else:
        print(f"  wall: {new:.0f} s (target ≤ 60 s)")
    from solver.table import preflight

    from .bench_fresh import YARDSTICK, yardstick

    est = preflight.estimate(req, workers)
    print(f"  preflight estimate {est.seconds:.0f} s for {est.solves} solves: measured/estimate "
          f"{new / est.seconds:.2f} (aim: within ±30 %); yardstick {yardstick(YARDSTICK):.2f} s")
    print("  stages (s): " + ", ".join(f"{k} {v:.1f}" for k, v in meta["timings_s"].items()))
    solves, apps = stats["solves"], stats["applications_mean"]
    per_solve = stats["solve_seconds_total"] / max(solves, 1)
    # the transforms the table's solves perform: the default backend's lateral pairs (one thread)
    floor = fft_floor(req.wave.grid, 1, op=_FFTOwner(get_fft(DEFAULT_FFT, 1))) * apps
    print(f"  {solves} table solves (+ the tier probe's), {apps:.1f} operator applications per solve; "
          f"{per_solve:.3f} s per solve in a worker against {floor:.3f} s for the FFTs it performs "
          f"({per_solve / floor:.1f}×)")
    print("  tier probe deviations from the full solve: "
          + ", ".join(f"{k} {v:.4f}" for k, v in meta["tier_probe"].get("deviation", {}).items()))
    print(f"  max standard error: Rbar {errors['Rbar_se_max']:.4f}, Tbar {errors['Tbar_se_max']:.4f}, "
          f"R_spec {errors['R_spec_se_max']:.4f} (target ≤ 0.011); energy closure {errors['energy_closure_max']:.1e}")
    return {"old_s": old, "new_s": new, "table": table}


def _unit_summary(req: TableRequest, realization: int, wavelength_index: int) -> tuple[np.ndarray, float]:
    """Azimuth-mean (Rbar, Tbar, |α00|²) per σ of one realization at one λ, and its seconds."""
    t0 = time.perf_counter()
    vox = geometry_unit(GeometryUnit(req, realization))
    u = solve_unit(SolveUnit(req, realization, wavelength_index, vox))
    vals = np.stack([u["Rbar"].mean(-1), u["Tbar"].mean(-1), (np.abs(u["alpha00"]) ** 2).mean(-1)])
    return vals, time.perf_counter() - t0


def realizations_curve(wavelengths=(450.0, 550.0, 650.0), max_n: int = 8) -> list[tuple]:
    """Standard error of the table columns vs the number of realizations (and its cost)."""
    req = table_request(INK, PARTICLES, wavelengths_nm=wavelengths, realizations=max_n,
                       sigma_rad=tuple(np.radians([0, 30, 60, 90])))
    samples, seconds = [], []
    for r in range(max_n):
        per_l = [_unit_summary(req, r, li) for li in range(len(wavelengths))]
        samples.append(np.stack([v for v, _ in per_l]))
        seconds.append(sum(s for _, s in per_l))
    samples = np.asarray(samples)                      # [N, λ, quantity, σ]
    spread = samples.std(axis=0, ddof=1)
    print("realizations knob (Y7.5+B7.5 300 nm, 3 λ × 3 σ, 2 azimuths; SE = σ_sample/√N):")
    rows = []
    for n in (1, 2, 4, 8):
        if n > max_n:
            break
        se = float(np.max(spread / np.sqrt(n)))
        cost = float(np.mean(seconds) * n) * 21 / len(wavelengths) * 7 / 3
        rows.append((n, se, cost))
        print(f"  N={n}: max SE {se:.4f}   estimated full-table solve time {cost / 60:.1f} min")
    return rows


def grid_curve(wavelengths=(450.0, 650.0)) -> list[tuple]:
    """Deviation of one realization's columns from a 128×128×64 reference vs the grid's cost."""
    grids = [(32, 32, 16), (48, 48, 24), (64, 64, 32), (96, 96, 48), (128, 128, 64)]
    results = {}
    for g in grids:
        req = table_request(INK, PARTICLES, wavelengths_nm=wavelengths, grid=g, realizations=1,
                           azimuths=1, sigma_rad=tuple(np.radians([0, 45, 90])))
        per_l = [_unit_summary(req, 0, li) for li in range(len(wavelengths))]
        results[g] = (np.stack([v for v, _ in per_l]), sum(s for _, s in per_l))
    ref = results[grids[-1]][0]
    print("grid knob (same realization, 2 λ × 2 σ; deviation in Rbar, Tbar, R_spec from 128×128×64):")
    rows = []
    for g in grids[:-1]:
        err = float(np.max(np.abs(results[g][0] - ref)))
        rows.append((g, err, results[g][1]))
        print(f"  {g[0]}×{g[1]}×{g[2]}: max deviation {err:.4f}   {results[g][1]:.1f} s for 4 solves")
    return rows


def born_control_study(wavelengths=(420.0, 460.0, 500.0, 600.0), n: int = 8) -> None:
    """Would the Born solves (1 operator application) make a control variate for the full ones?
    Per realization and cell (λ, σ) the azimuth-mean Tbar of both, their correlation ρ and the
    optimal coefficient β = cov/var(Born); CPU seconds of a unit of each; and what two-phase
    sampling (R full + Born pairs, N − R Born-only realizations) would give at the best
    allocation, against plain realizations of the same cost (docs/tables.md, "Tried")."""
    req = table_request(INK, PARTICLES, wavelengths_nm=wavelengths, realizations=n)
    vals, cost = {"full": [], "born": []}, {"full": 0.0, "born": 0.0}
    for r in range(n):
        vox = geometry_unit(GeometryUnit(req, r))
        for m in vals:
            t0 = time.process_time()
            vals[m].append([solve_unit(SolveUnit(req, r, li, vox, m))["Tbar"].mean(-1) for li in range(len(wavelengths))])
            cost[m] += time.process_time() - t0
    f, b = np.asarray(vals["full"]), np.asarray(vals["born"])          # [r, λ, σ]
    cells = [(li, si) for li in range(f.shape[1]) for si in range(f.shape[2])]        # the solved σ
    rho = np.array([np.corrcoef(f[:, li, si], b[:, li, si])[0, 1] for li, si in cells])
    beta = np.array([np.cov(f[:, li, si], b[:, li, si])[0, 1] / b[:, li, si].var(ddof=1) for li, si in cells])
    ratio = cost["born"] / cost["full"]
    print(f"Born control variate ({INK} 300 nm, {n} realizations, {len(wavelengths)} λ × {f.shape[2]} σ, Tbar):")
    print(f"  correlation full–Born per cell: median {np.median(rho):.2f}, range {rho.min():.2f}–{rho.max():.2f}; "
          f"optimal β median {np.median(beta):.2f}, range {beta.min():.2f}–{beta.max():.2f}")
    print(f"  CPU per unit: full {cost['full'] / (n * len(wavelengths)):.2f} s, Born "
          f"{cost['born'] / (n * len(wavelengths)):.2f} s ({100 * ratio:.0f} %)")
    for q in (float(np.median(rho)), float(rho.min())):
        # two-phase sampling, optimal β: var = (1 − ρ²)/R + ρ²/N (units of one realization's
        # variance), cost R·1 + N·c (c: a Born unit's share); best N/R = √(ρ²/((1 − ρ²)c));
        # the budget of 4 plain realizations (variance 1/4)
        k = max(1.0, math.sqrt(q * q / ((1 - q * q) * ratio)))
        r_full = 4.0 / (1 + k * ratio)
        var = (1 - q * q) / r_full + q * q / (k * r_full)
        print(f"  ρ = {q:.2f}: best allocation N/R = {k:.1f}; at the cost of 4 plain realizations R = {r_full:.1f}, "
              f"N = {k * r_full:.1f}: standard error × {math.sqrt(var / 0.25):.2f}")


def common_grains_study(inks=("R15", "Y15"), wavelengths=(450.0, 550.0, 650.0), n: int = 4) -> None:
    """Common random numbers: rows of a figure at the same concentration share their grains (a
    realization's seed does not depend on the ink), so the difference between two such cells is
    estimated from paired realizations.  Per cell (λ, σ) the correlation of the two inks'
    per-realization Tbar and the variance of their difference against independent grains."""
    reqs = [table_request(ink, PARTICLES, wavelengths_nm=wavelengths, realizations=n, tier="full") for ink in inks]
    vals = []
    for req in reqs:
        per = []
        for r in range(n):
            vox = geometry_unit(GeometryUnit(req, r))
            per.append([solve_unit(SolveUnit(req, r, li, vox))["Tbar"].mean(-1) for li in range(len(wavelengths))])
        vals.append(np.asarray(per))                                   # [r, λ, σ]
    a, b = vals
    cells = [(li, si) for li in range(a.shape[1]) for si in range(a.shape[2])]
    rho = np.array([np.corrcoef(a[:, li, si], b[:, li, si])[0, 1] for li, si in cells])
    paired = np.array([np.var(a[:, li, si] - b[:, li, si], ddof=1) for li, si in cells])
    indep = np.array([np.var(a[:, li, si], ddof=1) + np.var(b[:, li, si], ddof=1) for li, si in cells])
    print(f"common grains ({' vs '.join(inks)}, {PARTICLES}, {n} realizations, {len(wavelengths)} λ × {a.shape[2]} σ, Tbar):")
    print(f"  correlation per cell: median {np.median(rho):.2f}, range {rho.min():.2f}–{rho.max():.2f}; variance of the "
          f"difference, paired / independent grains: median {np.median(paired / indep):.2f}, range "
          f"{np.min(paired / indep):.2f}–{np.max(paired / indep):.2f}")


def stride_curve(realizations: int = 2, workers: int | None = None, strides=(2, 3, 4, 6, 8)) -> list[tuple]:
    """Error and cost of the film-guided wavelength stride on the default ink (module doc, 4)."""
    import dataclasses

    from solver.colour.cie import delta_e2000
    from solver.colour.measurement import DEFAULT as MEASURE
    from solver.paper import PAPER_ALBEDO
    from solver.table import builder, spectral
    from solver.table.wave_ensemble import reduce_units

    fine_wl = tuple(float(w) for w in np.arange(380.0, 781.0, 10.0))
    req = table_request(INK, PARTICLES, wavelengths_nm=fine_wl, realizations=realizations, tier="full",
                        wavelength_stride=1)
    nl = len(fine_wl)
    opts = dataclasses.replace(_options(workers or default_workers()), progress=False)
    timer = builder._Timer()
    t0 = time.perf_counter()
    with builder.pooled(opts) as o:
        vox = builder._geometry(req, o, timer)
        flat = builder._solves(req, o, timer, "full", vox, [(r, li) for r in range(realizations) for li in range(nl)])
    wall = time.perf_counter() - t0
    units = [[flat[r * nl + li] for li in range(nl)] for r in range(realizations)]
    film = spectral.guide_film(req)
    ref = reduce_units(req, units, {"schema_version": 2, "polarisation": req.polarisation})
    lab = lambda t: MEASURE.lab(t, PAPER_ALBEDO)
    ref_lab = lab(ref)

    def coarse(solved):
        sub = req.with_grids(wavelengths_nm=tuple(fine_wl[i] for i in solved))
        return reduce_units(sub, [[u[i] for i in solved] for u in units], dict(ref.meta))

    def linear(c, solved):           # plain linear interpolation of every column (no film)
        zero = dataclasses.replace(film, **{k: np.zeros_like(getattr(film, k)) for k in
                                            ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below", "Rbar_s", "Rbar_p",
                                             "Tbar_s", "Tbar_p", "r_s", "r_p")})
        return spectral.refine(c, zero, solved)

    def errs(t):
        d = {k: float(np.max(np.abs(getattr(t, k) - getattr(ref, k)))) for k in ("Rbar", "Tbar", "R_spec")}
        return d, float(delta_e2000(lab(t), ref_lab))

    print(f"wavelength stride (film-guided; {INK} {PARTICLES}, default grid and solver, {realizations} "
          f"realization(s), reference: every 10 nm solved, {nl} λ, {wall:.0f} s wall on {opts.workers} worker(s); "
          f"max SE Rbar {float(ref.errors['Rbar'].max()):.4f}, Tbar {float(ref.errors['Tbar'].max()):.4f}):")
    rows = []
    # today's default: a 20-nm grid, every wavelength solved (colour integrated on 21 nodes)
    solved20 = spectral.solved_indices(nl, 2)
    t20 = coarse(solved20)
    l20 = MEASURE.lab(t20, PAPER_ALBEDO)
    print(f"  20-nm grid, all solved ({len(solved20)} λ, today's default): ΔE2000 {float(delta_e2000(l20, ref_lab)):.2f}")
    for k in strides:
        solved = spectral.solved_indices(nl, k)
        c = coarse(solved)
        guided, de_g = errs(spectral.refine(c, film, solved))
        plain, de_p = errs(linear(c, solved))
        rows.append((k, len(solved), guided, de_g, plain, de_p))
        print(f"  stride {k} ({len(solved)} of {nl} λ solved, {len(solved) / nl:.0%} of the solves): film-guided "
              f"ΔE2000 {de_g:.2f}, max |Δ| Rbar {guided['Rbar']:.4f} Tbar {guided['Tbar']:.4f} "
              f"R_spec {guided['R_spec']:.4f}; linear ΔE2000 {de_p:.2f}, Rbar {plain['Rbar']:.4f} "
              f"Tbar {plain['Tbar']:.4f}")
    k = 4
    solved = spectral.solved_indices(nl, k)
    c = coarse(solved)
    scan = []
    for factor in (0.0, 1 / 3, 0.5, 2 / 3, 1.0, 4 / 3, 5 / 3):
        scan.append(f"{factor:.2f}d ΔE2000 {errs(spectral.refine(c, spectral.guide_film(req, factor), solved))[1]:.2f}")
    print(f"  the guide's grain path ℓ at stride {k} (0: the mean-ε film; default "
          f"{spectral.CHORD_PER_DIAMETER:.2f}d): " + ", ".join(scan))
    return rows


def film(ink: str, wavelengths_nm, sigma_rad):
    """The exact film table of a molecular ink on the given grids (through the request)."""
    return request_film(table_request(ink, wavelengths_nm=wavelengths_nm, sigma_rad=sigma_rad))


def wavelength_step_curve(ink: str = "G30") -> list[tuple]:
    """CIELAB ΔE of the ink on paper (45:0/D50) vs the table's wavelength step."""
    sigma = np.linspace(0, np.pi / 2, 46)

    def lab(step):
        wl = np.arange(380.0, 780.0 + 0.5, step)
        t0 = time.perf_counter()
        table = film(ink, wl, sigma)
        seconds = time.perf_counter() - t0
        return colour(table), seconds

    ref, _ = lab(1.0)
    print(f"wavelength-step knob ({ink} thin film on paper r=0.9, ΔE*ab vs 1-nm sampling):")
    rows = []
    for step in (5.0, 10.0, 20.0, 40.0):
        value, seconds = lab(step)
        de = float(np.linalg.norm(value - ref))
        rows.append((step, de, seconds))
        print(f"  {step:>4.0f} nm: ΔE {de:.2f}   ({int(400 / step) + 1} wavelengths)")
    return rows


def angle_count_curve(ink: str = "B30") -> list[tuple]:
    """Error of the interpolated directional albedo between nodes vs the number of σ nodes."""
    wl = np.arange(380.0, 781.0, 20.0)
    probe = np.radians(np.linspace(0.5, 89.5, 179))
    exact = film(ink, wl, np.concatenate([[0.0], probe, [np.pi / 2]]))
    ref = directional_albedo(exact, 0.9, probe)
    print(f"incidence-angle knob ({ink} thin film, max error of the interpolated albedo over 0–89.5°):")
    rows = []
    for n in (5, 8, 12, 24, 46):
        table = film(ink, wl, np.linspace(0, np.pi / 2, n))
        err = float(np.max(np.abs(directional_albedo(table, 0.9, probe) - ref)))
        rows.append((n, err, n))
        print(f"  {n:>2} angles: max error {err:.4f}")
    return rows


#: `--samples`: cells of the sample-design study (docs/tables.md, "Samples: one cell per solve")
SAMPLE_CELLS = (("R15", "sphere:300"), ("B30", "cylinder:200:inplane"), ("R30", "sphere:100"))
#: designs compared there: (realizations, azimuths per realization); one azimuth alternates TE/TM
SAMPLE_DESIGNS = ((4, 2), (3, 2), (6, 1), (5, 1), (8, 1))


def design_variance(comp: dict, realizations: int, azimuths: int) -> np.ndarray:
    """Variance of the unpolarised ensemble mean under a sample design, from the variance
    components (per node): a_p between cells, e_p between azimuths of one cell, c the TE–TM
    covariance of a cell's effect.  Even `azimuths`: every cell solves azimuths/2 of each
    polarisation (joint); one: the cells alternate TE, TM (independent groups)."""
    a, e, c = comp["a"], comp["e"], comp["c"]
    if azimuths == 1:
        n = {0: (realizations + 1) // 2, 1: realizations // 2}
        return sum((a[p] + e[p]) / n[p] for p in (0, 1)) / 4
    k = azimuths // 2
    return (a[0] + e[0] / k + a[1] + e[1] / k + 2 * c) / (4 * realizations)


def sample_design_study(realizations: int = 6, azimuths: int = 4, lambda_indices=(2, 10, 18)) -> None:
    """Variance components of the wave ensemble and what each sample design gives for them:
    `realizations` cells × `azimuths` azimuths (half TE, half TM) solved at three wavelengths,
    Tbar and Rbar per (λ, σ); the standard error of each design relative to the former default
    (4 realizations × 2 azimuths) at the median node, beside the solves it costs."""
    print(f"sample designs ({realizations} cells × {azimuths} azimuths solved, full tier, default grid; "
          "SE of the unpolarised mean relative to 4 × 2, median over (λ, σ) nodes)")
    print(f"  {'cell':28s} {'column':5s} {'e/a TE, TM':>12s} {'corr(a)':>8s}  "
          + "  ".join(f"{n}×{a} ({n * a} solves)" for n, a in SAMPLE_DESIGNS))
    for ink, particles in SAMPLE_CELLS:
        req = table_request(ink, particles, tier="full", realizations=realizations, azimuths=azimuths)
        units = []
        for r in range(realizations):
            vox = geometry_unit(GeometryUnit(req, r))
            units.append([solve_unit(SolveUnit(req, r, li, vox)) for li in lambda_indices])
        pol = units[0][0]["polarisation"]
        for key in ("Tbar", "Rbar"):
            x = np.stack([np.stack([u[key] for u in per_r]) for per_r in units])     # [r, λ, σ, sample]
            y = {p: x[..., pol == p] for p in (0, 1)}
            e = {p: y[p].var(axis=-1, ddof=1).mean(axis=0) for p in (0, 1)}
            m = {p: y[p].mean(axis=-1) for p in (0, 1)}
            a = {p: np.maximum(m[p].var(axis=0, ddof=1) - e[p] / y[p].shape[-1], 0.0) for p in (0, 1)}
            c = ((m[0] - m[0].mean(0)) * (m[1] - m[1].mean(0))).sum(axis=0) / (realizations - 1)
            comp = {"a": a, "e": e, "c": c}
            old = design_variance(comp, 4, 2)
            ok = old > 0
            ratio = lambda n, k: float(np.median(np.sqrt(design_variance(comp, n, k)[ok] / old[ok])))
            ea = [float(np.median(e[p][ok] / np.maximum(a[p][ok], 1e-15))) for p in (0, 1)]
            corr = float(np.median((c / np.sqrt(np.maximum(a[0] * a[1], 1e-30)))[ok]))
            print(f"  {ink + ' ' + particles:28s} {key:5s} {ea[0]:5.2f}, {ea[1]:5.2f} {corr:8.2f}  "
                  + "  ".join(f"{ratio(n, k):>{len(f'{n}×{k} ({n * k} solves)')}.2f}" for n, k in SAMPLE_DESIGNS),
                  flush=True)


#: `--default-knobs`: the default preset's grid and solver tolerance on cells across Fig. 7's
#: columns, each variant against a reference variant of the same cells (same seeds: the
#: difference is the knob's alone), tier full
KNOB_CELLS = {"grid": (("R50", "sphere:30"), ("R30", "sphere:100"), ("R30", "sphere:100:agglutinated"),
                       ("R15", "sphere:200"), ("R15", "sphere:300"), ("R50", "cylinder:100:vertical"),
                       ("R15", "sphere:450"), ("B30", "cylinder:200:inplane"), ("Y30", "cylinder:300:isotropic")),
              "solver_tol": (("R15", "sphere:300"), ("R15", "sphere:450"), ("B30", "cylinder:200:inplane"),
                             ("Y30", "cylinder:300:isotropic"), ("R15", "sphere:300:rough"))}
KNOB_VALUES = {"grid": ((64, 64, 32), (48, 48, 24), (40, 40, 20)), "solver_tol": (1e-3, 3e-3, 5e-3, 1e-2)}


def default_knobs(workers: int) -> None:
    """ΔE2000 (45:0/D50 on paper) of each value of the default's grid and solver tolerance against
    the first value, with the mean applications per solve and the solves that needed the retry
    ladder (docs/tables.md, "Samples: one cell per solve")."""
    from solver.colour.cie import delta_e2000
    from solver.table.builder import build_table, pooled
    from solver.table.request import table_request

    for knob, values in KNOB_VALUES.items():
        print(f"default preset, {knob} (ΔE2000 against {values[0]}; applications per solve; solves retried)")
        with tempfile.TemporaryDirectory() as tmp:
            opts = BuildOptions(workers=workers, progress=False, cache=TableCache(Path(tmp)))
            with pooled(opts) as running:
                for ink, particles in KNOB_CELLS[knob]:
                    rows = []
                    for v in values:
                        t = build_table(table_request(ink, particles, tier="full", **{knob: v}), running)
                        st = t.meta["solver_stats"]
                        rows.append((v, colour(t), st["applications_mean"], st["solves_retried"]))
                    ref = rows[0][1]
                    print(f"  {ink + ' ' + particles:30s} " + "  ".join(
                        f"{v}: ΔE {float(delta_e2000(lab, ref)):.3f}, {apps:.1f} apps, {retried} retried"
                        for v, lab, apps, retried in rows), flush=True)


def plot(curves: dict) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    OUT.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, 4, figsize=(16, 3.8))
    specs = [("realizations", "estimated table solve time (s)", "max standard error", lambda r: (r[2], r[1], f"N={r[0]}")),
             ("grid", "seconds (4 solves)", "max deviation from 128×128×64", lambda r: (r[2], r[1], f"{r[0][0]}")),
             ("wavelength step", "wavelengths in the table", "ΔE*ab vs 1 nm", lambda r: (400 / r[0] + 1, r[1], f"{r[0]:.0f} nm")),
             ("angles", "incidence angles (solves ∝)", "max albedo error", lambda r: (r[2], r[1], str(r[0])))]
    for ax, (name, xl, yl, xy) in zip(axes, specs):
        pts = [xy(r) for r in curves.get(name, [])]
        if not pts:
            ax.set_visible(False)
            continue
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-")
        for x, y, lab in pts:
            ax.annotate(lab, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
        ax.set(title=name, xlabel=xl, ylabel=yl)
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    path = OUT / "tables_accuracy_time.png"
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_tables")
    p.add_argument("--quick", action="store_true", help="knob curves only, no default table")
    p.add_argument("--workers", type=int, default=default_workers(),
                   help="processes for the default table (knob curves run in-process)")
    p.add_argument("--baseline", default=PREVIOUS_ROUND,
                   help="git revision timed beside the current code ('' to skip)")
    p.add_argument("--default-only", action="store_true", help="only the default table")
    p.add_argument("--control-variate", action="store_true",
                   help="only the Born control-variate study (tried, not built; ~2 min)")
    p.add_argument("--stride-curve", action="store_true",
                   help="only the film-guided wavelength-stride curve (module doc, 4; ~3 min)")
    p.add_argument("--realizations", type=int, default=2, help="realizations of the stride curve")
    p.add_argument("--common-grains", action="store_true",
                   help="only the common-random-numbers study (rows sharing grains; ~1 min)")
    p.add_argument("--default-knobs", action="store_true",
                   help="only the default's grid and solver-tolerance screen (ΔE2000 on Fig. 7 cells; ~25 min)")
    p.add_argument("--samples", action="store_true",
                   help="only the sample-design study (cells × azimuths, variance components; ~5 min)")
    args = p.parse_args(argv if argv is not None else [])
    if args.samples:
        sample_design_study()
        return 0
    if args.default_knobs:
        default_knobs(args.workers)
        return 0
    if args.common_grains:
        common_grains_study()
        return 0
    if args.stride_curve:
        stride_curve(args.realizations, args.workers)
        return 0
    if args.control_variate:
        born_control_study()
        return 0
    if not args.quick:
        default_table(args.workers, args.baseline or None)
    if args.default_only:
        return 0
    curves = {"wavelength step": wavelength_step_curve(), "angles": angle_count_curve(),
              "realizations": realizations_curve(), "grid": grid_curve()}
    plot(curves)
    if not args.quick:
        born_control_study()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
