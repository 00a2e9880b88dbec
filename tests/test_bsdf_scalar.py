"""`scalar_spectral` runs the same BSDF code lane by lane: it must agree with `llvm_ad_spectral`."""

import numpy as np
import pytest

from conftest import ink_bsdf, surface_interaction

N = 24


def _inputs(seed):
    rng = np.random.default_rng(seed)
    wi = rng.normal(size=(3, N))
    wo = rng.normal(size=(3, N))
    wi /= np.linalg.norm(wi, axis=0)
    wo /= np.linalg.norm(wo, axis=0)
    wi[2] = np.abs(wi[2])
    wo[2] = np.abs(wo[2])
    wo[2, :2] *= -1.0                                  # two lanes below the surface
    lam = rng.uniform(360.0, 830.0, size=(4, N))
    u = rng.random((3, N))
    return wi, wo, lam, u


def _run_llvm(mi, bsdf, wi, wo, lam, u):
    si = surface_interaction(mi, wi, lam)
    ctx = mi.BSDFContext()
    f, p = bsdf.eval_pdf(ctx, si, mi.Vector3f(*[mi.Float(c) for c in wo]))
    bs, w = bsdf.sample(ctx, si, mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    arr = lambda x, n: np.array([np.asarray(x[j]) for j in range(n)])   # noqa: E731
    return arr(f, 4), np.asarray(p), arr(w, 4), arr(bs.wo, 3), np.asarray(bs.pdf)


def _run_scalar(mi, bsdf, wi, wo, lam, u):
    import drjit as dr

    out = [[] for _ in range(5)]
    ctx = mi.BSDFContext()
    for k in range(N):
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wi = mi.Vector3f(*map(float, wi[:, k]))
        si.wavelengths = mi.Spectrum(*map(float, lam[:, k]))
        si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
        f, p = bsdf.eval_pdf(ctx, si, mi.Vector3f(*map(float, wo[:, k])))
        bs, w = bsdf.sample(ctx, si, float(u[0, k]), mi.Point2f(float(u[1, k]), float(u[2, k])))
        for lst, v in zip(out, (list(f), p, list(w), list(bs.wo), bs.pdf)):
            lst.append(v)
    return tuple(np.array(x, dtype=np.float64).T for x in out)


@pytest.mark.parametrize("ink", ["R30", "absorbing"])
def test_scalar_matches_llvm(use_variant, ink_tables, diffuse_tables, ink):
    path = {**ink_tables, **diffuse_tables}[ink]
    wi, wo, lam, u = _inputs(42)
    mi = use_variant("llvm_ad_spectral")
    ref = _run_llvm(mi, ink_bsdf(mi, path, 0.85, 0.7), wi, wo, lam, u)
    mi = use_variant("scalar_spectral")
    got = _run_scalar(mi, ink_bsdf(mi, path, 0.85, 0.7), wi, wo, lam, u)
    for name, a, b in zip(("eval", "pdf", "weight", "wo", "sample pdf"), got, ref):
        assert np.all(np.isfinite(a)), name
        np.testing.assert_allclose(a, b, rtol=2e-4, atol=1e-6, err_msg=name)
    assert np.any(ref[0] > 0) and np.all(ref[0][:, :2] == 0)          # non-trivial inputs


@pytest.mark.parametrize("model", ["clapper-yule", "murray-davies"])
def test_scalar_matches_llvm_three_inks(use_variant, ink_tables, diffuse_tables, tmp_path, model):
    """Three overlapping inks (one coverage a bitmap, analysed at load in each variant)."""
    from inkbsdf.inks import stack_provider
    from printing_tables import StackProvider

    wi, wo, lam, u = _inputs(43)
    img = np.full((4, 4, 1), 0.4, dtype=np.float32)
    img[3, 3] = 0.0

    def load(mi):
        mi.Bitmap(img, mi.Bitmap.PixelFormat.Y).write(str(tmp_path / "cov.exr"))
        with stack_provider(StackProvider()):
            return mi.load_dict({
                "type": "ink", "coverage_model": model, "paper": 0.85,
                "filename1": str(ink_tables["R30"]), "coverage1": 0.5,
                "filename2": str(diffuse_tables["absorbing"]),
                "coverage2": {"type": "bitmap", "filename": str(tmp_path / "cov.exr"), "raw": True},
                "filename3": str(ink_tables["B30"]), "coverage3": 0.6})

    mi = use_variant("llvm_ad_spectral")
    ref = _run_llvm(mi, load(mi), wi, wo, lam, u)
    mi = use_variant("scalar_spectral")
    got = _run_scalar(mi, load(mi), wi, wo, lam, u)
    for name, a, b in zip(("eval", "pdf", "weight", "wo", "sample pdf"), got, ref):
        assert np.all(np.isfinite(a)), name
        np.testing.assert_allclose(a, b, rtol=3e-4, atol=1e-6, err_msg=name)
    assert np.any(ref[0] > 0)
