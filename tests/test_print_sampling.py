"""Sampling of the `ink` BSDF with several overlapping inks: χ² of sample() against pdf() for
both coverage models, weights = eval/pdf, delta-lobe probability from the NumPy model."""

import numpy as np
import pytest

from bsdf_probes import chi2_adapter, sample_consistency
from printing_tables import StackProvider, load, reference, write_print_tables
from solver.printing import directional_albedo, specular_reflectance


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    return write_print_tables(tmp_path_factory.mktemp("print_tables"))


CASES = [  # (model, incidence °, wavelengths nm, coverages)
    ("clapper-yule", 20.0, (400.0, 480.0, 560.0, 700.0), (0.5, 0.4, 0.6)),
    ("clapper-yule", 70.0, (380.0, 520.0, 610.0, 780.0), (0.9, 0.2, 0.7)),
    ("murray-davies", 45.0, (430.0, 500.0, 590.0, 660.0), (0.5, 0.4, 0.6)),
]


def p_spec_reference(paths, cov, model, deg, wavelengths):
    """mean_λ(Σ a_S R_spec,S) / mean_λ(total albedo), from solver.printing."""
    printed = reference(paths)
    s = np.radians(deg)
    spec = specular_reflectance(printed, cov, s, wavelengths_nm=wavelengths)
    total = directional_albedo(printed, cov, 0.9, s, model, wavelengths_nm=wavelengths)
    return spec.mean() / total.mean()


@pytest.mark.parametrize("model,deg,wavelengths,cov", CASES)
def test_chi2_three_inks(use_variant, tables, model, deg, wavelengths, cov):
    mi = use_variant("llvm_ad_spectral")
    from mitsuba.chi2 import ChiSquareTest, SphericalDomain

    from inkbsdf.inks import stack_provider

    paths = (tables["R30"], tables["diffuse"], tables["B30"])
    with stack_provider(StackProvider()):
        bsdf = load(mi, paths, list(cov), model)
    s = np.radians(deg)
    sample, pdf = chi2_adapter(mi, bsdf, (np.sin(s), 0.0, np.cos(s)), wavelengths)
    chi2 = ChiSquareTest(domain=SphericalDomain(), sample_func=sample, pdf_func=pdf,
                         sample_dim=3, sample_count=400_000, res=61, seed=int(deg) + 5)
    assert chi2.run(significance_level=0.01, test_count=len(CASES), quiet=True), chi2.messages
    p_spec = p_spec_reference(paths, list(cov), model, deg, wavelengths)
    assert 0.005 < p_spec < 0.99
    assert abs(float(chi2.pdf_sum[0]) - (1.0 - p_spec)) < 2e-3
    assert abs(float(chi2.histogram_sum[0]) - (1.0 - p_spec)) < 5e-3


@pytest.mark.parametrize("model", ["clapper-yule", "murray-davies"])
def test_sample_weights_three_inks(use_variant, tables, model):
    """Smooth samples: weight = eval/pdf, bs.pdf = pdf(); delta samples: the mirror direction
(bsdf_probes.sample_consistency)."""
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    with stack_provider(StackProvider()):
        bsdf = load(mi, (tables["Y30"], tables["diffuse"], tables["B30"]), [0.6, 0.5, 0.4], model)
    got = sample_consistency(mi, bsdf, 55.0, 1 << 14, seed=12)
    assert 0.005 < got.delta.mean() < 0.9
    assert np.all(np.isfinite(got.weight)) and np.all(got.weight >= 0)
