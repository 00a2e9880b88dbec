"""The `ink` BSDF in Mitsuba's polarized variants: the mirror lobe's Mueller matrix.

Oracles, all outside the plugin: Mitsuba's own `conductor` plugin (its C++ Mueller matrix and
Stokes-frame rotation) for a table of one binder face; for the clear film, the Airy sum of
Mitsuba's `fresnel_polarized` face amplitudes turned into a Mueller matrix by the textbook Jones →
Mueller map (pinned to `mi.mueller.specular_reflection` here) and rotated into the Stokes bases
with `mi.mueller.rotate_mueller_basis` as Mitsuba's specular plugins do; and the spectral
(unpolarized) variant for the intensity M00.
"""

from __future__ import annotations


import numpy as np
import pytest

from solver.table import InkTable, validate, write_table
from solver.table.builder import build_table
from solver.table.request import table_request
from solver.thinfilm import stack, to_mitsuba_convention

N_BINDER = 1.558
FILM_NM = 1000.0
POLARIZED = "llvm_ad_spectral_polarized"
BREWSTER_DEG = float(np.degrees(np.arctan(N_BINDER)))


# ----------------------------------------------------------------------------- helpers
def directions(sigma_deg, rng):
    """Unit vectors [3, N] at polar angles `sigma_deg`, random azimuths."""
    s = np.radians(np.asarray(sigma_deg, dtype=np.float64))
    phi = rng.uniform(0.0, 2 * np.pi, s.size)
    return np.stack([np.sin(s) * np.cos(phi), np.sin(s) * np.sin(phi), np.cos(s)])


def interaction(mi, wi, lam):
    """SurfaceInteraction3f for N lanes (wi [3, N], wavelengths [4, N] nm), any spectral variant."""
    import drjit as dr

    si = dr.zeros(mi.SurfaceInteraction3f, wi.shape[1])
    si.wi = mi.Vector3f(*[mi.Float(c) for c in wi])
    si.wavelengths = mi.UnpolarizedSpectrum(*[mi.Float(c) for c in lam])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    return si


def as_numpy(mi, value, n=None):
    """A sample/eval value → [4, 4, 4 λ, N] (Mueller) or [4 λ, N] (unpolarized); entries that
    Dr.Jit keeps as width-1 literals (a depolariser's zeros) are broadcast to N lanes."""
    import drjit as dr

    dr.eval(value)                              # one kernel for all 64 entries, not one each
    n = dr.width(value) if n is None else n
    lanes = lambda x: np.broadcast_to(np.asarray(x, dtype=np.float64), (n,))      # noqa: E731
    if mi.is_polarized:
        return np.array([[[lanes(value[i][j][k]) for k in range(4)] for j in range(4)] for i in range(4)])
    return np.array([lanes(value[k]) for k in range(4)])


def to_spectrum(mi, m):
    """[4, 4, 4 λ, N] NumPy → a polarized variant's mi.Spectrum (Mueller matrix)."""
    return mi.Spectrum(*[mi.UnpolarizedSpectrum(*[mi.Float(m[i, j, k]) for k in range(4)])
                         for i in range(4) for j in range(4)])


