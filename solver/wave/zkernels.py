"""The z-Galerkin matrix of the layered Green's function, applied by recursions along z.

kernel1d.circulant_blocks gives the Galerkin matrix per harmonic as nb² Toeplitz + nb² Hankel
blocks.  Every entry is an exponential of the cell distance, so the matrix is semiseparable and
is applied in O(nz) per harmonic without any z-FFT (docs/wave_solver.md, "z-recursions").  With
a = e^{iκh}, the per-harmonic constants I_p (zbasis.single_integrals), F = P·h·I_0², ρ = I_1/I_0,
the diagonal Galerkin integrals c_pp, and for source moments x_p (x_1 = 0 when nb = 1)

    α_l = x_0,l − ρ x_1,l,   β_l = x_0,l + ρ x_1,l,

the moments of G·f are y_0 = F (P + Q) + c_00 x_0 and y_1 = ρF (P − Q) + c_11 x_1 with

    P_k = Σ_{l<k} a^{k−1−l} α_l + r_t r_b Σ_{l>k} a^{2nz−1−(l−k)} α_l + r_t a^k Σ_l a^l β_l
    Q_k = Σ_{l>k} a^{l−k−1} β_l + r_t r_b Σ_{l<k} a^{2nz−1−(k−l)} β_l + r_b a^{nz−1−k} Σ_l a^{nz−1−l} α_l

(the direct wave, the wave bounced off both faces, and the two single bounces).  Reversing the
cell index of the second channel (γ⁰ = α, γ¹_k = β_{nz−1−k}, r⁰ = r_t, r¹ = r_b) gives both
channels one form:

    Out^c_k = M^c_k + r_t r_b a^{nz+k}·S^c_{k+1},
    M^c_k = r^c S^{1−c}_0 a^k + Σ_{l<k} a^{k−1−l} γ^c_l   (M_0 = r^c S^{1−c}_0,
            M_k = a·M_{k−1} + γ_{k−1}: a forward recursion, |a| < 1),
    S^c_k = Σ_{l≥k} a^{nz−1−l} γ^c_l  (suffix sums of a weighted input; S_nz = 0),

P = Out⁰, Q_k = Out¹_{nz−1−k}.  Every factor has modulus ≤ 1 (evanescent harmonics only
decay, nothing is divided by a), and each step is an exact identity: the result equals the
Galerkin matrix to rounding (test: 1e-13 relative in complex128 against the dense blocks).

The operator's unknowns are laid out z-major here, (nb, nz, nx·ny): a z-cell is a contiguous
row of lateral harmonics, so every recursion step is one vector operation over nx·ny values
and the lateral FFTs run over the two contiguous last axes (operator.py).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fftback import FFT
from .scratch import borrow, give_back
from .kernel1d import SlabGreen
from .zbasis import diag_galerkin, single_integrals


@dataclass(frozen=True, eq=False)
class ZKernels:
    """Per-harmonic z-operator data in dtype; H = nx·ny lateral harmonics in FFT order
    (C order of the (nx, ny) arrays).

    step: (H,) a = e^{iκh}; powers: (nz, H) a^j for j = 0 … nz−1; edge: (H,) a^{nz};
    far_powers: (nz − 1, H) r_t r_b a^{nz+j}; refl: (2, H) [r_t, r_b]; integral0: (H,) I_0;
    scale: (H,) F = P·h·I_0² (nm); scale_ratio: (H,) F·ρ (nm);
    ratio: (H,) ρ = I_1/I_0 (0 when nb = 1); diag: (nb, H) c_00, c_11 (nm).  scale,
    scale_ratio and diag include the lateral 1/(nx·ny) of an unnormalised inverse FFT.
    """

    step: np.ndarray
    powers: np.ndarray
    edge: np.ndarray
    far_powers: np.ndarray
    refl: np.ndarray
    integral0: np.ndarray
    scale: np.ndarray
    scale_ratio: np.ndarray
    ratio: np.ndarray
    diag: np.ndarray
    nz: int
    nb: int


def z_kernels(sg: SlabGreen, dtype: type, normalised: bool = True,
              backend: FFT | None = None) -> ZKernels:
    """The recursion constants, computed in complex128 on the host and stored in dtype as
    arrays of the backend (fftback.py; None: host NumPy).

    normalised False: the operator's inverse lateral FFT does not divide by nx·ny, so 1/(nx·ny)
    is folded into scale, scale_ratio and diag here.
    """
    nz, nb, h = sg.nz, sg.nb, sg.h_nm
    size = sg.kappa.size
    rows = sg.exp_rows(nz + 1).reshape(nz + 1, size)      # a^j, j = 0 … nz
    step, edge = rows[1], rows[nz]
    rtrb = (sg.r_top * sg.r_bottom).reshape(size)
    x = 1j * sg.kappa.reshape(size) * h
    integ = single_integrals(x, nb)
    ph = sg.prefactor.reshape(size) * h
    lateral = 1.0 if normalised else 1.0 / size
    scale = ph * integ[0] * integ[0] * lateral
    ratio = integ[1] / integ[0] if nb > 1 else np.zeros_like(x)
    # e^{2iκH} = a^{2nz} and a^{2nz−1}: the wave bounced off both faces
    diag = [ph * (diag_galerkin(p, p, x, np.ones_like(x), step)
                  + rtrb * diag_galerkin(p, p, -x, edge * edge, edge * rows[nz - 1])) * lateral
            for p in range(nb)]
    far_powers = rtrb * edge * rows[:nz - 1]

    def cast(a) -> np.ndarray:
        return np.ascontiguousarray(a, dtype=dtype) if backend is None else backend.asarray(a, dtype)

    return ZKernels(cast(step), cast(rows[:nz]), cast(edge), cast(far_powers),
                    cast(np.stack([sg.r_top.reshape(size), sg.r_bottom.reshape(size)])),
                    cast(integ[0]), cast(scale), cast(scale * ratio), cast(ratio),
                    cast(np.stack(diag)), nz, nb)


class ZWork:
    """Scratch arrays of apply_z for nz cells × `size` harmonics (reused across applications;
    borrowed from the thread's scratch pool, scratch.py, until release())."""

    def __init__(self, nz: int, size: int, dtype: np.dtype, backend: FFT | None = None):
        self.backend = backend
        self.gam = borrow((2, nz, size), dtype, backend)
        self.suf = borrow((2, nz, size), dtype, backend)
        self.low = borrow((2, nz, size), dtype, backend)
        self.tmp = borrow((nz, size), dtype, backend)

    def release(self) -> None:
        give_back(self.gam, self.suf, self.low, self.tmp, backend=self.backend)
        del self.gam, self.suf, self.low, self.tmp


def z_sums(zk: ZKernels, xh: np.ndarray, work: ZWork) -> tuple[np.ndarray, np.ndarray]:
    """(P, Q) of the module doc, each (nz, H), for the lateral-DFT source moments xh
    (nb, nz, H) (unchanged); views into `work`, valid until its next use."""
    nz = zk.nz
    gam, suf, low, tmp = work.gam, work.suf, work.low, work.tmp
    x0 = xh[0]
    if zk.nb > 1:
        np.multiply(xh[1], zk.ratio, out=tmp)
        np.subtract(x0, tmp, out=gam[0])              # γ⁰ = α
        np.add(x0, tmp, out=gam[1, ::-1])             # γ¹ = β reversed
    else:
        gam[0] = x0
        gam[1, ::-1] = x0
    np.multiply(gam, zk.powers[::-1], out=suf)        # a^{nz−1−l} γ_l
    for k in range(nz - 2, -1, -1):                   # suffix sums S_k
        suf[:, k] += suf[:, k + 1]
    # L_k + a^k r^c S^{1−c}_0 = M_k: M_k = a M_{k−1} + γ_{k−1} from M_0 = r^c S^{1−c}_0
    np.multiply(zk.refl, suf[::-1, 0], out=low[:, 0])
    for k in range(1, nz):
        np.multiply(low[:, k - 1], zk.step, out=low[:, k])
        low[:, k] += gam[:, k - 1]
    bounce = suf[:, 1:]                               # r_t r_b a^{nz+k} S_{k+1}, k < nz−1
    bounce *= zk.far_powers
    low[:, :nz - 1] += bounce
    return low[0], low[1, ::-1]


def apply_z(zk: ZKernels, xh: np.ndarray, work: ZWork) -> np.ndarray:
    """Moments (nb, nz, H) of G·f from the lateral-DFT source moments xh (nb, nz, H), written
    into xh and returned (module doc)."""
    p, q = z_sums(zk, xh, work)
    tmp, x0 = work.tmp, xh[0]
    np.add(p, q, out=tmp)
    tmp *= zk.scale
    if zk.nb > 1:
        p -= q
        p *= zk.scale_ratio
        xh[1] *= zk.diag[1]
        xh[1] += p
    x0 *= zk.diag[0]
    x0 += tmp
    return xh


def face_sums(zk: ZKernels, xh: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Σ_{q,k} p_top[q, k]·xh[q, k] and the same with p_bot, per harmonic (H,), for z-major
    moments xh (nb, nz, H): the face profiles' moments (kernel1d.face_profiles) are
    p_top[q, k] = I_q (a^k + (−1)^q r_b a^{2nz−1−k}) and
    p_bot[q, k] = I_q ((−1)^q a^{nz−1−k} + r_t a^{nz+k}), so that with α, β of the module doc
    the sums are I_0 (T_β + r_b a^{nz} T_α) and I_0 (T_α + r_t a^{nz} T_β),
    T_α = Σ_k a^{nz−1−k} α_k, T_β = Σ_k a^k β_k: two weighted sums, no profile arrays."""
    x0 = xh[0]
    if zk.nb > 1:
        t = xh[1] * zk.ratio
        alpha, beta = x0 - t, x0 + t
    else:
        alpha = beta = x0
    t_a = np.einsum("kh,kh->h", zk.powers[::-1], alpha)
    t_b = np.einsum("kh,kh->h", zk.powers, beta)
    edge = zk.edge * zk.integral0
    return (zk.integral0 * t_b + zk.refl[1] * edge * t_a,
            zk.integral0 * t_a + zk.refl[0] * edge * t_b)
