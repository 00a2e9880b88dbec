"""Independent reference implementations the tests compare the code against (docs/design.md §6).

Written from textbook formulas, sharing no code with solver/ or inkbsdf/ (only the tables'
arrays are read):

- thin films: textbook Fresnel faces and the Airy sum of a slab between any two media (TE for
  E_y, TM for H_y), the characteristic (Abelès) matrix of a stack, the TE0 guided mode of a
  symmetric film;
- the layered Green's function of a slab (a point source and its reflections), with a complex
  quadrature to integrate it;
- the `ink` BSDF (docs/design.md §1): the smooth lobes' f·cos θo of one ink under either
  coverage model, its delta lobe (selection probability and weight), its directional albedo;
- polarisation: the Mueller matrix of a Jones matrix diag(a_s, a_p);
- ellipsoids: the depolarisation factor by its integral, the shape matrix of a spheroid, Perram & Wertheim's overlap function, the distance
  of two ellipsoids by constrained minimisation;
- a print's gamut: the largest chroma at a lightness and hue, by brute force over the 2-D faces
  of the coverage polytope (the print model and the hue function passed in).

Conventions as the solver's (docs/design.md §1, §4): nm, radians, e^(−iωt), z downward.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.integrate import quad
from scipy.interpolate import RegularGridInterpolator

CY, MD = "clapper-yule", "murray-davies"


# ------------------------------------------------------------------------------ thin films
def normal_wavenumber(eps, s2):
    """q = k_z/k0 = sqrt(ε − s²) on the branch Im q ≥ 0 (s² = ε_in sin²σ, the conserved
    tangential wavenumber squared over k0²)."""
    q = np.sqrt(np.asarray(eps, dtype=complex) - s2)
    return np.where(q.imag < 0, -q, q)


def fresnel(eps_i, eps_j, s2, pol):
    """(r, t) of the face from medium i into medium j: r = (y_i − y_j)/(y_i + y_j), t = 1 + r,
    with y = q (TE, amplitudes of E_y) or q/ε (TM, amplitudes of H_y: the H-field/Verdet sign,
    r_p = −r_s at normal incidence)."""
    q_i, q_j = normal_wavenumber(eps_i, s2), normal_wavenumber(eps_j, s2)
    y_i, y_j = (q_i, q_j) if pol == "te" else (q_i / eps_i, q_j / eps_j)
    r = (y_i - y_j) / (y_i + y_j)
    return r, 1.0 + r


def airy_sum(r12, r23, phase2):
    """Reflection of two faces summed over the round trips: (r12 + r23 p²)/(1 + r12 r23 p²),
    p² the round-trip phase factor."""
    return (r12 + r23 * phase2) / (1.0 + r12 * r23 * phase2)


def airy_slab(n_in, n_slab, n_out, d_nm, lam_nm, sigma, pol="te"):
    """(r, t, R, T) of a slab (index n_slab, thickness d) between n_in (incidence side, real)
    and n_out, polar angle σ in n_in; r referenced to the entry face, t to the exit face;
    T = Re(y_out)/Re(y_in)·|t|² (flux ∝ Re(k_z)|E|² in TE, Re(k_z/ε)|H|² in TM). Arrays
    broadcast."""
    eps = [np.asarray(n, dtype=complex) ** 2 for n in (n_in, n_slab, n_out)]
    s2 = eps[0].real * np.sin(sigma) ** 2
    r12, t12 = fresnel(eps[0], eps[1], s2, pol)
    r23, t23 = fresnel(eps[1], eps[2], s2, pol)
    phase = np.exp(1j * 2 * np.pi / np.asarray(lam_nm) * normal_wavenumber(eps[1], s2) * d_nm)
    r = airy_sum(r12, r23, phase**2)
    t = t12 * t23 * phase / (1.0 + r12 * r23 * phase**2)
    y_in, y_out = (normal_wavenumber(e, s2) / (1.0 if pol == "te" else e) for e in (eps[0], eps[2]))
    ratio = np.divide(y_out.real, y_in.real, out=np.zeros(np.broadcast(y_out, y_in).shape),
                      where=y_in.real > 0)
    return r, t, np.abs(r) ** 2, ratio * np.abs(t) ** 2


def abeles(eps_layers, d_layers, wl, sigma, pol, eps_in=1.0, eps_out=1.0):
    """(r, R, T) of a stack by the characteristic matrix of the tangential fields (Macleod's
    form). Tilted admittance η = Q (TE) or ε/Q (TM), Q = n cos θ = sqrt(ε − ε_in sin²σ),
    Im Q ≥ 0; layer matrix [[cos δ, −i sin δ/η], [−i η sin δ, cos δ]], δ = k0 Q d. r is the
    ratio of tangential E: for TM the H-field coefficient is −r (returned)."""
    k0 = 2 * np.pi / wl
    s2 = eps_in * np.sin(sigma) ** 2

    def admit(eps):
        q = np.sqrt(complex(eps - s2))
        q = q if q.imag >= 0 else -q
        return q, (q if pol == "te" else eps / q)

    m = np.eye(2, dtype=complex)
    for eps, d in zip(eps_layers, d_layers):
        q, eta = admit(eps)
        delta = k0 * q * d
        m = m @ np.array([[np.cos(delta), -1j * np.sin(delta) / eta], [-1j * eta * np.sin(delta), np.cos(delta)]])
    _, eta_in = admit(eps_in)
    _, eta_out = admit(eps_out)
    b, c = m @ np.array([1.0, eta_out])
    r = (eta_in * b - c) / (eta_in * b + c)
    T = 4 * eta_in.real * eta_out.real / abs(eta_in * b + c) ** 2
    return (r if pol == "te" else -r), abs(r) ** 2, T


def te0_propagation_constant(k0, eps_film, thickness_nm):
    """β of the TE0 mode of a symmetric lossless film in air: 2κH − 4 atan(γ/κ) = 0,
    κ = sqrt(k0²ε − β²), γ = sqrt(β² − k0²)."""
    from scipy.optimize import brentq

    def phase(beta):
        kap, gam = math.sqrt(k0 ** 2 * eps_film - beta ** 2), math.sqrt(beta ** 2 - k0 ** 2)
        return 2 * kap * thickness_nm - 4 * math.atan(gam / kap)
    return brentq(phase, k0 * 1.000001, k0 * math.sqrt(eps_film) * 0.999999)


# ------------------------------------------------------------------- layered Green's function
def complex_quad(f, a, b, points=None):
    """∫_a^b f of a complex function by scipy.integrate.quad (real and imaginary parts)."""
    kw = dict(points=points, limit=200, epsabs=1e-15, epsrel=1e-12)
    return quad(lambda t: f(t).real, a, b, **kw)[0] + 1j * quad(lambda t: f(t).imag, a, b, **kw)[0]


def layered_green(kap, ka, kc, big_h):
    """g(z, z′) of a slab [0, H] (k_z = κ) between media of k_z = ka (above) and kc (below): a
    point source plus its reflections at both faces; the multiple-reflection series
    Σ (r_t r_b e^{2iκH})^n summed in closed form."""
    rt, rb = (kap - ka) / (kap + ka), (kap - kc) / (kap + kc)
    series = 1 / (1 - rt * rb * np.exp(2j * kap * big_h))

    def g(z, zp):
        return 1j / (2 * kap) * series * (
            np.exp(1j * kap * abs(z - zp)) + rt * np.exp(1j * kap * (z + zp))
            + rb * np.exp(1j * kap * (2 * big_h - z - zp))
            + rt * rb * np.exp(1j * kap * (2 * big_h - abs(z - zp))))
    return g


# ---------------------------------------------------------------------------- the ink BSDF
@functools.lru_cache(maxsize=32)
def _cos_mean_weights(sigma: tuple) -> np.ndarray:
    """Weights w_j = 2∫ hat_j(s) cos s sin s ds of the piecewise-linear hat functions on the
    nodes `sigma`, by a fine trapezoid (200 001 points over [0, π/2])."""
    s = np.linspace(0.0, np.pi / 2, 200001)
    hats = np.array([np.interp(s, sigma, e) for e in np.eye(len(sigma))])
    return np.trapezoid(hats * 2.0 * np.cos(s) * np.sin(s), s, axis=-1)


def cos_mean(sigma, column):
    """2∫ f(s) cos s sin s ds over [0, π/2] of piecewise-linear rows f (one per row of
    `column`) on the nodes `sigma`, by a fine trapezoid."""
    return np.atleast_2d(column) @ _cos_mean_weights(tuple(np.asarray(sigma, dtype=np.float64)))


def azimuth_difference(wi, wo):
    """Δφ of two direction arrays [3, N], folded into [0, π]."""
    return np.abs(np.angle(np.exp(1j * (np.arctan2(wi[1], wi[0]) - np.arctan2(wo[1], wo[0])))))


def reference_eval(table, wi, wo, lam, coverage, paper, model=CY):
    """f(ωi, ωo)·cos θo of the smooth lobes of one ink, [4, N], from docs/design.md §1 with SciPy.

    Murray–Davies: c·f_ink + (1 − c)·r/π. Clapper–Yule: light enters through ink (c, ×T̄(σ)) or
    bare paper (1 − c), the paper's bounces see c·ρ̄, light leaves through ink (c, ×T̄(θ)) or not:
    c·R/π + r·(c T̄(σ) + 1 − c)(c T̄(θ) + 1 − c)/(π(1 − r c ρ̄))."""
    wl, sig = table.wavelengths, table.sigma
    lam = np.clip(lam, wl[0], wl[-1])
    s_i = np.arccos(np.clip(wi[2], 0, 1))       # below the surface: zeroed at the end
    s_o = np.arccos(np.clip(wo[2], 0, 1))
    grid2 = (wl, sig)
    t_in = RegularGridInterpolator(grid2, table.Tbar)((lam, np.broadcast_to(s_i, lam.shape)))
    t_out = RegularGridInterpolator(grid2, table.Tbar)((lam, np.broadcast_to(s_o, lam.shape)))
    rho = np.interp(lam, wl, cos_mean(sig, table.Rbar_below))
    c = coverage
    if model == MD:
        f = c * paper * t_in * t_out / (1 - paper * rho) / np.pi + (1 - c) * paper / np.pi
    else:
        f = paper * (c * t_in + 1 - c) * (c * t_out + 1 - c) / (1 - paper * c * rho) / np.pi
    if table.has_diffuse:
        pts = [np.broadcast_to(x, lam.shape) for x in (s_i, s_o, azimuth_difference(wi, wo))]
        R = RegularGridInterpolator((wl, sig, table.theta, table.dphi), table.R)((lam, *pts))
        f = f + coverage * R / np.pi
    ok = (wi[2] > 0) & (wo[2] > 0)
    return np.where(ok, f * np.clip(wo[2], 0, None), 0.0)


def _columns(table, lam, sigma):
    """R_spec, T̄ and the diffuse albedo ∫R cos θ dω/π at (λ, σ), and ρ̄, τ̄ at λ (cos-weighted
    means over σ of R̄_below and T̄), from the table's arrays."""
    wl = table.wavelengths
    lam, sigma = np.broadcast_arrays(np.clip(lam, wl[0], wl[-1]), sigma)
    pts = (lam, sigma)
    col = {k: RegularGridInterpolator((wl, table.sigma), getattr(table, k))(pts) for k in ("R_spec", "Tbar")}
    col["R_diff"] = RegularGridInterpolator((wl, table.sigma), table.Rbar - table.R_spec)(pts)
    col["rho"] = np.interp(lam, wl, cos_mean(table.sigma, table.Rbar_below))
    col["tau"] = np.interp(lam, wl, cos_mean(table.sigma, table.Tbar))
    return col