def delta_sample(mi, bsdf, wi, lam, mode=None):
    """(weight, wo) of the delta lobe alone (sampled with probability 1)."""
    ctx = mi.BSDFContext() if mode is None else mi.BSDFContext(mode)
    ctx.type_mask = +mi.BSDFFlags.DeltaReflection
    n = wi.shape[1]
    bs, w = bsdf.sample(ctx, interaction(mi, wi, lam), mi.Float(np.full(n, 0.5)),
                        mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
    return as_numpy(mi, w), np.array([np.asarray(bs.wo[i]) for i in range(3)]), np.asarray(bs.pdf)


def jones_to_mueller(a_s, a_p):
    """Textbook Mueller matrix [4, 4, ...] of the Jones matrix diag(a_s, a_p) (x = s, y = p):
    M = A (J ⊗ J*) A⁻¹, A = [[1, 0, 0, 1], [1, 0, 0, −1], [0, 1, 1, 0], [0, i, −i, 0]]
    (S3 = i(E_s E_p* − E_p E_s*); with Mitsuba's e^(+iωt) amplitudes this is its sign, pinned by
    test_jones_map_is_mitsubas_specular_reflection)."""
    a_s, a_p = np.broadcast_arrays(np.asarray(a_s, complex), np.asarray(a_p, complex))
    A = np.array([[1, 0, 0, 1], [1, 0, 0, -1], [0, 1, 1, 0], [0, 1j, -1j, 0]])
    jj = np.zeros((4, 4) + a_s.shape, complex)                 # J ⊗ J*, J = diag(a_s, a_p)
    for row, (u, v) in enumerate([(a_s, a_s), (a_s, a_p), (a_p, a_s), (a_p, a_p)]):
        jj[row, row] = u * np.conj(v)
    m = np.einsum("ij,jk...,kl->il...", A, jj, np.linalg.inv(A))
    assert np.max(np.abs(m.imag)) < 1e-12
    return m.real


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


def in_stokes_bases(mi, m, wi, wo, radiance=True):
    """Oracle matrices [4, 4, 4, N] (plane-of-incidence frame, s = basis vector) rotated as
    Mitsuba's conductor/dielectric plugins rotate theirs, with mi.mueller.rotate_mueller_basis."""
    import drjit as dr

    wo_hat, wi_hat = (wo, wi) if radiance else (wi, wo)
    v = lambda a: mi.Vector3f(*[mi.Float(c) for c in a])          # noqa: E731
    s_in = np.cross([0.0, 0.0, 1.0], -wo_hat.T).T
    s_out = np.cross([0.0, 0.0, 1.0], wi_hat.T).T
    for s in (s_in, s_out):
        norm = np.linalg.norm(s, axis=0)
        s[:, norm == 0] = np.array([[1.0], [0.0], [0.0]])
        s /= np.linalg.norm(s, axis=0)
    rotated = mi.mueller.rotate_mueller_basis(
        to_spectrum(mi, m), v(-wo_hat), v(s_in), mi.mueller.stokes_basis(v(-wo_hat)),
        v(wi_hat), v(s_out), mi.mueller.stokes_basis(v(wi_hat)))
    dr.eval(rotated)
    return as_numpy(mi, rotated)


def interface_table(sigma_deg, wavelengths_nm=(360.0, 830.0)) -> InkTable:
    """A table of one air → binder face (no film): the face's s, p amplitudes from
    solver.thinfilm in Mitsuba's convention, R_spec their mean power, everything else transmitted."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    sigma = np.radians(np.asarray(sigma_deg, dtype=np.float64))
    amp = {p: to_mitsuba_convention(stack([], [], wl[:, None], sigma[None, :], polarisation=p,
                                          eps_out=N_BINDER**2).r) for p in ("te", "tm")}
    r = 0.5 * (np.abs(amp["te"]) ** 2 + np.abs(amp["tm"]) ** 2)
    like = build_table(table_request("clear", polarisation="unpolarised"))
    meta = dict(like.meta, ink="binder face", tier="synthetic", tier_reason="test: one face")
    return validate(InkTable(wavelengths=wl, sigma=sigma, theta=like.theta, dphi=like.dphi,
                             R=np.zeros((wl.size, sigma.size) + like.R.shape[2:]), R_spec=r,
                             T_coh=1.0 - r, Rbar=r.copy(), Tbar=1.0 - r, Rbar_below=r.copy(),
                             meta=meta, r_s=amp["te"], r_p=amp["tm"]))


@pytest.fixture(scope="module")
def clear_table():
    """The exact Airy film of clear binder (1000 nm), unpolarised: (InkTable, path)."""
    table = build_table(table_request("clear", polarisation="unpolarised"))
    assert table.polarisation == "unpolarised" and table.r_s is not None
    return table


# ------------------------------------------------------------------------------- tests
def test_jones_map_is_mitsubas_specular_reflection(use_variant):
    """The test's Jones → Mueller map of fresnel_polarized's amplitudes is Mitsuba's
    mueller.specular_reflection (dielectric, Brewster, absorbing, total internal reflection)."""
    import drjit as dr

    mi = use_variant(POLARIZED)
    previous = mi.variant()
    cases = [(0.93, 1.558), (np.cos(np.radians(BREWSTER_DEG)), 1.558), (0.5, 1.4 + 0.8j),
             (0.2, 1.5 + 0.05j), (0.6, 1 / 1.558), (0.9, 1 / 1.558)]
    for cos_t, eta in cases:
        a_s, a_p = mitsuba_fresnel(mi, np.array([cos_t]), eta)
        mi.set_variant("scalar_rgb")
        try:
            ref = np.array(mi.mueller.specular_reflection(float(cos_t), dr.scalar.Complex2f(np.real(eta), np.imag(eta))))
        finally:
            mi.set_variant(previous)
        np.testing.assert_allclose(jones_to_mueller(a_s, a_p)[..., 0], ref, atol=2e-6, err_msg=str((cos_t, eta)))


def _both_modes(mi):
    return [(mi.TransportMode.Radiance, True), (mi.TransportMode.Importance, False)]


def test_face_matches_mitsuba_conductor(use_variant, tmp_path):
    """A table of one binder face (σ nodes at the test's angles, Brewster's among them) gives
    exactly the Mueller matrix, directions and frames of Mitsuba's smooth `conductor` with
    η = 1.558, κ = 0, in radiance and importance transport."""
    nodes = [0.0, 10.0, 25.0, 40.0, BREWSTER_DEG, 70.0, 80.0, 89.0, 90.0]
    path = write_table(tmp_path / "face.npz", interface_table(nodes))
    mi = use_variant(POLARIZED)
    ink = mi.load_dict({"type": "ink", "filename": str(path), "paper": 0.9})
    conductor = mi.load_dict({"type": "conductor", "eta": N_BINDER, "k": 0.0})
    rng = np.random.default_rng(3)
    wi = directions(np.repeat(nodes[:-1], 6), rng)
    lam = rng.uniform(400.0, 700.0, (4, wi.shape[1]))
    for mode, _ in _both_modes(mi):
        got, wo, pdf = delta_sample(mi, ink, wi, lam, mode)
        ctx = mi.BSDFContext(mode)
        n = wi.shape[1]
        bs, ref = conductor.sample(ctx, interaction(mi, wi, lam), mi.Float(np.full(n, 0.5)),
                                   mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
        ref = as_numpy(mi, ref)
        np.testing.assert_allclose(wo, [np.asarray(bs.wo[i]) for i in range(3)], atol=1e-6)
        np.testing.assert_allclose(pdf, 1.0)
        np.testing.assert_allclose(got, ref, atol=1e-5, err_msg=str(mode))
        assert np.max(np.abs(ref[0, 2])) > 0.02 and np.max(np.abs(ref[2, 3])) < 1e-6   # frames matter
        brewster = np.isclose(np.degrees(np.arccos(wi[2])), BREWSTER_DEG)
        np.testing.assert_allclose(np.hypot(got[0, 1], got[0, 2])[:, brewster], got[0, 0][:, brewster],
                                   rtol=1e-5)                   # fully polarised at Brewster's angle


def airy_film_amplitudes(mi, lam_nm, sigma_rad, thickness_nm=FILM_NM, n=N_BINDER):
    """(r_s, r_p) of a lossless film in air, Mitsuba's convention (e^(+iωt)), from Mitsuba's
    face amplitudes: r = (r01 + r12 p²)/(1 + r01 r12 p²), p² = exp(−2i k0 n cos θt d)."""
    sigma_rad = np.asarray(sigma_rad, dtype=np.float64)
    cos_i = np.cos(sigma_rad)
    cos_t = np.sqrt(1.0 - (np.sin(sigma_rad) / n) ** 2)
    top = mitsuba_fresnel(mi, cos_i, n)
    bottom = mitsuba_fresnel(mi, cos_t, 1.0 / n)
    p2 = np.exp(-2j * (2 * np.pi / np.asarray(lam_nm)) * n * cos_t * thickness_nm)
    return tuple((r01 + r12 * p2) / (1.0 + r01 * r12 * p2) for r01, r12 in zip(top, bottom))


def test_film_matches_airy_oracle(use_variant, clear_table, tmp_path):
    """The clear 1000-nm film: the delta lobe's Mueller matrix at table nodes equals the Airy
    film of Mitsuba's face amplitudes (Jones → Mueller, rotated into the Stokes bases), in both
    transport modes; between wavelength nodes it is the mean of the neighbours' matrices
    (element-wise linear interpolation, as R_spec is interpolated)."""
    path = write_table(tmp_path / "clear.npz", clear_table)
    mi = use_variant(POLARIZED)
    ink = mi.load_dict({"type": "ink", "filename": str(path), "paper": 0.9})
    rng = np.random.default_rng(5)
    angles = np.repeat([0.0, 20.0, 40.0, 56.0, 58.0, 70.0, 80.0, 88.0], 3)
    nodes = clear_table.wavelengths[(clear_table.wavelengths >= 400) & (clear_table.wavelengths <= 700)]
    assert np.all(np.isin(np.radians(angles), clear_table.sigma) | np.isclose(
        np.radians(angles)[:, None], clear_table.sigma[None, :]).any(axis=1))
    wi = directions(angles, rng)
    lam = rng.choice(nodes[:-1], (4, wi.shape[1]))
    step = float(nodes[1] - nodes[0])
    for mode, radiance in _both_modes(mi):
        got, wo, _ = delta_sample(mi, ink, wi, lam, mode)
        oracle = in_stokes_bases(mi, jones_to_mueller(*airy_film_amplitudes(mi, lam, np.radians(angles))),
                                 wi, wo, radiance)
        np.testing.assert_allclose(got, oracle, atol=2e-5, err_msg=str(mode))
        assert np.max(np.abs(oracle[2:, 2:] - oracle[0, 0] * np.eye(2)[:, :, None, None])) > 0.05
        mid, _, _ = delta_sample(mi, ink, wi, lam + 0.5 * step, mode)
        ends = [jones_to_mueller(*airy_film_amplitudes(mi, lam + d, np.radians(angles))) for d in (0.0, step)]
        mean = in_stokes_bases(mi, 0.5 * (ends[0] + ends[1]), wi, wo, radiance)
        np.testing.assert_allclose(mid, mean, atol=2e-5, err_msg=f"{mode}, between λ nodes")


def _random_lanes(rng, n):
    wi, wo = rng.normal(size=(3, n)), rng.normal(size=(3, n))
    wi /= np.linalg.norm(wi, axis=0)
    wo /= np.linalg.norm(wo, axis=0)
    wi[2], wo[2] = np.abs(wi[2]), np.abs(wo[2])
    wo[2, :3] *= -1.0                                   # a few lanes below the surface
    return wi, wo, rng.uniform(360.0, 830.0, (4, n)), rng.random((3, n))


def run_bsdf(mi, bsdf, wi, wo, lam, u):
    """eval, pdf, sample weight, sampled wo, sample pdf, sampled component (full context)."""
    import drjit as dr

    ctx = mi.BSDFContext()
    si = interaction(mi, wi, lam)
    f, p = bsdf.eval_pdf(ctx, si, mi.Vector3f(*[mi.Float(c) for c in wo]))
    f_only = bsdf.eval(ctx, si, mi.Vector3f(*[mi.Float(c) for c in wo]))
    bs, w = bsdf.sample(ctx, si, mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    dr.eval(f, p, f_only, bs, w)
    return (as_numpy(mi, f), np.asarray(p), as_numpy(mi, f_only), as_numpy(mi, w),
            np.array([np.asarray(bs.wo[i]) for i in range(3)]), np.asarray(bs.pdf),
            np.asarray(bs.sampled_component))


def compare_with_spectral(use_variant, scene: dict, n=256, seed=11):
    """Run the same lanes in llvm_ad_spectral and llvm_ad_spectral_polarized: M00 equals the
    spectral value, directions and pdfs agree, the smooth lobe depolarises. Returns
    (polarized weights [4, 4, 4, n], sampled component, spectral weights)."""
    rng = np.random.default_rng(seed)
    wi, wo, lam, u = _random_lanes(rng, n)
    mi = use_variant("llvm_ad_spectral")
    ref = run_bsdf(mi, mi.load_dict(scene), wi, wo, lam, u)
    mi = use_variant(POLARIZED)
    got = run_bsdf(mi, mi.load_dict(scene), wi, wo, lam, u)
    f, p, f_only, w, wo_s, pdf_s, comp = got
    for m in (f, f_only, w):
        assert np.all(np.isfinite(m))
    for name, a, b in (("eval", f[0, 0], ref[0]), ("eval only", f_only[0, 0], ref[2]),
                       ("weight", w[0, 0], ref[3])):
        np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-7, err_msg=name)
    for name, a, b in (("pdf", p, ref[1]), ("wo", wo_s, ref[4]), ("sample pdf", pdf_s, ref[5]),
                       ("component", comp, ref[6])):
        np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-7, err_msg=name)
    off = np.ones((4, 4), bool)
    off[0, 0] = False
    assert np.all(f[off] == 0) and np.all(f_only[off] == 0)          # the smooth lobe depolarises
    smooth = comp == 1
    assert np.all(w[off][..., smooth] == 0)
    assert np.any(ref[0] > 0) and np.any(smooth) and np.any(~smooth)      # both lobes exercised
    return w, comp, ref[3]


def test_intensity_equals_spectral_variant(use_variant, clear_table, tmp_path):
    """Clear film on paper 0.9 at coverage 0.7: M00 of eval, eval_pdf and sample equals the
    spectral variant's value on the same lanes (same sampled lobes and directions); the smooth
    lobe's matrix is an ideal depolariser; the mirror lobe's is not."""
    path = write_table(tmp_path / "clear.npz", clear_table)
    w, comp, _ = compare_with_spectral(use_variant, {"type": "ink", "filename": str(path), "paper": 0.9,
                                                     "coverage": 0.7})
    assert np.max(np.abs(w[0, 1:][..., comp == 0])) > 0.05


def test_tables_without_amplitudes_are_refused(use_variant, tmp_path):
    """A 'te' table (s light only, no r_s/r_p) in a polarized variant: one clear error at load,
    naming the table, what is missing and the two ways out; fine in the spectral variant."""
    te = write_table(tmp_path / "te.npz", build_table(table_request("clear", polarisation="te")))
    pol = write_table(tmp_path / "pol.npz", build_table(table_request("R30", polarisation="unpolarised")))
    mi = use_variant("llvm_ad_spectral")
    mi.load_dict({"type": "ink", "filename": str(te)})
    mi = use_variant(POLARIZED)
    for scene in ({"type": "ink", "filename": str(te)},
                  {"type": "ink", "filename1": str(pol), "filename2": str(te), "coverage2": 0.0}):
        with pytest.raises(Exception) as info:
            mi.load_dict(scene)
        message = str(info.value)
        for needle in ("te.npz", "r_s, r_p", "polarisation 'te'", "'unpolarised'", "'llvm_ad_spectral'"):
            assert needle in message, (needle, message)
        assert len(message.splitlines()) <= 4, message               # short, no caller stack


def test_hard_directions_are_finite(use_variant, clear_table, tmp_path):
    """Normal incidence (no plane of incidence), grazing, barely above and below the surface,
    in both transport modes and for either lobe alone: finite Mueller matrices, zero below the
    surface and at grazing incidence, and the mirror exact at normal incidence (b = 0, S = 0)."""
    path = write_table(tmp_path / "clear.npz", clear_table)
    mi = use_variant(POLARIZED)
    bsdf = mi.load_dict({"type": "ink", "filename": str(path), "paper": 0.9, "coverage": 0.9})
    wi = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.6, 0.8, 1e-7], [0.6, 0.8, 1e-4],
                   [0.0, 0.0, -1.0], [0.6, 0.0, -0.8], [0.6, 0.8, -1e-7]]).T
    wi /= np.linalg.norm(wi, axis=0)
    lam = np.tile([[400.0], [500.0], [600.0], [700.0]], (1, wi.shape[1]))
    for mode, _ in _both_modes(mi):
        for mask in (mi.BSDFFlags.DeltaReflection, mi.BSDFFlags.DiffuseReflection, mi.BSDFFlags.All):
            ctx = mi.BSDFContext(mode)
            ctx.type_mask = +mask
            for u in (0.01, 0.5, 0.99):
                n = wi.shape[1]
                si = interaction(mi, wi, lam)
                _, w = bsdf.sample(ctx, si, mi.Float(np.full(n, u)), mi.Point2f(mi.Float(np.full(n, u)),
                                                                             mi.Float(np.full(n, 0.3))))
                f = bsdf.eval(ctx, si, mi.Vector3f(*[mi.Float(c) for c in wi[:, [3] * n]]))
                w, f = as_numpy(mi, w, n), as_numpy(mi, f, n)
                assert np.all(np.isfinite(w)) and np.all(np.isfinite(f)), (mode, mask, u)
                assert np.all(w[..., [1, 4, 5, 6]] == 0) and np.all(f[..., [1, 4, 5, 6]] == 0)
    normal, _, _ = delta_sample(mi, bsdf, wi[:, :1], lam[:, :1])
    a = normal[0, 0]
    assert np.all(a > 0.01)
    np.testing.assert_allclose(np.abs(normal[1, 1]) + np.abs(normal[1, 2]), a, rtol=1e-5)   # |rotation| · a
    np.testing.assert_allclose(np.abs(normal[3, 3]), a, rtol=1e-5)                            # C = −a, S = 0
    np.testing.assert_allclose(normal[0, 1:], 0.0, atol=1e-7)                                 # b = 0
