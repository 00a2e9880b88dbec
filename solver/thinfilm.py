"""Exact thin-film optics of a homogeneous layer (scalar Helmholtz = TE Airy formulas).

A layer of permittivity ε (complex, Im ε ≥ 0 absorbing) and thickness d between a half-space
above (ε_above) and one below (ε_below).  Light of vacuum wavelength λ arrives at polar angle
σ (measured in the medium it comes from).  The layer is up-down symmetric when ε_above =
ε_below, so reflectance from below then equals reflectance from above.

Power fractions use the k_z weights of DESIGN.md §1: R = |r|², T = (k_z,out / k_z,in)·|t|².
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SlabResponse:
    """Coherent reflection and transmission of a slab; arrays broadcast over (λ, σ)."""

    r: np.ndarray      # complex amplitude reflection coefficient (reference plane: entry face)
    t: np.ndarray      # complex amplitude transmission coefficient (entry face → exit face)
    R: np.ndarray      # reflected power fraction
    T: np.ndarray      # transmitted power fraction

    @property
    def A(self) -> np.ndarray:
        """Absorbed power fraction."""
        return 1.0 - self.R - self.T


def kz(eps, k_parallel, k0) -> np.ndarray:
    """Normal wavenumber sqrt(k0²ε − k∥²) on the branch Im ≥ 0 (Re ≥ 0 when real)."""
    val = np.sqrt(np.asarray(k0**2 * eps - k_parallel**2, dtype=complex))
    return np.where(val.imag < 0, -val, val) if np.ndim(val) else (-val if val.imag < 0 else val)


def _interface(k_a, k_b) -> tuple[np.ndarray, np.ndarray]:
    """Fresnel (TE) amplitude coefficients a → b.  k_a = k_b = 0 happens only for identical
    media at grazing incidence: no interface there, so r = 0 and t = 1 (not 0/0)."""
    k_a, k_b = np.broadcast_arrays(k_a, k_b)
    den = k_a + k_b
    ok = den != 0
    safe = np.where(ok, den, 1.0)
    return np.where(ok, (k_a - k_b) / safe, 0.0), np.where(ok, 2.0 * k_a / safe, 1.0)


def slab(eps_layer, thickness_nm: float, wavelength_nm, sigma_rad, *,
         eps_in: complex = 1.0, eps_out: complex = 1.0) -> SlabResponse:
    """Airy reflection/transmission of a slab for light arriving from the `eps_in` side.

    `eps_layer` and `wavelength_nm` broadcast together (e.g. shape (nλ, 1)); `sigma_rad` is the
    polar angle in the incident medium (shape (nσ,) broadcasts to (nλ, nσ)).  Grazing σ = π/2
    is allowed (r = −1, T = 0).
    """
    if thickness_nm < 0:
        raise ValueError(f"thickness must be ≥ 0 nm, got {thickness_nm}")
    wl = np.asarray(wavelength_nm, dtype=float)
    k0 = 2.0 * np.pi / wl
    n_in = np.sqrt(complex(eps_in))
    k_par = k0 * n_in.real * np.sin(np.asarray(sigma_rad, dtype=float))
    k_in = kz(eps_in, k_par, k0)
    k_l = kz(np.asarray(eps_layer, dtype=complex), k_par, k0)
    k_out = kz(eps_out, k_par, k0)
    r01, t01 = _interface(k_in, k_l)
    r12, t12 = _interface(k_l, k_out)
    phase = np.exp(1j * k_l * thickness_nm)          # |phase| ≤ 1: stable for any absorption
    denom = 1.0 + r01 * r12 * phase**2
    r = (r01 + r12 * phase**2) / denom
    t = t01 * t12 * phase / denom
    # Flux ratio Re(k_out)/Re(k_in); zero at grazing incidence, where t = 0 as well.
    ratio = np.divide(k_out.real, k_in.real, out=np.zeros(np.broadcast(k_out, k_in).shape),
                      where=k_in.real > 0)
    R = np.abs(r) ** 2
    T = ratio * np.abs(t) ** 2
    return SlabResponse(r=r, t=t, R=R, T=T)
