"""Inner TM interfaces of a stack of layers (docs/wave_solver.md, "Stacks in TM"), and of a
layer's mean profile taken as such a stack (`mean_profile`: a rough top's, "The mean profile in
TM").

The background is one slab of ε_b; a stack's layers differ from it by their contrast, which the
scalar interior carries exactly for TE (u = E_y: u and ∂_z u continuous at every interface) but
not for TM, where what u stands for sets another condition at an interface between layers of
ε₁ (above) and ε₂ (below), by the face form of the coherent (00) harmonic (faces.py):

    h (u = H_y):  u and ∂_z u/ε continuous;        e (u = E_x): u and (ε/κ²)∂_z u continuous,
    κ_j² = k0²ε_j − k_t² (the incidence's k_t);    te: u and ∂_z u (nothing to add).

With c the factor (1/ε, ε/κ², 1) the condition c₁u'(z_i⁻) = c₂u'(z_i⁺) is a point source σ at
the interface, u'' + κ_b²u = −V·u − σδ(z − z_i), of strength σ = γ·u'(z_i⁻), γ = 1 − c₁/c₂
(the source makes the derivative jump by −σ).  One γ serves every lateral harmonic: the
coherent field's condition is exact for a homogeneous stack (only the 00 harmonic lives
there), and with one ratio per interface the scalar flux of every harmonic jumps by the same
c₁/c₂ = ℓ₂/ℓ₁ (ℓ = ε_f for h, κ²/(k0²ε_f) for e), so flux/ℓ is conserved through a lossless
stack of particle layers as it is through one layer.  (Per-harmonic forms at the interface,
tried: R + T of a lossless particle stack then missed 1 by up to 0.03 with `brewster`, 0.29
with `electric`: scattering mixes harmonics whose ℓ ratios differ.)  The derivative is that
of the scheme's own continuous field u = u_b + G·f + Σ_j g(·, z_j)σ_j, so per harmonic

    σ = S·(u_b'(z_i⁻) + D·f),    S = (I − Γ·M)⁻¹Γ,   Γ = diag(γ_i),  M_ij = ∂_z g(z_i⁻, z_j),

D·f = ∫∂_z g(z_i⁻, z′) f(z′) dz′: a rank-(number of interfaces) correction of the Green's
function per harmonic, G′ = G + Σ_i g(·, z_i)(S·D)_i, exact in the continuum (the layers'
contrast inside them is what the scalar equation solves exactly).  Interfaces lie on z-cell
boundaries (z_i = k_i·h), so every moment is an exponential integral with non-negative powers of
a = e^{iκh} (kernel1d's notation: I_q = ∫₀¹φ_q e^{iκht}dt, J_q = (−1)^q I_q):

    g(z, z_i) moments in cell k:   P·[a^{|·|}(J or I) + r_t a^{k+k_i} I + r_b a^{2N−k−k_i−1} J
                                      + r_t r_b a^{2N−|·|…}(I or J)]     (`profile`)
    ∂_z g(z_i⁻, z′) moments:       the same terms times iκ·(s, 1, −1, −s), s = +1 above z_i,
                                   −1 at and below it                    (`derivative`)

Energy: orders leaving through the far face are weighed with ℓ_in/ℓ_far (orders.py); with one
layer ℓ_in = ℓ_far.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .faces import FORMS
from .fftback import FFT
from .kernel1d import SlabGreen, background_amplitudes, face_weights, harmonic_green
from .zbasis import single_integrals
from .zkernels import ZKernels, ZWork, apply_z


@dataclass(frozen=True)
class FaceLayers:
    """The TM faces' permittivities of a stack: each layer's z-cells and ε_f, top first.  The
    top face takes eps[0], the bottom face eps[-1]; between layers of different ε_f the
    interface conditions above apply."""

    cells: tuple[int, ...]
    eps: tuple[complex, ...]

    def __post_init__(self):
        if len(self.cells) != len(self.eps) or not self.cells or min(self.cells) < 1:
            raise ValueError(f"FaceLayers needs one positive cell count per ε_f, got {self.cells}, "
                             f"{self.eps}")
        for ef in self.eps:
            ef = complex(ef)
            if not (ef.real > 0 and ef.imag >= 0 and np.isfinite(abs(ef))):
                raise ValueError(f"eps_face must have Re > 0 and Im ≥ 0, got {ef}")

    @property
    def boundaries(self) -> tuple[tuple[int, complex, complex], ...]:
        """(k_i, ε above, ε below) of every inner interface where ε_f changes."""
        out, k = [], 0
        for n, above, below in zip(self.cells, self.eps, self.eps[1:]):
            k += n
            if complex(above) != complex(below):
                out.append((k, complex(above), complex(below)))
        return tuple(out)


def mean_profile(eps: np.ndarray, merge: float = 0.0) -> FaceLayers:
    """The lateral-mean permittivity of the z-cells of a voxel grid eps (nx, ny, nz) as layers
    with Maxwell's TM conditions between them, on every harmonic (docs/wave_solver.md, "The mean
    profile in TM"): neighbouring z-cells within `merge` (relative |Δε̄|) of a layer's first cell
    join that layer, with their mean ε (0: one layer per z-cell, exact for a laterally
    homogeneous graded film)."""
    prof = np.asarray(eps).mean(axis=(0, 1))
    cells, values, start = [], [], 0
    for k in range(1, prof.size + 1):
        if k == prof.size or abs(prof[k] - prof[start]) > merge * abs(prof[start]):
            cells.append(k - start)
            values.append(complex(prof[start:k].mean()))
            start = k
    return FaceLayers(tuple(cells), tuple(values))


def layer_weight(form, eps_f: complex, kt2, k0: float):
    """ℓ: the factor by which a layer of ε_f weighs the scalar flux of a harmonic of that form
    (FORMS index) and k_t² (module doc)."""
    e, h = form == FORMS.index("e"), form == FORMS.index("h")
    return np.where(h, eps_f, np.where(e, (k0 * k0 * eps_f - kt2) / (k0 * k0 * eps_f), 1.0))


@dataclass(frozen=True, eq=False)
class Interfaces:
    """The correction of one Background's Green's function for its inner interfaces.

    index: k_i per interface; profile (H, nb·nz, n) and derivative (H, n, nb·nz) in the
    operator's dtype and backend (harmonic-major, so that every use is one batched matrix
    product; derivative includes the cell height h); gain (H, n, n): S;
    gain_lateral: S times the operator's inverse-FFT factor; face_top, face_bottom (n, H): the
    reported face amplitudes of a unit source at z_i (g(0, z_i), g(H, z_i) times the faces'
    reporting factor); background_above, background_below (n,): σ in the 00 background wave of
    a unit incident wave from above / below (host, complex128); weight_top, weight_bottom: ℓ
    of the top and the bottom layer.
    """

    index: tuple[int, ...]
    profile: np.ndarray
    derivative: np.ndarray
    gain: np.ndarray
    gain_lateral: np.ndarray
    face_top: np.ndarray
    face_bottom: np.ndarray
    background_above: np.ndarray
    background_below: np.ndarray
    weight_top: complex
    weight_bottom: complex

    def sources(self, fh: np.ndarray, lateral: bool = False) -> np.ndarray:
        """σ (n, H) of the lateral-DFT source moments fh (nb, nz, H) (times the inverse-FFT
        factor when `lateral`)."""
        f = fh.reshape(-1, fh.shape[-1]).T[..., None]                  # (H, nb·nz, 1)
        gain = self.gain_lateral if lateral else self.gain
        return (gain @ (self.derivative @ f))[..., 0].T

    def background(self, from_below: bool) -> np.ndarray:
        """σ (n,) of the 00 background wave of unit incidence from above or below."""
        return self.background_below if from_below else self.background_above

    def add_field(self, out: np.ndarray, sigma: np.ndarray) -> None:
        """out (nb, nz, H) += Σ_i g(·, z_i)·σ_i (moments)."""
        out += (self.profile @ sigma.T[..., None])[..., 0].T.reshape(out.shape)

    def coherent_profile(self, sigma: np.ndarray, to_host) -> np.ndarray:
        """Σ_i g(·, z_i)·σ_i of the 00 harmonic (nb·nz,) on the host, for σ (n,)."""
        return np.asarray(to_host(self.profile[0]), complex) @ sigma

    def correction(self, harmonics: np.ndarray, to_host) -> np.ndarray:
        """G′ − G of the harmonics (indices into H) as matrices (len, nb·nz, nb·nz) on the
        moments (host, complex): Σ_i g(·, z_i)(S·D)_i, the true G's (`gain`, no FFT factor)."""
        host = lambda x: np.asarray(to_host(x), complex)[harmonics]  # noqa: E731
        return host(self.profile) @ host(self.gain) @ host(self.derivative)


