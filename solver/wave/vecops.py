"""Vector operations of the Krylov solvers on one BLAS thread.

The work is memory bound, so one thread loses little, while OpenBLAS's threads were measured
up to 1000× slower on a 2-core machine shared with other jobs (thread wake-up under contention:
a threaded cgemv over 262 144 elements took 8–16 ms instead of 0.5 ms).  `one_blas_thread()`
sets NumPy's OpenBLAS to one thread for the calling thread only (openblas_set_num_threads_local,
OpenBLAS ≥ 0.3.27) and restores it; with any other BLAS it changes nothing.  Inner products
are accumulated in complex128 over chunks of CHUNK elements (single-precision BLAS sums inside
a chunk).
"""
from __future__ import annotations

import contextlib
import ctypes
import glob
import math
import os
from typing import Iterator

import numpy as np

from .fftback import aligned_empty

#: elements per BLAS call in inner products (partial sums in complex128 across chunks)
CHUNK = 32768


def _openblas_local_setter():
    """openblas_set_num_threads_local of NumPy's bundled OpenBLAS, or None."""
    libdir = os.path.join(os.path.dirname(np.__file__), os.pardir, "numpy.libs")
    for path in sorted(glob.glob(os.path.join(libdir, "*openblas*.so*"))):
        try:
            lib = ctypes.CDLL(path)
            fn = lib.openblas_set_num_threads_local
        except (OSError, AttributeError):
            continue
        fn.restype, fn.argtypes = ctypes.c_int, [ctypes.c_int]
        return fn
    return None


_SET_LOCAL = _openblas_local_setter()


def set_blas_threads_local(n: int) -> int | None:
    """Set NumPy's OpenBLAS threads for the calling thread; returns the previous count, or
    None (and does nothing) when NumPy's BLAS has no thread-local setting."""
    return None if _SET_LOCAL is None else int(_SET_LOCAL(int(n)))


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """NumPy's OpenBLAS on one thread inside the block, for the calling thread only."""
    previous = set_blas_threads_local(1)
    try:
        yield
    finally:
        if previous is not None:
            set_blas_threads_local(max(previous, 1))


def dot(a: np.ndarray, b: np.ndarray) -> complex:
    """⟨a, b⟩ = Σ conj(a)·b of two 1-D arrays."""
    return sum((complex(np.vdot(a[i:i + CHUNK], b[i:i + CHUNK]))
                for i in range(0, a.size, CHUNK)), 0j)


def norm(v: np.ndarray) -> float:
    return math.sqrt(max(dot(v, v).real, 0.0))


class Basis:
    """Krylov basis as rows of 2-D blocks of BLOCK rows, allocated as the iteration reaches
    them (memory follows the iterations taken, also as counted by tracemalloc)."""

    BLOCK = 16

    def __init__(self, rows: int, size: int, dtype: np.dtype):
        self.rows, self.size, self.dtype = rows, size, np.dtype(dtype)
        self.blocks: list[np.ndarray] = []
        self.n = 0

    def row(self, j: int) -> np.ndarray:
        """Row j (allocating its block when first reached)."""
        if j >= self.rows:
            raise IndexError(f"basis has {self.rows} rows")
        b, i = divmod(j, self.BLOCK)
        while len(self.blocks) <= b:
            rows = min(self.BLOCK, self.rows - len(self.blocks) * self.BLOCK)
            self.blocks.append(aligned_empty((rows, self.size), self.dtype))
        return self.blocks[b][i]

    def append(self, w: np.ndarray, scale: float) -> None:
        np.multiply(w, scale, out=self.row(self.n))
        self.n += 1

    def _spans(self, n: int):
        for b, block in enumerate(self.blocks):
            k = min(n - b * self.BLOCK, block.shape[0])
            if k <= 0:
                return
            yield b * self.BLOCK, block[:k]

    def project(self, w: np.ndarray, n: int) -> np.ndarray:
        """Coefficients ⟨v_i, w⟩ for the first n rows (complex128)."""
        h = np.zeros(n, dtype=complex)
        wc = np.conj(w)
        for start, block in self._spans(n):
            k = block.shape[0]
            for i in range(0, w.size, CHUNK):
                h[start:start + k] += block[:, i:i + CHUNK] @ wc[i:i + CHUNK]
        return h.conj()

    def subtract(self, w: np.ndarray, coef: np.ndarray, n: int) -> None:
        """w −= Σ_i coef_i v_i over the first n rows (in place)."""
        c = coef[:n].astype(self.dtype)
        for start, block in self._spans(n):
            w -= c[start:start + block.shape[0]] @ block
