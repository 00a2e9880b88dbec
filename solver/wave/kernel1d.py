"""Analytic Green's function of the layered background, one lateral harmonic at a time.

Background: half-space ε_a above (z < 0), a homogeneous slab ε_b over 0 ≤ z ≤ H, half-space ε_c
below (z > H); z is measured from the top face of the grid, in nm.  For the lateral harmonic
(kx, ky) the 1-D Green's function of u'' + κ(z)² u = −δ(z − z′) with outgoing/decaying waves on
both sides is, for 0 ≤ z, z′ ≤ H (κ = √(k0²ε_b − kt²), Im κ > 0):

    g(z, z′) = P·[E1 + r_t·E2 + r_b·E3 + r_t·r_b·E4],   P = i / (2κ·D),  D = 1 − r_t r_b e^{2iκH}
    E1 = e^{iκ|z−z′|}, E2 = e^{iκ(z+z′)}, E3 = e^{iκ(2H−z−z′)}, E4 = e^{iκ(2H−|z−z′|)}
    r_t = (κ − y_a)/(κ + y_a),   r_b = (κ − y_c)/(κ + y_c)   (internal reflection coefficients)

with the face admittances y_a = k_a, y_c = k_c for TE (u and ∂_z u continuous at the faces) and
y_a = (ε_f/ε_a)·k_a, y_c = (ε_f/ε_c)·k_c for TM (u and ∂_z u/ε continuous, ε_f the slab's face
permittivity): r_t = (κ/ε_f − k_a/ε_a)/(κ/ε_f + k_a/ε_a).  Every formula below holds for both
with k → y (docs/wave_solver.md, "TM polarisation").  The TM mode's per-harmonic face forms
(faces.py: TE, H_y or E_x conditions per class of harmonic) enter through `FaceCoefficients`:
r_t, r_b from them, and face weights / background amplitudes in their general form.

Every exponent has a non-negative argument, so every factor decays for evanescent harmonics;
they are all taken from a table e^{iκjh}, j = 0…2nz, times e^{±iκs} inside a cell.  At a Wood
anomaly (k_a = 0 or k_c = 0) r = 1: nothing divides by k_z.

z-discretisation: nz uniform cells of height h = H/nz, nb = 1 or 2 Legendre functions per cell
(zbasis.py).  The Galerkin matrix M^{pq}_{kl} = (1/h)∫_k∫_l φ_p g φ_q is Toeplitz (E1, E4) plus
Hankel (E2, E3) in the cell indices; circulant_kernels returns both as circulant embeddings of
length 2nz (circulant_blocks); the operator applies the same matrix by exact recursions along z
(zkernels.py; docs/wave_solver.md, "z-recursions"), and the blocks serve as its dense reference.
"""
from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Iterator

import numpy as np

from .faces import FaceCoefficients
from .zbasis import diag_galerkin, diag_point, diag_point_reflected, sign, single_integrals


def vertical_wavenumber(k0sq_eps: complex, kt2: np.ndarray) -> np.ndarray:
    """k_z = √(k0²ε − kt²) with Im k_z ≥ 0 (and Re k_z ≥ 0 when real), in 1/nm.

    Values within 1e-12·k0²|ε| of the light line are snapped to exactly 0 (Wood anomaly).
    """
    arg = k0sq_eps - np.asarray(kt2, dtype=float)
    arg = np.where(np.abs(arg) <= 1e-12 * abs(k0sq_eps), 0.0, arg).astype(complex)
    kz = np.sqrt(arg)
    flip = (kz.imag < 0) | ((kz.imag == 0) & (kz.real < 0))
    return np.where(flip, -kz, kz)


