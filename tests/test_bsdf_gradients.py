"""Derivatives of rendered images with respect to the `ink` BSDF's coverage and paper albedo,
under Mitsuba's differentiable integrators (docs/plugin.md, "Differentiable rendering").

The reference is the central finite difference of the primal image rendered with the same
random numbers (same seed), which needs no derivative from the BSDF at all: an independent
check of the derivatives that the integrators take through `sample`, `eval` and `eval_pdf`.
The scene is the one of issue 24: an R30 patch, coverage 0.5, paper 0.9, under a constant sky,
seen by an orthographic camera 30° off the normal (every pixel sees the same incidence), so the
mirror lobe reflects the sky into every pixel.
"""

import numpy as np
import pytest

SPP = 128
STEP = 0.02                 # central-difference step of coverage and paper albedo
TOLERANCE = 0.03            # relative, the brief's 3 %


def _scene(mi, table, integrator, bsdf=None):
    T = mi.ScalarTransform4f
    s = np.radians(30.0)
    eye = [3.0 * np.sin(s), 0.0, 3.0 * np.cos(s)]
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": integrator, "max_depth": 2},
        "sensor": {"type": "orthographic",
                   "to_world": T().look_at(origin=eye, target=[0, 0, 0], up=[0, 0, 1]) @ T().scale([0.2, 0.2, 1]),
                   "film": {"type": "hdrfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent"}},
        "sky": {"type": "constant", "radiance": 1.0},
        "patch": {"type": "rectangle",
                  "bsdf": bsdf or {"type": "ink", "filename": str(table), "coverage": 0.5, "paper": 0.9}}})


def _mean_image(mi, scene, params, spp):
    return float(np.mean(np.asarray(mi.render(scene, params, spp=spp, seed=7))))


def _derivatives(mi, dr, scene, key, spp=SPP):
    """(AD derivative of the mean image, its central finite difference) at the scene's value."""
    params = mi.traverse(scene)
    x0 = float(np.ravel(params[key])[0])
    values = []
    for step in (STEP, -STEP):
        params[key] = x0 + step
        params.update()
        values.append(_mean_image(mi, scene, params, spp))
    x = mi.Float(x0)
    dr.enable_grad(x)
    params[key] = x
    params.update()
    dr.backward(dr.mean(mi.render(scene, params, spp=spp, seed=7), axis=None))
    ad = float(dr.grad(x)[0])
    return ad, (values[0] - values[1]) / (2 * STEP)


@pytest.mark.parametrize("integrator", ["prb", "direct_projective", "path"])
def test_derivatives_match_finite_differences(use_variant, ink_tables, integrator):
    """d(image)/d(coverage) and d(image)/d(paper) within 3 % of finite differences (before the
    delta lobe carried its derivatives, prb and direct_projective were 17 % and 7 % off)."""
    mi = use_variant("llvm_ad_spectral")
    import drjit as dr

    scene = _scene(mi, ink_tables["R30"], integrator)
    for key in ("patch.bsdf.coverage.value", "patch.bsdf.paper.value"):
        ad, fd = _derivatives(mi, dr, scene, key)
        assert abs(fd) > 0.1, f"{key}: the finite difference {fd} is too small to test against"
        assert ad == pytest.approx(fd, rel=TOLERANCE), f"{integrator}, {key}: AD {ad:.4f}, FD {fd:.4f}"


def test_two_inks_derivatives_match_finite_differences(use_variant, ink_tables):
    """Y30 printed over R30 at 60 % and 50 % (an overprint's table from the default provider):
    prb's derivatives by each coverage within 3 % of finite differences. The primal renders use
    the premixed table (`inkbsdf.premix`), the derivatives the per-primary sums. 1024 spp: the
    smaller derivative's finite difference is ~3 % noisy at 128."""
    mi = use_variant("llvm_ad_spectral")
    import drjit as dr

    bsdf = {"type": "ink", "paper": 0.9, "filename1": str(ink_tables["R30"]), "coverage1": 0.6,
            "filename2": str(ink_tables["Y30"]), "coverage2": 0.5}
    scene = _scene(mi, None, "prb", bsdf)
    for key in ("patch.bsdf.coverage1.value", "patch.bsdf.coverage2.value"):
        ad, fd = _derivatives(mi, dr, scene, key, spp=1024)
        assert abs(fd) > 0.05, f"{key}: the finite difference {fd} is too small to test against"
        assert ad == pytest.approx(fd, rel=TOLERANCE), f"{key}: AD {ad:.4f}, FD {fd:.4f}"


def test_mirror_stand_in_only_while_differentiating(use_variant, ink_tables):
    """eval at the exact mirror direction is the smooth lobe in a primal evaluation (continuous
    with a direction 0.01 rad away) and the delta lobe's Σ a_S R_spec only while derivatives
    are tracked."""
    mi = use_variant("llvm_ad_spectral")
    import drjit as dr
    from bsdf_probes import as_numpy, delta_sample, ink_bsdf, surface_interaction, vector

    bsdf = ink_bsdf(mi, ink_tables["R30"], paper=0.9, coverage=0.5)
    s = np.radians(30.0)
    wi = np.array([[np.sin(s)], [0.0], [np.cos(s)]])
    lam = np.array([[450.0], [520.0], [600.0], [680.0]])
    si = surface_interaction(mi, wi, lam)
    ctx = mi.BSDFContext()
    mirror = vector(mi, [[-wi[0, 0]], [0.0], [wi[2, 0]]])
    near = vector(mi, [[-np.sin(s + 0.01)], [0.0], [np.cos(s + 0.01)]])
    primal = as_numpy(mi, bsdf.eval(ctx, si, mirror))
    np.testing.assert_allclose(primal, as_numpy(mi, bsdf.eval(ctx, si, near)), rtol=0.02)

    params = mi.traverse(bsdf)
    c = mi.Float(0.5)
    dr.enable_grad(c)
    params["coverage.value"] = c
    params.update()
    tracked = as_numpy(mi, bsdf.eval(ctx, si, mirror))
    specular = delta_sample(mi, bsdf, wi, lam)[0]
    assert not np.allclose(tracked, primal, rtol=0.05)
    np.testing.assert_allclose(tracked, specular, rtol=1e-5)
