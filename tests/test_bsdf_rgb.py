"""The `ink` BSDF in RGB and mono variants (tables reduced to the channels at load,
`inkbsdf.colour_space`), registration that follows the variant, and two-sided use
(docs/plugin.md, "RGB and mono variants")."""

import subprocess
import sys

import numpy as np

from conftest import ROOT


def test_import_sets_no_variant_and_registers_for_each_variant(ink_tables):
    """`import inkbsdf` leaves the variant unset; `ink` then loads in every variant set later
    (RGB, mono), with no call to register()."""
    code = ("import mitsuba as mi, inkbsdf\n"
            "print(mi.variant())\n"
            "for v in ('llvm_ad_rgb', 'llvm_ad_mono'):\n"
            "    mi.set_variant(v)\n"
            f"    b = mi.load_dict({{'type': 'ink', 'filename': {str(ink_tables['R30'])!r}}})\n"
            "    print(v, type(b).__name__)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.split("\n")
    assert lines[0] == "None"
    assert [line.split()[0] for line in lines[1:3]] == ["llvm_ad_rgb", "llvm_ad_mono"]


def test_rgb_and_mono_against_spectral(ink_tables):
    """Against the spectral BSDF (D65, 2°): the mirror lobe within 0.5 ΔE2000 (one reflectance,
    reduced exactly); the smooth lobe within 4 ΔE2000 beyond what sRGB cannot show at all
    (the spectral colour's distance to its gamut-clipped sRGB); mono luminance within 7 L*.
    The reduction to channel means alone missed the first bound by 6 ΔE2000 and mono by 20 L*."""
    from benchmarks.bench_variants import compare

    rows = compare(ink_tables, inks=("R30", "Y30", "B30", "G30"))
    for r in rows:
        assert np.all(r.mirror_de < 0.5), (r.ink, r.coverage, r.mirror_de)
        assert np.all(r.smooth_de < r.smooth_gamut_de + 4.0), (r.ink, r.coverage, r.smooth_de, r.smooth_gamut_de)
        assert np.all(r.smooth_dl < 7.0), (r.ink, r.coverage, r.smooth_dl)


def test_rgb_bare_paper_is_the_builtin_diffuse(use_variant, ink_tables):
    """In an RGB variant, coverage 0 with an RGB paper albedo is exactly Mitsuba's `diffuse`."""
    mi = use_variant("llvm_ad_rgb")
    import drjit as dr

    paper = {"type": "rgb", "value": [0.8, 0.5, 0.2]}
    ink = mi.load_dict({"type": "ink", "filename": str(ink_tables["R30"]), "paper": paper, "coverage": 0.0})
    ref = mi.load_dict({"type": "diffuse", "reflectance": paper})
    rng = np.random.default_rng(1)
    wi, wo = rng.normal(size=(2, 3, 64))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    si = dr.zeros(mi.SurfaceInteraction3f, 64)
    si.wi = dr.normalize(mi.Vector3f(*[mi.Float(c) for c in wi]))
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    d = dr.normalize(mi.Vector3f(*[mi.Float(c) for c in wo]))
    ctx = mi.BSDFContext()
    got, want = ink.eval(ctx, si, d), ref.eval(ctx, si, d)
    for k in range(3):
        np.testing.assert_allclose(np.asarray(got[k]), np.asarray(want[k]), rtol=1e-5, atol=1e-7)


def test_twosided_back_face(use_variant, ink_tables):
    """The BSDF is one-sided (black from below); inside `twosided` the back face is the front
    face's mirror image: eval(−ωi, −ωo) = eval(ωi, ωo) (z flipped)."""
    mi = use_variant("llvm_ad_spectral")
    from bsdf_probes import as_numpy, hemisphere, surface_interaction, vector

    inner = {"type": "ink", "filename": str(ink_tables["G30"]), "paper": 0.9, "coverage": 0.7}
    one = mi.load_dict(inner)
    two = mi.load_dict({"type": "twosided", "bsdf": inner})
    rng = np.random.default_rng(2)
    wi, wo = hemisphere(rng, 64, lift=0.2), hemisphere(rng, 64, lift=0.2)
    lam = rng.uniform(400, 700, (4, 64))
    flip = np.array([[1.0], [1.0], [-1.0]])
    ctx = mi.BSDFContext()
    front = as_numpy(mi, one.eval(ctx, surface_interaction(mi, wi, lam), vector(mi, wo)))
    back_one = as_numpy(mi, one.eval(ctx, surface_interaction(mi, wi * flip, lam), vector(mi, wo * flip)))
    back_two = as_numpy(mi, two.eval(ctx, surface_interaction(mi, wi * flip, lam), vector(mi, wo * flip)))
    assert np.all(front > 0) and np.all(back_one == 0)
    np.testing.assert_allclose(back_two, front, rtol=1e-5)


def test_mono_render_written_as_grey():
    """A mono variant's [H, W, 1] luminance image is written as grey RGB (R = G = B = Y)."""
    from inkbsdf.apps.imageio import to_rgb_array

    y = np.random.default_rng(3).random((4, 5, 1)).astype(np.float32)
    rgb = to_rgb_array(y)
    assert rgb.shape == (4, 5, 3) and np.array_equal(rgb, np.repeat(y, 3, axis=2))
