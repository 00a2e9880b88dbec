"""Wave solver: speed, memory and accuracy on the reference case (`make bench`; not a test).

Reference case (issue "The wave solver"): 2000×2000×1000 nm cell, 30 % of 300-nm spheres
η = 1.4 + 0.2i in binder 1.558, λ = 500 nm, σ = 25°, tolerance 1e-4.

    python -m benchmarks.bench_wave            # everything below, ~2–4 min on 2 cores
    python -m benchmarks.bench_wave --quick    # the two reference grids only

Prints operator applications, seconds, peak memory, residual and energy balance for
64×64×32 and 128×128×64 (each in a fresh process, so that its peak RSS is its own), the
solver comparison (GMRES / BiCGStab / Born), the fictitious-loss study, and accuracy-vs-time
for the resolution and tolerance knobs (numbers on stdout, plot in out/bench/).
"""
from __future__ import annotations

import math
import multiprocessing as mp
import resource
import sys
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np

from solver.geometry import LayerSpec, generate, parse_particles, voxelize
from solver.inks import parse_ink
from solver.wave import (BornDivergenceError, Cell, ConvergenceWarning, Incidence, bloch_vector,
                         prepare, solve_prepared)

PERIOD, THICK, DIAM, FILL = (2000.0, 2000.0), 1000.0, 300.0, 0.30
ETA_PIGMENT, ETA_BINDER = 1.4 + 0.2j, 1.558
LAM, SIGMA, TOL, SEED = 500.0, math.radians(25.0), 1e-4, 1
OUT = Path("out/bench")


def reference_cell(shape, eta_pigment=ETA_PIGMENT, seed=SEED) -> Cell:
    """The reference layer from the project's geometry generator: 30 % of 300-nm spheres,
    voxelised with exact sub-voxel fractions; the grains get the fixed index η_pigment (the
    case's 1.4 + 0.2i) instead of a pigment spectrum."""
    layer = LayerSpec(parse_ink(f"R{100 * FILL:g}"), parse_particles(f"sphere:{DIAM:g}"),
                      thickness_nm=THICK, cell_nm=PERIOD)
    vox = voxelize(generate(layer, seed), shape)
    f = dict(zip(vox.materials, vox.fractions.astype(np.float64)))
    eps = f["binder"] * ETA_BINDER ** 2 + f["air"] * 1.0 + f["R"] * eta_pigment ** 2
    return Cell(eps, PERIOD, vox.z_range_nm)


# ------------------------------------------------------------------------------------------
def run_case(shape, tol=TOL, method="auto", eta_pigment=ETA_PIGMENT, dtype=np.complex64,
             z_order=1, min_loss=None, memory=False, repeat=1) -> dict:
    """Solve the reference incidence on one grid; returns the numbers of one table row.

    repeat > 1 solves again with the prepared operator and reports the fastest solve
    (solve_s) and the median (solve_med_s): the machine is shared, timings are noisy."""
    cell = reference_cell(shape, eta_pigment)
    if memory:
        tracemalloc.start()
    kx0, ky0 = bloch_vector(cell, Incidence(LAM, SIGMA))
    kw = {} if min_loss is None else {"min_loss": min_loss}
    t0 = time.perf_counter()
    op = prepare(cell, LAM, kx0, ky0, dtype=dtype, z_order=z_order, **kw)
    t1 = time.perf_counter()
    row = {"shape": "×".join(map(str, shape)), "method": method, "tol": tol}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = solve_prepared(op, tol=tol, method=method, maxiter=1000)
    except BornDivergenceError as err:
        row.update(apps=len(err.residuals), seconds=time.perf_counter() - t0, converged=False,
                   residual=err.residuals[-1], note=f"diverges ×{err.growth_factor:.2f}/it")
        return row
    t2 = time.perf_counter()
    times = [t2 - t1]
    for _ in range(repeat - 1):
        t3 = time.perf_counter()
        solve_prepared(op, tol=tol, method=method, maxiter=1000)
        times.append(time.perf_counter() - t3)
    row.update(apps=res.applications, prepare_s=t1 - t0, solve_s=min(times),
               solve_med_s=float(np.median(times)), seconds=t1 - t0 + min(times),
               residual=res.residual, converged=res.converged, R=res.R, T=res.T,
               R_spec=res.R_spec, T_coh=res.T_coh, A=res.absorbed, A_mid=res.absorbed_midpoint,
               energy=res.energy_error, method=res.method, note="")
    if memory:
        row["traced_MB"] = tracemalloc.get_traced_memory()[1] / 2 ** 20
        tracemalloc.stop()
        row["rss_MB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return row


def _child(queue, args, kwargs):
    queue.put(run_case(*args, **kwargs))


def run_isolated(*args, **kwargs) -> dict:
    """run_case in a fresh process (spawn), so that ru_maxrss is this case's peak."""
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_child, args=(queue, args, kwargs))
    proc.start()
    row = queue.get()
    proc.join()
    return row


