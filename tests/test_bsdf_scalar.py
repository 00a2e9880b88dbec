"""`scalar_spectral` runs the same BSDF code lane by lane: it must agree with `llvm_ad_spectral`."""

import numpy as np
import pytest

from bsdf_probes import ink_bsdf, random_lanes, run_bsdf, run_bsdf_lanewise

N = 24
COMPARED = ("f", "pdf", "weight", "wo", "sample_pdf")


def _inputs(seed):
    """N lanes, two of them with ωo below the surface."""
    return random_lanes(np.random.default_rng(seed), N, below=2)


@pytest.mark.parametrize("ink", ["R30", "absorbing"])
def test_scalar_matches_llvm(use_variant, ink_tables, diffuse_tables, ink):
    path = {**ink_tables, **diffuse_tables}[ink]
    wi, wo, lam, u = _inputs(42)
    mi = use_variant("llvm_ad_spectral")
    ref = run_bsdf(mi, ink_bsdf(mi, path, 0.85, 0.7), wi, wo, lam, u)
    mi = use_variant("scalar_spectral")
    got = run_bsdf_lanewise(mi, ink_bsdf(mi, path, 0.85, 0.7), wi, wo, lam, u)
    for name in COMPARED:
        assert np.all(np.isfinite(getattr(got, name))), name
        np.testing.assert_allclose(getattr(got, name), getattr(ref, name), rtol=2e-4, atol=1e-6, err_msg=name)
    assert np.any(ref.f > 0) and np.all(ref.f[:, :2] == 0)          # non-trivial inputs


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
    ref = run_bsdf(mi, load(mi), wi, wo, lam, u)
    mi = use_variant("scalar_spectral")
    got = run_bsdf_lanewise(mi, load(mi), wi, wo, lam, u)
    for name in COMPARED:
        assert np.all(np.isfinite(getattr(got, name))), name
        np.testing.assert_allclose(getattr(got, name), getattr(ref, name), rtol=3e-4, atol=1e-6, err_msg=name)
    assert np.any(ref.f > 0)
