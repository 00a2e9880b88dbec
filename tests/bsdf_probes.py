"""Probing a Mitsuba BSDF from NumPy, in spectral and polarized variants: random directions and
lanes, surface interactions, eval / pdf / sample on [3, N] and [4, N] arrays (back as NumPy:
[4 λ, N], or Mueller matrices [4, 4, 4 λ, N]), the delta lobe alone, the directional albedo by
sampling and by quadrature, a χ² adapter, lane-by-lane runs in scalar variants, and the
oracles of the polarized tests that are built from Mitsuba's own functions.

`mi` is the mitsuba module with the variant set (the `use_variant` fixture of conftest.py).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from oracles import airy_sum

POLARIZED = "llvm_ad_spectral_polarized"


# --------------------------------------------------------------------------- NumPy inputs
def hemisphere(rng, n, below=0, lift=0.0):
    """Random unit vectors [3, n] above the surface (z += lift before normalising keeps them
    off grazing); the first `below` of them mirrored below it."""
    v = rng.normal(size=(3, n))
    v /= np.linalg.norm(v, axis=0)
    v[2] = np.abs(v[2]) + lift
    v /= np.linalg.norm(v, axis=0)
    v[2, :below] *= -1.0
    return v


def incident(deg, n=1):
    """n copies of the direction at polar angle `deg` in the xz-plane, [3, n]."""
    s = np.radians(deg)
    return np.tile([[np.sin(s)], [0.0], [np.cos(s)]], (1, n))


def at_polar_angles(sigma_deg, rng):
    """Unit vectors [3, N] at the polar angles `sigma_deg`, random azimuths."""
    s = np.radians(np.asarray(sigma_deg, dtype=np.float64))
    phi = rng.uniform(0.0, 2 * np.pi, s.size)
    return np.stack([np.sin(s) * np.cos(phi), np.sin(s) * np.sin(phi), np.cos(s)])


def random_lanes(rng, n, below=0):
    """(wi, wo [3, n], wavelengths [4, n] in 360–830 nm, sample() inputs u [3, n]); the first
    `below` wo under the surface."""
    wi, wo = hemisphere(rng, n), hemisphere(rng, n, below)
    return wi, wo, rng.uniform(360.0, 830.0, (4, n)), rng.random((3, n))


# ------------------------------------------------------------------------ Mitsuba <-> NumPy
def vector(mi, v):
    """mi.Vector3f of directions [3, N]."""
    return mi.Vector3f(*[mi.Float(c) for c in np.asarray(v, dtype=np.float64)])


def surface_interaction(mi, wi, wavelengths_nm):
    """A SurfaceInteraction3f for N lanes: wi [3, N] (local frame), wavelengths [4, N] nm."""
    import drjit as dr

    wi = np.asarray(wi, dtype=np.float64)
    lam = np.broadcast_to(np.asarray(wavelengths_nm, dtype=np.float64).reshape(4, -1), (4, wi.shape[1]))
    si = dr.zeros(mi.SurfaceInteraction3f, wi.shape[1])
    si.wi = vector(mi, wi)
    si.wavelengths = mi.UnpolarizedSpectrum(*[mi.Float(c) for c in lam])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    return si


def as_numpy(mi, value, n=None):
    """A sample/eval value → [4 λ, N] (unpolarized) or [4, 4, 4 λ, N] (Mueller); entries that
    Dr.Jit keeps as width-1 literals (a depolariser's zeros) are broadcast to N lanes."""
    import drjit as dr

    dr.eval(value)                              # one kernel for all entries, not one each
    n = dr.width(value) if n is None else n
    lanes = lambda x: np.broadcast_to(np.asarray(x, dtype=np.float64), (n,))      # noqa: E731
    if mi.is_polarized:
        return np.array([[[lanes(value[i][j][k]) for k in range(4)] for j in range(4)] for i in range(4)])
    return np.array([lanes(value[k]) for k in range(4)])


def to_spectrum(mi, m):
    """Mueller matrices [4, 4, 4 λ, N] → a polarized variant's mi.Spectrum."""
    return mi.Spectrum(*[mi.UnpolarizedSpectrum(*[mi.Float(m[i, j, k]) for k in range(4)])
                         for i in range(4) for j in range(4)])


# -------------------------------------------------------------------------------- queries
def ink_bsdf(mi, path, paper=0.9, coverage=1.0, model=None, **extra):
    """An `ink` BSDF of one table with uniform paper albedo and coverage (coverage model: the
    plugin's default unless given)."""
    d = {"type": "ink", "filename": str(path), "paper": paper, "coverage": coverage, **extra}
    if model is not None:
        d["coverage_model"] = model
    return mi.load_dict(d)


def evaluate(mi, bsdf, wi, wo, lam, ctx=None):
    """bsdf.eval (f·cos θo) for wi, wo [3, N] and wavelengths [4, N] (or [4]: every lane)."""
    si = surface_interaction(mi, wi, lam)
    return as_numpy(mi, bsdf.eval(mi.BSDFContext() if ctx is None else ctx, si, vector(mi, wo)))


def draw(mi, bsdf, deg, n, seed, ctx=None):
    """n samples at incidence `deg` (azimuth 0), wavelengths uniform in 360–830 nm:
    (si, bs, weight as NumPy, wavelengths [4, n], wi [3, n])."""
    rng = np.random.default_rng(seed)
    wi = incident(deg, n)
    lam = rng.uniform(360.0, 830.0, size=(4, n))
    si = surface_interaction(mi, wi, lam)
    u = rng.random((3, n))
    ctx = mi.BSDFContext() if ctx is None else ctx
    bs, w = bsdf.sample(ctx, si, mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    return si, bs, as_numpy(mi, w), lam, wi


class Draw(NamedTuple):
    """Samples of `sample_consistency`, as NumPy."""
    weight: np.ndarray         # [4, n]
    lam: np.ndarray            # [4, n] nm
    wi: np.ndarray             # [3, n]
    wo: np.ndarray             # [3, n]
    delta: np.ndarray          # [n] bool: the delta lobe was sampled
    pdf: np.ndarray            # eval_pdf's pdf at wo
    sample_pdf: np.ndarray     # bs.pdf


def sample_consistency(mi, bsdf, deg, n, seed) -> Draw:
    """`draw` n samples and assert what holds for every sample: a smooth one has bs.pdf = pdf()
    = eval_pdf's pdf and weight = eval/pdf; a delta one the mirror direction."""
    si, bs, weight, lam, wi = draw(mi, bsdf, deg, n, seed)
    delta = np.asarray(mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta))
    value, pdf = bsdf.eval_pdf(mi.BSDFContext(), si, bs.wo)
    value, pdf, bs_pdf = as_numpy(mi, value), np.asarray(pdf), np.asarray(bs.pdf)
    d = ~delta
    np.testing.assert_allclose(bs_pdf[d], pdf[d], rtol=1e-5)
    np.testing.assert_allclose(weight[:, d], value[:, d] / pdf[d], rtol=1e-4, atol=1e-7)
    np.testing.assert_allclose(np.asarray(bsdf.pdf(mi.BSDFContext(), si, bs.wo))[d], pdf[d], rtol=1e-6)
    wo = np.array([np.asarray(bs.wo[k]) for k in range(3)])
    np.testing.assert_allclose(wo[:, delta], (wi * [[-1], [-1], [1]])[:, delta], atol=1e-6)
    return Draw(weight, lam, wi, wo, delta, pdf, bs_pdf)


def delta_sample(mi, bsdf, wi, lam, mode=None):
    """(weight, wo, pdf) of the delta lobe alone (sampled with probability 1: the weight is
    c·R_spec, or its Mueller matrix)."""
    ctx = mi.BSDFContext() if mode is None else mi.BSDFContext(mode)
    ctx.type_mask = +mi.BSDFFlags.DeltaReflection
    n = wi.shape[1]
    half = mi.Float(np.full(n, 0.5))
    bs, w = bsdf.sample(ctx, surface_interaction(mi, wi, lam), half, mi.Point2f(half, half))
    return as_numpy(mi, w), np.array([np.asarray(bs.wo[i]) for i in range(3)]), np.asarray(bs.pdf)


def sample_weights(mi, bsdf, deg, wavelengths, seed=None):
    """sample() weights at incidence `deg` (azimuth 0) for lanes of wavelengths [4, n]; finite."""
    n = wavelengths.shape[1]
    rng = np.random.default_rng(int(deg * 10) + 1 if seed is None else seed)
    u = rng.random((3, n))
    _, w = bsdf.sample(mi.BSDFContext(), surface_interaction(mi, incident(deg, n), wavelengths),
                       mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    w = as_numpy(mi, w)
    assert np.all(np.isfinite(w))
    return w


def albedo_estimate(weights):
    """(mean, standard error) of the directional albedo from sample weights (M00 of Mueller
    weights). A lane's wavelengths share its direction (correlated): lanes are averaged first."""
    w = weights[0, 0] if weights.ndim == 4 else weights
    assert np.all(w >= 0)
    per_lane = w.mean(axis=0)
    return per_lane.mean(), per_lane.std() / np.sqrt(per_lane.size)


def sampled_albedo(mi, bsdf, deg, wavelengths, seed=None):
    """Mean and standard error of sample() weights: the directional albedo, estimated."""
    return albedo_estimate(sample_weights(mi, bsdf, deg, wavelengths, seed))


def quadrature_albedo(mi, bsdf, deg, wavelengths_nm, n_theta=720, n_phi=96):
    """∫ eval dωo by the midpoint rule, plus the delta lobe's weight, per wavelength [4]."""
    th = (np.arange(n_theta) + 0.5) * (np.pi / 2 / n_theta)
    ph = (np.arange(n_phi) + 0.5) * (2 * np.pi / n_phi)
    T, P = np.meshgrid(th, ph, indexing="ij")
    wo = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)]).reshape(3, -1)
    lam = np.asarray(wavelengths_nm, float)[:, None]
    value = evaluate(mi, bsdf, incident(deg, wo.shape[1]), wo, lam)
    d_omega = (np.sin(T) * (np.pi / 2 / n_theta) * (2 * np.pi / n_phi)).ravel()
    return value @ d_omega + delta_sample(mi, bsdf, incident(deg), lam)[0][:, 0]