def _print_rows(rows, cols):
    print("  ".join(f"{c:>10}" for c in cols))
    for r in rows:
        cells = []
        for c in cols:
            v = r.get(c, "")
            cells.append(f"{v:>10.4g}" if isinstance(v, float) else f"{str(v):>10}")
        print("  ".join(cells), flush=True)


def _metric(r, ref):
    """Sum of absolute errors of R, T, R_spec, T_coh against a reference row."""
    return sum(abs(r[k] - ref[k]) for k in ("R", "T", "R_spec", "T_coh"))


def reference_runs():
    print("\n--- reference case, 30 % 300-nm spheres (1.4+0.2i) in 1.558, λ=500 nm, σ=25°, "
          "tol 1e-4, complex64, fresh process per grid ---")
    rows = [run_isolated(s, memory=True, repeat=3) for s in ((64, 64, 32), (128, 128, 64))]
    _print_rows(rows, ["shape", "apps", "prepare_s", "solve_s", "solve_med_s", "seconds",
                       "rss_MB", "traced_MB", "residual", "energy", "R", "T", "A"])
    print("(seconds = prepare + fastest of 3 solves; solve includes the exact energy check)")
    return rows


def method_comparison():
    print("\n--- methods on the reference case 64×64×32 (tol 1e-4) ---")
    rows = [run_case((64, 64, 32), method=m, repeat=3) for m in ("gmres", "bicgstab", "born")]
    rows += [run_case((64, 64, 32), method=m, eta_pigment=1.4 + 1.1j, repeat=3)
             for m in ("gmres", "bicgstab", "born")]
    for r, eta in zip(rows, ["k=0.2"] * 3 + ["k=1.1"] * 3):
        r["case"] = eta
    _print_rows(rows, ["case", "method", "apps", "seconds", "residual", "converged", "note"])


def loss_study():
    print("\n--- fictitious loss δ = min Im ε_b on a lossless layer (spheres η=1.4), "
          "32×32×16 ---")
    rows = []
    for delta in (0.003, 0.01, 0.03, 0.1, 0.3):
        r = run_case((32, 32, 16), eta_pigment=1.4 + 0j, min_loss=delta, tol=1e-5, repeat=3)
        r["delta"] = delta
        rows.append(r)
    _print_rows(rows, ["delta", "apps", "seconds", "residual", "A", "energy"])


def resolution_knob():
    print("\n--- resolution knob (tol 1e-4); reference: Richardson extrapolation of "
          "64×64×32 and 128×128×64 (O(h²)) ---")
    shapes = [(24, 24, 12), (32, 32, 16), (48, 48, 24), (64, 64, 32), (96, 96, 48), (128, 128, 64)]
    rows = [run_case(s, repeat=2) for s in shapes]
    fine, mid = rows[-1], rows[3]
    ref = {k: fine[k] + (fine[k] - mid[k]) / 3 for k in ("R", "T", "R_spec", "T_coh")}
    for r in rows:
        r["error"] = _metric(r, ref)
    rows0 = [run_case(s, z_order=0, repeat=2) for s in shapes[:5]]
    for r in rows0:
        r["error"] = _metric(r, ref)
        r["method"] = "gmres/P0"
    _print_rows(rows + rows0, ["shape", "method", "apps", "seconds", "error", "R_spec", "T_coh",
                               "energy"])
    return rows, rows0


