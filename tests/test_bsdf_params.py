"""`ink` BSDF parameters: paper and coverage as values, spectra and textures; traverse/update."""

import numpy as np

from bsdf_probes import as_numpy, hemisphere, ink_bsdf, surface_interaction, vector


def _setup(mi, n=512, seed=0):
    rng = np.random.default_rng(seed)
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    si = surface_interaction(mi, wi, rng.uniform(360, 830, size=(4, n)))
    si.uv = mi.Point2f(mi.Float(rng.random(n)), mi.Float(rng.random(n)))
    return si, vector(mi, wo)


def test_bare_paper_is_the_builtin_diffuse(use_variant, ink_tables):
    """coverage 0 with an RGB paper albedo is exactly Mitsuba's `diffuse` with that reflectance."""
    mi = use_variant("llvm_ad_spectral")
    paper = {"type": "rgb", "value": [0.8, 0.5, 0.2]}
    ink = mi.load_dict({"type": "ink", "filename": str(ink_tables["R30"]), "paper": paper, "coverage": 0.0})
    ref = mi.load_dict({"type": "diffuse", "reflectance": paper})
    si, wo = _setup(mi)
    ctx = mi.BSDFContext()
    np.testing.assert_allclose(as_numpy(mi, ink.eval(ctx, si, wo)), as_numpy(mi, ref.eval(ctx, si, wo)),
                               rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(np.asarray(ink.pdf(ctx, si, wo)), np.asarray(ref.pdf(ctx, si, wo)), rtol=1e-5)


def test_traverse_exposes_paper_and_coverage(use_variant, ink_tables):
    mi = use_variant("llvm_ad_spectral")
    bsdf = ink_bsdf(mi, ink_tables["G30"], paper=0.9, coverage=1.0)
    params = mi.traverse(bsdf)
    assert "paper.value" in params and "coverage.value" in params
    si, wo = _setup(mi)
    ctx = mi.BSDFContext()
    full = as_numpy(mi, bsdf.eval(ctx, si, wo))
    params["coverage.value"] = 0.0
    params.update()
    bare = as_numpy(mi, bsdf.eval(ctx, si, wo))
    cos_o = np.asarray(wo[2])
    np.testing.assert_allclose(bare, np.broadcast_to(0.9 / np.pi * cos_o, bare.shape), rtol=1e-5)
    assert np.max(np.abs(full - bare)) > 0.01
    params["coverage.value"] = 0.25
    params["paper.value"] = 0.5
    params.update()
    quarter = as_numpy(mi, bsdf.eval(ctx, si, wo))
    half_paper = ink_bsdf(mi, ink_tables["G30"], paper=0.5, coverage=0.25)
    np.testing.assert_allclose(quarter, as_numpy(mi, half_paper.eval(ctx, si, wo)), rtol=1e-5)


def test_coverage_texture(use_variant, ink_tables, tmp_path):
    """A bitmap coverage (0 left half, 1 right half) gives bare paper or full ink per uv."""
    mi = use_variant("llvm_ad_spectral")
    img = np.zeros((8, 8, 1), dtype=np.float32)
    img[:, 4:] = 1.0
    mi.Bitmap(img, mi.Bitmap.PixelFormat.Y).write(str(tmp_path / "cov.exr"))
    path = str(ink_tables["Y30"])
    textured = mi.load_dict({"type": "ink", "filename": path, "coverage": {
        "type": "bitmap", "filename": str(tmp_path / "cov.exr"), "raw": True, "filter_type": "nearest"}})
    si, wo = _setup(mi, seed=3)
    u = np.asarray(si.uv.x)
    ctx = mi.BSDFContext()
    got = as_numpy(mi, textured.eval(ctx, si, wo))
    full = as_numpy(mi, ink_bsdf(mi, path, coverage=1.0).eval(ctx, si, wo))
    bare = as_numpy(mi, ink_bsdf(mi, path, coverage=0.0).eval(ctx, si, wo))
    right, left = u > 0.51, u < 0.49
    np.testing.assert_allclose(got[:, right], full[:, right], rtol=1e-5)
    np.testing.assert_allclose(got[:, left], bare[:, left], rtol=1e-5)
    assert textured.flags() & mi.BSDFFlags.SpatiallyVarying