def smooth_albedo(col, paper, coverage, model=CY):
    """Albedo of the smooth part: c·R_diff + the paper term of the coverage model (Murray–Davies:
    c·r·T̄τ̄/(1 − rρ̄) + (1 − c)·r; Clapper–Yule: r·(cT̄ + 1 − c)(cτ̄ + 1 − c)/(1 − rcρ̄))."""
    c, r = coverage, paper
    if model == MD:
        return c * (col["R_diff"] + r * col["Tbar"] * col["tau"] / (1 - r * col["rho"])) + (1 - c) * r
    return c * col["R_diff"] + r * (c * col["Tbar"] + 1 - c) * (c * col["tau"] + 1 - c) / (1 - r * c * col["rho"])


def reference_delta(table, lam, deg, paper, coverage, model=CY):
    """(P_spec [n], delta-lobe weight c·R_spec/P_spec [4, n]) for wavelengths lam [4, n] at
    incidence `deg`: P_spec = mean_λ(c·R_spec)/mean_λ(c·R_spec + smooth albedo)."""
    col = _columns(table, np.asarray(lam, dtype=np.float64), np.radians(deg))
    spec = coverage * col["R_spec"]
    p_spec = spec.mean(axis=0) / (spec + smooth_albedo(col, paper, coverage, model)).mean(axis=0)
    return p_spec, spec / p_spec


