"""Wave solver: speed, memory and accuracy on the reference case (`make bench`; not a test).

Reference case (issue "The wave solver"): 2000×2000×1000 nm cell, 30 % of 300-nm spheres
η = 1.4 + 0.2i in binder 1.558, λ = 500 nm, σ = 25°, tolerance 1e-4.

    python -m benchmarks.bench_wave                      # everything, ~5–10 min on 2 cores
    python -m benchmarks.bench_wave --quick              # the reference rows only (1, 1b)
    python -m benchmarks.bench_wave --fft-libraries      # section 5a only (FFT libraries, layouts)
    PYTHONPATH=<dir with pyfftw, ducc0> python -m benchmarks.bench_wave --quick   # + FFTW rows
    python -m benchmarks.bench_wave --table              # the table solves only (section 6)
    python -m benchmarks.bench_wave --baseline REV       # old solver from git revision REV
    python -m benchmarks.bench_wave --table-baseline REV # section 6's old solver

1. Reference solve, old (solver/ of --baseline, default 98de97b, the solver before the
   "six times faster" work) and new side by side, each in a fresh process
   (benchmarks/wave_reference.py): CPU and wall seconds, applications, the FFT floor (CPU time
   of the transforms the solve performs), ratio, per-stage profile, peak memory.
2. Tolerance curve (error in R, T, R_spec, T_coh, diffuse orders vs tol 1e-6), warm starts on
   realistic sequences, shared background preparation across realizations, Krylov methods,
   fictitious loss, TM vs TE cost, oracle convergence tables, resolution knob (plot in
   out/bench/); the "tried and dropped" measurements (benchmarks/wave_tried.py: FFT libraries
   where installed, FFT layouts).
6. The default particle table's solves (`ink-tables build --ink Y7.5+B7.5 --particles
   sphere:300`: 64×64×32, tol 1e-3, one FFT thread) timed the way a table worker runs them,
   old (--table-baseline, default 96fb031: main before the "table speed" work) and new side by
   side, fresh processes, alternating (benchmarks/wave_table_solves.py): CPU per solve,
   applications, results old vs new, stage profile; GMRES vs BiCGStab on the same solves.
"""
from __future__ import annotations

import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

from solver.geometry import LayerSpec, generate, parse_particles, voxelize
from solver.inks import parse_ink
from solver.wave import (BornDivergenceError, Cell, Incidence, bloch_vector, prepare,
                         prepare_background, with_contrast)
from solver.wave.fftback import fftw_available
from solver.wave.validation import grating_errors, mie_relative_errors, slab_error

from .baseline import ROOT, extract, run_python
from .wave_checks import (cpu_time, energy_checks, loss_study, polarisation_cost, print_rows,
                          quiet_solve)
from .wave_floor import floor_decomposition
from .wave_table import table_methods, table_solves
from .wave_tried import fft_libraries

PERIOD, THICK, DIAM, FILL = (2000.0, 2000.0), 1000.0, 300.0, 0.30
ETA_PIGMENT, ETA_BINDER = 1.4 + 0.2j, 1.558
LAM, SIGMA, SEED = 500.0, math.radians(25.0), 1
BASELINE = "98de97b"
TABLE_BASELINE = "96fb031"
OUT = Path("out/bench")
TABLE_SIGMA_DEG = (0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0)
TABLE_WAVELENGTHS = tuple(np.arange(380.0, 781.0, 20.0))


def reference_cell(shape, eta_pigment=ETA_PIGMENT, seed=SEED) -> Cell:
    """The reference layer from the project's geometry generator: 30 % of 300-nm spheres,
    voxelised with exact sub-voxel fractions; the grains get the fixed index η_pigment."""
    layer = LayerSpec(parse_ink(f"R{100 * FILL:g}"), parse_particles(f"sphere:{DIAM:g}"),
                      thickness_nm=THICK, cell_nm=PERIOD)
    vox = voxelize(generate(layer, seed), shape)
    f = dict(zip(vox.materials, vox.fractions.astype(np.float64)))
    eps = f["binder"] * ETA_BINDER ** 2 + f["air"] * 1.0 + f["R"] * eta_pigment ** 2
    return Cell(eps, PERIOD, vox.z_range_nm)


