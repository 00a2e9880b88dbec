"""The discretised Lippmann–Schwinger operator of one cell, prepared once per (λ, Bloch vector).

Field u = e^{i(kx0·x + ky0·y)}·w(x, y, z) with w periodic; unknowns: w at the lateral voxel
centres × Legendre moments in every z-cell (shape (nb, nx, ny, nz); nb = z_order + 1; moment
0 is the cell average).  Lateral: pseudo-spectral (DFT, exact Bloch harmonics
kx = kx0 + 2πm/Lx, ky = ky0 + 2πn/Ly).  z: Galerkin with the exact layered-background Green's
function (kernel1d.py), applied by FFT along z (Toeplitz + Hankel).

    w − G·(V·w) = w_b,      V = k0²(ε − ε_b)   (1/nm²),   w_b = background (Airy) field.

Everything here is shared by incidence from above and from below with the same (kx0, ky0).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from .kernel1d import (SlabGreen, circulant_blocks, face_profiles, slab_green,
                       vertical_wavenumber)
from .types import Cell

#: default minimum Im ε_b of the background slab (fictitious loss that keeps the guided-mode
#: poles of a lossless film off the real axis; the contrast carries −i·δ back).  See docs.
DEFAULT_MIN_LOSS = 0.01


def default_workers() -> int:
    """Threads for scipy.fft: the machine's cores, at most 8."""
    return max(1, min(os.cpu_count() or 1, 8))


@dataclass(frozen=True, eq=False)
class LayerOperator:
    """Everything that depends on (cell, λ, kx0, ky0) but not on the side of incidence.

    Arrays of shape (nx, ny) are per lateral harmonic in FFT order; order indices m, n.
    contrast = k0²(ε − ε_b) in 1/nm², shape (nx, ny, nz); toe_spec, han_spec: FFTs (length
    2nz) of the circulant kernels, (nb, nb, nx, ny, 2nz); ptop, pbot: moments of the face
    profiles (kernel1d.face_profiles), (nb, nx, ny, nz).
    """

    cell: Cell
    wavelength_nm: float
    kx0: float
    ky0: float
    eps_background: complex
    m: np.ndarray
    n: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    green: SlabGreen
    contrast: np.ndarray
    toe_spec: np.ndarray
    han_spec: np.ndarray
    ptop: np.ndarray
    pbot: np.ndarray
    workers: int

    @property
    def k0(self) -> float:
        return 2 * math.pi / self.wavelength_nm

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.cell.shape

    @property
    def nb(self) -> int:
        """Legendre functions per z-cell (z_order + 1)."""
        return self.green.nb

    @property
    def unknown_shape(self) -> tuple[int, int, int, int]:
        return (self.nb,) + self.shape

    @property
    def dtype(self) -> np.dtype:
        return self.contrast.dtype

    @property
    def lateral_phase(self) -> np.ndarray:
        """e^{−iπ(m/nx + n/ny)}: maps DFT coefficients of node values (voxel centres) to
        Fourier coefficients referenced to x = y = 0."""
        nx, ny, _ = self.shape
        return np.exp(-1j * math.pi * (self.m / nx + self.n / ny))


def choose_background(eps: np.ndarray, min_loss: float) -> complex:
    """Volume mean of ε with Im ε_b raised to at least min_loss."""
    mean = complex(np.mean(eps))
    return complex(mean.real, max(mean.imag, float(min_loss)))


