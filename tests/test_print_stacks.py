"""Overprints in a scene: two overlapping in-scene inks build the stack table of the overprint
through the cache (an exact multilayer film, ink 2 over ink 1), and the BSDF equals the NumPy
printing model with that stack written independently (build_stack_table)."""

import numpy as np

from bsdf_probes import evaluate, hemisphere
from oracles import azimuth_difference
from solver.inks import parse_ink
from solver.materials import DISSOLVED_FIELD, default_materials
from solver.printing import PrintedInks, brdf_smooth
from solver.table.builder import build_table
from solver.table.request import DEFAULT_POLARISATION, table_request
from solver.table.thinfilm_tier import build_stack_table

LAMBDAS = (415.0, 505.0, 590.0, 675.0)


def test_overlapping_inks_build_their_stack_through_the_cache(tmp_path, use_variant):
    mi = use_variant("llvm_ad_spectral")
    cache = tmp_path / "cache"
    bsdf = mi.load_dict({"type": "ink", "ink1": "Y30", "ink2": "B30", "coverage1": 0.6, "coverage2": 0.5,
                         "cache": str(cache)})
    assert len(list((cache / "tables").glob("*.npz"))) == 3          # Y30, B30 and the overprint B30/Y30
    y, b = (build_table(table_request(ink)) for ink in ("Y30", "B30"))
    stack = build_stack_table([(parse_ink("B30"), 1000.0), (parse_ink("Y30"), 1000.0)], y.wavelengths, y.sigma,
                              default_materials().with_local_field(DISSOLVED_FIELD),   # dissolved pigment
                              polarisation=DEFAULT_POLARISATION)
    printed = PrintedInks((y, b), {(0, 1): stack})
    rng = np.random.default_rng(3)
    wi, wo = hemisphere(rng, 512, lift=0.05), hemisphere(rng, 512, lift=0.05)
    got = evaluate(mi, bsdf, wi, wo, np.asarray(LAMBDAS))
    want = brdf_smooth(printed, np.array([0.6, 0.5]), 0.9, np.arccos(wi[2]), np.arccos(wo[2]),
                       azimuth_difference(wi, wo), "clapper-yule", wavelengths_nm=LAMBDAS) * wo[2]
    np.testing.assert_allclose(got, want, rtol=3e-4, atol=1e-6)
