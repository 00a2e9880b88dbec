"""Absorbed power from ∫ Im ε |u|², the independent check of the energy balance.

With the discretisation of operator.py the scheme's field obeys an exact discrete energy
identity:  R + T + A = 1 with

    A = k0² [Σ_cells Im(ε − ε_b) Σ_q|c_q|² ΔV + Im(ε_b) ∫_slab |u|² dV] / (Lx·Ly·k_z,inc)

(lateral Parseval on the trigonometric interpolant; the source is the Legendre projection of
V·u in every z-cell, c_q the field's orthonormal moments, c_0 = ū the cell average).  ∫|u|²
uses the exact intra-cell field of the scheme, evaluated at Gauss–Legendre points of every
z-cell.  The midpoint value k0² Σ Im ε |ū|² ΔV/(Lx·Ly·k_z,inc) differs from it by O(h²).
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from .kernel1d import background_amplitudes, face_profiles
from .operator import LayerOperator, convolve_z, kernel_spectra

#: Gauss–Legendre points per z-cell for ∫|u|²: the intra-cell field is smooth (exponentials
#: plus a polynomial).  On the reference case at 64×64×32, 3 points agree with 6 to 1e-8
#: relative; 2 points leave an energy error ~1e-6 on a k = 1.1 slab.
GAUSS_POINTS = 3


def slab_field_energy(op: LayerOperator, w_b_coef: complex, f: np.ndarray, from_below: bool,
                      n_gauss: int = GAUSS_POINTS) -> float:
    """∫_slab |u|² dV (nm³) of the scheme's continuous field (unit incident amplitude)."""
    nx, ny, nz = op.shape
    h = op.green.h_nm
    xg, wg = np.polynomial.legendre.leggauss(n_gauss)
    fh = sfft.fft2(f, axes=(1, 2), workers=op.workers)
    total = 0.0
    for xq, wq in zip(xg, wg):
        s = 0.5 * h * (xq + 1)
        ts, hs = kernel_spectra(op.green, s, op.dtype, op.workers)
        u = convolve_z(op, fh, ts, hs)              # lateral DFT of the scattered field
        ptop, pbot = face_profiles(op.green, s)
        prof = pbot if from_below else ptop
        u[0, 0, 0] += nx * ny * w_b_coef * prof[0, 0, 0]
        total += 0.5 * wq * h * float(np.sum(np.abs(u) ** 2))
    lx, ly = op.cell.period_nm
    return total * lx * ly / (nx * ny) ** 2


def absorption(op: LayerOperator, w: np.ndarray, f: np.ndarray, from_below: bool,
               kz_inc: float, exact: bool = True) -> tuple[float, float]:
    """(A_scheme, A_midpoint) as fractions of the incident power.

    w: the solved periodic field (moments, (nb, nx, ny, nz)); f = V·w.  When exact is False,
    A_scheme is returned equal to A_midpoint.
    """
    nx, ny, nz = op.shape
    lx, ly = op.cell.period_nm
    h = op.green.h_nm
    k2 = op.k0 ** 2
    eps = np.asarray(op.cell.eps)
    moments2 = np.sum(np.abs(w.astype(np.complex128)) ** 2, axis=0)
    scale = k2 * h / (nx * ny * kz_inc)            # k0²·ΔV/(Lx·Ly·kz_inc)
    a_mid = scale * float(np.sum(eps.imag * np.abs(w[0].astype(np.complex128)) ** 2))
    if not exact:
        return a_mid, a_mid
    eb = op.eps_background
    coef, _, _ = background_amplitudes(op.green, from_below)
    a_contrast = scale * float(np.sum((eps.imag - eb.imag) * moments2))
    slab = slab_field_energy(op, complex(coef[0, 0]), f, from_below)
    a_scheme = a_contrast + k2 * eb.imag * slab / (lx * ly * kz_inc)
    return a_scheme, a_mid
