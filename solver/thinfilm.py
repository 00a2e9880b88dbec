"""Exact thin-film optics of homogeneous layers, TE (s) and TM (p), one layer or a stack.

Conventions (docs/design.md §1, §4): lengths in nm, angles in rad, time factor e^(−iωt),
Im ε ≥ 0 absorbing, normal wavenumbers k_z on the branch Im k_z ≥ 0.  Light of vacuum
wavelength λ arrives at polar angle σ, measured in the medium it comes from, with the
tangential wavenumber k∥ = k0·Re(√ε_src)·sin σ shared by every medium (Snell).

Polarisation and the reflection coefficients:

- TE (s): E is along the faces; r and t are ratios of the E-field amplitude, the scalar
  Helmholtz (Airy) case.  Face admittance q = k_z.
- TM (p): H is along the faces; r and t are ratios of the **H-field** amplitude (the tangential
  H is continuous, like E in TE).  Face admittance q = k_z / ε.  At normal incidence
  r_p = −r_s.  This is the "Verdet" sign that Mitsuba's `fresnel_polarized` uses for a_p,
  a_p = (η cos θi − cos θt)/(η cos θi + cos θt), so r_p plugs into its Mueller matrices.

Both polarisations share one face formula, r_ab = (q_a − q_b)/(q_a + q_b),
t_ab = 2 q_a/(q_a + q_b), and one flux weight: R = |r|², T = Re(q_out)/Re(q_in)·|t|² (TM:
the k_z/ε weights; with the same medium on both sides it equals the TE weight k_z).

A stack is folded from the exit face up (Rouard's recursion, the S-matrix of a layered
medium): with p = e^(i k_z d), |p| ≤ 1,

    r ← (r_face + r·p²) / (1 + r_face·r·p²),   t ← t_face·t·p / (1 + r_face·r·p²)

so no growing exponential appears for thick, strongly absorbing or evanescent layers.
r is referenced to the entry face, t maps the entry face's field to the exit face's.
Mitsuba's own formulas use η = n − iκ (the e^(+iωt) convention): `to_mitsuba_convention`
converts an amplitude (complex conjugate) for a Mueller-matrix renderer.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

POLARISATIONS = ("te", "tm")


@dataclass(frozen=True)
class SlabResponse:
    """Coherent reflection and transmission of a slab or stack; arrays broadcast over (λ, σ)."""

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


def admittance(k_z, eps, polarisation: str) -> np.ndarray:
    """Face admittance: k_z for TE, k_z/ε for TM (so that one Fresnel formula serves both)."""
    return k_z if polarisation == "te" else k_z / np.asarray(eps, dtype=complex)


def to_mitsuba_convention(amplitude) -> np.ndarray:
    """An e^(−iωt) amplitude as Mitsuba's `fresnel_polarized` writes it (η = n − iκ, i.e.
    e^(+iωt)): the complex conjugate.  Magnitudes are unchanged; the s–p phase delay flips."""
    return np.conj(amplitude)


def _interface(q_a, q_b) -> tuple[np.ndarray, np.ndarray]:
    """Fresnel amplitude coefficients a → b from face admittances (TE: k_z, TM: k_z/ε).
    q_a = q_b = 0 happens only for identical media at grazing incidence: no interface there,
    so r = 0 and t = 1 (not 0/0)."""
    q_a, q_b = np.broadcast_arrays(q_a, q_b)
    den = q_a + q_b
    ok = den != 0
    safe = np.where(ok, den, 1.0)
    return np.where(ok, (q_a - q_b) / safe, 0.0), np.where(ok, 2.0 * q_a / safe, 1.0)


def _check_inputs(n_layers: int, thickness_nm_layers, polarisation: str) -> list[float]:
    if polarisation not in POLARISATIONS:
        raise ValueError(f"polarisation must be one of {POLARISATIONS}, got {polarisation!r}")
    thicknesses = [float(d) for d in thickness_nm_layers]
    if len(thicknesses) != n_layers:
        raise ValueError(f"stack has {n_layers} permittivities but {len(thicknesses)} thicknesses")
    for d in thicknesses:
        if not (np.isfinite(d) and d >= 0):
            raise ValueError(f"thickness must be ≥ 0 nm, got {d}")
    return thicknesses


def _fold(q: list, k: list, thicknesses: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """Rouard's recursion from the exit face up: (r, t) of the whole stack at the entry face."""
    r, t = _interface(q[-2], q[-1])
    with np.errstate(invalid="ignore", divide="ignore"):    # 0/0: handled by the caller
        for j in range(len(thicknesses), 0, -1):     # layer j lies between faces j−1|j and j|j+1
            r_face, t_face = _interface(q[j - 1], q[j])
            phase = np.exp(1j * k[j] * thicknesses[j - 1])   # |phase| ≤ 1: stable for any absorption
            denom = 1.0 + r_face * r * phase**2
            r = (r_face + r * phase**2) / denom
            t = t_face * t * phase / denom
    return r, t


