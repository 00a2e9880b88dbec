"""Scratch arrays reused from one solve to the next on the same thread.

A solve's large scratch arrays (the Krylov basis blocks, the operator's workspace) are touched
for the first time in every solve when they are allocated anew: the kernel maps and zeroes their
pages, which took 8–10 ms of system time in a 75-ms solve at 64×64×32 (3600 page faults per
solve; docs/wave_solver.md, "Performance").  `borrow` hands out an aligned array of a given
shape and dtype (contents undefined), taken from this thread's pool when one was given back;
`give_back` returns arrays to the pool, which keeps them while it holds at most POOL_BYTES;
`release` empties it.  Arrays must not be used after they are given back.
"""
from __future__ import annotations

import threading

import numpy as np

from .fftback import FFT, aligned_empty

#: most bytes of scratch arrays a thread keeps between solves (64×64×32: one basis block of 16
#: rows is 34 MB, the workspace 9 MB)
POOL_BYTES = 256 * 2 ** 20


class _Pool(threading.local):
    def __init__(self):
        self.free: dict[tuple, list[np.ndarray]] = {}
        self.nbytes = 0


_POOL = _Pool()


def borrow(shape, dtype, backend: FFT | None = None) -> np.ndarray:
    """An array of `shape` and `dtype` with undefined contents, of the array backend
    (fftback.py; None: host NumPy, aligned)."""
    name = _where(backend)
    key = (tuple(int(s) for s in np.atleast_1d(shape)), np.dtype(dtype).str, name)
    stack = _POOL.free.get(key)
    if stack:
        a = stack.pop()
        _POOL.nbytes -= a.nbytes
        return a
    return aligned_empty(key[0], dtype) if name == "host" else backend.empty(key[0], dtype)


def _where(backend: FFT | None) -> str:
    """The pool of a backend's arrays: 'host' for NumPy's (scipy.fft, FFTW), else its name."""
    return "host" if backend is None or backend.name in ("scipy", "fftw") else backend.name


def give_back(*arrays: np.ndarray, backend: FFT | None = None) -> None:
    """Return arrays borrowed for `backend` to this thread's pool (kept while it stays under
    POOL_BYTES)."""
    for a in arrays:
        if _POOL.nbytes + a.nbytes > POOL_BYTES:
            continue
        _POOL.free.setdefault((a.shape, a.dtype.str, _where(backend)), []).append(a)
        _POOL.nbytes += a.nbytes


def release() -> None:
    """Drop this thread's pooled arrays."""
    _POOL.free.clear()
    _POOL.nbytes = 0


def pooled_bytes() -> int:
    """Bytes held by this thread's pool."""
    return _POOL.nbytes
