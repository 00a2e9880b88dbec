"""The layered preconditioner: the cell's lateral-mean contrast per z-cell, solved exactly per
lateral harmonic (docs/wave_solver.md, "Layered preconditioner").

A rough top (grains standing out of the binder into air) puts a strong, laterally uniform
contrast into the cell: the air between the grains differs from the slab's ε_b by about −1.3
over the top few hundred nm.  The uniform background slab sees it as scattering, and GMRES needs
2–3× the applications of the flat layer.  Split the contrast into its lateral mean per z-cell
and the rest, V = V̄(z) + V′; V̄ does not couple lateral harmonics, so M = I − G·V̄ is, per
harmonic h, the (nb·nz)² matrix M_h = I − G_h·diag(v̄) of a 1-D stack — exactly the layered
background's Dyson equation.  The preconditioner P is M_h on the harmonics that propagate in
the slab or are weakly evanescent (|k_t| ≤ CUTOFF·k0·√|ε_b|) and the identity on the others
(their G_h is short-ranged), and the solver iterates the left-preconditioned system

    P⁻¹(I − G·V)·w = P⁻¹·w_b

(the same solution w for any P).  G_h is the z-recursion operator (zkernels.apply_z) applied to the
unit moments of every z-cell, for all kept harmonics in one call.  Where V̄ is weak (a flat
layer: ε_b is the layer's own mean) the preconditioner gains nothing and is not used
(`wanted`).  With TM inner interfaces (a stack, a rough top's mean profile) G_h carries their
rank-n correction (interfaces.Interfaces.correction), in M_h as in every application.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from .scratch import borrow, give_back
from .interfaces import green_moments
from .zkernels import ZKernels, ZWork, apply_z

#: harmonics with |k_t| ≤ CUTOFF·k0·√|ε_b| get the exact 1-D inverse (the rest: identity)
CUTOFF = 1.0
#: the preconditioner is used when the lateral-mean contrast reaches this |Δε| in some z-cell
#: (a rough top's air: ≈ 1.1; a flat layer of 300-nm spheres at 15 %: ≤ 0.2)
MIN_MEAN_CONTRAST = 0.5
MODES = ("auto", "layered", "none")


@dataclass(frozen=True, eq=False)
class Layered:
    """kept: indices of the kept harmonics in the flattened (nx·ny) FFT order; inverse and
    matrix: (S, n, n) M_h⁻¹ and M_h for them, n = nb·nz, ordered (moment, z-cell); scale:
    1/(nx·ny) when the backend's inverse FFT does not normalise (else 1)."""

    kept: np.ndarray
    inverse: np.ndarray
    matrix: np.ndarray
    scale: float


def mean_contrast(op) -> np.ndarray:
    """V̄: the lateral mean of the contrast per z-cell (nz,), 1/nm², on the host."""
    return np.asarray(op.fft.to_host(op.contrast_zmajor.mean(axis=(1, 2))))


def wanted(op, mode: str = "auto") -> bool:
    """Whether `op` gets the layered preconditioner: mode 'layered' (where it applies) or 'auto'
    (where its lateral-mean contrast is strong, MIN_MEAN_CONTRAST)."""
    if mode not in MODES:
        raise ValueError(f"preconditioner must be one of {MODES}, got {mode!r}")
    if mode == "none":
        return False
    return mode == "layered" or float(np.max(np.abs(mean_contrast(op)))) >= MIN_MEAN_CONTRAST * op.k0 ** 2


def _subset(zk: ZKernels, kept: np.ndarray, copies: int) -> ZKernels:
    """The z-constants of the kept harmonics, repeated `copies` times along the harmonic axis
    (one copy per unit source)."""
    pick = lambda a: np.tile(np.asarray(a)[..., kept], copies)
    return ZKernels(*(pick(getattr(zk, f)) for f in ("step", "powers", "edge", "far_powers", "refl",
                                                      "integral0", "scale", "scale_ratio", "ratio", "diag")),
                    nz=zk.nz, nb=zk.nb)


_PREPARED: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def prepare_layered(op) -> Layered:
    """M_h⁻¹ of the kept harmonics and V′ for the operator `op` (operator.LayerOperator),
    prepared once per operator (both sides of an incidence share it)."""
    lay = _PREPARED.get(op)
    if lay is None:
        lay = _PREPARED[op] = _prepare(op)
    return lay


