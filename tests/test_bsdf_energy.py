"""Energy of the `ink` BSDF: white furnace (by sampling and by quadrature), ≤ 1 for every ink,
for both coverage models."""

import numpy as np
import pytest

from bsdf_probes import ink_bsdf, quadrature_albedo, sampled_albedo
from inkbsdf.apps.demo_tables import DEMO_INKS, build_tables
from inkbsdf.lut import load_lut
from oracles import CY, MD, reference_albedo
from solver.table import read_table
from solver.table.evaluate import directional_albedo as table_albedo


def lut_albedo(path, paper, coverage=1.0, model=MD):
    """Total reflectance at the σ nodes from the plugin's load-time integrals (inkbsdf.lut) and
    the NumPy evaluator. Murray–Davies: c·[R_spec + R_diff + r·Tbar·τ̄/(1−rρ̄)] + (1−c)·r;
    Clapper–Yule: c·[R_spec + R_diff] + r·(c·Tbar + 1−c)(c·τ̄ + 1−c)/(1 − r·c·ρ̄)."""
    table = read_table(path)
    if model == MD:
        return coverage * table_albedo(table, paper, table.sigma) + (1.0 - coverage) * paper
    lut = load_lut(path)
    c = coverage
    paper_term = (paper * (c * lut.Tbar + 1 - c) * (c * lut.tau_bar + 1 - c)[:, None]
                  / (1 - paper * c * lut.rho_bar)[:, None])
    return c * (lut.R_spec + lut.R_diff) + paper_term


FURNACE_ANGLES_DEG = (0.0, 20.0, 40.0, 60.0, 80.0)
N_SAMPLES = 1 << 18


@pytest.fixture(scope="module")
def odd_grid_tables(tmp_path_factory):
    """Clear varnish on non-uniform λ and σ grids (exercises the cell-table locator)."""
    folder = tmp_path_factory.mktemp("odd")
    from solver.inks import parse_ink
    from solver.table import write_table
    from solver.table.thinfilm_tier import build_thinfilm_table

    wl = np.array([380.0, 390.0, 405.0, 430.0, 470.0, 520.0, 600.0, 690.0, 760.0, 780.0])
    sigma = (np.pi / 2) * np.sin(np.linspace(0.0, np.pi / 2, 23))        # dense near grazing
    return write_table(folder / "clear_odd.npz", build_thinfilm_table(parse_ink("clear"), 1000.0, wl, sigma))


@pytest.mark.parametrize("deg", FURNACE_ANGLES_DEG)
@pytest.mark.parametrize("which", ["clear", "clear_odd", "lossless", "clear_half_covered"])
def test_white_furnace_by_sampling(use_variant, ink_tables, diffuse_tables, odd_grid_tables, which, deg):
    """A lossless layer on white paper (r = 1) reflects exactly 1 at every incidence 0–80°
    (half covered: Clapper–Yule, the default; its paper term r(cT̄+1−c)(cτ̄+1−c)/(1−rcρ̄) is
    (cT̄+1−c) when ρ̄ = 1 − τ̄, so the total is c(R̄ + T̄) + 1 − c = 1)."""
    mi = use_variant("llvm_ad_spectral")
    path = {"clear": ink_tables["clear"], "clear_half_covered": ink_tables["clear"],
            "clear_odd": odd_grid_tables, "lossless": diffuse_tables["lossless"]}[which]
    coverage = 0.5 if which == "clear_half_covered" else 1.0
    bsdf = ink_bsdf(mi, path, paper=1.0, coverage=coverage, model=CY)
    lam = np.random.default_rng(3).uniform(360.0, 830.0, size=(4, N_SAMPLES))
    mean, err = sampled_albedo(mi, bsdf, deg, lam)
    assert err < 4e-3
    assert abs(mean - 1.0) < 4.5 * err + 1e-4, (mean, err)


@pytest.mark.parametrize("model", [CY, MD])
@pytest.mark.parametrize("which", ["clear", "lossless", "absorbing", "R30"])
def test_albedo_quadrature_matches_exact(use_variant, ink_tables, diffuse_tables, which, model):
    """∫ eval dω + c·R_spec equals the closed form of the coverage model (the oracle)."""
    mi = use_variant("llvm_ad_spectral")
    path = {**ink_tables, **diffuse_tables}[which]
    lut = load_lut(path)
    paper, coverage = 0.8, 0.6
    bsdf = ink_bsdf(mi, path, paper=paper, coverage=coverage, model=model)
    exact_nodes = reference_albedo(read_table(path), paper, coverage, model)
    lam_idx = np.round(np.linspace(1, lut.wavelengths_nm.size - 2, 4)).astype(int)
    for s_idx in (0, lut.sigma_rad.size // 3, (2 * lut.sigma_rad.size) // 3):
        deg = np.degrees(lut.sigma_rad[s_idx])
        got = quadrature_albedo(mi, bsdf, deg, lut.wavelengths_nm[lam_idx])
        np.testing.assert_allclose(got, exact_nodes[lam_idx, s_idx], rtol=5e-4, atol=1e-5)


def test_exact_furnace_of_lossless_tables(ink_tables, diffuse_tables):
    """The load-time integrals make a lossless layer on white paper reflect 1 at every node,
    at any coverage with either model, and equal the oracle's closed form on any paper."""
    for path in (ink_tables["clear"], diffuse_tables["lossless"]):
        for coverage in (1.0, 0.5, 0.2):
            for model in (CY, MD):
                albedo = lut_albedo(path, paper=1.0, coverage=coverage, model=model)
                np.testing.assert_allclose(albedo, 1.0, atol=1e-9)
    assert lut_albedo(diffuse_tables["absorbing"], paper=1.0).max() < 0.99
    for path in (ink_tables["R30"], diffuse_tables["absorbing"]):
        for model in (CY, MD):
            np.testing.assert_allclose(lut_albedo(path, 0.8, 0.6, model),
                                       reference_albedo(read_table(path), 0.8, 0.6, model), atol=1e-9)


@pytest.mark.parametrize("ink", DEMO_INKS + ("B50", "R15+Y15+B15"))
def test_energy_at_most_one(use_variant, tmp_path, ink):
    """Every ink on white or 0.9 paper reflects at most 1, at every incidence, by sampling too."""
    mi = use_variant("llvm_ad_spectral")
    path = build_tables(tmp_path, [ink])[ink]
    for paper, coverage in ((1.0, 1.0), (0.9, 1.0), (1.0, 0.5)):
        for model in (CY, MD):
            assert lut_albedo(path, paper, coverage, model).max() <= 1.0 + 1e-9
        bsdf = ink_bsdf(mi, path, paper=paper, coverage=coverage, model=CY)
        lam = np.random.default_rng(5).uniform(360.0, 830.0, size=(4, 1 << 15))
        for deg in (0.0, 45.0, 85.0):
            mean, err = sampled_albedo(mi, bsdf, deg, lam)
            assert mean <= 1.0 + 4.5 * err + 1e-4
            assert mean > 0.04        # the binder face alone reflects 0.048 at 0°, more obliquely
