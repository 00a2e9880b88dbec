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

from .fftback import FFT, HOST
from .scratch import borrow, give_back

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
    them (memory follows the iterations taken, also as counted by tracemalloc), borrowed from
    the thread's scratch pool (scratch.py) and given back by release().

    The Gram–Schmidt products run chunk by chunk (CHUNK elements of every row, cache-sized):
    each pass reads the basis and the vector once, whatever it computes besides (the vector's
    norm with the projection, the scaling with the subtraction, the solution and the residual
    together); products are summed in complex128 across chunks."""

    BLOCK = 16

    def __init__(self, rows: int, size: int, dtype: np.dtype, backend: FFT = HOST):
        self.rows, self.size, self.dtype = rows, size, np.dtype(dtype)
        self.backend = backend
        self.blocks: list[np.ndarray] = []
        self.n = 0
        self._buf = backend.empty(min(CHUNK, size), self.dtype)

    def row(self, j: int) -> np.ndarray:
        """Row j (allocating its block when first reached)."""
        if j >= self.rows:
            raise IndexError(f"basis has {self.rows} rows")
        b, i = divmod(j, self.BLOCK)
        while len(self.blocks) <= b:      # full blocks: one shape for the pool
            self.blocks.append(borrow((self.BLOCK, self.size), self.dtype, self.backend))
        return self.blocks[b][i]

    def release(self) -> None:
        """Give the blocks back to the thread's scratch pool (scratch.py); the basis is empty
        afterwards."""
        give_back(*self.blocks, backend=self.backend)
        self.blocks, self.n = [], 0

    def append(self, w: np.ndarray, scale: float) -> None:
        np.multiply(w, scale, out=self.row(self.n))
        self.n += 1

    def _spans(self, n: int):
        for b, block in enumerate(self.blocks):
            k = min(n - b * self.BLOCK, block.shape[0])
            if k <= 0:
                return
            yield b * self.BLOCK, block[:k]

    def project(self, w: np.ndarray, n: int) -> tuple[np.ndarray, float]:
        """(⟨v_i, w⟩ for the first n rows (complex128), ‖w‖²), in one pass."""
        h = self.backend.zeros(n, complex)
        norm2 = 0.0
        spans = list(self._spans(n))
        for i in range(0, w.size, CHUNK):
            wc = np.conjugate(w[i:i + CHUNK], out=self._buf[:min(CHUNK, w.size - i)])
            norm2 += float(np.vdot(wc, wc).real)
            for start, block in spans:
                h[start:start + block.shape[0]] += block[:, i:i + CHUNK] @ wc
        return self.backend.to_host(h).conj(), norm2

    def subtract(self, w: np.ndarray, coef: np.ndarray, n: int, scale: float = 1.0) -> None:
        """w ← (w − Σ_i coef_i v_i)·scale over the first n rows (in place, one pass)."""
        c = self.backend.asarray(coef[:n], self.dtype)
        spans = list(self._spans(n))
        for i in range(0, w.size, CHUNK):
            part = w[i:i + CHUNK]
            for start, block in spans:
                part -= c[start:start + block.shape[0]] @ block[:, i:i + CHUNK]
            if scale != 1.0:
                part *= scale

    def combine(self, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, float]:
        """x += Σ_i y_i v_i (in place) and r = Σ_i z_i v_i (a new array) in one pass over the
        first len(z) ≥ len(y) rows; returns (r, ‖r‖²)."""
        n = len(z)
        host = np.zeros((2, n), dtype=self.dtype)
        host[0, :len(y)] = y
        host[1] = z
        coef = self.backend.asarray(host)
        r = np.empty_like(x)
        norm2 = 0.0
        spans = list(self._spans(n))
        for i in range(0, x.size, CHUNK):
            part = r[i:i + CHUNK]
            part[...] = 0
            for start, block in spans:
                both = coef[:, start:start + block.shape[0]] @ block[:, i:i + CHUNK]
                x[i:i + CHUNK] += both[0]
                part += both[1]
            norm2 += float(np.vdot(part, part).real)
        return r, norm2