def chi2_adapter(mi, bsdf, wi, wavelengths_nm, ctx=None):
    """Like mitsuba.chi2.BSDFAdapter, but with si.wavelengths set to real wavelengths (nm) and
    delta-lobe samples given weight 0 (the histogram then holds the smooth part, as pdf())."""
    import drjit as dr

    ctx = mi.BSDFContext() if ctx is None else ctx

    def make_si(n):
        si = dr.zeros(mi.SurfaceInteraction3f, n)
        si.wi = mi.Vector3f(*[float(x) for x in wi])
        si.wavelengths = mi.Spectrum(*[float(x) for x in wavelengths_nm])
        si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
        return si

    def sample(u, *args):
        bs, weight = bsdf.sample(ctx, make_si(dr.width(u)), u[0], mi.Vector2f(u[1], u[2]))
        smooth = mi.has_flag(bs.sampled_type, mi.BSDFFlags.Smooth)
        keep = smooth & dr.any(weight != 0)
        return bs.wo, dr.select(keep, mi.Float(1.0), mi.Float(0.0))

    def pdf(wo, *args):
        return bsdf.pdf(ctx, make_si(dr.width(wo)), wo)

    return sample, pdf


class Probe(NamedTuple):
    """One lane set through eval_pdf, eval and sample (full context), as NumPy."""
    f: np.ndarray              # eval_pdf's value
    pdf: np.ndarray
    f_only: np.ndarray         # eval's value
    weight: np.ndarray         # sample's weight
    wo: np.ndarray             # sampled direction [3, N]
    sample_pdf: np.ndarray
    component: np.ndarray      # sampled component (0: the delta lobe)