# ------------------------------------------------------------------------------ 1. reference
def _child(tree: Path, eps_path: Path, out: Path, workers: int, repeats: int,
           fft: str | None = None) -> dict:
    """The harness in a fresh process with `tree` first on the path (then the caller's other
    PYTHONPATH entries, e.g. where optional packages live)."""
    run_python(tree, [str(ROOT / "benchmarks" / "wave_reference.py"), str(eps_path), str(out),
                      "--workers", str(workers), "--repeats", str(repeats)]
               + ([] if fft is None else ["--fft", fft]))
    return json.loads(out.read_text())


def reference_runs(baseline: str, shapes=((64, 64, 32), (128, 128, 64))) -> list[dict]:
    print("\n--- 1. reference solve (tol 1e-4, complex64), old vs new, fresh process each, "
          "best of 3, CPU seconds unless named wall ---")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        old_tree = extract(baseline, tmp / "old")
        for shape in shapes:
            eps_path = tmp / f"eps_{shape[0]}.npy"
            np.save(eps_path, np.asarray(reference_cell(shape).eps))
            runs = [("new", ROOT, 1, "scipy"), ("new 2 thr", ROOT, 2, "scipy")]
            if fftw_available():
                runs.insert(1, ("new", ROOT, 1, "fftw"))
            if old_tree is not None:
                runs.insert(0, (f"old {baseline}", old_tree, 1, None))
            for name, tree, workers, fft in runs:
                r = _child(tree, eps_path, tmp / "row.json", workers, 3 if shape[0] <= 64 else 2,
                           fft)
                r.update(code=f"{name} {r['fft']}", shape="×".join(map(str, shape)),
                         workers=workers,
                         ratio=r["solve_cpu"] / r["fft_floor"],
                         ratio_all=(r["solve_cpu"] + r["prepare_cpu"]) / r["fft_floor"])
                rows.append(r)
    print_rows(rows, ["shape", "code", "apps", "prepare_cpu", "solve_cpu", "solve_wall",
                       "fft_floor", "ratio", "ratio_all", "first_cpu", "traced_MB", "rss_MB",
                       "energy"])
    print("ratio = solve / FFT floor; ratio_all = (prepare + solve) / FFT floor (the floor with "
          "the row's FFT library); first_cpu: the first prepare + solve of the process (FFTW "
          "plans); traced_MB: tracemalloc peak of one prepare + solve; rss_MB: the process's "
          "peak RSS")
    print("\nstage profile (CPU s of one profiled prepare + solve, cProfile):")
    stages = list(rows[0]["stages"])
    print(f"{'':>28} " + " ".join(f"{s[:14]:>14}" for s in stages))
    for r in rows:
        print(f"{r['shape'] + ' ' + r['code']:>28} "
              + " ".join(f"{r['stages'][s]:14.4f}" for s in stages))
    return rows


# ------------------------------------------------------------------------------ 2. knobs
def _diffuse(res) -> np.ndarray:
    """Power of every non-00 order (reflected then transmitted)."""
    out = []
    for o in (res.reflected, res.transmitted):
        out.append(np.where((o.m == 0) & (o.n == 0), 0.0, o.power))
    return np.concatenate(out)


def tolerance_curve(shape=(64, 64, 32)) -> list[dict]:
    print("\n--- 2a. tolerance curve; errors against tol 1e-6 in complex128, "
          f"{'×'.join(map(str, shape))}, CPU s of the solve ---")
    rows = []
    for case, eta, sigma in (("k=0.2 25°", ETA_PIGMENT, SIGMA),
                             ("k=0 25°", 1.4 + 0j, SIGMA),
                             ("k=0 80°", 1.4 + 0j, math.radians(80.0)),
                             ("k=1.1 80°", 1.4 + 1.1j, math.radians(80.0))):
        cell = reference_cell(shape, eta)
        kx0, ky0 = bloch_vector(cell, Incidence(LAM, sigma))
        ref, _ = quiet_solve(prepare(cell, LAM, kx0, ky0, dtype=np.complex128, workers=1), tol=1e-6)
        op = prepare(cell, LAM, kx0, ky0, workers=1)
        for tol in (1e-2, 3e-3, 1e-3, 3e-4, 1e-4):
            res, cpu = min((quiet_solve(op, tol=tol) for _ in range(2)), key=lambda rc: rc[1])
            dd = np.abs(_diffuse(res) - _diffuse(ref))
            rows.append(dict(case=case, tol=tol, apps=res.applications, cpu_s=cpu,
                             dR=abs(res.R - ref.R), dT=abs(res.T - ref.T),
                             dR_spec=abs(res.R_spec - ref.R_spec),
                             dT_coh=abs(res.T_coh - ref.T_coh), d_diffuse=float(dd.sum()),
                             max_order=float(dd.max()), energy=res.energy_error))
    print_rows(rows, ["case", "tol", "apps", "cpu_s", "dR", "dT", "dR_spec", "dT_coh",
                       "d_diffuse", "max_order", "energy"])
    print("d_diffuse: Σ|ΔP| over all non-00 orders; max_order: the largest |ΔP| of one order; "
          "energy: the residual closure R+T+A−1")
    return [r for r in rows if r["case"] == "k=0.2 25°"]


