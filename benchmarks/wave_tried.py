"""Measurements behind the wave solver's "tried and dropped" list (docs/wave_solver.md):
FFT libraries from the package index and batched right-hand sides.  Called by
benchmarks/bench_wave.py; the FFT libraries are measured only where they are installed
(pyFFTW, ducc0 are not dependencies of the project)."""
from __future__ import annotations

import importlib.util

import numpy as np
import scipy.fft as sfft

from solver.wave import Cell, Incidence, bloch_vector, prepare, solve_prepared
from solver.wave.fftback import fftw_available

from .wave_reference import best_cpu


def _per_application(lateral, zfft, shape) -> float:
    """CPU s of one application's transforms: lateral pair over (2, nx, ny, nz), z pair over
    (2, nx, ny, 2nz), in place."""
    nx, ny, nz = shape
    a = np.zeros((2, nx, ny, nz), np.complex64)
    b = np.zeros((2, nx, ny, 2 * nz), np.complex64)
    return best_cpu(lambda: (lateral(a, False), zfft(b, False), zfft(b, True),
                              lateral(a, True)))


def fft_libraries(cell: Cell, wavelength: float, sigma: float) -> None:
    shape = cell.shape
    print(f"\n--- 5a. FFT libraries, one application's transforms on {'×'.join(map(str, shape))}"
          " (CPU ms, 1 thread), and the reference solve (tol 1e-4) ---")
    ms = {"scipy.fft (used)": _per_application(
        lambda a, inv: (sfft.ifft2 if inv else sfft.fft2)(a, axes=(1, 2), workers=1,
                                                           overwrite_x=True),
        lambda a, inv: (sfft.ifft if inv else sfft.fft)(a, axis=-1, workers=1, overwrite_x=True),
        shape)}
    if importlib.util.find_spec("ducc0"):
        import ducc0
        ms["ducc0"] = _per_application(
            lambda a, inv: ducc0.fft.c2c(a, axes=(1, 2), forward=not inv, inorm=2 if inv else 0,
                                         nthreads=1, out=a),
            lambda a, inv: ducc0.fft.c2c(a, axes=(3,), forward=not inv, inorm=2 if inv else 0,
                                         nthreads=1, out=a), shape)
    if importlib.util.find_spec("pyfftw"):
        import pyfftw
        nx, ny, nz = shape
        a = pyfftw.zeros_aligned((2, nx, ny, nz), "complex64")
        b = pyfftw.zeros_aligned((2, nx, ny, 2 * nz), "complex64")
        plans = [pyfftw.FFTW(x, x, axes=ax, direction=d, flags=("FFTW_MEASURE",), threads=1)
                 for x, ax in ((a, (1, 2)), (b, (3,)))
                 for d in ("FFTW_FORWARD", "FFTW_BACKWARD")]
        ms["pyFFTW (planned, in place)"] = best_cpu(lambda: [p() for p in plans])
    for name, t in ms.items():
        print(f"{name:>28}: {1e3 * t:.2f} ms")
    kx0, ky0 = bloch_vector(cell, Incidence(wavelength, sigma))

    def solve_cpu(fft: str) -> float:
        op = prepare(cell, wavelength, kx0, ky0, workers=1, fft=fft)
        return best_cpu(lambda: solve_prepared(op, tol=1e-4), repeats=3)

    for fft in ("scipy", "fftw") if fftw_available() else ("scipy",):
        print(f"{'solve, fft=' + repr(fft):>28}: {1e3 * solve_cpu(fft):.1f} ms")


def batched_rhs(cell: Cell, wavelength: float, sigma: float) -> None:
    """FFTs and spectrum products of B right-hand sides in one call (the kernel spectra read
    once for all), per right-hand side."""
    nx, ny, nz = cell.shape
    op = prepare(cell, wavelength, *bloch_vector(cell, Incidence(wavelength, sigma)), workers=1,
                 fft="scipy")
    spec = op.zk.spec
    print("\n--- 5b. batched right-hand sides: one application's FFTs + spectrum products, "
          "CPU ms per right-hand side ---")
    for batch in (1, 2, 4):
        lead = (batch,) if batch > 1 else ()
        x = np.zeros(lead + (2, nx, ny, nz), np.complex64)
        buf = np.zeros(lead + (2, nx, ny, 2 * nz), np.complex64)
        ta = np.empty(lead + (nx, ny, 2 * nz), np.complex64)
        tb = np.empty_like(ta)

        def run():
            sfft.fft2(x, axes=(-3, -2), workers=1, overwrite_x=True)
            f = sfft.fft(buf, axis=-1, workers=1, overwrite_x=True)
            f0, f1 = f[..., 0, :, :, :], f[..., 1, :, :, :]
            np.multiply(spec[2], f0, out=ta)
            f0 *= spec[0]
            np.multiply(spec[1], f1, out=tb)
            f0 += tb
            f1 *= spec[3]
            f1 += ta
            sfft.ifft(f, axis=-1, workers=1, overwrite_x=True)
            sfft.ifft2(x, axes=(-3, -2), workers=1, overwrite_x=True)

        print(f"{batch} right-hand side(s) per call: {1e3 * best_cpu(run) / batch:.2f} ms")