def tolerance_knob():
    print("\n--- tolerance knob on 64×64×32; reference: tol 1e-8 in complex128 ---")
    ref = run_case((64, 64, 32), tol=1e-8, dtype=np.complex128)
    tols = (3e-1, 1e-1, 3e-2, 1e-2, 1e-3, 1e-4, 1e-5)
    rows = [run_case((64, 64, 32), tol=t, repeat=3) for t in tols]
    for r in rows:
        r["error"] = _metric(r, ref)
    _print_rows(rows, ["tol", "apps", "seconds", "residual", "error", "energy"])
    return rows


def convergence_tables():
    """Errors against the exact oracles, through the tests' own helpers (no second copy)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    from test_wave_convergence import slab_error
    from test_wave_grating import grating_errors
    from test_wave_mie import mie_relative_errors

    def orders(errs):
        return [""] + [f"{math.log2(a / b):.2f}" for a, b in zip(errs, errs[1:])]

    def row(name, values, fmt):
        print(f"{name:>36} " + " ".join(fmt(v) for v in values))

    ns = (16, 32, 64, 128, 256, 512)
    print("\n--- slab, 1000 nm, λ=500 nm, σ=0.4: |Δr|+|Δt| against Airy "
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

    print("\n--- lamellar grating vs RCWA (period 800, strip [130, 410) 1.4+0.2i in 1.558, "
          "400 nm, nz=16): max |Δamp| over propagating orders ---")
    nxs = (16, 32, 64, 128, 256)
    errs = [grating_errors((1.4 + 0.2j) ** 2, 130.0, 410.0, nx)[0] for nx in nxs]
    row("nodes per period", nxs, lambda v: f"{v:>9}")
    row("error", errs, lambda v: f"{v:9.2e}")
    row("order", orders(errs), lambda v: f"{v:>9}")

    print("\n--- sphere lattice (a=60 nm, 1.05+0.01i, period 400, depth 200) vs Mie single "
          "scattering: max relative order error ---")
    shapes = ((16, 16, 8), (32, 32, 16), (64, 64, 32))
    row("grid", ["×".join(map(str, sh)) for sh in shapes], lambda v: f"{v:>10}")
    row("relative error", [mie_relative_errors(sh).max() for sh in shapes],
        lambda v: f"{v:10.4f}")


def plot(res_rows, res_rows0, tol_rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    OUT.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    curves = ((res_rows[:-1], "linear per z-cell (default)"), (res_rows0, "constant per z-cell"))
    for rows, label in curves:
        ax[0].loglog([r["seconds"] for r in rows], [max(r["error"], 1e-7) for r in rows], "o-",
                     label=label)
        for r in rows:
            ax[0].annotate(r["shape"], (r["seconds"], max(r["error"], 1e-7)), fontsize=7)
    ax[0].set(xlabel="seconds", ylabel="|ΔR|+|ΔT|+|ΔR_spec|+|ΔT_coh|", title="resolution knob")
    ax[0].legend(fontsize=8)
    ax[1].loglog([r["seconds"] for r in tol_rows], [max(r["error"], 1e-9) for r in tol_rows], "s-")
    for r in tol_rows:
        ax[1].annotate(f"{r['tol']:.0e}", (r["seconds"], max(r["error"], 1e-9)), fontsize=7)
    ax[1].set(xlabel="seconds", ylabel="error vs tol 1e-8", title="tolerance knob, 64×64×32")
    fig.suptitle("wave solver, reference case (2-core VM; timings noisy under load)")
    fig.tight_layout()
    path = OUT / "wave_accuracy_time.png"
    fig.savefig(path, dpi=120)
    print(f"\nplot: {path}")


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    load = Path("/proc/loadavg")
    print("wave solver benchmark; load average at start:",
          load.read_text().split()[:3] if load.exists() else "unknown")
    reference_runs()
    if "--quick" in argv:
        return 0
    method_comparison()
    loss_study()
    convergence_tables()
    res_rows, res_rows0 = resolution_knob()
    tol_rows = tolerance_knob()
    plot(res_rows, res_rows0, tol_rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
