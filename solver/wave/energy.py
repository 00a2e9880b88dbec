"""Absorbed power and the energy closure R + T + A − 1 of a solve.

The scheme's field u = u_b + G·s (s: the Legendre projection of V·w in every z-cell,
trigonometric laterally) solves the background equation exactly, so Green's identity over the
slab holds per lateral harmonic (docs/wave_solver.md, "Energy"):

    TE:  R + T − 1 + A_b + Im⟨u, s⟩/N = 0,   A_b = k0² Im ε_b ∫_slab |u|² dV / N,
    N = Lx·Ly·k_z,inc.  With A = a_V + A_b, a_V = k0² Σ Im(ε − ε_b) Σ_q |c_q|² ΔV / N:

    E = R + T + A − 1 = Im⟨w − P u, V w⟩ ΔV / N = −Im⟨r, f⟩ ΔV / N,

r = b − (I − GV)·w the true residual, f = V·w.  `closure` gives A and E from r at the cost of
one inner product: E measures how far w is from solving the scheme (it is 0 for an exact
solve), the kernels being right.  `absorption` computes A independently by quadrature of
∫|u|² (GAUSS_POINTS per z-cell, exact intra-cell field), a check of the kernels themselves:
its E agrees with the closure's to ~1e-8 (tests).

TM (per-harmonic face forms, faces.py): at a face the slab-side flux of a harmonic whose
reported amplitude is a is Re(ψ)|a|² (ψ the face's flux coefficient; H_y faces: ψ = (ε_f/ε)k_z),
and the incident 00 wave with reflection ρ carries Re(ψ_in)(1 − |ρ|²) + 2s·Im(ψ_in)·Im ρ
(s = ±1, faces.py), so the scalar identity becomes

    Re ψ_in·(R + T − 1) + Φ + k_z,inc·(a_V + A_b + Im⟨u, s⟩/N) = 0,
    Φ = −2s·Im(ψ_in)·Im(ρ) + Σ_non-propagating, both faces Re(ψ)|a|²

(powers R, T = Σ Re(ψ)|a|²/Re ψ_in over propagating orders), hence
A = (k_z,inc·(a_V + A_b) + Φ)/Re ψ_in and E = (k_z,inc/Re ψ_in)·E_TE.  With H_y faces everywhere
(the first TM model) this is Re ε_f·(R + T − 1) + Im ε_f·Φ' + ε_in·(…) = 0: the faces exchange
energy only through Im ε_f.
"""
from __future__ import annotations

import numpy as np

from .kernel1d import background_amplitudes, face_profiles, harmonic_green, point_self_terms
from .operator import LayerOperator
from .orders import OrderSet
from .vecops import dot
from .zbasis import single_integrals
from .zkernels import ZWork, z_kernels, z_sums

#: Gauss–Legendre points per z-cell for ∫|u|²: the intra-cell field is smooth (exponentials
#: plus a polynomial).  On a k = 1.1 slab at 60°, 32 cells per µm, the identity closes to
#: 2e-7 (TE) / 3.2e-7 (TM, default faces) with 3 points, 2e-10 / 3.5e-10 with 4, 1e-15 with 6.
GAUSS_POINTS = 4


def _tm_scale(op: LayerOperator, from_below: bool, kz_inc: float) -> float | None:
    """k_z,inc/Re ψ_in for per-harmonic face forms (TM), None for TE."""
    faces = op.green.faces
    if faces is None:
        return None
    psi_in = (faces[1] if from_below else faces[0]).psi[0, 0]
    return kz_inc / float(psi_in.real)


def _scale(op: LayerOperator, kz_inc: float) -> float:
    """ΔV/(Lx·Ly·k_z,inc) = h/(nx·ny·k_z,inc) in nm²."""
    nx, ny, _ = op.shape
    return op.green.h_nm / (nx * ny * kz_inc)


def midpoint_absorption(op: LayerOperator, w: np.ndarray, from_below: bool,
                        kz_inc: float) -> float:
    """k0² Σ Im ε |ū|² ΔV / N from the cell averages (O(h²) below the scheme's A); TM: times
    k_z,inc/Re ψ_in."""
    eps = np.asarray(op.cell.eps)
    a_mid = op.k0 ** 2 * _scale(op, kz_inc) * float(
        np.sum(eps.imag * np.abs(w[0].astype(np.complex128)) ** 2))
    tm = _tm_scale(op, from_below, kz_inc)
    return a_mid if tm is None else tm * a_mid


def closure(op: LayerOperator, r: np.ndarray, f: np.ndarray, big_r: float, big_t: float,
            from_below: bool, kz_inc: float) -> tuple[float, float]:
    """(A, E) from the true residual r = b − (I − GV)w and f = V·w (see the module doc)."""
    e = -_scale(op, kz_inc) * dot(r.ravel(), f.ravel()).imag
    tm = _tm_scale(op, from_below, kz_inc)
    if tm is not None:
        e *= tm
    return 1.0 - big_r - big_t + e, e


