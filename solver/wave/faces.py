"""Face conditions of the TM mode, chosen per lateral harmonic (docs/wave_solver.md, "TM faces").

The scalar field u solves u'' + κ²u = −V·u inside the slab whatever it stands for; what it
stands for is fixed by the face conditions of each lateral harmonic (kx, ky), with ε the
half-space's permittivity, ε_f the slab's face permittivity and k_z the half-space's normal
wavenumber (docs/design.md §1):

* ``te``: u = E_y, u and ∂_z u continuous; admittance y = k_z.
* ``h``: u = H_y, u and ∂_z u/ε continuous; y = (ε_f/ε)·k_z.
* ``e``: u = E_x, the tangential electric field in the harmonic's plane of incidence; E_x and
  H_y = (k0·ε/(i k_z²))·∂_z E_x continuous (Gaussian units, c = 1; a plane wave has
  E_x = ±(k_z/(k0·ε))·H_y, + going down), so y = κ_f²·ε/(ε_f·k_z) with
  κ_f² = k0²ε_f − k_t² (the slab side's own k_z², taken with ε_f).  The amplitudes reported
  outside are H_y (as for ``h``), so r_p, t_p keep one convention: r_p^H = −r^{E_x}.

At normal incidence the ``e`` form of the 00 harmonic is the TE face exactly (κ_f²/ε_f = k0²):
a stratified medium's E_x obeys the scalar equation exactly there, its H_y does not (it misses
the −(ε'/ε)∂_z H term), which is why the scalar particles see the right mean field only
through E_x.  A homogeneous slab has no scattered harmonics: every form gives its exact film.

`TMFaces` says which form each class of harmonic gets, by its lateral wavevector |q| in the
face's half-space ε: `inner` below the Brewster wavevector q_B = k0·√Re(ε_f·ε/(ε_f + ε)),
`outer` from q_B to the light line k0·√ε (propagating), `evanescent` beyond (for unequal
half-spaces see harmonic_forms); `mean`, if given, overrides the form of the 00 harmonic (the
coherent mean field).  A rule that depends on
|q| alone keeps the model reciprocal (the reversed problem sees the same faces); a `mean`
override does not.  Where two classes meet the forms should agree for the field to be
continuous in λ and σ: 'te' and 'h' agree at the light line (y = 0), 'e' and 'h' at Brewster's
q_B (y_e = y_h, r = 0; exactly for real ε_f), 'e' and 'te' nowhere but k_t = 0.  Presets are the
variants measured against the vector referee (docs/vector_referee.md, "TM faces").

Per face and harmonic, `FaceCoefficients` holds everything the Green's function, the order
amplitudes and the energy identity need, all finite at Wood anomalies (k_z = 0):

    r       internal reflection of the slab field: (κ − y)/(κ + y)
    out     rep/(κ + y), rep = the reported amplitude per unit of u at the face (te/h: 1,
            e: ∓k0ε/k_z): the face weight is i·h·out/D (kernel1d.face_weights), finite
            for e as −/+ k0·ε·ε_f/(κε_f k_z + κ_f²ε)
    launch  slab wave launched by a unit reported incident wave: te/h 2y/(κ + y)
    psi     flux coefficient: a reported amplitude a carries the scalar flux Re(ψ)·|a|²
            (te/h: ψ = y); the power fraction of an order is Re(ψ)|a|²/Re(ψ_incident)
    sign    s = (reported/slab) × (slab/reported incident) of the 00 wave: +1 te/h, −1 e
    flux_factor  f = ψ/(k_z/ε) for a propagating harmonic (te: ε, h: ε_f, e: κ_f²/(k0²ε_f)):
            a propagating order's amplitude is reported as a·√(f/f_incident) (orders.py), so
            that every TM amplitude obeys the TM reciprocity relation and, for real ε_f, has the
            power (ε_in/ε_out)(k_z/k_z,inc)|a|²: one convention for every form
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FORMS = ("te", "h", "e")


@dataclass(frozen=True)
class TMFaces:
    """Face form ('te' | 'h' | 'e') per class of lateral harmonic, for the TM mode.

    inner: harmonics with |q| < q_B (Brewster's wavevector of that face); outer: q_B ≤ |q| and
    propagating in that half-space (k_z real, > 0); evanescent: the rest (k_z = 0 included);
    mean: None, or a form for the 00 harmonic alone (breaks reciprocity, module doc).
    """

    inner: str = "e"
    outer: str = "h"
    evanescent: str = "te"
    mean: str | None = None

    def __post_init__(self):
        for name in ("inner", "outer", "evanescent", "mean"):
            v = getattr(self, name)
            if not (v in FORMS or (name == "mean" and v is None)):
                raise ValueError(f"TMFaces.{name} must be one of {FORMS}"
                                 f"{' or None' if name == 'mean' else ''}, got {v!r}")


#: The variants measured against the vector referee (docs/vector_referee.md, "TM faces").
PRESETS = {
    "all": TMFaces("h", "h", "h"),                    # H_y everywhere (the first TM model)
    "mean": TMFaces("te", "te", "te", mean="h"),      # H_y for the coherent field only
    "propagating": TMFaces("h", "h", "te"),           # H_y for the harmonics that leave
    "electric": TMFaces("e", "e", "e"),               # E_x everywhere
    "electric-mean": TMFaces("te", "te", "te", mean="e"),
    "electric-propagating": TMFaces("e", "e", "te"),
    "hybrid": TMFaces("h", "h", "te", mean="e"),      # E_x mean field, H_y diffuse light
    "brewster": TMFaces("e", "h", "te"),              # E_x below Brewster, H_y above, TE near field
}
#: the one default of the TM mode (chosen by the referee, docs/vector_referee.md)
DEFAULT_TM_FACES = "brewster"


def parse_tm_faces(value: "str | TMFaces") -> TMFaces:
    """A preset name or a TMFaces → TMFaces."""
    if isinstance(value, TMFaces):
        return value
    if isinstance(value, str) and value in PRESETS:
        return PRESETS[value]
    raise ValueError(f"tm_faces must be one of {sorted(PRESETS)} or a TMFaces, got {value!r}")


def preset_name(faces: TMFaces) -> str:
    """The preset's name, or 'inner=…,outer=…,evanescent=…,mean=…'."""
    for name, p in PRESETS.items():
        if p == faces:
            return name
    return (f"inner={faces.inner},outer={faces.outer},evanescent={faces.evanescent},"
            f"mean={faces.mean}")


@dataclass(frozen=True, eq=False)
class FaceCoefficients:
    """One face's per-harmonic coefficients (lateral shape); see the module doc."""

    r: np.ndarray
    out: np.ndarray
    launch: np.ndarray
    psi: np.ndarray
    sign: np.ndarray
    flux_factor: np.ndarray
    form: np.ndarray          # index into FORMS per harmonic, as used


def harmonic_forms(faces: TMFaces, kt2: np.ndarray, k_denser: np.ndarray, eps_above: float,
                   eps_below: float, eps_face: tuple[complex, complex], k0: float) -> np.ndarray:
    """FORMS index per harmonic, common to both faces (u is one field in the slab); index
    [0, 0] is the 00 harmonic (FFT order).

    A harmonic is propagating if it propagates in either half-space (|q| < k0·√max ε: the 00
    harmonic always is; k_denser: k_z in the denser one, 0 at a Wood anomaly, which counts as
    evanescent), inner below the Brewster wavevector of the rarer half-space
    (ε_m = min ε).  With equal half-spaces (the tables) both faces see the same bounds and the
    forms meet where they agree; with unequal ones they agree at one face only (a small jump
    where a harmonic crosses a bound, docs/wave_solver.md).
    The 'e' form needs the 00 harmonic to propagate in the face medium (Re κ_f²/ε_f > 0), where
    it carries the incident power: it falls back to 'h' where it does not (incidence from a
    half-space denser than the slab beyond its critical angle, beyond q_B as well).
    eps_face: (ε_f top, ε_f bottom); the Brewster bound takes their mean (one bound for both
    faces: u is one field; equal ε_f — a single layer — meet exactly at q_B, unequal ones — a
    stack — nearly)."""
    top, bottom = (complex(e) for e in eps_face)
    ef = 0.5 * (top + bottom)
    eps_m = min(float(eps_above), float(eps_below))
    q_b2 = k0 * k0 * (ef * eps_m / (ef + eps_m)).real
    prop = (k_denser.imag == 0) & (k_denser.real > 0)
    form = np.where(prop, np.where(kt2 < q_b2, FORMS.index(faces.inner),
                                   FORMS.index(faces.outer)),
                    FORMS.index(faces.evanescent))
    if faces.mean is not None:
        form[0, 0] = FORMS.index(faces.mean)
    if form[0, 0] == FORMS.index("e") and not all((kt2[0, 0] / (k0 * k0 * e)).real < 1.0
                                                   for e in (top, bottom)):
        form[0, 0] = FORMS.index("h")
    return form


def face_coefficients(form: np.ndarray, kappa: np.ndarray, k_half: np.ndarray, kt2: np.ndarray,
                      eps_half: float, eps_face: complex, k0: float, top: bool
                      ) -> FaceCoefficients:
    """Coefficients of the top (half-space above) or bottom face for every harmonic.

    form: FORMS index per harmonic (harmonic_forms); kappa: κ in the slab (with the fictitious
    loss), k_half: k_z in the half-space, kt2: k_t² (1/nm²); eps_half: the half-space's ε,
    eps_face: ε_f; k0 = 2π/λ (1/nm).
    """
    ef = complex(eps_face)
    kf2 = k0 * k0 * ef - kt2                                  # κ_f²
    ratio = np.where(form == FORMS.index("h"), ef / eps_half, 1.0 + 0j)
    y = ratio * k_half                                        # te, h
    den_y = kappa + y
    r = (kappa - y) / den_y
    out = 1.0 / den_y
    launch = 2.0 * y / den_y
    psi = y.astype(complex)
    sign = np.ones(kappa.shape)
    flux = np.where(form == FORMS.index("h"), ef, complex(eps_half)) * np.ones(kappa.shape)
    is_e = form == FORMS.index("e")
    if np.any(is_e):
        den = kappa * ef * k_half + kf2 * eps_half             # (κ + y_e)·ε_f·k_z
        bad = is_e & (den == 0)
        if np.any(bad):                                       # κ_f = k_z = 0: use 'h' there
            is_e = is_e & ~bad
            form = np.where(bad, FORMS.index("h"), form)
            y_h = ef / eps_half * k_half
            r = np.where(bad, (kappa - y_h) / (kappa + y_h), r)
            out = np.where(bad, 1.0 / (kappa + y_h), out)
            launch = np.where(bad, 2.0 * y_h / (kappa + y_h), launch)
            psi = np.where(bad, y_h, psi)
            flux = np.where(bad, ef, flux)
        safe = np.where(is_e, den, 1.0)
        # reported H_y = rep·E_x: rep = −k0ε/k_z upward (top face), +k0ε/k_z downward
        # (bottom); a unit incident H_y is E_x = +k_z/(k0ε) from above, −k_z/(k0ε) from below
        rep_sign = -1.0 if top else 1.0
        r = np.where(is_e, (kappa * ef * k_half - kf2 * eps_half) / safe, r)
        out = np.where(is_e, rep_sign * k0 * eps_half * ef / safe, out)
        launch = np.where(is_e, -rep_sign * 2.0 * kf2 * k_half / (k0 * safe), launch)
        psi = np.where(is_e, kf2 * np.conj(k_half) / (k0 * k0 * ef * eps_half), psi)
        sign = np.where(is_e, -1.0, sign)
        flux = np.where(is_e, kf2 / (ef * k0 * k0), flux)
    return FaceCoefficients(r, out, launch, psi, sign, flux, form)