def run_bsdf(mi, bsdf, wi, wo, lam, u) -> Probe:
    """eval_pdf, eval and sample on all lanes at once (a JIT variant)."""
    import drjit as dr

    ctx = mi.BSDFContext()
    si = surface_interaction(mi, wi, lam)
    f, p = bsdf.eval_pdf(ctx, si, vector(mi, wo))
    f_only = bsdf.eval(ctx, si, vector(mi, wo))
    bs, w = bsdf.sample(ctx, si, mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    dr.eval(f, p, f_only, bs, w)
    return Probe(as_numpy(mi, f), np.asarray(p), as_numpy(mi, f_only), as_numpy(mi, w),
                 np.array([np.asarray(bs.wo[i]) for i in range(3)]), np.asarray(bs.pdf),
                 np.asarray(bs.sampled_component))


def run_bsdf_lanewise(mi, bsdf, wi, wo, lam, u) -> Probe:
    """As run_bsdf, one lane at a time (a scalar variant)."""
    import drjit as dr

    ctx = mi.BSDFContext()
    lanes = []
    for k in range(wi.shape[1]):
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wi = mi.Vector3f(*map(float, wi[:, k]))
        si.wavelengths = mi.UnpolarizedSpectrum(*map(float, lam[:, k]))
        si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
        out = mi.Vector3f(*map(float, wo[:, k]))
        f, p = bsdf.eval_pdf(ctx, si, out)
        f_only = bsdf.eval(ctx, si, out)
        bs, w = bsdf.sample(ctx, si, float(u[0, k]), mi.Point2f(float(u[1, k]), float(u[2, k])))
        lanes.append((as_numpy(mi, f, 1)[..., 0], float(p), as_numpy(mi, f_only, 1)[..., 0],
                      as_numpy(mi, w, 1)[..., 0], np.array(list(bs.wo), dtype=np.float64), float(bs.pdf),
                      int(bs.sampled_component)))
    return Probe(*(np.moveaxis(np.array(column), 0, -1) for column in zip(*lanes)))


# ------------------------------------------------------------- polarized variants' oracles
def compare_with_spectral(use_variant, scene: dict, n=256, seed=11):
    """Run the same lanes in llvm_ad_spectral and llvm_ad_spectral_polarized: M00 equals the
    spectral value, directions and pdfs agree, the smooth lobe depolarises. Returns
    (polarized weights [4, 4, 4, n], sampled component, spectral weights)."""
    wi, wo, lam, u = random_lanes(np.random.default_rng(seed), n, below=3)
    mi = use_variant("llvm_ad_spectral")
    ref = run_bsdf(mi, mi.load_dict(scene), wi, wo, lam, u)
    mi = use_variant(POLARIZED)
    got = run_bsdf(mi, mi.load_dict(scene), wi, wo, lam, u)
    for m in (got.f, got.f_only, got.weight):
        assert np.all(np.isfinite(m))
    for name in ("f", "f_only", "weight"):
        np.testing.assert_allclose(getattr(got, name)[0, 0], getattr(ref, name), rtol=1e-6, atol=1e-7, err_msg=name)
    for name in ("pdf", "wo", "sample_pdf", "component"):
        np.testing.assert_allclose(getattr(got, name), getattr(ref, name), rtol=1e-6, atol=1e-7, err_msg=name)
    off = np.ones((4, 4), bool)
    off[0, 0] = False
    assert np.all(got.f[off] == 0) and np.all(got.f_only[off] == 0)      # the smooth lobe depolarises
    smooth = got.component == 1
    assert np.all(got.weight[off][..., smooth] == 0)
    assert np.any(ref.f > 0) and np.any(smooth) and np.any(~smooth)      # both lobes exercised
    return got.weight, got.component, ref.weight


def mitsuba_fresnel(mi, cos_theta, eta):
    """(a_s, a_p) of mi.fresnel_polarized (scalar variant) as complex NumPy arrays."""
    import drjit as dr

    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    try:
        out = []
        for c, e in zip(np.ravel(cos_theta), np.broadcast_to(eta, np.shape(cos_theta)).ravel()):
            eta_c = dr.scalar.Complex2f(float(np.real(e)), float(np.imag(e)))
            a_s, a_p = mi.fresnel_polarized(float(c), eta_c)[:2]
            out.append([complex(dr.real(a_s), dr.imag(a_s)), complex(dr.real(a_p), dr.imag(a_p))])
    finally:
        if previous is not None:
            mi.set_variant(previous)
    out = np.array(out).reshape(np.shape(cos_theta) + (2,))
    return out[..., 0], out[..., 1]


def airy_film_amplitudes(mi, lam_nm, sigma_rad, thickness_nm, n):
    """(r_s, r_p) of a lossless film in air, Mitsuba's convention (e^(+iωt)), from Mitsuba's
    face amplitudes: the Airy sum of r01, r12 with p² = exp(−2i k0 n cos θt d)."""
    sigma_rad = np.asarray(sigma_rad, dtype=np.float64)
    cos_t = np.sqrt(1.0 - (np.sin(sigma_rad) / n) ** 2)
    top = mitsuba_fresnel(mi, np.cos(sigma_rad), n)
    bottom = mitsuba_fresnel(mi, cos_t, 1.0 / n)
    p2 = np.exp(-2j * (2 * np.pi / np.asarray(lam_nm)) * n * cos_t * thickness_nm)
    return tuple(airy_sum(r01, r12, p2) for r01, r12 in zip(top, bottom))


def in_stokes_bases(mi, m, wi, wo, radiance=True):
    """Oracle matrices [4, 4, 4, N] (plane-of-incidence frame, s = basis vector) rotated as
    Mitsuba's conductor/dielectric plugins rotate theirs, with mi.mueller.rotate_mueller_basis."""
    import drjit as dr

    wo_hat, wi_hat = (wo, wi) if radiance else (wi, wo)
    s_in = np.cross([0.0, 0.0, 1.0], -wo_hat.T).T
    s_out = np.cross([0.0, 0.0, 1.0], wi_hat.T).T
    for s in (s_in, s_out):
        norm = np.linalg.norm(s, axis=0)
        s[:, norm == 0] = np.array([[1.0], [0.0], [0.0]])
        s /= np.linalg.norm(s, axis=0)
    rotated = mi.mueller.rotate_mueller_basis(
        to_spectrum(mi, m), vector(mi, -wo_hat), vector(mi, s_in), mi.mueller.stokes_basis(vector(mi, -wo_hat)),
        vector(mi, wi_hat), vector(mi, s_out), mi.mueller.stokes_basis(vector(mi, wi_hat)))
    dr.eval(rotated)
    return as_numpy(mi, rotated)
