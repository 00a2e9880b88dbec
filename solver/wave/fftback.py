"""The wave solver's array backend (the seam, issue 25): where its arrays live and how they are
made, moved and transformed — NumPy on the host (FFTs from scipy.fft or FFTW) or CuPy on a GPU
(optional, `fft="cupy"`).  Every module of the solve allocates (`empty`, `zeros`, `asarray`),
moves results to the host (`to_host`) and transforms (`lateral`) through the operator's
backend (`Background.fft`); the arithmetic is NumPy's functions and operators, which CuPy
arrays follow through NumPy's dispatch protocols (`__array_ufunc__`, `__array_function__`).
The preparation (Green's function constants in complex128) runs on the host and is moved once.

In-place FFTs of the operator: lateral 2-D transforms over the two last axes of its z-major
arrays (nb, nz, nx, ny), from scipy.fft (default) or FFTW (pyFFTW, optional) or cupy.fft.

scipy.fft (pocketfft) is always available, keeps complex64 in single precision and transforms in
place with overwrite_x; its inverse transforms divide by n.  FFTW (`fft="fftw"`, needs
`pip install pyfftw`, GPL) transforms the reference grid's arrays ≈ 2.4× faster (planned once
per array layout and thread) and does not normalise: the operator folds 1/(nx·ny)
into its z-constants (zkernels.z_kernels, `normalised`).  Arrays that the hot path transforms are
allocated 64-byte aligned (`aligned_empty`) so that FFTW's SIMD plans apply; others get an
FFTW_UNALIGNED plan.  Measurements: docs/wave_solver.md, "FFT library".
"""
from __future__ import annotations

import functools
import importlib.util
import threading
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft

from .. import host

#: default FFT library of prepare_background / prepare / solve: 'auto' = FFTW where pyFFTW is
#: installed (the optional dependency `inkbsdf[fftw]`; its speed-up: docs/wave_solver.md, "FFT library"), else scipy.fft
DEFAULT_FFT = "auto"
FFT_NAMES = ("scipy", "fftw", "cupy", "auto")
ALIGNMENT = 64
#: FFTW plans arrays of at least this many elements with FFTW_MEASURE (64×64×32 moments:
#: 0.33 s once per process, 1.34 ms per application vs 1.72 ms with FFTW_ESTIMATE; 128×128×64:
#: 1.4 s, 15.8 vs 21.7 ms) and `workers` threads, smaller ones with FFTW_ESTIMATE (planning
#: 14 ms → 1 ms each) on one thread (FFTW's threads only slow small transforms down)
MEASURE_MIN_ELEMENTS = 1 << 17


def default_workers() -> int:
    """Threads for scipy.fft: the machine's cores, at most 8."""
    return max(1, min(host.cpu_count(), 8))


def aligned_empty(shape, dtype) -> np.ndarray:
    """np.empty with the data 64-byte aligned (SIMD plans of FFTW)."""
    dt = np.dtype(dtype)
    n = int(np.prod(shape)) * dt.itemsize
    raw = np.empty(n + ALIGNMENT, dtype=np.uint8)
    start = (-raw.ctypes.data) % ALIGNMENT
    return raw[start:start + n].view(dt).reshape(shape)


@functools.lru_cache(maxsize=None)
def fftw_available() -> bool:
    """Whether pyFFTW is installed (looked up once per process)."""
    return importlib.util.find_spec("pyfftw") is not None


@functools.lru_cache(maxsize=None)
def cupy_available() -> bool:
    """Whether CuPy is installed and sees a GPU (looked up once per process)."""
    if importlib.util.find_spec("cupy") is None:
        return False
    try:
        import cupy

        return cupy.cuda.runtime.getDeviceCount() > 0
    except Exception:                     # noqa: BLE001 — no driver, no device: not available
        return False


