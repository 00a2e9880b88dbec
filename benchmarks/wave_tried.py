"""Measurements behind the wave solver's "tried and dropped" list (docs/wave_solver.md):
FFT libraries from the package index and FFT layouts.  Called by benchmarks/bench_wave.py; the
FFT libraries are measured only where they are installed (pyFFTW, ducc0 are not dependencies
of the project).  (The batched right-hand sides of the list were measured on the z-FFT operator
of revision 96fb031, `python -m benchmarks.bench_wave`, section 5b; that operator is gone.)"""
from __future__ import annotations

import importlib.util

import numpy as np
import scipy.fft as sfft

from solver.wave import Cell, Incidence, bloch_vector, prepare, solve_prepared
from solver.wave.fftback import fftw_available

from .wave_reference import best_cpu


def _pair(transform, shape) -> float:
    """CPU s of a forward + inverse transform(a, inverse) of a complex64 array, in place."""
    a = np.zeros(shape, np.complex64)
    return best_cpu(lambda: (transform(a, False), transform(a, True)))


def _scipy(axes):
    return lambda a, inv: (sfft.ifftn if inv else sfft.fftn)(a, axes=axes, workers=1,
                                                           overwrite_x=True)


def fft_libraries(cell: Cell, wavelength: float, sigma: float) -> None:
    nx, ny, nz = cell.shape
    print(f"\n--- 5a. FFTs of one application on {nx}×{ny}×{nz} (CPU ms, 1 thread, complex64, "
          "in place), layouts and libraries; the reference solve (tol 1e-4) per library ---")
    zmajor = (2, nz, nx, ny)
    ms = {
        "scipy, z-major (2,nz,nx,ny), last two axes (used)": _pair(_scipy((-2, -1)), zmajor),
        "scipy, (2,nx,ny,nz), axes (1,2) (before)": _pair(_scipy((1, 2)), (2, nx, ny, nz)),
        "scipy, z pair (2,nx,ny,2nz), last axis (before)": _pair(_scipy((-1,)),
                                                                 (2, nx, ny, 2 * nz)),
    }
    if importlib.util.find_spec("ducc0"):
        import ducc0
        ms["ducc0, z-major, last two axes"] = _pair(
            lambda a, inv: ducc0.fft.c2c(a, axes=(2, 3), forward=not inv, inorm=2 if inv else 0,
                                         nthreads=1, out=a), zmajor)
    if importlib.util.find_spec("pyfftw"):
        import pyfftw
        a = pyfftw.zeros_aligned(zmajor, "complex64")
        plans = [pyfftw.FFTW(a, a, axes=(2, 3), direction=d, flags=("FFTW_MEASURE",), threads=1)
                 for d in ("FFTW_FORWARD", "FFTW_BACKWARD")]
        ms["pyFFTW, z-major, last two axes"] = best_cpu(lambda: [p() for p in plans])
    for name, t in ms.items():
        print(f"{name:>52}: {1e3 * t:.2f} ms")
    kx0, ky0 = bloch_vector(cell, Incidence(wavelength, sigma))

    def solve_cpu(fft: str) -> float:
        op = prepare(cell, wavelength, kx0, ky0, workers=1, fft=fft)
        return best_cpu(lambda: solve_prepared(op, tol=1e-4), repeats=3)

    for fft in ("scipy", "fftw") if fftw_available() else ("scipy",):
        print(f"{'solve, fft=' + repr(fft):>52}: {1e3 * solve_cpu(fft):.1f} ms")
