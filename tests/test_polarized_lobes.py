"""The `ink` BSDF in polarized variants: tables with a diffuse lobe, coverage models, several
inks with overprints, energy (white furnace on M00), physical Mueller matrices."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from bsdf_probes import (POLARIZED, albedo_estimate, at_polar_angles, compare_with_spectral, delta_sample,
                         random_lanes, run_bsdf, run_bsdf_lanewise, sample_weights)
from conftest import diffuse_layer_table
from solver.table import validate, write_table
from solver.table.builder import build_table
from solver.table.request import table_request


def polarized_diffuse_table(lossless: bool):
    """conftest's synthetic diffuse-lobe table made unpolarised: its mirror beam is half the
    unpolarised clear film's (r_s, r_p / √2 on the same grids), R̄, T̄ rebuilt around it."""
    base = diffuse_layer_table(lossless=lossless)
    film = build_table(table_request("clear", polarisation="unpolarised", wavelengths_nm=base.wavelengths,
                                     sigma_rad=base.sigma))
    r_s, r_p = film.r_s / np.sqrt(2.0), film.r_p / np.sqrt(2.0)
    r_spec = 0.5 * (np.abs(r_s) ** 2 + np.abs(r_p) ** 2)
    rbar = r_spec + (base.Rbar - base.R_spec)
    tbar = (1.0 - rbar) * (1.0 if lossless else 0.8)
    return validate(dataclasses.replace(base, R_spec=r_spec, Rbar=rbar, Tbar=tbar, T_coh=0.7 * tbar,
                                        Rbar_below=rbar.copy(), r_s=r_s, r_p=r_p,
                                        meta=dict(base.meta, polarisation="unpolarised")))


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    """{name: path}: unpolarised molecular films (clear, R30, Y30) and synthetic diffuse tables."""
    folder = tmp_path_factory.mktemp("polarized_tables")
    out = {ink: write_table(folder / f"{ink}.npz", build_table(table_request(ink, polarisation="unpolarised")))
           for ink in ("clear", "R30", "Y30")}
    for name in ("lossless", "absorbing"):
        out[name] = write_table(folder / f"{name}.npz", polarized_diffuse_table(name == "lossless"))
    return out


def pure_defect(m):
    """4·M00² − tr(MᵀM) per lane and wavelength: 0 for a pure (non-depolarising) Mueller
    matrix, > 0 for a mix of them, < 0 never for a physical one."""
    return 4 * m[0, 0] ** 2 - np.einsum("ij...,ij...->...", m, m)


@pytest.mark.parametrize("model", ["clapper-yule", "murray-davies"])
@pytest.mark.parametrize("which", ["lossless", "absorbing"])
def test_diffuse_tables_match_spectral_variant(use_variant, tables, which, model):
    """Tables with a diffuse lobe, both coverage models: M00 of eval/sample equals the spectral
    variant's value, the smooth lobe (layer lobe + paper) is an ideal depolariser."""
    compare_with_spectral(use_variant, {"type": "ink", "filename": str(tables[which]), "paper": 0.8,
                                        "coverage": 0.6, "coverage_model": model}, seed=17)


@pytest.mark.parametrize("coverage", [1.0, 0.5])
@pytest.mark.parametrize("which", ["clear", "lossless"])
def test_white_furnace_on_m00(use_variant, tables, which, coverage):
    """A lossless layer on white paper reflects exactly 1 of unpolarised light (M00) at every
    incidence, sampled in the polarized variant; every weight is a physical Mueller matrix."""
    mi = use_variant(POLARIZED)
    bsdf = mi.load_dict({"type": "ink", "filename": str(tables[which]), "paper": 1.0, "coverage": coverage})
    rng = np.random.default_rng(7)
    for deg in (0.0, 40.0, 75.0):
        w = sample_weights(mi, bsdf, deg, rng.uniform(360.0, 830.0, (4, 40000)))
        mean, err = albedo_estimate(w)
        assert err < 4e-3 and abs(mean - 1.0) < 4.5 * err + 1e-4, (deg, mean, err)
        assert np.all(pure_defect(w) >= -1e-5 * np.maximum(w[0, 0], 1.0) ** 2), deg


def test_overprints_mix_mueller_matrices(use_variant, tables):
    """Two inks with overlap (stack Y30/R30 built through the cache, unpolarised, with its own
    r_s, r_p): the delta lobe's Mueller matrix is Σ a_S M_S over the Demichel primaries, each M_S
    that of the primary's table alone; M00 equals the spectral variant; the mix depolarises
    partly (4·M00² − tr(MᵀM) ≥ 0, > 0 somewhere) where each primary alone is pure."""
    c1, c2 = 0.6, 0.5
    scene = {"type": "ink", "paper": 0.85, "filename1": str(tables["R30"]), "coverage1": c1,
             "filename2": str(tables["Y30"]), "coverage2": c2}
    compare_with_spectral(use_variant, scene, seed=23)
    mi = use_variant(POLARIZED)
    printed = mi.load_dict(scene)
    alone = {(0,): {"filename": str(tables["R30"])}, (1,): {"filename": str(tables["Y30"])},
             (0, 1): {"ink": "Y30/R30", "polarisation": "unpolarised"}}
    weight = {(0,): c1 * (1 - c2), (1,): (1 - c1) * c2, (0, 1): c1 * c2}
    rng = np.random.default_rng(29)
    wi = at_polar_angles(rng.choice(np.arange(0.0, 85.0, 2.0), 64), rng)       # on the tables' nodes:
    lam = rng.choice(np.arange(400.0, 701.0, 10.0), (4, wi.shape[1]))      # each M_S is pure there
    got, _, _ = delta_sample(mi, printed, wi, lam)
    expected = 0.0
    for subset, params in alone.items():
        m, _, _ = delta_sample(mi, mi.load_dict({"type": "ink", "paper": 0.85, **params}), wi, lam)
        assert np.all(np.abs(pure_defect(m)) <= 1e-5)
        expected = expected + weight[subset] * m
    np.testing.assert_allclose(got, expected, atol=1e-6)
    defect = pure_defect(got)
    assert np.all(defect >= -1e-6) and np.max(defect) > 1e-3


def test_scalar_polarized_matches_llvm(use_variant, tables):
    """scalar_spectral_polarized runs the same code lane by lane: the same Mueller matrices as
    llvm_ad_spectral_polarized (a diffuse table; two inks with an overprint; both lobes)."""
    wi, wo, lam, u = random_lanes(np.random.default_rng(31), 16)
    scenes = [{"type": "ink", "paper": 0.85, "filename": str(tables["absorbing"]), "coverage": 0.6,
               "coverage_model": "murray-davies"},
              {"type": "ink", "paper": 0.85, "filename1": str(tables["R30"]), "coverage1": 0.6,
               "filename2": str(tables["Y30"]), "coverage2": 0.5}]
    components = set()
    for scene in scenes:
        mi = use_variant(POLARIZED)
        ref = run_bsdf(mi, mi.load_dict(scene), wi, wo, lam, u)
        components |= set(ref.component.tolist())
        mi = use_variant("scalar_spectral_polarized")
        got = run_bsdf_lanewise(mi, mi.load_dict(scene), wi, wo, lam, u)
        for name in ("f", "weight", "pdf"):
            np.testing.assert_allclose(getattr(got, name), getattr(ref, name), rtol=2e-4, atol=1e-6, err_msg=name)
        np.testing.assert_array_equal(got.component, ref.component)
    assert components == {0, 1}                   # both lobes sampled
