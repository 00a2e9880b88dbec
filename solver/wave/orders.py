"""Diffraction orders from the solved field: amplitudes, directions, power fractions.

Reference planes: a wave leaving through the top face is referenced to z_top, one leaving
through the bottom face to z_bottom, and the incident wave has unit amplitude on its face of
entry.  With this choice the scattering amplitudes obey amp(a→b)/k_z,a = amp(b̄→ā)/k_z,b, where
b̄ is the reversed direction (docs/design.md §1, reciprocity).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .kernel1d import background_amplitudes, face_weights
from .operator import LayerOperator, to_zmajor
from .zkernels import face_sums


@dataclass(frozen=True, eq=False)
class OrderSet:
    """All nx·ny orders on one side, flattened (FFT order of (m, n)).

    kx, ky: in-plane wavevector (1/nm); kz: normal component in the exit medium, Im kz ≥ 0
    (0 exactly at a Wood anomaly); amplitude: complex order amplitude on the exit face;
    power: (kz/kz_inc)·|amplitude|² for propagating orders (TM: times ε_in/ε_exit), 0 for
    evanescent ones;
    theta_rad: angle of the outgoing direction to the outward normal of the exit face (π/2 for
    evanescent orders, whose direction is undefined: use the mask); phi_rad: atan2(ky, kx).
    """

    m: np.ndarray
    n: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    kz: np.ndarray
    amplitude: np.ndarray
    power: np.ndarray
    propagating: np.ndarray
    theta_rad: np.ndarray
    phi_rad: np.ndarray

    @property
    def total(self) -> float:
        """Σ of the power fractions (propagating orders)."""
        return float(np.sum(self.power))

    def index(self, m: int, n: int) -> int:
        hits = np.flatnonzero((self.m == m) & (self.n == n))
        if hits.size != 1:
            raise KeyError(f"order ({m}, {n}) is not on this grid")
        return int(hits[0])

    def amp(self, m: int, n: int) -> complex:
        return complex(self.amplitude[self.index(m, n)])

    def pwr(self, m: int, n: int) -> float:
        return float(self.power[self.index(m, n)])


def face_amplitudes(op: LayerOperator, f: np.ndarray, zmajor: bool = False
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Scattered-field harmonics at z = 0 and z = H for the node source f = V·w (moments
    (nb, nx, ny, nz), or z-major (nb, nz, nx, ny) with zmajor=True, operator.py): the face
    weights times the face profiles' moments against the lateral DFT of f
    (zkernels.face_sums)."""
    nx, ny, nz = op.shape
    if zmajor:                        # f stays as it is: transform a copy (operator's backend)
        fz = op.fft.empty(f.shape, f.dtype)
        np.copyto(fz, f)
    else:
        fz = to_zmajor(f, op.fft)
    fh = op.fft.lateral(fz).reshape(op.nb, nz, nx * ny)
    sum_top, sum_bot = (op.fft.to_host(s).reshape(nx, ny) for s in face_sums(op.zk, fh))
    ctop, cbot = face_weights(op.green)
    scale = op.lateral_phase / (nx * ny)
    top, bot = ctop * scale * sum_top, cbot * scale * sum_bot
    inner = op.interfaces
    if inner is not None:             # the inner interfaces' sources (interfaces.py)
        sigma = op.fft.to_host(inner.sources(fh))
        top = top + scale * np.sum(inner.face_top * sigma, axis=0).reshape(nx, ny)
        bot = bot + scale * np.sum(inner.face_bottom * sigma, axis=0).reshape(nx, ny)
    return top, bot


def _order_set(op: LayerOperator, amp: np.ndarray, kz: np.ndarray, kz_inc: float,
               face=None, face_in=None, through=1.0) -> OrderSet:
    """face None: TE powers (kz/kz_inc)|amp|²; else (TM, faces.py) Re ψ|amp|²/Re ψ_in and the
    propagating amplitudes rescaled by √(f/f_in) (f the faces' flux factors); through: the
    layer weights ℓ_in/ℓ_far of a stack's faces for the orders that cross it (interfaces.py)."""
    prop = (kz.imag == 0) & (kz.real >= 0)
    kzr = np.where(prop, kz.real, 0.0)
    if face is None:
        power = np.where(prop, kzr / kz_inc * np.abs(amp) ** 2, 0.0)
    else:
        power = np.where(prop, (face.psi * through).real / face_in.psi[0, 0].real
                         * np.abs(amp) ** 2, 0.0)
        scale = np.sqrt(face.flux_factor / face_in.flux_factor[0, 0] * through)
        amp = np.where(prop, amp * scale, amp)
    kt = np.hypot(op.kx, op.ky)
    theta = np.where(prop, np.arctan2(kt, kzr), math.pi / 2)
    phi = np.arctan2(op.ky, op.kx)
    flat = [np.ravel(a) for a in (op.m, op.n, op.kx, op.ky, kz, amp, power, prop, theta, phi)]
    return OrderSet(*flat)


def diffraction_orders(op: LayerOperator, f: np.ndarray, from_below: bool, zmajor: bool = False
                       ) -> tuple[OrderSet, OrderSet, float]:
    """(reflected, transmitted, kz_inc) for incidence from above (below), for the source
    moments f = V·w (zmajor: in the z-major layout, face_amplitudes).

    Reflected orders leave through the face of entry, transmitted through the other face;
    the 00 orders include the background's Airy reflection/transmission.  TM powers are
    Re(ψ)|a|²/Re(ψ_inc) with the faces' flux coefficients (faces.py; for H_y faces on both
    sides: ε_in/ε_exit·(k_z/k_z,inc)|a|², the flux of a TM wave being ∝ Re(k_z/ε)·|H|²).
    """
    top, bot = face_amplitudes(op, f, zmajor)
    _, refl_b, trans_b = background_amplitudes(op.green, from_below)
    inner = op.interfaces
    if inner is not None:             # the inner interfaces' sources in the background wave
        sigma = inner.background(from_below)
        at_top, at_bottom = complex(inner.face_top[:, 0] @ sigma), complex(inner.face_bottom[:, 0] @ sigma)
        refl_b, trans_b = refl_b.copy(), trans_b.copy()
        refl_b[0, 0] += at_bottom if from_below else at_top
        trans_b[0, 0] += at_top if from_below else at_bottom
    g = op.green
    k_in, k_out = (g.k_below, g.k_above) if from_below else (g.k_above, g.k_below)
    refl, trans = (bot, top) if from_below else (top, bot)
    refl = refl.copy()
    trans = trans.copy()
    refl[0, 0] += refl_b[0, 0]
    trans[0, 0] += trans_b[0, 0]
    kz_inc = float(k_in[0, 0].real)
    faces = g.faces
    if faces is None:
        return (_order_set(op, refl, k_in, kz_inc), _order_set(op, trans, k_out, kz_inc), kz_inc)
    f_in, f_out = (faces[1], faces[0]) if from_below else faces
    through = 1.0
    if inner is not None:
        w_in, w_out = ((inner.weight_bottom, inner.weight_top) if from_below
                       else (inner.weight_top, inner.weight_bottom))
        through = w_in / w_out
    return (_order_set(op, refl, k_in, kz_inc, f_in, f_in),
            _order_set(op, trans, k_out, kz_inc, f_out, f_in, through), kz_inc)
