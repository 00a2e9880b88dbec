"""One reference solve, timed and profiled: the child process of benchmarks/bench_wave.py.

Run as a script (`python benchmarks/wave_reference.py EPS.npy OUT.json [options]`) with the
solver to measure first on PYTHONPATH, so that the same harness times today's solver and an
older revision extracted by bench_wave (it uses only the API both have: Cell, Incidence,
bloch_vector, prepare, solve_prepared with their defaults).  Times are CPU seconds of this
process (time.process_time, robust to other jobs on a shared machine) and wall seconds; the
best of `repeats`.  The FFT floor is the CPU time of the transforms one solve performs
(fft_floor: per application a lateral 2-D FFT pair, and a z-FFT pair in solvers before the
z-recursions), replayed here on the same shapes; the profile (cProfile with the CPU clock,
one extra solve) splits the solve into stages.
"""
from __future__ import annotations

import argparse
import json
import math
import resource
import time
import tracemalloc

import numpy as np
import scipy.fft as sfft

try:
    from .cprofile_stages import grouped_profile
except ImportError:                      # run as a script: the benchmark's child process
    from cprofile_stages import grouped_profile


def fft_floor(shape: tuple[int, int, int], workers: int, op=None, repeats: int = 20) -> float:
    """CPU seconds of the FFTs of one operator application (best of repeats), with the
    operator's FFT backend where it has one (op.fft), else scipy.fft.  Solvers with z-FFTs
    (before the z-recursions, backends with a `z` method): a lateral pair over (2, nx, ny, nz)
    and a z pair over (2, nx, ny, 2nz); since: a lateral pair over the z-major (2, nz, nx, ny)."""
    nx, ny, nz = shape
    backend = getattr(op, "fft", None)
    if backend is None:
        a = np.zeros((2, nx, ny, nz), np.complex64)
        b = np.zeros((2, nx, ny, 2 * nz), np.complex64)

        def run():
            sfft.fft2(a, axes=(1, 2), workers=workers, overwrite_x=True)
            sfft.fft(b, axis=-1, workers=workers, overwrite_x=True)
            sfft.ifft(b, axis=-1, workers=workers, overwrite_x=True)
            sfft.ifft2(a, axes=(1, 2), workers=workers, overwrite_x=True)
    elif hasattr(backend, "z"):
        from solver.wave.fftback import aligned_empty
        a = aligned_empty((2, nx, ny, nz), np.complex64)
        b = aligned_empty((2, nx, ny, 2 * nz), np.complex64)
        a[...] = 0
        b[...] = 0

        def run():
            backend.lateral(a)
            backend.z(b)
            backend.z(b, inverse=True)
            backend.lateral(a, inverse=True)
    else:
        from solver.wave.fftback import aligned_empty
        a = aligned_empty((2, nz, nx, ny), np.complex64)
        a[...] = 0

        def run():
            backend.lateral(a)
            backend.lateral(a, inverse=True)
    return best_cpu(run, repeats)


def best_cpu(fn, repeats: int = 20) -> float:
    """Best CPU seconds of fn() over `repeats` calls, after one warm-up call."""
    fn()
    best = math.inf
    for _ in range(repeats):
        t = time.process_time()
        fn()
        best = min(best, time.process_time() - t)
    return best


STAGES = (  # (stage, how a profile entry is recognised: (file suffix or "", function name))
    ("FFT", ("", "c2c"), ("wave/fftback.py", "_fftw")),
    ("z-kernel elementwise", ("wave/zkernels.py", "apply_z"), ("wave/zkernels.py", "z_sums"),
     ("wave/operator.py", "convolve_z")),
    ("contrast · w, I − GV", ("wave/operator.py", "apply_system"),
     ("wave/operator.py", "apply_scattering"), ("wave/operator.py", "apply_green"),
     ("wave/operator.py", "scatter_zmajor"), ("wave/operator.py", "system_zmajor"),
     ("wave/operator.py", "_green_zmajor")),
    ("Krylov vector ops", ("wave/krylov.py", "*"), ("wave/vecops.py", "*"),
     ("multiarray.py", "vdot")),
)


CUMULATIVE = (("energy check", "wave/energy.py", "absorption"), ("energy check", "wave/energy.py", "closure"),
              ("energy check", "wave/energy.py", "midpoint_absorption"),
              ("orders", "wave/orders.py", "diffraction_orders"), ("prepare", "wave/operator.py", "prepare"))


def profile_stages(fn) -> dict:
    """CPU seconds per stage of fn() (own time grouped by STAGES; cumulative for the energy
    check, the orders and prepare)."""
    own, cum, total = grouped_profile(fn, STAGES, CUMULATIVE)
    return {**own, **cum, "total": total}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("eps")
    ap.add_argument("out")
    ap.add_argument("--period", type=float, nargs=2, default=(2000.0, 2000.0))
    ap.add_argument("--z-range", type=float, nargs=2, default=(0.0, 1000.0))
    ap.add_argument("--wavelength", type=float, default=500.0)
    ap.add_argument("--sigma-deg", type=float, default=25.0)
    ap.add_argument("--tol", type=float, default=1e-4)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--fft", default=None, help="FFT backend (solvers that have the option)")
    args = ap.parse_args()

    from solver.wave import Cell, Incidence, bloch_vector, prepare, solve_prepared

    cell = Cell(np.load(args.eps), tuple(args.period), tuple(args.z_range))
    kx0, ky0 = bloch_vector(cell, Incidence(args.wavelength, math.radians(args.sigma_deg)))

    extra = {} if args.fft is None else {"fft": args.fft}

    def prep():
        return prepare(cell, args.wavelength, kx0, ky0, workers=args.workers, **extra)

    def once():
        op = prep()
        return solve_prepared(op, tol=args.tol)

    c0 = time.process_time()
    once()                                                   # warm-up (FFTW plans, caches)
    first = time.process_time() - c0
    best = {"prepare_cpu": math.inf, "solve_cpu": math.inf, "prepare_wall": math.inf,
            "solve_wall": math.inf}
    for _ in range(args.repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        op = prep()
        c1, w1 = time.process_time(), time.perf_counter()
        res = solve_prepared(op, tol=args.tol)
        c2, w2 = time.process_time(), time.perf_counter()
        for key, v in (("prepare_cpu", c1 - c0), ("solve_cpu", c2 - c1),
                       ("prepare_wall", w1 - w0), ("solve_wall", w2 - w1)):
            best[key] = min(best[key], v)
    tracemalloc.start()
    once()
    traced = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    stages = profile_stages(once)
    floor_app = fft_floor(cell.shape, args.workers, op)
    backend = getattr(op, "fft", None)
    row = dict(best, first_cpu=first, apps=res.applications, fft_floor_per_app=floor_app,
               fft=getattr(backend, "name", "scipy"),
               fft_floor=floor_app * res.applications, R=res.R, T=res.T,
               R_spec=res.R_spec, T_coh=res.T_coh, A=res.absorbed,
               energy=res.energy_error, residual=res.residual, stages=stages,
               traced_MB=traced / 2 ** 20,
               rss_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    with open(args.out, "w") as f:
        json.dump(row, f)


if __name__ == "__main__":
    main()
