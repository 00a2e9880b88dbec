"""Diffraction orders from the solved field: amplitudes, directions, power fractions.

Reference planes: a wave leaving through the top face is referenced to z_top, one leaving
through the bottom face to z_bottom, and the incident wave has unit amplitude on its face of
entry.  With this choice the scattering amplitudes obey amp(a→b)/k_z,a = amp(b̄→ā)/k_z,b, where
b̄ is the reversed direction (DESIGN §1, reciprocity).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from .kernel1d import background_amplitudes, face_weights
from .operator import LayerOperator


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


def face_amplitudes(op: LayerOperator, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Scattered-field harmonics at z = 0 and z = H for the node source f = V·w (moments)."""
    nx, ny, _ = op.shape
    fh = sfft.fft2(f, axes=(1, 2), workers=op.workers)
    ctop, cbot = face_weights(op.green)
    scale = op.lateral_phase / (nx * ny)
    top = ctop * scale * np.einsum("qijk,qijk->ij", op.ptop, fh)
    bot = cbot * scale * np.einsum("qijk,qijk->ij", op.pbot, fh)
    return top, bot


def _order_set(op: LayerOperator, amp: np.ndarray, kz: np.ndarray, kz_inc: float,
               weight: float) -> OrderSet:
    prop = (kz.imag == 0) & (kz.real >= 0)
    kzr = np.where(prop, kz.real, 0.0)
    power = np.where(prop, kzr / kz_inc * np.abs(amp) ** 2, 0.0)
    if weight != 1.0:
        power *= weight
    kt = np.hypot(op.kx, op.ky)
    theta = np.where(prop, np.arctan2(kt, kzr), math.pi / 2)
    phi = np.arctan2(op.ky, op.kx)
    flat = [np.ravel(a) for a in (op.m, op.n, op.kx, op.ky, kz, amp, power, prop, theta, phi)]
    return OrderSet(*flat)


def diffraction_orders(op: LayerOperator, f: np.ndarray, from_below: bool
                       ) -> tuple[OrderSet, OrderSet, float]:
    """(reflected, transmitted, kz_inc) for incidence from above (below).

    Reflected orders leave through the face of entry, transmitted through the other face;
    the 00 orders include the background's Airy reflection/transmission.  TM powers carry
    ε_in/ε_exit (the flux of a TM wave is ∝ Re(k_z/ε)·|u|²).
    """
    top, bot = face_amplitudes(op, f)
    _, refl_b, trans_b = background_amplitudes(op.green, from_below)
    g = op.green
    k_in, k_out = (g.k_below, g.k_above) if from_below else (g.k_above, g.k_below)
    refl, trans = (bot, top) if from_below else (top, bot)
    refl = refl.copy()
    trans = trans.copy()
    refl[0, 0] += refl_b[0, 0]
    trans[0, 0] += trans_b[0, 0]
    kz_inc = float(k_in[0, 0].real)
    eps_in, eps_out = (op.eps_below, op.eps_above) if from_below else (op.eps_above,
                                                                       op.eps_below)
    weight = eps_in / eps_out if op.polarisation == "tm" else 1.0
    return (_order_set(op, refl, k_in, kz_inc, 1.0), _order_set(op, trans, k_out, kz_inc, weight),
            kz_inc)