@dataclass(frozen=True, eq=False)
class SlabGreen:
    """Per-harmonic constants of the layered Green's function; arrays of the lateral shape.

    kappa: κ in the slab; k_above, k_below: k_z in the half-spaces (1/nm); y_above, y_below:
    face admittances (k_z for TE, (ε_f/ε_half-space)·k_z for TM; 1/nm); r_top, r_bottom:
    internal reflection coefficients; denom: D; thickness_nm: H; nz cells; nb functions per cell.
    faces: (top, bottom) FaceCoefficients of per-harmonic face forms (faces.py), or None for
    the plain admittances (then y_above / y_below are used as above).
    """

    kappa: np.ndarray
    k_above: np.ndarray
    k_below: np.ndarray
    r_top: np.ndarray
    r_bottom: np.ndarray
    denom: np.ndarray
    thickness_nm: float
    nz: int
    nb: int
    y_above: np.ndarray
    y_below: np.ndarray
    faces: tuple[FaceCoefficients, FaceCoefficients] | None = None

    @property
    def h_nm(self) -> float:
        return self.thickness_nm / self.nz

    @property
    def prefactor(self) -> np.ndarray:
        """P = i/(2κD) in nm."""
        return 1j / (2 * self.kappa * self.denom)

    def exp_table(self) -> np.ndarray:
        """e^{iκjh} for j = 0 … 2nz along a new last axis (every |·| ≤ 1).

        Computed as e^{iκh·8a}·e^{iκh·b} (j = 8a + b): 2 × 9 exponentials per harmonic instead
        of 2nz + 1; it differs from e^{iκ·(jh)} by ≤ 3e-14 relative, the rounding of the
        argument jh itself."""
        return np.moveaxis(self.exp_rows(2 * self.nz + 1), 0, -1)

    def exp_rows(self, count: int) -> np.ndarray:
        """e^{iκjh} for j = 0 … count−1 along a new first axis, C-contiguous (as exp_table)."""
        step = 1j * self.kappa * self.h_nm
        coarse = np.exp(step * (8.0 * np.arange((count + 7) // 8)).reshape((-1,) + (1,) * step.ndim))
        fine = np.exp(step * np.arange(8.0).reshape((-1,) + (1,) * step.ndim))
        return (coarse[:, None] * fine[None, :]).reshape((-1,) + step.shape)[:count]


def harmonic_green(sg: SlabGreen, index: tuple[slice, ...]) -> SlabGreen:
    """The constants of the harmonics sg.kappa[index] alone (e.g. (slice(0, 1),) * 2: the 00
    harmonic), faces included."""
    def cut(obj, names):
        return replace(obj, **{n: getattr(obj, n)[index] for n in names})

    arrays = ("kappa", "k_above", "k_below", "r_top", "r_bottom", "denom", "y_above", "y_below")
    faces = None if sg.faces is None else tuple(
        cut(f, [fld.name for fld in fields(f)]) for f in sg.faces)
    return replace(cut(sg, arrays), faces=faces)


def slab_green(kappa: np.ndarray, k_above: np.ndarray, k_below: np.ndarray,
               thickness_nm: float, nz: int, nb: int = 2, *,
               face_ratio_above: complex | None = None,
               face_ratio_below: complex | None = None,
               faces: tuple[FaceCoefficients, FaceCoefficients] | None = None) -> SlabGreen:
    """Reflection coefficients and the resonance denominator D for every harmonic.

    face_ratio_above / _below: ε_f/ε_a and ε_f/ε_c (scalars or per-harmonic arrays) for
    u = H_y faces; None (TE): admittance = k_z.  faces: per-harmonic face forms (faces.py);
    they replace the ratios (then y_above / y_below hold the flux coefficients ψ).
    """
    if np.any(kappa.imag <= 0):
        raise ValueError("the background slab needs Im κ > 0 for every harmonic (Im ε_b > 0)")
    if nb not in (1, 2):
        raise ValueError("nb (functions per z-cell) must be 1 or 2")
    if faces is not None:
        ya, yc = faces[0].psi, faces[1].psi
        rt, rb = faces[0].r, faces[1].r
    else:
        ya = k_above if face_ratio_above is None else face_ratio_above * k_above
        yc = k_below if face_ratio_below is None else face_ratio_below * k_below
        rt = (kappa - ya) / (kappa + ya)
        rb = (kappa - yc) / (kappa + yc)
    denom = 1 - rt * rb * np.exp(2j * kappa * thickness_nm)
    return SlabGreen(kappa, k_above, k_below, rt, rb, denom, float(thickness_nm), int(nz), nb,
                     ya, yc, faces)


def circulant_blocks(sg: SlabGreen, offset_nm: float | None = None
                     ) -> Iterator[tuple[int, int, np.ndarray, np.ndarray]]:
    """Circulant embeddings of the Toeplitz and Hankel parts, one (p, q) block at a time.

    Yields (p, q, toe, han) with arrays of shape (..., 2nz) (lateral axes in "...").
    offset_nm None: Galerkin moments of the field (p = 0 … nb−1 test functions per cell).
    offset_nm s ∈ [0, h]: the field at the points z = k·h + s (p = 0 only).
    y[p, k] = Σ_{q,l} toe_pq[(k−l) mod 2nz]·f[q, l] + han_pq[k+l]·f[q, l].
    Entries: toe[d] for d = k − l = 1 … nz−1 at index d, for d = −1 … −(nz−1) at 2nz − |d|;
    han[σ] for σ = k + l = 0 … 2nz−2.  All table look-ups below are slices (views).
    """
    nz, nb, h = sg.nz, sg.nb, sg.h_nm
    rt, rb = sg.r_top[..., None], sg.r_bottom[..., None]
    rtrb = rt * rb
    tab = sg.exp_table()
    x = 1j * sg.kappa * h
    integ = single_integrals(x, nb)
    ph = (sg.prefactor * h)[..., None]
    shape = sg.kappa.shape + (2 * nz,)
    # e^{iκjh} for the offsets that occur, as views of the table, indexed by d = 1 … nz−1
    e_dm1 = tab[..., 0:nz - 1]                    # j = d − 1
    e_d = tab[..., 1:nz]                          # j = d
    e_far = tab[..., nz:2 * nz - 1][..., ::-1]    # j = 2nz − d − 1
    e_far0 = tab[..., nz + 1:2 * nz][..., ::-1]   # j = 2nz − d
    e_sig = tab[..., 0:2 * nz - 1]                # j = σ, σ = 0 … 2nz−2
    e_sig_far = tab[..., 1:2 * nz][..., ::-1]     # j = 2nz − σ − 1
    if offset_nm is None:
        e_sig_far2 = tab[..., 0:2 * nz - 1][..., ::-1]   # j = 2nz − σ − 2
        for p in range(nb):
            for q in range(nb):
                toe = np.zeros(shape, dtype=complex)
                han = np.zeros(shape, dtype=complex)
                w = ph * (integ[p] * integ[q])[..., None]
                sp, sq = sign(p), sign(q)
                toe[..., 1:nz] = w * (sq * e_dm1 + (rtrb * sp) * e_far)
                toe[..., nz + 1:] = (w * (sp * e_dm1 + (rtrb * sq) * e_far))[..., ::-1]
                direct = diag_galerkin(p, q, x, np.ones_like(x), tab[..., 1])
                bounced = diag_galerkin(p, q, -x, tab[..., 2 * nz], tab[..., 2 * nz - 1])
                toe[..., 0] = ph[..., 0] * (direct + rtrb[..., 0] * bounced)
                han[..., :-1] = w * (rt * e_sig + (rb * sp * sq) * e_sig_far2)
                yield p, q, toe, han
        return
    s = float(offset_nm)
    ep, em = np.exp(1j * sg.kappa * s)[..., None], np.exp(-1j * sg.kappa * s)[..., None]
    self_terms = point_self_terms(sg, s, tab)
    for q in range(nb):
        toe = np.zeros(shape, dtype=complex)
        han = np.zeros(shape, dtype=complex)
        w = ph * integ[q][..., None]
        sq = sign(q)
        toe[..., 1:nz] = w * ((sq * ep) * e_dm1 + (rtrb * em) * e_far0)            # k > l
        toe[..., nz + 1:] = (w * (em * e_d + (rtrb * sq * ep) * e_far))[..., ::-1]  # k < l
        toe[..., 0] = self_terms[q]
        han[..., :-1] = w * ((rt * ep) * e_sig + (rb * sq * em) * e_sig_far)
        yield 0, q, toe, han


def point_self_terms(sg: SlabGreen, offset_nm: float, tab: np.ndarray | None = None
                     ) -> list[np.ndarray]:
    """The k = l Toeplitz entries of the point kernels (circulant_blocks with offset_nm s):
    for each source function q, the field at z = k·h + s of the source φ_q in the same cell
    (direct wave and the wave bounced off both faces), per harmonic (nm)."""
    nz, h = sg.nz, sg.h_nm
    s = float(offset_nm)
    if not 0.0 <= s <= h * (1 + 1e-12):
        raise ValueError(f"offset_nm must lie in [0, h={h}], got {s}")
    tab = sg.exp_table() if tab is None else tab
    tau = min(s / h, 1.0)
    x = 1j * sg.kappa * h
    ep, em = np.exp(1j * sg.kappa * s), np.exp(-1j * sg.kappa * s)
    ph, rtrb = sg.prefactor * h, sg.r_top * sg.r_bottom
    out = []
    for q in range(sg.nb):
        lq, rq = diag_point(q, tau, x)
        lr, rr = diag_point_reflected(q, tau, x)
        out.append(ph * (lq + rq + rtrb * (tab[..., 2 * nz] * em * lr
                                           + tab[..., 2 * nz - 1] * ep * rr)))
    return out


def face_profiles(sg: SlabGreen, offset_nm: float | None = None,
                  tab: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Moments (offset None; shape (nb, ..., nz)) or point values at z = k·h + s (shape
    (1, ..., nz)) of the two face profiles

        p_top(z) = e^{iκz} + r_b e^{iκ(2H−z)},   p_bot(z) = e^{iκ(H−z)} + r_t e^{iκ(H+z)}.

    g(0, z) = i·p_top(z)/((κ + y_a)D) and g(H, z) = i·p_bot(z)/((κ + y_c)D); the background field
    of a unit wave from above (below) is 2y_a/((κ+y_a)D)·p_top (2y_c/((κ+y_c)D)·p_bot).
    tab: sg.exp_table() if already computed.
    """
    nz, nb = sg.nz, sg.nb
    rt, rb = sg.r_top[..., None], sg.r_bottom[..., None]
    tab = sg.exp_table() if tab is None else tab
    k = np.arange(nz)
    if offset_nm is None:
        integ = single_integrals(1j * sg.kappa * sg.h_nm, nb)
        ptop = np.stack([integ[q][..., None]
                         * (tab[..., k] + rb * sign(q) * tab[..., 2 * nz - k - 1])
                         for q in range(nb)])
        pbot = np.stack([integ[q][..., None]
                         * (sign(q) * tab[..., nz - k - 1] + rt * tab[..., nz + k])
                         for q in range(nb)])
        return ptop, pbot
    s = float(offset_nm)
    ep, em = np.exp(1j * sg.kappa * s)[..., None], np.exp(-1j * sg.kappa * s)[..., None]
    ptop = tab[..., k] * ep + rb * tab[..., 2 * nz - k] * em
    pbot = tab[..., nz - k] * em + rt * tab[..., nz + k] * ep
    return ptop[None], pbot[None]


def face_weights(sg: SlabGreen) -> tuple[np.ndarray, np.ndarray]:
    """c_top = i·h/((κ + y_a)D), c_bot = i·h/((κ + y_c)D) in nm: for a source with moments f,
    u_s(0) = c_top·Σ_{q,l} p_top[q, l]·f[q, l] and u_s(H) = c_bot·Σ p_bot[q, l]·f[q, l].
    With face forms (sg.faces): c = i·h·out/D, the reported outgoing amplitude (faces.py)."""
    h = sg.h_nm
    if sg.faces is not None:
        return (1j * h * sg.faces[0].out / sg.denom, 1j * h * sg.faces[1].out / sg.denom)
    return (1j * h / ((sg.kappa + sg.y_above) * sg.denom),
            1j * h / ((sg.kappa + sg.y_below) * sg.denom))


def background_amplitudes(sg: SlabGreen, from_below: bool
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact (Airy) response of the background to a unit plane wave, per harmonic.

    Returns (coef, reflected, transmitted): the slab field is coef·p_top (from above) or
    coef·p_bot (from below); reflected/transmitted are the outgoing amplitudes on the face of
    entry / exit.  With face forms (sg.faces), in terms of the faces' coefficients
    (faces.py): coef = launch_in/D, reflected = s_in·((1 − r_in)(1 + r_far e^{2iκH})/D − 1),
    transmitted = 2κ·out_far·launch_in·e^{iκH}/D (amplitudes as reported: H_y for TM).
    """
    kap, rt, rb, big_h = sg.kappa, sg.r_top, sg.r_bottom, sg.thickness_nm
    e1 = np.exp(1j * kap * big_h)
    if sg.faces is not None:
        f_in, f_far = (sg.faces[1], sg.faces[0]) if from_below else sg.faces
        coef = f_in.launch / sg.denom
        refl = f_in.sign * ((1 - f_in.r) * (1 + f_far.r * e1 * e1) / sg.denom - 1)
        return coef, refl, 2 * kap * f_far.out * f_in.launch * e1 / sg.denom
    k_in, r_far = (sg.y_below, rt) if from_below else (sg.y_above, rb)
    coef = 2 * k_in / ((kap + k_in) * sg.denom)
    return coef, coef * (1 + r_far * e1 * e1) - 1, coef * e1 * (1 + r_far)