def warm_starts(shape=(64, 64, 32)) -> None:
    print("\n--- 2b. warm starts (x0 = the previous solve's solution), tol 1e-4, "
          f"{'×'.join(map(str, shape))}: applications cold → warm ---")
    cell = reference_cell(shape)
    seqs = {
        "σ sweep (table σ, λ 500)": [(LAM, math.radians(s), 0.0) for s in TABLE_SIGMA_DEG],
        "λ sweep (380…780/20, σ 25°)": [(lam, SIGMA, 0.0) for lam in TABLE_WAVELENGTHS],
        "azimuth pair (0, 0.97 rad)": [(LAM, SIGMA, 0.0), (LAM, SIGMA, 0.97)] * 1,
    }
    for name, seq in seqs.items():
        cold_apps = warm_apps = 0
        cold_cpu = warm_cpu = 0.0
        worst = 0.0
        prev = None
        for lam, sig, phi in seq:
            op = prepare(cell, lam, *bloch_vector(cell, Incidence(lam, sig, phi)), workers=1)
            cold, c1 = quiet_solve(op)
            warm, c2 = quiet_solve(op, x0=None if prev is None else prev.solution)
            prev = warm
            cold_apps += cold.applications
            warm_apps += warm.applications
            cold_cpu += c1
            warm_cpu += c2
            worst = max(worst, abs(warm.R - cold.R), abs(warm.T - cold.T))
        print(f"{name:>30}: {len(seq)} solves, applications {cold_apps} → {warm_apps} "
              f"({warm_apps / cold_apps:.2f}), CPU {cold_cpu:.2f} → {warm_cpu:.2f} s, "
              f"max |ΔR|,|ΔT| warm vs cold {worst:.1e}")
    cells = [reference_cell(shape, seed=s) for s in (1, 2, 3, 4)]
    kx0, ky0 = bloch_vector(cells[0], Incidence(LAM, SIGMA))
    cold = warm = 0
    prev = None
    for c in cells:
        op = prepare(c, LAM, kx0, ky0, workers=1)
        cold += quiet_solve(op)[0].applications
        res = quiet_solve(op, x0=None if prev is None else prev.solution)[0]
        warm += res.applications
        prev = res
    print(f"{'across 4 realizations':>30}: applications {cold} → {warm} ({warm / cold:.2f})")


def shared_background(shape=(64, 64, 32)) -> None:
    print("\n--- 2c. one background for 4 realizations (ε_b = mean of their mean ε) vs one "
          f"preparation each (own mean ε_b), {'×'.join(map(str, shape))}, tol 1e-4 ---")
    cells = [reference_cell(shape, seed=s) for s in (1, 2, 3, 4)]
    kx0, ky0 = bloch_vector(cells[0], Incidence(LAM, SIGMA))
    eps_b = complex(np.mean([np.mean(c.eps) for c in cells]))
    own_prep = shared_prep = 0.0
    own_apps = shared_apps = 0
    worst = 0.0
    bg, t_bg = cpu_time(lambda: prepare_background(shape, PERIOD, THICK, LAM, kx0, ky0, eps_b,
                                               workers=1))
    shared_prep += t_bg
    for c in cells:
        op, t = cpu_time(lambda: prepare(c, LAM, kx0, ky0, workers=1))
        own_prep += t
        own, _ = quiet_solve(op)
        op2, t2 = cpu_time(lambda: with_contrast(bg, c))
        shared_prep += t2
        shared, _ = quiet_solve(op2)
        own_apps += own.applications
        shared_apps += shared.applications
        worst = max(worst, abs(own.R - shared.R), abs(own.T - shared.T),
                    abs(own.R_spec - shared.R_spec))
    print(f"prepare CPU {own_prep:.3f} s → {shared_prep:.3f} s; applications {own_apps} → "
          f"{shared_apps}; max |ΔR|, |ΔT|, |ΔR_spec| between the two {worst:.1e} "
          "(discretisation error moves with ε_b)")


