"""The z-Galerkin matrix of the layered Green's function in its reduced FFT form.

kernel1d.circulant_blocks gives the Galerkin matrix per harmonic as nb² Toeplitz + nb² Hankel
blocks (8 kernel spectra for nb = 2).  Their structure makes 4 enough (docs/wave_solver.md,
"Reduced z-kernels"): with the per-harmonic constants I_p (zbasis.single_integrals),
s_p = P·h·I_p and the diagonal Galerkin integrals c_pp, and the sequences (d = 1 … nz−1,
σ = 0 … 2nz−2; tab[j] = e^{iκjh})

    A[d] = tab[d−1],  B[d] = r_t r_b·tab[2nz−d−1],  C[σ] = r_t·tab[σ],  D[σ] = r_b·tab[2nz−2−σ],

the moments y_p of G·f for source moments x_p are, with α = I_0 x_0 − I_1 x_1 and
β = I_0 x_0 + I_1 x_1 (x_1 = 0 when nb = 1),

    p = K_A ⊛ α + C ⋆ β,   q = K_B ⊛ β + D ⋆ α,
    y_0 = s_0 (p + q) + c_00 x_0,   y_1 = s_1 (p − q) + c_11 x_1,

where ⊛ is the circular convolution of length 2nz, ⋆ the Hankel product Σ_l C[k+l]·β_l,
K_A the circulant with A below the diagonal and B above it, K_B the reverse.  The Hankel
products are circular convolutions with the index-reversed input β̃_j = β_{−j mod 2nz}, and q
is computed in the reversed frame (q̌_j = q_{−j}), so all four spectra multiply the same two
transformed rows [α, β̃]: one forward and one inverse z-FFT of two rows, 4 products, 2 sums.
The factors I_0 (of α, β) and s_0 (of p, q) are folded into the spectra, so that the inputs are
α′ = x_0 − ρ x_1, β′ = x_0 + ρ x_1 with ρ = I_1/I_0 = s_1/s_0; so is the diagonal c_00 (a
constant c_00/2 added to the spectra of K_A and K̃_B adds c_00·x_0 to y_0 and −ρ² c_00 x_1 to
y_1), leaving y_0 = p′ + q′ and y_1 = ρ(p′ − q′) + (c_11 + ρ² c_00)·x_1.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fftback import aligned_empty
from .kernel1d import SlabGreen
from .zbasis import diag_galerkin, single_integrals


@dataclass(frozen=True, eq=False)
class ZKernels:
    """Per-harmonic z-operator data (lateral shape (nx, ny) in FFT order), in dtype.

    spec: (4, nx, ny, 2nz) spectra s_0·I_0·[K_A, C, D̃, K̃_B] + c_00/2·[1, 0, 0, 1]
    (D̃, K̃_B index-reversed), nm; ratio: (nx, ny, 1) ρ = I_1/I_0 (0 when nb = 1);
    diag1: (nx, ny, 1) c_11 + ρ² c_00 (nm).
    """

    spec: np.ndarray
    ratio: np.ndarray
    diag1: np.ndarray
    nz: int
    nb: int


def _reverse(a: np.ndarray) -> np.ndarray:
    """b[j] = a[(−j) mod n] along the last axis."""
    return np.concatenate([a[..., :1], a[..., :0:-1]], axis=-1)


def z_kernels(sg: SlabGreen, dtype: type, fft, normalised: bool = True) -> ZKernels:
    """Build the reduced kernels in complex128 and store them in dtype.

    fft(a) transforms along the last axis (the operator's FFT backend, fftback.py).
    normalised False: the backend's inverse transforms do not divide by n, so 1/(2nz) (z) and
    1/(nx·ny) (lateral) are folded into the spectra and diag1 here.
    """
    nz, nb, h = sg.nz, sg.nb, sg.h_nm
    m = 2 * nz
    tab = sg.exp_table()
    rt, rb = sg.r_top[..., None], sg.r_bottom[..., None]
    rtrb = rt * rb
    x = 1j * sg.kappa * h
    integ = single_integrals(x, nb)
    ph = sg.prefactor * h
    kern = np.zeros((4,) + sg.kappa.shape + (m,), dtype=complex)
    a = tab[..., 0:nz - 1]                            # A[d], d = 1 … nz−1
    b = rtrb * tab[..., nz:2 * nz - 1][..., ::-1]     # B[d] = r_t r_b tab[2nz − d − 1]
    kern[0, ..., 1:nz] = a                            # K_A: A below, B above the diagonal
    kern[0, ..., nz + 1:] = b[..., ::-1]
    kern[3, ..., 1:nz] = b                            # K_B: B below, A above
    kern[3, ..., nz + 1:] = a[..., ::-1]
    kern[1, ..., :m - 1] = rt * tab[..., 0:m - 1]                 # C[σ]
    kern[2, ..., :m - 1] = rb * tab[..., 0:m - 1][..., ::-1]      # D[σ] = r_b tab[2nz−2−σ]
    kern[2] = _reverse(kern[2])
    kern[3] = _reverse(kern[3])
    kern *= (ph * integ[0] * integ[0])[..., None]
    spec = fft(kern)
    diag = [ph * (diag_galerkin(p, p, x, np.ones_like(x), tab[..., 1])
                  + rtrb[..., 0] * diag_galerkin(p, p, -x, tab[..., m], tab[..., m - 1]))
            for p in range(nb)]
    spec[0] += 0.5 * diag[0][..., None]
    spec[3] += 0.5 * diag[0][..., None]
    ratio = integ[1] / integ[0] if nb > 1 else np.zeros_like(x)
    diag1 = diag[1] + ratio * ratio * diag[0] if nb > 1 else np.zeros_like(x)
    if not normalised:
        lateral = 1.0 / x.size
        spec *= lateral / m
        diag1 = diag1 * lateral
    return ZKernels(spec.astype(dtype), ratio[..., None].astype(dtype),
                    diag1[..., None].astype(dtype), nz, nb)


class ZWork:
    """Scratch arrays of apply_z for one lateral shape (reused across applications)."""

    def __init__(self, lateral: tuple[int, int], nz: int, dtype: np.dtype):
        self.buf = aligned_empty((2,) + lateral + (2 * nz,), dtype)
        self.ta = np.empty(lateral + (2 * nz,), dtype=dtype)
        self.tb = np.empty(lateral + (2 * nz,), dtype=dtype)
        self.v = np.empty(lateral + (nz,), dtype=dtype)


def apply_z(zk: ZKernels, xh: np.ndarray, work: ZWork, fft, ifft) -> np.ndarray:
    """Moments (nb, nx, ny, nz) of G·f from the lateral-DFT source moments xh, written into xh.

    fft / ifft: in-place length-2nz transforms along the last axis.
    """
    nz = zk.nz
    buf, v = work.buf, work.v
    x0 = xh[0]
    if zk.nb > 1:
        np.multiply(xh[1], zk.ratio, out=v)
        np.subtract(x0, v, out=buf[0, ..., :nz])      # α′
        v += x0                                       # β′
    else:
        buf[0, ..., :nz] = x0
        v[...] = x0
    buf[0, ..., nz:] = 0
    buf[1, ..., 0] = v[..., 0]                        # β̃′_j = β′_{−j mod 2nz}
    buf[1, ..., 1:nz + 1] = 0
    buf[1, ..., nz + 1:] = v[..., :0:-1]
    f = fft(buf)
    f0, f1 = f
    spec = zk.spec
    np.multiply(spec[2], f0, out=work.ta)
    f0 *= spec[0]
    np.multiply(spec[1], f1, out=work.tb)
    f0 += work.tb                                     # P = K_A·A + C·B̃
    f1 *= spec[3]
    f1 += work.ta                                     # Q̌ = D̃·A + K̃_B·B̃
    r = ifft(f)
    p = r[0, ..., :nz]
    v[..., 0] = r[1, ..., 0]                          # q_k = q̌_{−k mod 2nz}
    v[..., 1:] = r[1, ..., :nz:-1]
    if zk.nb > 1:
        xh[1] *= zk.diag1
        np.add(p, v, out=x0)
        p -= v
        p *= zk.ratio
        xh[1] += p
    else:
        np.add(p, v, out=x0)
    return xh
