"""The default particle table's solves, timed the way the table runs them: the child process of
benchmarks/bench_wave.py, section 6.

Run as a script (`python benchmarks/wave_table_solves.py OUT.json [options]`) with the solver to
measure first on PYTHONPATH, so that the same harness times today's solver and an older revision
(it uses the table tier's work units, whose API both have: table_request, geometry_unit,
SolveUnit, solve_unit).  For each wavelength index it runs the unit "realization 0, that
wavelength" (7 solved σ × 2 samples = 14 solves, one FFT thread, as a table worker does) and
records the CPU seconds per solve (time.process_time, best of `repeats`), the applications and
the results; then one profiled unit (cProfile, CPU clock) split into stages.
"""
from __future__ import annotations

import argparse
import json
import time

try:
    from .cprofile_stages import grouped_profile
except ImportError:                      # run as a script with the solver to measure on the path
    from cprofile_stages import grouped_profile

STAGES = (  # (stage, rules: (file suffix or "", function name or "*")); tottime is grouped
    ("FFT", ("", "c2c"), ("wave/fftback.py", "_fftw")),
    ("z-operator", ("wave/zkernels.py", "apply_z"), ("wave/zkernels.py", "z_sums"),
     ("wave/operator.py", "convolve_z")),
    ("contrast · w", ("wave/operator.py", "apply_system"), ("wave/operator.py", "apply_scattering"),
     ("wave/operator.py", "apply_green"), ("wave/operator.py", "scatter_zmajor"),
     ("wave/operator.py", "system_zmajor"), ("wave/operator.py", "_green_zmajor")),
    ("Gram–Schmidt, Krylov", ("wave/krylov.py", "*"), ("wave/vecops.py", "*"),
     ("multiarray.py", "vdot")),
)
CUMULATIVE = (  # (stage, file suffix, function): cumulative time
    ("prepare", "wave/operator.py", "prepare"),
    ("orders", "wave/orders.py", "diffraction_orders"),
    ("energy", "wave/energy.py", "absorption"),
    ("energy", "wave/energy.py", "closure"),
    ("energy", "wave/energy.py", "midpoint_absorption"),
)


def stage_profile(fn, solves: int) -> dict:
    """CPU ms per solve of fn() by stage: STAGES by own time (their sum and 'rest' make up
    'total'), CUMULATIVE by cumulative time (a separate view: the FFTs and z-work inside
    prepare or the energy check are also counted in their STAGES)."""
    own, cum, total = grouped_profile(fn, STAGES, CUMULATIVE)
    out = {**own, "rest": total - sum(own.values()), "total": total}
    out.update({name + " (cum.)": v for name, v in cum.items()})
    return {k: 1e3 * v / solves for k, v in out.items()}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--ink", default="Y7.5+B7.5")
    ap.add_argument("--particles", default="sphere:300")
    ap.add_argument("--indices", type=int, nargs="+", default=(2, 8, 14))
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--profile-index", type=int, default=2)
    args = ap.parse_args()

    from solver.table.request import table_request
    from solver.table.wave_tier import GeometryUnit, SolveUnit, geometry_unit, solve_unit

    req = table_request(args.ink, args.particles)
    vox = geometry_unit(GeometryUnit(req, 0))

    def unit(li: int) -> dict:
        return solve_unit(SolveUnit(req, 0, li, vox, threads=1))

    unit(args.indices[0])                                     # warm-up (imports, pools)
    rows = []
    for li in args.indices:
        best, res = float("inf"), None
        for _ in range(args.repeats):
            t = time.process_time()
            res = unit(li)
            best = min(best, time.process_time() - t)
        n = res["applications"].size
        rows.append(dict(index=li, wavelength_nm=float(req.grids.wavelengths_nm[li]),
                         cpu_ms=1e3 * best / n, apps=float(res["applications"].mean()),
                         **{k: res[k].ravel().tolist()
                            for k in ("Rbar", "Tbar", "A", "energy_error")}))
    solves = unit(args.profile_index)["applications"].size
    stages = stage_profile(lambda: unit(args.profile_index), solves)
    with open(args.out, "w") as f:
        json.dump(dict(rows=rows, stages=stages), f)


if __name__ == "__main__":
    main()
