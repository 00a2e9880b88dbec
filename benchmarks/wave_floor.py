"""What one reference solve spends beside its FFTs, part by part, and the floor that the
operator itself sets (benchmarks/bench_wave.py, section 1b; docs/wave_solver.md, "How close
to the FFT floor").

Every part is timed alone, on the solve's own operator and arrays, in CPU seconds (best of
`REPEATS` after a warm-up, one FFT thread, NumPy's BLAS on one thread as in a solve):

- fft: the lateral FFT pair of one application (the FFT floor per application), with scipy.fft
  and, where pyFFTW is installed, FFTW (one row each);
- z: the z-recursions of one application (zkernels.apply_z);
- contrast: the product contrast · w of one application;
- application: one whole application of G·V (scatter_zmajor), the three above and the glue;
- Gram–Schmidt: the projection and subtraction passes GMRES makes over its basis in a solve of
  `apps` iterations (vecops.Basis.project and subtract with j = 1 … apps rows);
- rest: the measured solve minus apps × application and the Gram–Schmidt passes: the
  right-hand side, the Krylov bookkeeping and the final combination, the orders, the energy
  identity, and what the applications cost more inside the solve than alone (there, their input
  and output are basis rows that come from and go to memory, not the cache).

Bounds printed: the operator's own ratio (application / fft: what any Krylov method pays per
application, before a single vector operation) and the GMRES ratio without the rest
((apps × application + Gram–Schmidt) / (apps × fft)).
"""
from __future__ import annotations

import math
import time

import numpy as np

from solver.wave import Incidence, bloch_vector, prepare, solve_prepared
from solver.wave.fftback import aligned_empty, fftw_available
from solver.wave.operator import Workspace, scatter_zmajor
from solver.wave.vecops import Basis, one_blas_thread
from solver.wave.zkernels import apply_z

REPEATS = 15


def _best(fn, setup=None, repeats: int = REPEATS) -> float:
    """Best CPU seconds of fn() over `repeats` calls (after one warm-up); setup() runs before
    each call, untimed."""
    best = math.inf
    for i in range(repeats + 1):
        if setup is not None:
            setup()
        t = time.process_time()
        fn()
        dt = time.process_time() - t
        if i:
            best = min(best, dt)
    return best


def decompose(cell, wavelength_nm: float, sigma_rad: float, fft: str, tol: float = 1e-4) -> dict:
    """The parts of one reference solve (module doc) with the FFT library `fft`, CPU seconds."""
    kx0, ky0 = bloch_vector(cell, Incidence(wavelength_nm, sigma_rad))
    op = prepare(cell, wavelength_nm, kx0, ky0, workers=1, fft=fft)
    res = solve_prepared(op, tol=tol)
    solve_s = _best(lambda: solve_prepared(op, tol=tol), repeats=5)
    rng = np.random.default_rng(0)
    shape = op.zmajor_shape
    data, work, out = (aligned_empty(shape, op.dtype) for _ in range(3))   # as the hot path's
    data[...] = rng.standard_normal(shape) + 1j * rng.standard_normal(shape)
    ws = Workspace(op)
    nb, nz, nx, ny = shape
    refill = lambda: np.copyto(work, data)                       # noqa: E731
    with one_blas_thread():
        fft = _best(lambda: (op.fft.lateral(work), op.fft.lateral(work, inverse=True)), refill)
        z = _best(lambda: apply_z(op.zk, work.reshape(nb, nz, nx * ny), ws.z), refill)
        contrast = _best(lambda: np.multiply(op.contrast_zmajor, data, out=out))
        application = _best(lambda: scatter_zmajor(op, data, ws, out))
        gs = _gram_schmidt(data.ravel(), res.applications)
    ws.release()
    apps = res.applications
    return dict(apps=apps, library=op.fft.name, fft=fft, z=z, contrast=contrast, application=application,
                gram_schmidt=gs, solve=solve_s,
                rest=solve_s - apps * application - gs,
                operator_ratio=application / fft,
                gmres_bound=(apps * application + gs) / (apps * fft),
                ratio=solve_s / (apps * fft))


def _gram_schmidt(v: np.ndarray, iterations: int) -> float:
    """CPU seconds of GMRES's projection + subtraction passes over j = 1 … iterations rows."""
    basis = Basis(iterations + 1, v.size, v.dtype)
    for _ in range(iterations):
        basis.append(v, 1.0 / math.sqrt(v.size))
    w = v.copy()
    total = 0.0
    for j in range(1, iterations + 1):
        def passes(j=j):
            h, _ = basis.project(w, j)
            basis.subtract(w, 1e-3 * h, j)
        total += _best(passes, repeats=5)
    basis.release()
    return total


def floor_decomposition(cells: dict, wavelength_nm: float, sigma_rad: float) -> list[dict]:
    """Section 1b of bench_wave: one row per named cell."""
    print("\n--- 1b. one reference solve part by part (tol 1e-4, complex64, 1 thread; CPU ms, "
          "best of repeats; benchmarks/wave_floor.py) ---")
    cols = ("apps", "fft", "z", "contrast", "application", "gram_schmidt", "rest", "solve",
            "operator_ratio", "gmres_bound", "ratio")
    print(f"{'shape, FFT':>18} " + " ".join(f"{c:>14}" for c in cols))
    rows = []
    for (name, cell), fft in ((c, f) for c in cells.items()
                              for f in ("scipy",) + (("fftw",) if fftw_available() else ())):
        r = decompose(cell, wavelength_nm, sigma_rad, fft)
        name = f"{name} {r['library']}"
        rows.append(dict(r, shape=name))
        cells_txt = [f"{r['apps']:>14d}"] + [
            f"{1e3 * r[c]:>14.3f}" for c in cols[1:8]] + [f"{r[c]:>14.2f}" for c in cols[8:]]
        print(f"{name:>18} " + " ".join(cells_txt), flush=True)
    print("fft, z, contrast, application: per application; gram_schmidt, rest, solve: per "
          "solve. operator_ratio = application / fft: what every iteration pays before any "
          "vector operation; gmres_bound = (apps·application + gram_schmidt) / (apps·fft): "
          "the ratio with nothing else; ratio = solve / (apps·fft); rest: see the module doc")
    return rows
