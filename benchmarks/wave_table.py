"""Section 6 of benchmarks/bench_wave.py: the default particle table's solves, old and new side
by side (fresh processes running benchmarks/wave_table_solves.py, alternating, best of the
rounds), and GMRES against BiCGStab on the same solves (docs/wave_solver.md, "Performance")."""
from __future__ import annotations

import json
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from .baseline import ROOT, extract, run_python

INK, PARTICLES = "Y7.5+B7.5", "sphere:300"
INDICES = (2, 8, 14)                    # λ 420 and 540 nm (absorbing), 660 nm (more iterations)


def _child(tree: Path, out: Path, repeats: int) -> dict:
    run_python(tree, [str(ROOT / "benchmarks" / "wave_table_solves.py"), str(out),
                      "--ink", INK, "--particles", PARTICLES, "--repeats", str(repeats),
                      "--indices", *map(str, INDICES)])
    return json.loads(out.read_text())


def table_solves(baseline: str, rounds: int = 2, repeats: int = 2) -> None:
    print(f"\n--- 6. the default particle table's solves ({INK}, {PARTICLES}: 64×64×32, tol "
          "1e-3, 1 FFT thread), realization 0, 14 solves per wavelength; CPU ms per solve, "
          f"best of {rounds} alternating fresh processes × {repeats} repeats ---")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        old_tree = extract(baseline, tmp / "old")
        trees = ([(f"old {baseline}", old_tree)] if old_tree is not None else []) \
            + [("new", ROOT)]
        runs: dict[str, list[dict]] = {name: [] for name, _ in trees}
        for _ in range(rounds):
            for name, tree in trees:
                runs[name].append(_child(tree, tmp / "out.json", repeats))
    best = {}
    for name, rs in runs.items():
        rows = []
        for i in range(len(INDICES)):
            r = min((x["rows"][i] for x in rs), key=lambda row: row["cpu_ms"])
            rows.append(r)
        stages = min((x["stages"] for x in rs), key=lambda st: st["total"])
        best[name] = (rows, stages)
    names = list(best)
    print(f"{'λ nm':>6} " + " ".join(f"{n + ' ms':>16} {n + ' apps':>14}" for n in names)
          + ("   old/new" if len(names) == 2 else ""))
    for i in range(len(INDICES)):
        cells = [best[n][0][i] for n in names]
        line = f"{cells[0]['wavelength_nm']:6.0f} " + " ".join(
            f"{c['cpu_ms']:16.1f} {c['apps']:14.2f}" for c in cells)
        if len(names) == 2:
            line += f"   {cells[0]['cpu_ms'] / cells[1]['cpu_ms']:7.2f}"
        print(line)
    means = {n: float(np.mean([r["cpu_ms"] for r in best[n][0]])) for n in names}
    print("mean: " + ", ".join(f"{n} {m:.1f} ms" for n, m in means.items())
          + (f", old/new {means[names[0]] / means[names[1]]:.2f}" if len(names) == 2 else ""))
    if len(names) == 2:
        diff = {k: max(float(np.max(np.abs(np.subtract(a[k], b[k]))))
                       for a, b in zip(best[names[0]][0], best[names[1]][0]))
                for k in ("Rbar", "Tbar", "A", "energy_error")}
        print("max |new − old| over these solves: "
              + ", ".join(f"{k} {v:.1e}" for k, v in diff.items()))
    print("\nstage profile, CPU ms per solve (one profiled unit at "
          f"λ index {INDICES[0]}; own time by stage, then cumulative views):")
    keys = list(best[names[-1]][1])
    print(f"{'':>10} " + " ".join(f"{k[:16]:>16}" for k in keys))
    for n in names:
        st = best[n][1]
        print(f"{n[:10]:>10} " + " ".join(f"{st.get(k, 0.0):16.2f}" for k in keys))


def table_methods(indices=(2, 8, 14, 15)) -> None:
    """GMRES (the default) and BiCGStab on the table's 14 solves per wavelength (new code,
    in this process)."""
    from solver.geometry import eps_grid
    from solver.table.request import table_request
    from solver.table.wave_tier import (GeometryUnit, azimuths, geometry_unit, nominal_eps,
                                        samples)
    from solver.wave import Cell, prepare, solve_prepared

    print("\n--- 6b. GMRES vs BiCGStab on the same table solves (realization 0; CPU ms per "
          "solve of solve_prepared, applications per solve) ---")
    req = table_request(INK, PARTICLES)
    vox = geometry_unit(GeometryUnit(req, 0))
    sig, phis, todo = req.grids.solved_sigma_rad, azimuths(req, 0), samples(req)
    for li in indices:
        wl = req.grids.wavelengths_nm[li]
        cell = Cell(eps_grid(vox, wl, req.materials), tuple(vox.period_nm),
                    tuple(vox.z_range_nm))
        eps_b = nominal_eps(req, wl)
        k0 = 2 * np.pi / wl
        out = {}
        for method in ("gmres", "bicgstab"):
            apps, cpu, rbar = 0, 0.0, []
            for s in sig:
                for j, pol in todo:
                    kx0, ky0 = k0 * np.sin(s) * np.cos(phis[j]), k0 * np.sin(s) * np.sin(phis[j])
                    op = prepare(cell, wl, kx0, ky0, eps_background=eps_b, workers=1,
                                 polarisation=("te", "tm")[pol])
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        t = time.process_time()
                        res = solve_prepared(op, method=method)
                        cpu += time.process_time() - t
                    apps += res.applications
                    rbar.append(res.R)
            n = len(sig) * len(todo)
            out[method] = (apps / n, 1e3 * cpu / n, np.array(rbar))
        g, b = out["gmres"], out["bicgstab"]
        print(f"λ {wl:.0f} nm (ε_b = {eps_b:.3f}): GMRES {g[0]:.1f} apps, {g[1]:.1f} ms; "
              f"BiCGStab {b[0]:.1f} apps, {b[1]:.1f} ms; max |ΔR| {np.abs(g[2] - b[2]).max():.1e}")