def stack(eps_layers: Sequence, thickness_nm_layers: Sequence[float], wavelength_nm, sigma_rad, *,
          polarisation: str, eps_in=1.0, eps_out=1.0, from_below: bool = False) -> SlabResponse:
    """Reflection/transmission of homogeneous layers (listed top first) between two half-spaces.

    `eps_in` is the medium above the top layer, `eps_out` the one below the last.  Light comes
    from above, or from below when `from_below` (then σ is measured in `eps_out`, r is
    referenced to the bottom face and t runs bottom → top).  Each permittivity broadcasts with
    `wavelength_nm` (e.g. shape (nλ, 1)); `sigma_rad` (shape (nσ,)) broadcasts to (nλ, nσ).
    An empty stack is the single interface.  Grazing σ = π/2 is allowed (r = −1, T = 0).
    `polarisation`: "te" (E-field coefficients) or "tm" (H-field coefficients).
    """
    layers = list(eps_layers)
    thicknesses = _check_inputs(len(layers), thickness_nm_layers, polarisation)
    if from_below:
        layers, thicknesses, eps_in, eps_out = layers[::-1], thicknesses[::-1], eps_out, eps_in
    kept = [j for j, d in enumerate(thicknesses) if d > 0]    # a 0-nm layer is no layer at all
    layers, thicknesses = [layers[j] for j in kept], [thicknesses[j] for j in kept]
    wl = np.asarray(wavelength_nm, dtype=float)
    k0 = 2.0 * np.pi / wl
    n_in = np.sqrt(np.asarray(eps_in, dtype=complex))
    k_par = k0 * n_in.real * np.sin(np.asarray(sigma_rad, dtype=float))
    media = [eps_in] + [np.asarray(e, dtype=complex) for e in layers] + [eps_out]
    k = [kz(e, k_par, k0) for e in media]
    q = [admittance(kj, e, polarisation) for kj, e in zip(k, media)]
    r, t = _fold(q, k, thicknesses)
    bad = ~(np.isfinite(r) & np.isfinite(t))
    q_in, q_out = q[0], q[-1]
    grazing = q_in == 0
    if np.any(bad & ~grazing):
        # A layer with k_z = 0 exactly carries a field linear in z, which the two-wave basis
        # cannot hold (0/0): nudge its k_z by 1e-7·k0 there, a change of O((1e-7·k0·d)²).
        k_n = k[:1] + [np.where(kj == 0, 1e-7j * k0, kj) for kj in k[1:-1]] + k[-1:]
        q_n = [admittance(kj, e, polarisation) for kj, e in zip(k_n, media)]
        r_n, t_n = _fold(q_n, k_n, thicknesses)
        r, t = np.where(bad, r_n, r), np.where(bad, t_n, t)
        bad = ~(np.isfinite(r) & np.isfinite(t))
    if np.any(bad & grazing):
        # Grazing entry (k_z,in = 0): the fold gives r = −1, t = 0 up to round-off, or 0/0
        # where 1 + r_face·r·p² vanishes; the limit there is r = −1, t = 0, unless every medium
        # equals the entry medium (no interface at all: r = 0, t = 1).
        matched = np.logical_and.reduce([np.broadcast_to(qj == 0, np.shape(r)) for qj in q])
        fix = bad & grazing
        r = np.where(fix, np.where(matched, 0.0, -1.0), r)
        t = np.where(fix, np.where(matched, 1.0, 0.0), t)
    # Flux ratio Re(q_out)/Re(q_in); zero at grazing incidence, where no flux crosses the faces.
    ratio = np.divide(q_out.real, q_in.real, out=np.zeros(np.broadcast(q_out, q_in).shape),
                      where=q_in.real > 0)
    return SlabResponse(r=r, t=t, R=np.abs(r) ** 2, T=ratio * np.abs(t) ** 2)


def slab(eps_layer, thickness_nm: float, wavelength_nm, sigma_rad, *,
         eps_in: complex = 1.0, eps_out: complex = 1.0, polarisation: str = "te") -> SlabResponse:
    """Airy reflection/transmission of one layer for light arriving from the `eps_in` side.

    `eps_layer` and `wavelength_nm` broadcast together (e.g. shape (nλ, 1)); `sigma_rad` is the
    polar angle in the incident medium (shape (nσ,) broadcasts to (nλ, nσ)).  Grazing σ = π/2
    is allowed (r = −1, T = 0).  The one-layer case of `stack`.
    """
    if thickness_nm < 0:
        raise ValueError(f"thickness must be ≥ 0 nm, got {thickness_nm}")
    return stack([eps_layer], [thickness_nm], wavelength_nm, sigma_rad, polarisation=polarisation,
                 eps_in=eps_in, eps_out=eps_out)
