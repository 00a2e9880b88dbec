"""`ink` BSDF sampling: χ² of sample() against pdf() with real wavelengths, weights = eval/pdf,
the delta lobe's weight and probability, and the context's lobe selection."""

import numpy as np
import pytest

from bsdf_probes import as_numpy, chi2_adapter, draw, ink_bsdf, sample_consistency, surface_interaction, vector
from oracles import CY, MD, reference_delta
from solver.table import read_table


CHI2_CASES = [  # (ink, incidence °, wavelengths nm, paper, coverage, coverage model)
    ("clear", 10.0, (400.0, 455.0, 530.0, 690.0), 0.9, 1.0, CY),
    ("clear", 75.0, (365.0, 480.0, 610.0, 825.0), 1.0, 1.0, CY),      # grazing, P_spec large
    ("R30", 45.0, (420.0, 505.0, 580.0, 650.0), 0.9, 0.7, CY),
    ("R30", 45.0, (420.0, 505.0, 580.0, 650.0), 0.9, 0.7, MD),
    ("B30", 60.0, (390.0, 470.0, 560.0, 720.0), 0.5, 1.0, MD),
    ("lossless", 30.0, (410.0, 500.0, 600.0, 700.0), 0.9, 1.0, CY),
    ("absorbing", 70.0, (380.0, 550.0, 620.0, 780.0), 0.9, 0.4, CY),
    ("absorbing", 70.0, (380.0, 550.0, 620.0, 780.0), 0.9, 0.4, MD),
]


@pytest.mark.parametrize("ink,deg,wavelengths,paper,coverage,model", CHI2_CASES)
def test_chi2_sample_vs_pdf(use_variant, ink_tables, diffuse_tables, ink, deg, wavelengths, paper, coverage,
                            model):
    mi = use_variant("llvm_ad_spectral")
    from mitsuba.chi2 import ChiSquareTest, SphericalDomain

    path = {**ink_tables, **diffuse_tables}[ink]
    bsdf = ink_bsdf(mi, path, paper, coverage, model)
    s = np.radians(deg)
    sample, pdf = chi2_adapter(mi, bsdf, (np.sin(s), 0.0, np.cos(s)), wavelengths)
    chi2 = ChiSquareTest(domain=SphericalDomain(), sample_func=sample, pdf_func=pdf,
                         sample_dim=3, sample_count=400_000, res=61, seed=int(deg))
    assert chi2.run(significance_level=0.01, test_count=len(CHI2_CASES), quiet=True), chi2.messages
    # The smooth part holds 1 − P_spec of the samples (P_spec computed independently).
    p_spec, _ = reference_delta(read_table(path), np.array(wavelengths)[:, None], deg, paper, coverage, model)
    assert 0.01 < p_spec[0] < 0.99
    assert abs(float(chi2.pdf_sum[0]) - (1.0 - p_spec[0])) < 2e-3
    assert abs(float(chi2.histogram_sum[0]) - (1.0 - p_spec[0])) < 5e-3


@pytest.mark.parametrize("ink,deg,model", [("clear", 20.0, CY), ("G30", 65.0, CY), ("absorbing", 50.0, CY),
                                           ("absorbing", 50.0, MD)])
def test_sample_weights(use_variant, ink_tables, diffuse_tables, ink, deg, model):
    """Diffuse samples: weight = eval/pdf and bs.pdf = pdf(); delta samples: mirror direction,
    weight c·R_spec/P_spec and bs.pdf = P_spec, P_spec from an independent evaluation."""
    mi = use_variant("llvm_ad_spectral")
    path = {**ink_tables, **diffuse_tables}[ink]
    paper, coverage = 0.85, 0.8
    bsdf = ink_bsdf(mi, path, paper, coverage, model)
    got = sample_consistency(mi, bsdf, deg, 1 << 14, seed=11)
    delta, d = got.delta, ~got.delta
    assert 0.01 < delta.mean() < 0.9
    p_spec, w_spec = reference_delta(read_table(path), got.lam, deg, paper, coverage, model)
    np.testing.assert_allclose(got.sample_pdf[delta], p_spec[delta], rtol=2e-4)
    np.testing.assert_allclose(got.weight[:, delta], w_spec[:, delta], rtol=5e-4)
    np.testing.assert_allclose(got.pdf[d], (1 - p_spec[d]) * got.wo[2, d] / np.pi, rtol=3e-4)


