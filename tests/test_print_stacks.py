"""Overprints in a scene: two overlapping in-scene inks build the stack table of the overprint
through the cache (an exact multilayer film, ink 2 over ink 1), and the BSDF equals the NumPy
printing model with that stack written independently (build_stack_table)."""

import numpy as np

from conftest import surface_interaction
from solver.inks import parse_ink
from solver.printing import PrintedInks, brdf_smooth
from solver.table.builder import build_table
from solver.table.request import DEFAULT_POLARISATION, table_request
from solver.table.thinfilm_tier import build_stack_table

LAMBDAS = (415.0, 505.0, 590.0, 675.0)


def test_overlapping_inks_build_their_stack_through_the_cache(tmp_path, use_variant):
    import drjit as dr

    mi = use_variant("llvm_ad_spectral")
    cache = tmp_path / "cache"
    bsdf = mi.load_dict({"type": "ink", "ink1": "Y30", "ink2": "B30", "coverage1": 0.6, "coverage2": 0.5,
                         "cache": str(cache)})
    assert len(list((cache / "tables").glob("*.npz"))) == 3          # Y30, B30 and the overprint B30/Y30
    y, b = (build_table(table_request(ink)) for ink in ("Y30", "B30"))
    stack = build_stack_table([(parse_ink("B30"), 1000.0), (parse_ink("Y30"), 1000.0)], y.wavelengths, y.sigma,
                              polarisation=DEFAULT_POLARISATION)
    printed = PrintedInks((y, b), {(0, 1): stack})
    rng = np.random.default_rng(3)
    wi, wo = rng.normal(size=(3, 512)), rng.normal(size=(3, 512))
    for v in (wi, wo):
        v[2] = np.abs(v[2]) + 0.05
        v /= np.linalg.norm(v, axis=0)
    si = surface_interaction(mi, wi, np.tile(np.asarray(LAMBDAS)[:, None], (1, wi.shape[1])))
    value = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(*[mi.Float(c) for c in wo]))
    got = np.array([np.asarray(value[j]) for j in range(dr.size_v(mi.Spectrum))])
    sigma, theta = np.arccos(wi[2]), np.arccos(wo[2])
    dphi = np.abs(np.angle(np.exp(1j * (np.arctan2(wi[1], wi[0]) - np.arctan2(wo[1], wo[0])))))
    want = brdf_smooth(printed, np.array([0.6, 0.5]), 0.9, sigma, theta, dphi, "clapper-yule",
                       wavelengths_nm=LAMBDAS) * wo[2]
    np.testing.assert_allclose(got, want, rtol=3e-4, atol=1e-6)