@dataclass(frozen=True, eq=False)
class FFT:
    """The array backend: `name` 'scipy' | 'fftw' (NumPy arrays on the host) or 'cupy' (CuPy
    arrays on the GPU); in-place transforms, `normalised`: whether inverse transforms divide
    by n."""

    name: str
    workers: int
    normalised: bool
    _plans: threading.local = field(default_factory=threading.local, repr=False)

    def __reduce__(self):
        """Pickles without its plans (per process and thread): backgrounds travel to workers."""
        return (FFT, (self.name, self.workers, self.normalised))

    @property
    def xp(self):
        """The array module: numpy, or cupy."""
        if self.name == "cupy":
            import cupy

            return cupy
        return np

    def empty(self, shape, dtype):
        """An uninitialised array (host: 64-byte aligned for FFTW's SIMD plans)."""
        return self.xp.empty(shape, dtype) if self.name == "cupy" else aligned_empty(shape, dtype)

    def zeros(self, shape, dtype):
        return self.xp.zeros(shape, dtype)

    def asarray(self, a, dtype=None):
        """`a` as a C-contiguous array of this backend (copied only when needed)."""
        return self.xp.ascontiguousarray(self.xp.asarray(a, dtype=dtype))

    def to_host(self, a) -> np.ndarray:
        """A NumPy array with the values of `a` (a copy from the GPU; `a` itself on the host)."""
        return a.get() if self.name == "cupy" else np.asarray(a)

    def same_buffer(self, a, b) -> bool:
        """Whether two arrays start at the same address."""
        if self.name == "cupy":
            return a.data.ptr == b.data.ptr
        return a.ctypes.data == b.ctypes.data

    def lateral(self, a: np.ndarray, inverse: bool = False) -> np.ndarray:
        """2-D DFT over the two last axes (contiguous: pocketfft's fastest layout), in place;
        returns the result (a itself for FFTW, and for scipy.fft on C-contiguous arrays)."""
        if self.name == "scipy":
            f = sfft.ifft2 if inverse else sfft.fft2
            return f(a, axes=(-2, -1), workers=self.workers, overwrite_x=True)
        if self.name == "cupy":
            import cupyx.scipy.fft as cfft

            f = cfft.ifft2 if inverse else cfft.fft2
            return f(a, axes=(-2, -1), overwrite_x=True)
        return self._fftw(a, (a.ndim - 2, a.ndim - 1), inverse)

    def _fftw(self, a: np.ndarray, axes: tuple[int, ...], inverse: bool) -> np.ndarray:
        import pyfftw

        if not a.flags.c_contiguous:
            raise ValueError("FFTW transforms need C-contiguous arrays")
        aligned = a.ctypes.data % ALIGNMENT == 0
        key = (a.shape, a.dtype.str, axes, inverse, aligned)
        cache = self._plans.__dict__.setdefault("plans", {})
        plan = cache.get(key)
        if plan is None:
            template = aligned_empty(a.shape, a.dtype)
            effort = "FFTW_MEASURE" if a.size >= MEASURE_MIN_ELEMENTS else "FFTW_ESTIMATE"
            flags = (effort,) if aligned else (effort, "FFTW_UNALIGNED")
            threads = self.workers if a.size >= MEASURE_MIN_ELEMENTS else 1
            plan = pyfftw.FFTW(template, template, axes=axes,
                               direction="FFTW_BACKWARD" if inverse else "FFTW_FORWARD",
                               flags=flags, threads=threads)
            cache[key] = plan
        plan.update_arrays(a, a)
        plan.execute()
        return a


#: the host backend (NumPy, scipy.fft on one thread): the default of the Krylov solvers and
#: the scratch pool when no operator says otherwise
HOST = FFT("scipy", 1, normalised=True)


def get_fft(name: str, workers: int) -> FFT:
    """The backend `name` ('scipy', 'fftw', 'cupy', 'auto': the host's fastest, FFTW where
    installed, else scipy; CuPy is asked for by name) with `workers` host threads."""
    if name not in FFT_NAMES:
        raise ValueError(f"fft must be one of {FFT_NAMES}, got {name!r}")
    if name == "auto":
        name = "fftw" if fftw_available() else "scipy"
    if name == "fftw" and not fftw_available():
        raise ValueError("fft='fftw' needs pyFFTW (pip install pyfftw); use fft='scipy'")
    if name == "cupy" and not cupy_available():
        raise ValueError("fft='cupy' needs CuPy and a GPU (pip install cupy-cuda12x); use fft='scipy'")
    return FFT(name, int(workers), normalised=(name in ("scipy", "cupy")))


#: the backends this machine can run, for tests parametrised over them
def available() -> tuple[str, ...]:
    return tuple(n for n in ("scipy", "fftw", "cupy")
                 if n == "scipy" or (fftw_available() if n == "fftw" else cupy_available()))