def test_context_selects_lobes(use_variant, ink_tables):
    mi = use_variant("llvm_ad_spectral")
    path = ink_tables["Y30"]
    bsdf = ink_bsdf(mi, path, 0.9, 1.0, CY)
    n, deg = 4096, 40.0
    only_diffuse = mi.BSDFContext()
    only_diffuse.type_mask = +mi.BSDFFlags.DiffuseReflection
    si, bs, w, lam, wi = draw(mi, bsdf, deg, n, 1, only_diffuse)
    assert not np.any(np.asarray(mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)))
    cos_o = np.asarray(bs.wo[2])
    np.testing.assert_allclose(np.asarray(bs.pdf), cos_o / np.pi, rtol=1e-5)
    np.testing.assert_allclose(np.asarray(bsdf.pdf(only_diffuse, si, bs.wo)), cos_o / np.pi, rtol=1e-5)

    only_delta = mi.BSDFContext()
    only_delta.component = 0                       # component 0: the specular (delta) lobe
    si, bs, w, lam, wi = draw(mi, bsdf, deg, n, 2, only_delta)
    assert np.all(np.asarray(mi.has_flag(bs.sampled_type, mi.BSDFFlags.DeltaReflection)))
    np.testing.assert_allclose(np.asarray(bs.pdf), 1.0)
    p_spec, w_spec = reference_delta(read_table(path), lam, deg, 0.9, 1.0)
    np.testing.assert_allclose(w, w_spec * p_spec, rtol=5e-4)          # c·R_spec, no division
    assert np.all(np.asarray(bsdf.pdf(only_delta, si, bs.wo)) == 0.0)
    assert np.all(as_numpy(mi, bsdf.eval(only_delta, si, bs.wo)) == 0.0)


def test_below_surface_gives_zero(use_variant, ink_tables):
    mi = use_variant("llvm_ad_spectral")
    bsdf = ink_bsdf(mi, ink_tables["R30"], model=CY)
    si, bs, w, lam, wi = draw(mi, bsdf, 120.0, 256, 3)            # ωi below the sheet
    assert np.all(w == 0.0) and np.all(np.isfinite(w))
    assert np.all(np.asarray(bs.pdf) == 0.0)


def test_extreme_inputs_are_finite(use_variant, ink_tables, diffuse_tables):
    """Grazing and vertical directions, far-out wavelengths, paper 0 or 1: never NaN or Inf."""
    mi = use_variant("llvm_ad_spectral")
    cos_i = np.array([1.0, 1e-7, 0.0, 1e-3, 0.5, 1.0 - 1e-7, -1e-7, 0.3])
    sin_i = np.sqrt(np.clip(1 - cos_i**2, 0, None))
    wi = np.stack([sin_i, np.zeros_like(sin_i), cos_i])
    n = wi.shape[1]
    lam = np.tile(np.array([[1.0], [359.0], [831.0], [1e4]]), (1, n))
    wo = np.stack([np.zeros(n), sin_i[::-1], cos_i[::-1]])
    for path in (ink_tables["clear"], ink_tables["B30"], diffuse_tables["absorbing"]):
        for paper, coverage, model in ((1.0, 1.0, CY), (0.0, 0.5, CY), (1.0, 0.5, MD)):
            bsdf = ink_bsdf(mi, path, paper, coverage, model)
            si = surface_interaction(mi, wi, lam)
            for u in (0.0, 1.0 - 1e-7):
                bs, w = bsdf.sample(mi.BSDFContext(), si, mi.Float(np.full(n, u)), mi.Point2f(u, u))
                f, p = bsdf.eval_pdf(mi.BSDFContext(), si, vector(mi, wo))
                for arr in (w, f):
                    assert np.all(np.isfinite(as_numpy(mi, arr, n)))
                assert np.all(np.isfinite(np.asarray(p))) and np.all(np.isfinite(np.asarray(bs.pdf)))