def green_moments(zk: ZKernels, inner: "Interfaces | None", flat: np.ndarray, work: ZWork) -> np.ndarray:
    """G (the slab's, corrected for the inner interfaces when `inner` is given) on lateral-DFT
    source moments flat (nb, nz, H), in place; the inverse-FFT factor as zkernels folds it."""
    sigma = None if inner is None else inner.sources(flat, lateral=True)   # before apply_z
    apply_z(zk, flat, work)
    if sigma is not None:
        inner.add_field(flat, sigma)
    return flat


def _powers(sg: SlabGreen) -> np.ndarray:
    """a^j, j = 0 … 2nz, on the last axis of (H, 2nz + 1)."""
    return sg.exp_table().reshape(-1, 2 * sg.nz + 1)


def build(sg: SlabGreen, layers: FaceLayers, form: np.ndarray, kt2: np.ndarray, k0: float,
          dtype, backend: FFT) -> Interfaces | None:
    """The correction of `sg` for the inner interfaces of `layers` (None when there are none or
    every harmonic has TE conditions); form: the FORMS index per harmonic (faces.py)."""
    bounds = layers.boundaries
    if not bounds or form.reshape(-1)[0] == FORMS.index("te"):
        return None
    if sum(layers.cells) != sg.nz:
        raise ValueError(f"FaceLayers cover {sum(layers.cells)} z-cells, the grid has {sg.nz}")
    form = form.reshape(-1)
    kt2 = np.asarray(kt2, float).reshape(-1)
    kap = sg.kappa.reshape(-1)
    rt, rb = sg.r_top.reshape(-1), sg.r_bottom.reshape(-1)
    pre = sg.prefactor.reshape(-1)
    nz, nb, h, size = sg.nz, sg.nb, sg.h_nm, kap.size
    a = _powers(sg)                                             # (H, 2N + 1)
    integ = single_integrals(1j * kap * h, nb)
    i_q = np.stack(integ)                                       # (nb, H)
    j_q = np.stack([(-1) ** q * integ[q] for q in range(nb)])
    big = 2 * nz
    cells = np.arange(nz)
    n = len(bounds)
    profile = np.empty((n, nb, nz, size), complex)
    deriv = np.empty((n, nb, nz, size), complex)
    gamma = np.zeros((size, n), complex)
    m = np.empty((size, n, n), complex)
    face_top, face_bottom = np.empty((n, size), complex), np.empty((n, size), complex)
    slope_above, slope_below = np.empty(n, complex), np.empty(n, complex)

    def pw(exponent: np.ndarray) -> np.ndarray:                 # a^exponent per cell: (nz, H)
        return a[:, exponent].T

    kj = np.array([k for k, _, _ in bounds])
    ctop, cbot = face_weights(sg)
    ctop, cbot = ctop.reshape(-1) / h, cbot.reshape(-1) / h
    for i, (ki, above, below) in enumerate(bounds):
        up = cells < ki                                         # cells above the interface
        e1_up, e1_dn = pw(np.where(up, ki - cells - 1, 0)), pw(np.where(up, 0, cells - ki))
        e2 = pw(cells + ki)
        e3 = pw(big - cells - ki - 1)
        e4_up, e4_dn = pw(np.where(up, big - ki + cells, 0)), pw(np.where(up, 0, big - cells + ki - 1))
        upq = up[None, :, None]
        # g(z, z_i) over z in cell k; ∂_z g(z_i⁻, z′) over z′ in cell l (the same exponentials)
        direct = np.where(upq, j_q[:, None] * e1_up[None], i_q[:, None] * e1_dn[None])
        double = np.where(upq, i_q[:, None] * e4_up[None], j_q[:, None] * e4_dn[None])
        single_t = i_q[:, None] * e2[None]
        single_b = j_q[:, None] * e3[None]
        profile[i] = pre * (direct + rt * single_t + rb * single_b + rt * rb * double)
        s = np.where(upq, 1.0, -1.0)
        deriv[i] = h * pre * 1j * kap * (s * direct + rt * single_t - rb * single_b
                                          - s * rt * rb * double)
        gamma[:, i] = 1.0 - layer_weight(form[0], below, kt2[0], k0) / layer_weight(
            form[0], above, kt2[0], k0)                     # γ = 1 − c₁/c₂ = 1 − ℓ₂/ℓ₁ (00)
        sj = np.where(kj >= ki, -1.0, 1.0)                     # M_ij = ∂_z g(z_i⁻, z_j)
        d = np.abs(ki - kj)
        m[:, i, :] = (pre * 1j * kap)[:, None] * (sj * a[:, d] + rt[:, None] * a[:, ki + kj]
                                                  - rb[:, None] * a[:, big - ki - kj]
                                                  - sj * (rt * rb)[:, None] * a[:, big - d])
        face_top[i] = ctop * (a[:, ki] + rb * a[:, big - ki])
        face_bottom[i] = cbot * (a[:, nz - ki] + rt * a[:, nz + ki])
        slope_above[i] = 1j * kap[0] * (a[0, ki] - rb[0] * a[0, big - ki])
        slope_below[i] = 1j * kap[0] * (-a[0, nz - ki] + rt[0] * a[0, nz + ki])
    gm = gamma[:, :, None] * m                                  # Γ·M per harmonic
    gain = np.linalg.solve(np.eye(n)[None] - gm, np.einsum("hi,ij->hij", gamma, np.eye(n)))
    sg00 = harmonic_green(sg, (slice(0, 1), slice(0, 1)))
    coef_a, coef_b = (background_amplitudes(sg00, below)[0][0, 0] for below in (False, True))
    sigma_a, sigma_b = gain[0] @ (coef_a * slope_above), gain[0] @ (coef_b * slope_below)
    top_w = complex(layer_weight(form[0], complex(layers.eps[0]), kt2[0], k0))
    bottom_w = complex(layer_weight(form[0], complex(layers.eps[-1]), kt2[0], k0))
    lateral = 1.0 if backend.normalised else 1.0 / size
    cast = lambda x: backend.asarray(x, dtype)                  # noqa: E731
    points = nb * nz
    profile = np.ascontiguousarray(profile.reshape(n, points, size).transpose(2, 1, 0))
    deriv = np.ascontiguousarray(deriv.reshape(n, points, size).transpose(2, 0, 1))
    return Interfaces(tuple(k for k, _, _ in bounds), cast(profile), cast(deriv), cast(gain),
                      cast(gain * lateral), face_top, face_bottom, sigma_a, sigma_b,
                      top_w, bottom_w)