def slab_field_energy(op: LayerOperator, w_b_coef: complex, f: np.ndarray, from_below: bool,
                      n_gauss: int = GAUSS_POINTS) -> float:
    """∫_slab |u|² dV (nm³) of the scheme's continuous field (unit incident amplitude), in
    complex128, for the z-major source moments f (nb, nz, nx, ny) of the operator's backend.

    The scattered field at z = k·h + s inside cell k is, per lateral harmonic, with the
    z-recursion sums (P, Q) of the operator (zkernels.py) for the source moments f:
    u = P·h·I_0·(e^{iκs}·P_k + e^{iκ(h−s)}·Q_k) + Σ_q d_q(s)·f_q,k, d_q the same-cell terms
    (kernel1d.point_self_terms): the point kernels of kernel1d.circulant_blocks, regrouped
    (docs/wave_solver.md, "Energy closure").  One recursion serves every quadrature point.
    """
    nx, ny, nz = op.shape
    sg, size = op.green, nx * ny
    h = sg.h_nm
    arrays = op.fft                                   # the operator's array backend (fftback.py)
    xg, wg = np.polynomial.legendre.leggauss(n_gauss)
    fz = arrays.empty(f.shape, np.complex128)
    np.copyto(fz, f)                                  # z-major source moments, complex128
    fh = arrays.lateral(fz).reshape(sg.nb, nz, size)
    tab = sg.exp_table()
    work = ZWork(nz, size, np.complex128, arrays)
    p, q = z_sums(z_kernels(sg, np.complex128, backend=arrays), fh, work)
    amp = (sg.prefactor * h * single_integrals(1j * sg.kappa * h, 1)[0]).reshape(size)
    kappa = sg.kappa.reshape(size)
    u = arrays.empty((nz, size), np.complex128)
    sg00 = harmonic_green(sg, (slice(0, 1), slice(0, 1)))
    total = 0.0
    for xq, wq in zip(xg, wg):
        s = 0.5 * h * (xq + 1)
        np.multiply(arrays.asarray(amp * np.exp(1j * kappa * s)), p, out=u)
        u += arrays.asarray(amp * np.exp(1j * kappa * (h - s))) * q
        for moment, term in zip(fh, point_self_terms(sg, s, tab)):
            u += arrays.asarray(term.reshape(size)) * moment
        ptop, pbot = face_profiles(sg00, s)
        prof = pbot if from_below else ptop
        u[:, 0] += arrays.asarray(size * w_b_coef * prof[0, 0, 0])   # the background wave (00)
        total += 0.5 * wq * h * float(np.vdot(u, u).real)
    work.release()
    lx, ly = op.cell.period_nm
    return total * lx * ly / size ** 2


def face_term(op: LayerOperator, refl: OrderSet, trans: OrderSet, from_below: bool) -> float:
    """Φ of the TM identity (module doc, 1/nm): what the faces exchange besides the orders'
    powers (Im ψ of the incident wave, flux coefficients of the non-propagating harmonics)."""
    faces = op.green.faces
    f_in, f_out = (faces[1], faces[0]) if from_below else faces
    psi_in, s_in = f_in.psi[0, 0], float(f_in.sign[0, 0])
    total = -2.0 * s_in * psi_in.imag * refl.amp(0, 0).imag
    for orders, face in ((refl, f_in), (trans, f_out)):
        evan = ~orders.propagating
        total += float(np.sum(face.psi.ravel()[evan].real * np.abs(orders.amplitude[evan]) ** 2))
    return float(total)


def absorption(op: LayerOperator, w: np.ndarray, f: np.ndarray, from_below: bool,
               kz_inc: float, refl: OrderSet, trans: OrderSet) -> float:
    """A by quadrature of ∫|u|² (independent of R and T), as a fraction of the incident power.

    w: the solved periodic field (moments, (nb, nx, ny, nz), on the host); f = V·w (z-major,
    (nb, nz, nx, ny), an array of the operator's backend).
    """
    if op.interfaces is not None:
        raise ValueError("exact_energy: the quadrature of ∫|u|² does not weigh a TM stack's layers "
                         "(interfaces.py); its energy closes from the residual (exact_energy=False)")
    lx, ly = op.cell.period_nm
    eb = op.eps_background
    eps = np.asarray(op.cell.eps)
    moments2 = np.sum(np.abs(w.astype(np.complex128)) ** 2, axis=0)
    a_contrast = op.k0 ** 2 * _scale(op, kz_inc) * float(np.sum((eps.imag - eb.imag) * moments2))
    coef, _, _ = background_amplitudes(op.green, from_below)
    slab = slab_field_energy(op, complex(coef[0, 0]), f, from_below)
    a_scalar = a_contrast + op.k0 ** 2 * eb.imag * slab / (lx * ly * kz_inc)
    tm = _tm_scale(op, from_below, kz_inc)
    if tm is None:
        return a_scalar
    return tm * (a_scalar + face_term(op, refl, trans, from_below) / kz_inc)