def _prepare(op) -> Layered:
    nx, ny, nz = op.shape
    nb, size = op.nb, nx * ny
    n = nb * nz
    vbar = mean_contrast(op)
    kt = np.hypot(np.asarray(op.kx), np.asarray(op.ky)).reshape(size)
    kept = np.flatnonzero(kt <= CUTOFF * op.k0 * np.sqrt(abs(op.eps_background)))
    count = kept.size
    host_zk = ZKernels(*(np.asarray(op.fft.to_host(getattr(op.zk, f)), complex)
                         for f in ("step", "powers", "edge", "far_powers", "refl", "integral0", "scale",
                                   "scale_ratio", "ratio", "diag")), nz=nz, nb=nb)
    unit = np.zeros((nb, nz, n, count), complex)                   # unit source j in column block j
    unit.reshape(n, n, count)[np.arange(n), np.arange(n)] = 1.0
    unit = unit.reshape(nb, nz, n * count)
    work = ZWork(nz, n * count, complex)
    try:
        green = apply_z(_subset(host_zk, kept, n), unit, work).reshape(n, n, count)   # [i, j, h]
    finally:
        work.release()
    if not op.fft.normalised:
        green = green * size                                       # the true G (zk folds 1/N)
    green = np.moveaxis(green, 2, 0)                               # [h, i, j]
    if op.interfaces is not None:                                  # a TM stack or profile
        green = green + op.interfaces.correction(kept, op.fft.to_host)
    m = np.eye(n)[None] - green * np.tile(vbar, nb)[None, None, :]
    inverse = op.fft.asarray(np.linalg.inv(m), op.dtype)
    return Layered(op.fft.asarray(kept), inverse, op.fft.asarray(m, op.dtype),
                   1.0 if op.fft.normalised else 1.0 / size)


def _apply(matrices: np.ndarray, lay: Layered, flat: np.ndarray) -> np.ndarray:
    """matrices (S, n, n) on the kept harmonics of lateral-DFT moments flat (nb, nz, nx·ny), in
    place (the others unchanged)."""
    nb, nz, size = flat.shape
    rows = flat.reshape(nb * nz, size)
    rows[:, lay.kept] = np.einsum("hij,jh->ih", matrices, rows[:, lay.kept])
    return flat


def apply_inverse(lay: Layered, flat: np.ndarray) -> np.ndarray:
    """P⁻¹ (M_h⁻¹ on the kept harmonics) on lateral-DFT moments flat (nb, nz, nx·ny), in place."""
    return _apply(lay.inverse, lay, flat)


def unpreconditioned(op, lay: Layered, rh: np.ndarray) -> np.ndarray:
    """P·r̂ in real space (a new z-major array) for the spectrum r̂ of a preconditioned residual:
    the residual b − (I − GV)w of the system itself, since P(P⁻¹b − P⁻¹(I − GV)w) = b − (I − GV)w.
    GMRES's residual comes from its Arnoldi relation (krylov.gmres), so the true residual costs
    one inverse DFT here instead of an operator application."""
    nb, nz, nx, ny = rh.shape
    flat = rh.copy()
    _apply(lay.matrix, lay, flat.reshape(nb, nz, nx * ny))
    return op.fft.lateral(flat, inverse=True)


def to_fourier(op, lay: Layered, w: np.ndarray) -> np.ndarray:
    """ŵ = lay.scale · DFT(w) of z-major moments w (nb, nz, nx, ny), a new array: the lateral
    spectrum in the convention of apply_z's output, so that the backend's inverse lateral DFT
    of ŵ is w again."""
    wh = op.fft.lateral(op.fft.asarray(w).copy())
    if lay.scale != 1.0:
        wh *= lay.scale
    return wh


def from_fourier(op, wh: np.ndarray) -> np.ndarray:
    """w from its spectrum ŵ (to_fourier), a new array."""
    return op.fft.lateral(wh.copy(), inverse=True)


def scatter(op, lay: Layered, wh: np.ndarray, ws, out: np.ndarray | None = None) -> np.ndarray:
    """K′·ŵ = ŵ − P⁻¹(I − GV)·ŵ on the lateral spectrum ŵ (to_fourier) of z-major moments
    (nb, nz, nx, ny), into out or a new array: the map whose fixed-point equation ŵ − K′ŵ = P⁻¹b̂
    is the preconditioned system.  The iteration runs on spectra (the DFT is unitary up to a
    constant, so GMRES's iterates and relative residuals are those of the real-space system):
    with w the inverse DFT of ŵ and g = (GVw)^, per kept harmonic ŵ + M_h⁻¹(g − ŵ), elsewhere g
    (P = I) — two lateral DFTs per application, as an unpreconditioned one (in real space it
    took a third, for ŵ)."""
    if out is None:
        out = op.fft.empty(wh.shape, op.dtype)
    nb, nz, nx, ny = wh.shape
    size = nx * ny
    spare = borrow(wh.shape, op.dtype, op.fft)
    try:
        np.copyto(spare, wh)
        w = op.fft.lateral(spare, inverse=True)
        fh = op.fft.lateral(np.multiply(op.contrast_zmajor, w, out=out))
    finally:
        give_back(spare, backend=op.fft)
    flat = fh.reshape(nb, nz, size)
    green_moments(op.zk, op.interfaces, flat, ws.z)
    rows = flat.reshape(nb * nz, size)
    src = wh.reshape(nb * nz, size)[:, lay.kept]
    rows[:, lay.kept] = src + np.einsum("hij,jh->ih", lay.inverse, rows[:, lay.kept] - src)
    if not op.fft.same_buffer(fh, out):
        np.copyto(out, fh)
    return out


def right_hand_side(op, lay: Layered, b: np.ndarray) -> np.ndarray:
    """The spectrum (to_fourier's convention) of M⁻¹·b for a z-major right-hand side b (a new
    array)."""
    nb, nz, nx, ny = b.shape
    fh = to_fourier(op, lay, b)
    apply_inverse(lay, fh.reshape(nb, nz, nx * ny))
    return fh
