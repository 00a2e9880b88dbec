"""In-place FFTs of the operator: lateral 2-D transforms and z-transforms along the last axis.

scipy.fft (pocketfft) is the backend: it is always available, keeps complex64 in single
precision and transforms in place with overwrite_x (no allocation per application).  pyFFTW
(FFTW) transforms these sizes about 2× faster but made a whole solve only ≈ 1.2× faster
(docs/wave_solver.md, "Tried and dropped"), for a GPL dependency: not used.
"""
from __future__ import annotations

import os

import numpy as np
import scipy.fft as sfft


def default_workers() -> int:
    """Threads for scipy.fft: the machine's cores, at most 8."""
    return max(1, min(os.cpu_count() or 1, 8))


def fft_lateral(a: np.ndarray, workers: int, inverse: bool = False) -> np.ndarray:
    """2-D DFT over axes (1, 2) of a (nb, nx, ny, nz) array, in place (returns the result)."""
    f = sfft.ifft2 if inverse else sfft.fft2
    return f(a, axes=(1, 2), workers=workers, overwrite_x=True)


def fft_z(a: np.ndarray, workers: int, inverse: bool = False) -> np.ndarray:
    """DFT along the last axis, in place (returns the result)."""
    f = sfft.ifft if inverse else sfft.fft
    return f(a, axis=-1, workers=workers, overwrite_x=True)