def method_comparison(shape=(64, 64, 32)) -> None:
    print("\n--- 2d. Krylov methods on the reference case (tol 1e-4), CPU s ---")
    rows = []
    for case, eta in (("k=0.2", ETA_PIGMENT), ("k=1.1", 1.4 + 1.1j), ("k=0", 1.4 + 0j)):
        cell = reference_cell(shape, eta)
        op = prepare(cell, LAM, *bloch_vector(cell, Incidence(LAM, SIGMA)), workers=1)
        for method in ("gmres", "bicgstab", "born"):
            try:
                res, cpu = quiet_solve(op, method=method)
                rows.append(dict(case=case, method=method, apps=res.applications, cpu_s=cpu,
                                 residual=res.residual, converged=res.converged, note=""))
            except BornDivergenceError as err:
                rows.append(dict(case=case, method=method, apps=len(err.residuals),
                                 converged=False, note=f"diverges ×{err.growth_factor:.2f}/it"))
    print_rows(rows, ["case", "method", "apps", "cpu_s", "residual", "converged", "note"])


def convergence_tables() -> None:
    """Errors against the exact oracles (solver/wave/validation.py, shared with the tests)."""
    def orders(errs):
        return [""] + [f"{math.log2(a / b):.2f}" for a, b in zip(errs, errs[1:])]

    def row(name, values, fmt):
        print(f"{name:>36} " + " ".join(fmt(v) for v in values))

    ns = (16, 32, 64, 128, 256, 512)
    print("\n--- 3a. slab, 1000 nm, λ=500 nm, σ=0.4: |Δr|+|Δt| against Airy "
          "(order = log2 of successive ratios) ---")
    row("cells per 1000 nm", ns, lambda v: f"{v:>9}")
    cases = [("binder, contrast to air bg, linear", 1.558, 1, False),
             ("binder, contrast to air bg, P0", 1.558, 0, False),
             ("pigment 1.4+0.2i, half voxels", 1.4 + 0.2j, 1, True),
             ("binder, half voxels", 1.558, 1, True)]
    for name, eta, z_order, half in cases:
        errs = [slab_error(eta, n, half_voxels=half, z_order=z_order) for n in ns]
        row(name, errs, lambda v: f"{v:9.2e}")
        row("order", orders(errs), lambda v: f"{v:>9}")
    print("\n--- 3b. lamellar grating vs RCWA (period 800, strip [130, 410) 1.4+0.2i in 1.558, "
          "400 nm, nz=16): max |Δamp| over propagating orders ---")
    nxs = (16, 32, 64, 128, 256)
    errs = [grating_errors((1.4 + 0.2j) ** 2, 130.0, 410.0, nx)[0] for nx in nxs]
    row("nodes per period", nxs, lambda v: f"{v:>9}")
    row("error", errs, lambda v: f"{v:9.2e}")
    row("order", orders(errs), lambda v: f"{v:>9}")
    print("\n--- 3c. sphere lattice (a=60 nm, 1.05+0.01i, period 400, depth 200) vs Mie single "
          "scattering: max relative order error ---")
    shapes = ((16, 16, 8), (32, 32, 16), (64, 64, 32))
    row("grid", ["×".join(map(str, sh)) for sh in shapes], lambda v: f"{v:>10}")
    row("relative error", [mie_relative_errors(sh).max() for sh in shapes],
        lambda v: f"{v:10.4f}")