def prepare(cell: Cell, wavelength_nm: float, kx0: float, ky0: float, *,
            eps_background: complex | None = None, min_loss: float = DEFAULT_MIN_LOSS,
            z_order: int = 1, dtype: type = np.complex64,
            workers: int | None = None) -> LayerOperator:
    """Build the operator for one cell, wavelength (nm) and Bloch vector (kx0, ky0) in 1/nm.

    eps_background: ε_b of the background slab (default: volume mean of ε); its imaginary part
    is raised to min_loss if smaller.  z_order: polynomial degree per z-cell (1: O(h⁴) in z
    where ε is piecewise constant on z-cells; 0: cell averages only, O(h²)).  dtype: complex64
    (default) or complex128 for the operator arrays and Krylov vectors (kernels are computed
    in complex128).  workers: scipy.fft threads (default: all cores, at most 8).
    """
    if not (wavelength_nm > 0 and math.isfinite(wavelength_nm)):
        raise ValueError(f"wavelength_nm must be positive, got {wavelength_nm}")
    if min_loss <= 0:
        raise ValueError("min_loss must be positive (it keeps the background's poles complex)")
    if z_order not in (0, 1):
        raise ValueError("z_order must be 0 or 1")
    eps = np.asarray(cell.eps, dtype=complex)
    nx, ny, nz = eps.shape
    lx, ly = (float(p) for p in cell.period_nm)
    eb = choose_background(eps, min_loss) if eps_background is None else \
        complex(complex(eps_background).real, max(complex(eps_background).imag, min_loss))
    k0 = 2 * math.pi / wavelength_nm
    m = np.rint(sfft.fftfreq(nx, 1.0 / nx)).astype(int)[:, None] * np.ones((1, ny), int)
    n = np.rint(sfft.fftfreq(ny, 1.0 / ny)).astype(int)[None, :] * np.ones((nx, 1), int)
    kx = kx0 + 2 * math.pi * m / lx
    ky = ky0 + 2 * math.pi * n / ly
    kt2 = kx * kx + ky * ky
    k2 = k0 * k0
    kap = vertical_wavenumber(k2 * eb, kt2)
    ka = vertical_wavenumber(k2 * complex(cell.eps_above).real, kt2)
    kc = vertical_wavenumber(k2 * complex(cell.eps_below).real, kt2)
    sg = slab_green(kap, ka, kc, cell.thickness_nm, nz, z_order + 1)
    w = default_workers() if workers is None else int(workers)
    toe_spec, han_spec = kernel_spectra(sg, None, dtype, w)
    ptop, pbot = face_profiles(sg)
    contrast = (k2 * (eps - eb)).astype(dtype)
    return LayerOperator(cell, float(wavelength_nm), float(kx0), float(ky0), eb, m, n, kx, ky, sg,
                         contrast, toe_spec, han_spec, ptop.astype(dtype), pbot.astype(dtype), w)


def kernel_spectra(sg: SlabGreen, offset_nm: float | None, dtype: type, workers: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """FFTs (length 2nz) of the circulant kernels, shape (P, nb, nx, ny, 2nz), built one block at
    a time in complex128 and stored in dtype."""
    npt = sg.nb if offset_nm is None else 1
    shape = (npt, sg.nb) + sg.kappa.shape + (2 * sg.nz,)
    toe_spec, han_spec = np.empty(shape, dtype=dtype), np.empty(shape, dtype=dtype)
    for p, q, toe, han in circulant_blocks(sg, offset_nm):
        toe_spec[p, q] = sfft.fft(toe, axis=-1, workers=workers, overwrite_x=True)
        han_spec[p, q] = sfft.fft(han, axis=-1, workers=workers, overwrite_x=True)
    return toe_spec, han_spec


def convolve_z(op: LayerOperator, fhat: np.ndarray, toe_spec: np.ndarray,
               han_spec: np.ndarray) -> np.ndarray:
    """Apply Toeplitz+Hankel z-kernels (P, nb, ..., 2nz) to lateral-DFT moments (nb, ..., nz).

    Circular convolution for the Toeplitz part, T̂[q]·X[q]; the Hankel part is a correlation,
    Ĥ[q]·X[−q mod 2nz], taken from a reversed view of X (no copy).
    """
    nz = fhat.shape[-1]
    xs = sfft.fft(fhat, n=2 * nz, axis=-1, workers=op.workers)
    xrev = xs[..., :0:-1]                       # X[−q] for q = 1 … 2nz−1
    npt, nb = toe_spec.shape[:2]
    ys = np.empty((npt,) + xs.shape[1:], dtype=np.result_type(xs, toe_spec))
    tmp = np.empty(xs.shape[1:], dtype=ys.dtype)
    for p in range(npt):
        acc = ys[p]
        for q in range(nb):
            if q == 0:
                np.multiply(toe_spec[p, q], xs[q], out=acc)
            else:
                np.multiply(toe_spec[p, q], xs[q], out=tmp)
                acc += tmp
            np.multiply(han_spec[p, q, ..., 1:], xrev[q], out=tmp[..., 1:])
            tmp[..., 0] = han_spec[p, q, ..., 0] * xs[q, ..., 0]
            acc += tmp
    return sfft.ifft(ys, axis=-1, workers=op.workers, overwrite_x=True)[..., :nz]


def apply_green(op: LayerOperator, f: np.ndarray) -> np.ndarray:
    """Galerkin moments of G·f for a source f with moments (nb, nx, ny, nz) at the nodes."""
    fh = sfft.fft2(f, axes=(1, 2), workers=op.workers)
    y = convolve_z(op, fh, op.toe_spec, op.han_spec)
    return sfft.ifft2(y, axes=(1, 2), workers=op.workers, overwrite_x=True)


def apply_system(op: LayerOperator, w: np.ndarray) -> np.ndarray:
    """(I − G V)·w: one operator application."""
    return w - apply_green(op, op.contrast * w)


def apply_scattering(op: LayerOperator, w: np.ndarray) -> np.ndarray:
    """G V·w (the Born-series map without the source)."""
    return apply_green(op, op.contrast * w)
