"""Renders with the `ink` BSDF in llvm_ad_spectral_polarized: a plane under a uniform sky, seen
by an orthographic camera (every pixel sees the plane at one angle).

- the intensity image equals llvm_ad_spectral's pixel for pixel (same sampler and seed: the
  same paths; every Mueller product that reaches the camera from an unpolarised sky starts with
  M00 when only one surface is polarising);
- the Stokes image (Mitsuba's `stokes` integrator) of a table of one binder face equals that of
  Mitsuba's own `conductor` with the same index, and at Brewster's angle the glare is fully
  polarised along the image's horizontal (s: normal to the plane of incidence).
"""

from __future__ import annotations

import numpy as np
import pytest

from bsdf_probes import POLARIZED
from conftest import BREWSTER_DEG, N_BINDER, interface_table
from solver.table import write_table
from solver.table.builder import build_table
from solver.table.request import table_request

pytestmark = pytest.mark.render
SIZE, SPP = 12, 16


def plane_scene(mi, bsdf: dict, view_deg: float, integrator: dict) -> dict:
    """A 2×2 rectangle at z = 0 under a constant sky of radiance 1, viewed from azimuth −y at
    `view_deg` from the normal by an orthographic camera that sees only the plane."""
    s = np.radians(view_deg)
    look = mi.ScalarTransform4f().look_at(origin=[0.0, -3.0 * np.sin(s), 3.0 * np.cos(s)],
                                          target=[0.0, 0.0, 0.0], up=[0.0, 1.0, 1.0])
    return {"type": "scene", "integrator": integrator,
            "sensor": {"type": "orthographic", "to_world": look @ mi.ScalarTransform4f().scale([0.15, 0.15, 1.0]),
                       "film": {"type": "hdrfilm", "width": SIZE, "height": SIZE, "pixel_format": "rgb",
                                "rfilter": {"type": "box"}},
                       "sampler": {"type": "independent", "sample_count": SPP, "seed": 5}},
            "plane": {"type": "rectangle", "bsdf": bsdf},
            "sky": {"type": "constant", "radiance": {"type": "uniform", "value": 1.0}}}


def render(mi, bsdf: dict, view_deg: float, stokes: bool = False) -> np.ndarray:
    """[H, W, C]: RGB, then with `stokes` S0, S1, S2, S3 (RGB each) as Mitsuba's stokes
    integrator writes them."""
    integrator = {"type": "path", "max_depth": 4}
    if stokes:
        integrator = {"type": "stokes", "integrator": integrator}
    image = np.array(mi.render(mi.load_dict(plane_scene(mi, bsdf, view_deg, integrator))))
    assert np.all(np.isfinite(image))
    return image


@pytest.fixture(scope="module")
def clear_path(tmp_path_factory):
    table = build_table(table_request("clear", polarisation="unpolarised"))
    return write_table(tmp_path_factory.mktemp("render") / "clear.npz", table)


@pytest.mark.parametrize("view_deg", [0.0, 50.0, 75.0])
def test_intensity_equals_spectral_render(use_variant, clear_path, view_deg):
    """Clear varnish on paper 0.9 at coverage 0.8 (mirror and smooth lobes): the polarized
    render's intensity equals the spectral render's pixel for pixel."""
    bsdf = {"type": "ink", "filename": str(clear_path), "paper": 0.9, "coverage": 0.8}
    mi = use_variant("llvm_ad_spectral")
    spectral = render(mi, bsdf, view_deg)
    mi = use_variant(POLARIZED)
    polarized = render(mi, bsdf, view_deg, stokes=True)
    np.testing.assert_allclose(polarized[..., :3], spectral, rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(polarized[..., 3:6], spectral, rtol=1e-4, atol=1e-6)      # S0
    assert spectral.mean() > 0.1


@pytest.mark.parametrize("view_deg", [30.0, BREWSTER_DEG, 75.0])
def test_face_stokes_image_equals_mitsuba_conductor(use_variant, tmp_path, view_deg):
    """A binder face on black paper against Mitsuba's conductor (η = 1.558, κ = 0): the same
    Stokes image; at Brewster's angle fully polarised along the image's horizontal."""
    path = write_table(tmp_path / "face.npz", interface_table([0.0, 15.0, 30.0, 45.0, BREWSTER_DEG, 65.0,
                                                              75.0, 85.0, 90.0]))
    mi = use_variant(POLARIZED)
    ink = render(mi, {"type": "ink", "filename": str(path), "paper": 0.0}, view_deg, stokes=True)
    conductor = render(mi, {"type": "conductor", "eta": N_BINDER, "k": 0.0}, view_deg, stokes=True)
    np.testing.assert_allclose(ink, conductor, rtol=1e-4, atol=1e-6)
    s0, s1, s2, s3 = (ink[..., 3 + 3 * k: 6 + 3 * k] for k in range(4))
    assert np.all(s1 > 0.05 * s0) and np.all(np.abs(s2) < 1e-5) and np.all(np.abs(s3) < 1e-5)
    if view_deg == BREWSTER_DEG:
        np.testing.assert_allclose(s1, s0, rtol=1e-4)
