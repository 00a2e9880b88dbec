"""Integrals of the z-basis against exponentials, in forms that stay accurate for small |x|.

Per z-cell the field is expanded in orthonormal Legendre polynomials of t = (z − z_cell)/h:
φ_0 = 1 and (z_order 1) φ_1 = √3·(2t − 1).  With x = iκh (Re x ≤ 0) this module gives

    I_q(x)   = ∫₀¹ φ_q(t) e^{x t} dt,   and ∫₀¹ φ_q(t) e^{x(1−t)} dt = s_q·I_q, s_q = (−1)^q
    J_pq(x)  = ∫₀¹∫₀¹ φ_p(t) φ_q(t′) e^{x|t−t′|} dt dt′ = A_pq(x) + e^x·B_pq(x)
    L_q, R_q = ∫₀^τ φ_q(t′) e^{x(τ−t′)} dt′,  ∫_τ¹ φ_q(t′) e^{x(t′−τ)} dt′   (τ inside the cell)

Series are used for |x| < 0.5 (cancellation-free), closed forms above.  J_01 = J_10 = 0.
"""
from __future__ import annotations

import math

import numpy as np

_SERIES_RADIUS = 0.5
_NTERMS = 18
_SQ3 = math.sqrt(3.0)
_F = [math.factorial(n) for n in range(_NTERMS + 6)]

# Taylor coefficients c_n of the functions below, f(x) = Σ c_n x^n
_C_PHI1 = [1 / _F[n + 1] for n in range(_NTERMS)]
_C_PHI2 = [1 / _F[n + 2] for n in range(_NTERMS)]
_C_PSI = [1 / (_F[n] * (n + 2)) for n in range(_NTERMS)]
_C_I1 = [_SQ3 * n / _F[n + 2] for n in range(_NTERMS)]
_C_J11 = [6 / _F[n] * (1 / (3 * (n + 1)) - 1 / (n + 2) + 2 / (3 * (n + 4))) for n in range(_NTERMS)]


def _horner(x: np.ndarray, coeffs: list[float]) -> np.ndarray:
    out = np.full_like(x, coeffs[-1])
    for c in coeffs[-2::-1]:
        out = out * x + c
    return out


def _blend(x: np.ndarray, coeffs: list[float], closed) -> np.ndarray:
    """Series where |x| < radius, closed(x) elsewhere."""
    x = np.asarray(x, dtype=complex)
    small = np.abs(x) < _SERIES_RADIUS
    out = np.empty_like(x)
    out[small] = _horner(x[small], coeffs)
    xl = x[~small]
    out[~small] = closed(xl)
    return out


def phi1(x: np.ndarray) -> np.ndarray:
    """(e^x − 1)/x = ∫₀¹ e^{xt} dt."""
    return _blend(x, _C_PHI1, lambda y: np.expm1(y) / y)


def phi2(x: np.ndarray) -> np.ndarray:
    """(e^x − 1 − x)/x² = ∫₀¹ (1 − t) e^{xt} dt."""
    return _blend(x, _C_PHI2, lambda y: (np.expm1(y) - y) / (y * y))


def psi(x: np.ndarray) -> np.ndarray:
    """(e^x (x − 1) + 1)/x² = ∫₀¹ t e^{xt} dt."""
    return _blend(x, _C_PSI, lambda y: (np.exp(y) * (y - 1) + 1) / (y * y))


def single_integrals(x: np.ndarray, nb: int) -> list[np.ndarray]:
    """[I_0(x), I_1(x)][:nb]."""
    out = [phi1(x)]
    if nb > 1:
        out.append(_blend(x, _C_I1, lambda y: _SQ3 * (np.exp(y) * (y - 2) + y + 2) / (y * y)))
    return out


def sign(q: int) -> int:
    return -1 if q % 2 else 1


def diag_galerkin(p: int, q: int, x: np.ndarray, scale_a: np.ndarray,
                  scale_b: np.ndarray) -> np.ndarray:
    """scale_a·J_pq(x) with the e^x part of J taken as scale_b·B_pq(x), scale_b = scale_a·e^x.

    Passing the product scale_b separately keeps e^{2iκH}·J(−iκh) finite for evanescent κ.
    """
    x = np.asarray(x, dtype=complex)
    if p != q:
        return np.zeros_like(x)
    small = np.abs(x) < _SERIES_RADIUS
    out = np.empty_like(x)
    xs, xl = x[small], x[~small]
    if p == 0:
        out[small] = 2 * _horner(xs, _C_PHI2) * scale_a[small]
        a, b = -2 * (1 + xl) / xl ** 2, 2 / xl ** 2
    else:
        out[small] = _horner(xs, _C_J11) * scale_a[small]
        a = -6 * (1 / (3 * xl) + 1 / xl ** 2 - 4 / xl ** 4)
        b = 6 * (-1 / xl ** 2 + 4 / xl ** 3 - 4 / xl ** 4)
    out[~small] = a * scale_a[~small] + b * scale_b[~small]
    return out


def diag_point(q: int, tau: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(L_q, R_q) at the point τ ∈ [0, 1] of the cell, for decaying x (Re x ≤ 0)."""
    a, b = tau, 1.0 - tau
    fa, fb = phi1(x * a), phi1(x * b)
    if q == 0:
        return a * fa, b * fb
    pa, pb = psi(x * a), psi(x * b)
    return (_SQ3 * ((2 * a - 1) * a * fa - 2 * a * a * pa),
            _SQ3 * ((2 * a - 1) * b * fb + 2 * b * b * pb))


def diag_point_reflected(q: int, tau: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Factors (Lr_q, Rr_q) with ∫₀¹ φ_q(t′) e^{−x|τ−t′|} dt′ = e^{−xτ}·Lr_q + e^{x(τ−1)}·Rr_q."""
    a, b = tau, 1.0 - tau
    fa, fb = phi1(x * a), phi1(x * b)
    if q == 0:
        return a * fa, b * fb
    pa, pb = psi(x * a), psi(x * b)
    return (_SQ3 * (2 * a * a * pa - a * fa), _SQ3 * (b * fb - 2 * b * b * pb))