def reference_albedo(table, paper, coverage=1.0, model=MD):
    """Directional albedo (smooth + delta) at the table's nodes [λ, σ]."""
    col = _columns(table, table.wavelengths[:, None], table.sigma[None, :])
    return coverage * col["R_spec"] + smooth_albedo(col, paper, coverage, model)


# ---------------------------------------------------------------------------- polarisation
def jones_to_mueller(a_s, a_p):
    """Textbook Mueller matrix [4, 4, ...] of the Jones matrix diag(a_s, a_p) (x = s, y = p):
    M = A (J ⊗ J*) A⁻¹, A = [[1, 0, 0, 1], [1, 0, 0, −1], [0, 1, 1, 0], [0, i, −i, 0]]
    (S3 = i(E_s E_p* − E_p E_s*); with Mitsuba's e^(+iωt) amplitudes this is its sign, pinned by
    test_polarized_mirror.test_jones_map_is_mitsubas_specular_reflection)."""
    a_s, a_p = np.broadcast_arrays(np.asarray(a_s, complex), np.asarray(a_p, complex))
    A = np.array([[1, 0, 0, 1], [1, 0, 0, -1], [0, 1, 1, 0], [0, 1j, -1j, 0]])
    jj = np.zeros((4, 4) + a_s.shape, complex)                 # J ⊗ J*, J = diag(a_s, a_p)
    for row, (u, v) in enumerate([(a_s, a_s), (a_s, a_p), (a_p, a_s), (a_p, a_p)]):
        jj[row, row] = u * np.conj(v)
    m = np.einsum("ij,jk...,kl->il...", A, jj, np.linalg.inv(A))
    assert np.max(np.abs(m.imag)) < 1e-12
    return m.real


