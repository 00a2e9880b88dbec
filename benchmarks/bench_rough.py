"""A rough top's solves, this tree beside a baseline revision in one run (the layered
preconditioner's cost: docs/wave_solver.md, "Layered preconditioner").

    python -m benchmarks.bench_rough                 # this tree and b635770 (before the fourth stop), ~30 s
    python -m benchmarks.bench_rough --baseline REV

48 solves of the R15 300-nm rough top (realization 0 of the default figure's request, 48×48×24):
λ 420, 540, 660, 740 nm × σ 0, 30, 60° × TE, TM × from above and below, tolerance 3e-3, one
process; prints operator applications, CPU seconds and how far R and T moved from the baseline's.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

from .baseline import ROOT, extract, run_python

#: main before the fourth stop of 2026-12-02 (real-space layered iteration, explicit residual)
BEFORE = "b635770"

CHILD = r'''
import json, time
import numpy as np
from solver.apps.figures.cells import FigureSettings
from solver.table.wave_tier import GeometryUnit, cell_eps, face_eps, geometry_unit, nominal_eps
from solver.wave import Cell, prepare, solve_prepared
req = FigureSettings("default").request("R15", "sphere:300:rough")
vox = geometry_unit(GeometryUnit(req, 0))
cpu, apps, rt = 0.0, 0, []
for wl in (420.0, 540.0, 660.0, 740.0):
    cell = Cell(cell_eps(req, vox, wl), tuple(vox.period_nm), tuple(vox.z_range_nm))
    k0 = 2 * np.pi / wl
    for sdeg in (0, 30, 60):
        for pol in ("te", "tm"):
            op = prepare(cell, wl, k0 * np.sin(np.radians(sdeg)), 0.0, eps_background=nominal_eps(req, wl),
                         eps_face=face_eps(req, wl), polarisation=pol, workers=1)
            for below in (False, True):
                t = time.process_time()
                res = solve_prepared(op, below, tol=3e-3)
                cpu += time.process_time() - t
                apps += res.applications
                rt.append([res.R, res.T])
print(json.dumps({"cpu_s": cpu, "applications": apps, "RT": rt}))
'''


def run(tree: Path) -> dict:
    out = run_python(tree, ["-c", CHILD], capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_rough", description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", default=BEFORE, help=f"git revision to time beside this tree (default {BEFORE})")
    args = p.parse_args(argv)
    rows = [("this tree", run(ROOT))]
    with tempfile.TemporaryDirectory(prefix="rough_baseline_") as tmp:
        tree = extract(args.baseline, Path(tmp))
        if tree is not None:
            rows.append((args.baseline, run(tree)))
    print("48 solves of the R15 300-nm rough top (48×48×24, tol 3e-3, one process)")
    for name, r in rows:
        print(f"  {name:12s} {r['applications']:5d} applications, {r['cpu_s']:6.2f} CPU-s")
    if len(rows) == 2:
        import numpy as np

        new, old = (np.array(r["RT"]) for _, r in rows)
        print(f"  ratio new/old: applications {rows[0][1]['applications'] / rows[1][1]['applications']:.3f}, "
              f"CPU {rows[0][1]['cpu_s'] / rows[1][1]['cpu_s']:.3f}; max |ΔR|, |ΔT| {np.abs(new - old).max():.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
