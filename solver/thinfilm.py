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

A stack is folded from the exit face up on the tangential pair (u, v): u = E_y (TE) or H_y
(TM), v = ∂_z u/(i c) with c = 1 (TE) or ε (TM), so a wave e^(±i k_z z) has v = ±q u and both
are continuous at every face.  Start (u, v) = (1, q_out) at the exit face; through a layer of
thickness d, with δ = k_z d, p = e^(iδ) (|p| ≤ 1), E = 1 − p² (from expm1) and
G = E/q = c·d·E/δ (→ −2i c d as k_z → 0), the characteristic matrix times p is

    p·(u, v)_top = ½ [[1 + p², G], [q·E, 1 + p²]] · (u, v)_bottom

applied without the 1/p (no growing exponential for thick, strongly absorbing or evanescent
layers) and renormalised each layer; the dropped factors p/scale make up t.  At the entry:
r = (q_in u − v)/(q_in u + v), t = 2 q_in Π(p/scale)/(q_in u + v).  A layer with k_z = 0
(grazing in a medium of the entry's ε: a field linear in z) is the smooth limit, and no
intermediate quantity has a pole (not even a sub-stack's guided mode).
r is referenced to the entry face, t maps the entry face's field to the exit face's.
`slab` keeps the textbook Airy formula for one layer (bit-identical with earlier tables) and
uses the stack recursion only where Airy is degenerate (0/0 or k_z,layer ≈ 0).
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


def entry_kz(eps_in, k_parallel, k0) -> np.ndarray:
    """k_z in the medium light comes from.  A lossless entry medium has k_z = k0·n·cos σ ≥ 0
    real; an imaginary part there is round-off of k0²ε − k∥² near grazing, and would turn the
    incident wave evanescent (|r| > 1 over a totally reflecting stack): drop it."""
    k = kz(eps_in, k_parallel, k0)
    return k.real + 0j if np.all(np.imag(eps_in) == 0) else k


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


def _airy(q_in, q_l, q_out, k_l, thickness_nm: float) -> tuple[np.ndarray, np.ndarray]:
    """Airy's formula for one layer from its two faces' Fresnel coefficients."""
    r01, t01 = _interface(q_in, q_l)
    r12, t12 = _interface(q_l, q_out)
    phase = np.exp(1j * k_l * thickness_nm)          # |phase| ≤ 1: stable for any absorption
    with np.errstate(invalid="ignore", divide="ignore"):     # 0/0 only where slab falls back
        denom = 1.0 + r01 * r12 * phase**2
        return (r01 + r12 * phase**2) / denom, t01 * t12 * phase / denom


def _fold(q: list, k: list, c: list, thicknesses: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """(r, t) of a stack by the normalised characteristic-matrix fold of the module docstring."""
    u, v = np.ones_like(q[-1]), q[-1]
    gain = 1.0                                      # Π p/scale
    for j in range(len(thicknesses), 0, -1):
        delta = k[j] * thicknesses[j - 1]
        e = -np.expm1(2j * delta)                   # 1 − p², accurate as δ → 0
        g = c[j] * thicknesses[j - 1] * np.where(delta == 0, -2j, e / np.where(delta == 0, 1.0, delta))
        u, v = 0.5 * ((2.0 - e) * u + g * v), 0.5 * (q[j] * e * u + (2.0 - e) * v)
        scale = np.maximum(np.abs(u), np.abs(v))
        scale = np.where(scale > 0, scale, 1.0)
        u, v = u / scale, v / scale
        gain = gain * np.exp(1j * delta) / scale
    den = q[0] * u + v
    nothing = den == 0                 # grazing with every medium equal to the entry: no face
    safe = np.where(nothing, 1.0, den)
    r = np.where(nothing, 0.0, (q[0] * u - v) / safe)
    t = np.where(nothing, 1.0, 2.0 * q[0] * gain / safe)
    return r, t


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
    k = [entry_kz(eps_in, k_par, k0)] + [kz(e, k_par, k0) for e in media[1:]]
    q = [admittance(kj, e, polarisation) for kj, e in zip(k, media)]
    c = [1.0 if polarisation == "te" else np.asarray(e, dtype=complex) for e in media]
    r, t = _fold(q, k, c, thicknesses)
    return _response(r, t, q[0], q[-1])


def _response(r, t, q_in, q_out) -> SlabResponse:
    """Power fractions from amplitudes: R = |r|², T = Re(q_out)/Re(q_in)·|t|²."""
    # Flux ratio Re(q_out)/Re(q_in); zero at grazing incidence, where no flux crosses the faces.
    ratio = np.divide(q_out.real, q_in.real, out=np.zeros(np.broadcast(q_out, q_in).shape),
                      where=q_in.real > 0)
    return SlabResponse(r=r, t=t, R=np.abs(r) ** 2, T=ratio * np.abs(t) ** 2)


def slab(eps_layer, thickness_nm: float, wavelength_nm, sigma_rad, *,
         eps_in: complex = 1.0, eps_out: complex = 1.0, polarisation: str = "te") -> SlabResponse:
    """Airy reflection/transmission of one layer for light arriving from the `eps_in` side.

    `eps_layer` and `wavelength_nm` broadcast together (e.g. shape (nλ, 1)); `sigma_rad` is the
    polar angle in the incident medium (shape (nσ,) broadcasts to (nλ, nσ)).  Grazing σ = π/2
    is allowed (r = −1, T = 0).  Equals `stack([eps_layer], [thickness_nm], ...)` to round-off.
    """
    _check_inputs(1, [thickness_nm], polarisation)
    if thickness_nm == 0:
        return stack([], [], wavelength_nm, sigma_rad, polarisation=polarisation,
                     eps_in=eps_in, eps_out=eps_out)
    wl = np.asarray(wavelength_nm, dtype=float)
    k0 = 2.0 * np.pi / wl
    n_in = np.sqrt(complex(eps_in))
    k_par = k0 * n_in.real * np.sin(np.asarray(sigma_rad, dtype=float))
    eps_layer = np.asarray(eps_layer, dtype=complex)
    k_in, k_l, k_out = entry_kz(eps_in, k_par, k0), kz(eps_layer, k_par, k0), kz(eps_out, k_par, k0)
    q_in, q_out = admittance(k_in, eps_in, polarisation), admittance(k_out, eps_out, polarisation)
    r, t = _airy(q_in, admittance(k_l, eps_layer, polarisation), q_out, k_l, thickness_nm)
    # Airy's two-wave form is 0/0 or loses digits where the layer's k_z is ~0 (≲ 1e-3·k0):
    # the stack fold is the smooth limit there.
    bad = ~(np.isfinite(r) & np.isfinite(t)) | (np.abs(k_l) < 1e-3 * k0)
    if np.any(bad):
        fold = stack([eps_layer], [thickness_nm], wl, sigma_rad, polarisation=polarisation,
                     eps_in=eps_in, eps_out=eps_out)
        r, t = np.where(bad, fold.r, r), np.where(bad, fold.t, t)
    return _response(r, t, q_in, q_out)