# ------------------------------------------------------------------------------ ellipsoids
def depolarisation_integral(a: float, b: float, c: float) -> float:
    """L along semi-axis a of the ellipsoid (a, b, c): (abc/2) ∫₀^∞ ds / ((s + a²) √((s+a²)(s+b²)(s+c²)))."""
    f = lambda s: 1.0 / ((s + a * a) * math.sqrt((s + a * a) * (s + b * b) * (s + c * c)))  # noqa: E731
    return 0.5 * a * b * c * quad(f, 0.0, np.inf, limit=200)[0]


def spheroid_matrix(equatorial_nm, polar_nm, axis) -> np.ndarray:
    """Shape matrix M = R·diag(r², r², h²)·Rᵀ of spheroids with equatorial semi-axes r and polar
    semi-axes h along the unit axes (R's last column): each body is {x : xᵀ M⁻¹ x ≤ 1}.
    r, h (...,), axis (..., 3) → (..., 3, 3)."""
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    helper = np.where((np.abs(axis[..., 0]) < 0.9)[..., None], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    e1 = helper - np.sum(helper * axis, axis=-1, keepdims=True) * axis
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    rot = np.stack([e1, np.cross(axis, e1), axis], axis=-1)
    r2, h2 = np.asarray(equatorial_nm, dtype=float) ** 2, np.asarray(polar_nm, dtype=float) ** 2
    diag = np.stack([r2, r2, h2], axis=-1)
    return np.einsum("...ik,...k,...jk->...ij", rot, diag, rot)


def perram_wertheim(d, m_a, m_b, steps: int = 60) -> np.ndarray:
    """Perram & Wertheim's contact function (J. Comput. Phys. 58, 409, 1985) of ellipsoids with
    shape matrices m_a, m_b (..., 3, 3) and centres d (..., 3) apart: the maximum over λ ∈ [0, 1]
    of F(λ) = λ(1 − λ)·dᵀ[(1 − λ)A + λB]⁻¹d, by golden section (F is concave in λ).
    < 1: they overlap; 1: they touch; > 1: they are apart."""
    d, m_a, m_b = (np.asarray(x, dtype=float) for x in (d, m_a, m_b))

    def f(lam):
        mix = (1 - lam)[..., None, None] * m_a + lam[..., None, None] * m_b
        return lam * (1 - lam) * np.einsum("...i,...i->...", d, np.linalg.solve(mix, d[..., None])[..., 0])

    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    lo, hi = np.zeros(d.shape[:-1]), np.ones(d.shape[:-1])
    x1, x2 = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
    f1, f2 = f(x1), f(x2)
    for _ in range(steps):
        left = f1 >= f2                               # the maximum lies in [lo, x2]
        hi, lo = np.where(left, x2, hi), np.where(left, lo, x1)
        new = np.where(left, hi - ratio * (hi - lo), lo + ratio * (hi - lo))
        fn = f(new)
        x1, x2 = np.where(left, new, x2), np.where(left, x1, new)
        f1, f2 = np.where(left, fn, f2), np.where(left, f1, fn)
    return np.maximum(f1, f2)


def ellipsoid_distance(d, m_a, m_b) -> float:
    """Euclidean distance between ellipsoids centred at 0 and d (0 when they meet): min |x − y|
    over xᵀA⁻¹x ≤ 1, (y − d)ᵀB⁻¹(y − d) ≤ 1, a convex problem solved by SLSQP from the centres."""
    from scipy.optimize import minimize

    d = np.asarray(d, dtype=float)
    ia, ib = np.linalg.inv(m_a), np.linalg.inv(m_b)
    scale = float(np.sqrt(max(np.linalg.eigvalsh(m_a).max(), np.linalg.eigvalsh(m_b).max())))
    qa, qb, c = ia * scale**2, ib * scale**2, d / scale            # unknowns in units of `scale`
    zero = np.zeros(3)
    cons = [{"type": "ineq", "fun": lambda z: 1.0 - z[:3] @ qa @ z[:3],
             "jac": lambda z: np.concatenate([-2.0 * qa @ z[:3], zero])},
            {"type": "ineq", "fun": lambda z: 1.0 - (z[3:] - c) @ qb @ (z[3:] - c),
             "jac": lambda z: np.concatenate([zero, -2.0 * qb @ (z[3:] - c)])}]
    res = minimize(lambda z: float(np.sum((z[:3] - z[3:]) ** 2)), np.concatenate([zero, c]),
                   jac=lambda z: np.concatenate([2.0 * (z[:3] - z[3:]), -2.0 * (z[:3] - z[3:])]),
                   constraints=cons, method="SLSQP", options={"ftol": 1e-16, "maxiter": 500})
    return scale * math.sqrt(max(res.fun, 0.0))


# ------------------------------------------------------------------------------ a print's gamut
def _polytope_faces(n_inks: int, tac: float, nodes: int) -> np.ndarray:
    """Coverages [F, nodes, nodes, k] on every 2-D face of {c ∈ [0, 1]^k, Σc ≤ tac}: faces of
    the cube (two inks free, the others 0 or 1) and faces on the limit (two inks free, one
    ink taking the rest of the limit, the others 0 or 1); nodes outside the polytope are NaN."""
    from itertools import combinations, product

    u = np.linspace(0.0, 1.0, nodes)
    a, b = np.meshgrid(u, u, indexing="ij")
    faces = []
    for i, j in combinations(range(n_inks), 2):
        rest = [m for m in range(n_inks) if m not in (i, j)]
        for fixed in product((0.0, 1.0), repeat=len(rest)):
            c = np.zeros((nodes, nodes, n_inks))
            c[..., i], c[..., j] = a, b
            c[..., rest] = fixed
            faces.append(c)
        for m in rest:                       # ink m takes the rest of the limit
            others = [x for x in rest if x != m]
            for fixed in product((0.0, 1.0), repeat=len(others)):
                c = np.zeros((nodes, nodes, n_inks))
                c[..., i], c[..., j] = a, b
                c[..., others] = fixed
                c[..., m] = tac - a - b - sum(fixed)
                faces.append(c)
    c = np.stack(faces)
    bad = (c.sum(-1) > tac + 1e-9) | (c < -1e-9).any(-1) | (c > 1 + 1e-9).any(-1)
    c[bad] = np.nan
    return c


def gamut_chroma_max(lab_of, hue_of, n_inks: int, tac: float, L, h_deg, nodes: int = 65) -> np.ndarray:
    """The largest chroma C* a print reaches at lightness L* and hue h (degrees), [N], by brute
    force: the print's gamut is bounded by the images of the 2-D faces of its coverage
    polytope (`_polytope_faces`); each face is sampled on a nodes × nodes grid, cut into
    triangles, and the colour's (L*, h) located in every triangle (barycentric, piecewise
    linear): the largest C* of those that contain it (0 where none does). `lab_of`: coverages
    [..., k] → CIELAB; `hue_of`: CIELAB → the hue of the slices (degrees)."""
    c = _polytope_faces(n_inks, tac, nodes)
    ok = ~np.isnan(c[..., 0])
    lab = np.full(c.shape[:-1] + (3,), np.nan)
    lab[ok] = lab_of(c[ok])
    Lg, Cg = lab[..., 0], np.hypot(lab[..., 1], lab[..., 2])
    hg = np.full(Lg.shape, np.nan)
    hg[ok] = hue_of(lab[ok])
    tris = []
    for (di, dj), (ei, ej) in (((1, 0), (1, 1)), ((1, 1), (0, 1))):        # two triangles per cell
        idx = lambda oi, oj: (slice(None), slice(oi, nodes - 1 + oi), slice(oj, nodes - 1 + oj))  # noqa: E731
        tris.append(np.stack([np.stack([g[idx(0, 0)], g[idx(di, dj)], g[idx(ei, ej)]], -1)
                              for g in (Lg, Cg, hg)], -1).reshape(-1, 3, 3))
    t = np.concatenate(tris)                                   # [T, vertex, (L, C, h)]
    t = t[~np.isnan(t).any(axis=(1, 2)) & (t[:, :, 1].min(axis=1) > 1.0)]   # hue defined
    h0 = t[:, 0, 2]
    dh = (t[:, :, 2] - h0[:, None] + 180.0) % 360.0 - 180.0     # hues unwrapped about vertex 0
    t = t[np.abs(dh).max(axis=1) < 30.0]
    dh = dh[np.abs(dh).max(axis=1) < 30.0]
    h0 = t[:, 0, 2]
    lo, hi = np.floor(h0 + dh.min(axis=1)).astype(int), np.floor(h0 + dh.max(axis=1)).astype(int)
    L, h_deg = np.broadcast_arrays(np.asarray(L, dtype=np.float64), np.asarray(h_deg, dtype=np.float64))
    out = np.zeros(L.shape)
    bins = np.floor(h_deg % 360.0).astype(int)
    for b in np.unique(bins):
        cand = t[((lo <= b) & (hi >= b)) | ((lo <= b + 360) & (hi >= b + 360)) | ((lo <= b - 360) & (hi >= b - 360))]
        if cand.size == 0:
            continue
        sel = np.flatnonzero(bins == b)
        # (L, h) of each target in each candidate triangle's coordinates
        hv = (cand[None, :, :, 2] - h_deg[sel, None, None] + 180.0) % 360.0 - 180.0   # [n, T, 3]
        Lv = cand[None, :, :, 0] - L[sel, None, None]
        x1, y1 = Lv[..., 1] - Lv[..., 0], hv[..., 1] - hv[..., 0]
        x2, y2 = Lv[..., 2] - Lv[..., 0], hv[..., 2] - hv[..., 0]
        det = x1 * y2 - x2 * y1
        safe = np.where(np.abs(det) > 1e-12, det, 1.0)
        p, q = -Lv[..., 0], -hv[..., 0]
        s = (p * y2 - x2 * q) / safe
        r = (x1 * q - p * y1) / safe
        inside = (np.abs(det) > 1e-12) & (s >= 0) & (r >= 0) & (s + r <= 1)
        C = cand[None, :, 0, 1] + s * (cand[None, :, 1, 1] - cand[None, :, 0, 1]) + r * (cand[None, :, 2, 1] - cand[None, :, 0, 1])
        out[sel] = np.max(np.where(inside, C, 0.0), axis=1)
    return out