def resolution_knob() -> tuple[list[dict], list[dict]]:
    print("\n--- 4. resolution knob (tol 1e-4); reference: Richardson extrapolation of "
          "64×64×32 and 128×128×64 (O(h²)); CPU s = prepare + solve ---")
    shapes = [(24, 24, 12), (32, 32, 16), (48, 48, 24), (64, 64, 32), (96, 96, 48), (128, 128, 64)]

    def run(shape, z_order):
        cell = reference_cell(shape)
        kx0, ky0 = bloch_vector(cell, Incidence(LAM, SIGMA))
        op, tp = cpu_time(lambda: prepare(cell, LAM, kx0, ky0, z_order=z_order, workers=1))
        res, ts = quiet_solve(op)
        return dict(shape="×".join(map(str, shape)), method=f"P{z_order}", apps=res.applications,
                    seconds=tp + ts, R=res.R, T=res.T, R_spec=res.R_spec, T_coh=res.T_coh,
                    energy=res.energy_error)

    rows = [run(s, 1) for s in shapes]
    fine, mid = rows[-1], rows[3]
    ref = {k: fine[k] + (fine[k] - mid[k]) / 3 for k in ("R", "T", "R_spec", "T_coh")}
    rows0 = [run(s, 0) for s in shapes[:5]]
    for r in rows + rows0:
        r["error"] = sum(abs(r[k] - ref[k]) for k in ("R", "T", "R_spec", "T_coh"))
    print_rows(rows + rows0, ["shape", "method", "apps", "seconds", "error", "R_spec", "T_coh",
                               "energy"])
    return rows, rows0


def plot(res_rows, res_rows0, tol_rows) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    OUT.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for rows, label in ((res_rows[:-1], "linear per z-cell (default)"),
                        (res_rows0, "constant per z-cell")):
        ax[0].loglog([r["seconds"] for r in rows], [max(r["error"], 1e-7) for r in rows], "o-",
                     label=label)
        for r in rows:
            ax[0].annotate(r["shape"], (r["seconds"], max(r["error"], 1e-7)), fontsize=7)
    ax[0].set(xlabel="CPU seconds (prepare + solve)", ylabel="|ΔR|+|ΔT|+|ΔR_spec|+|ΔT_coh|",
              title="resolution knob")
    ax[0].legend(fontsize=8)
    for key, label in (("dR", "R"), ("dT", "T"), ("dR_spec", "R_spec"), ("d_diffuse", "Σ diffuse")):
        ax[1].loglog([r["cpu_s"] for r in tol_rows], [max(r[key], 1e-9) for r in tol_rows], "s-",
                     label=label)
    for r in tol_rows:
        ax[1].annotate(f"{r['tol']:.0e}", (r["cpu_s"], max(r["dR"], 1e-9)), fontsize=7)
    ax[1].set(xlabel="CPU seconds (solve)", ylabel="error vs tol 1e-6",
              title="tolerance knob, 64×64×32")
    ax[1].legend(fontsize=8)
    fig.suptitle("wave solver, reference case")
    fig.tight_layout()
    path = OUT / "wave_accuracy_time.png"
    fig.savefig(path, dpi=120)
    print(f"\nplot: {path}")


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    baseline = argv[argv.index("--baseline") + 1] if "--baseline" in argv else BASELINE
    table_baseline = (argv[argv.index("--table-baseline") + 1] if "--table-baseline" in argv
                      else TABLE_BASELINE)
    load = Path("/proc/loadavg")
    print("wave solver benchmark; load average at start:",
          load.read_text().split()[:3] if load.exists() else "unknown")
    if "--fft-libraries" in argv:
        fft_libraries(reference_cell((64, 64, 32)), LAM, SIGMA)
        return 0
    if "--table" in argv:
        table_solves(table_baseline)
        table_methods()
        return 0
    reference_runs(baseline)
    floor_decomposition({"×".join(map(str, s)): reference_cell(s)
                         for s in ((64, 64, 32), (128, 128, 64))}, LAM, SIGMA)
    if "--quick" in argv:
        return 0
    tol_rows = tolerance_curve()
    warm_starts()
    shared_background()
    method_comparison()
    polarisation_cost(reference_cell((64, 64, 32)), LAM, SIGMA)
    energy_checks(reference_cell((64, 64, 32)), LAM, SIGMA)
    loss_study(reference_cell((32, 32, 16), 1.4 + 0j), LAM, SIGMA)
    convergence_tables()
    res_rows, res_rows0 = resolution_knob()
    plot(res_rows, res_rows0, tol_rows)
    cell = reference_cell((64, 64, 32))
    fft_libraries(cell, LAM, SIGMA)
    table_solves(table_baseline)
    table_methods()
    return 0


if __name__ == "__main__":
    sys.exit(main())
