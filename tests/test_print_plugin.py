"""The `ink` BSDF with coverage models and several inks, against the NumPy reference model
(solver.printing): eval, delta lobe, albedo; c = 0 / 1 as before; reciprocity, white furnace,
energy; which overprints are evaluated (decided at load); parameters and their errors."""

import numpy as np
import pytest

from bsdf_probes import delta_sample, evaluate, hemisphere, incident, quadrature_albedo, sampled_albedo
from oracles import CY, MD, azimuth_difference
from printing_tables import StackProvider, load, reference, write_print_tables
from solver.printing import PrintedInks, brdf_smooth, directional_albedo, specular_reflectance
from solver.table import read_table

LAMBDAS = (415.0, 505.0, 590.0, 675.0)
N_LANES = 4096


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    return write_print_tables(tmp_path_factory.mktemp("print_tables"))


def directions(rng, n):
    return hemisphere(rng, n, lift=1e-3)


def plugin_eval(mi, bsdf, wi, wo):
    return evaluate(mi, bsdf, wi, wo, np.asarray(LAMBDAS))


def model_eval(printed, coverages, wi, wo, model, paper=0.9):
    """f·cos θo of the smooth part from the NumPy model (solver.printing), [4, N]."""
    f = brdf_smooth(printed, coverages, paper, np.arccos(wi[2]), np.arccos(wo[2]), azimuth_difference(wi, wo),
                    model, wavelengths_nm=LAMBDAS)
    return f * wo[2]


def delta_weight(mi, bsdf, deg):
    """Σ a_S R_spec,S(σ) as the plugin samples it (delta lobe alone: weight without division)."""
    return delta_sample(mi, bsdf, incident(deg), np.asarray(LAMBDAS)[:, None])[0][:, 0]


@pytest.mark.parametrize("model", [CY, MD])
@pytest.mark.parametrize("ink,coverage", [("R30", 0.5), ("diffuse", 0.35)])
def test_single_ink_matches_numpy_model(use_variant, tables, model, ink, coverage):
    mi = use_variant("llvm_ad_spectral")
    bsdf = mi.load_dict({"type": "ink", "filename": str(tables[ink]), "coverage": coverage,
                         "coverage_model": model, "paper": 0.9})
    printed = PrintedInks((read_table(tables[ink]),))
    rng = np.random.default_rng(1)
    wi, wo = directions(rng, N_LANES), directions(rng, N_LANES)
    np.testing.assert_allclose(plugin_eval(mi, bsdf, wi, wo), model_eval(printed, [coverage], wi, wo, model),
                               rtol=2e-4, atol=2e-6)
    for deg in (0.0, 40.0, 70.0):
        want = directional_albedo(printed, [coverage], 0.9, np.radians(deg), model, wavelengths_nm=LAMBDAS)
        np.testing.assert_allclose(quadrature_albedo(mi, bsdf, deg, LAMBDAS), want, rtol=5e-4, atol=1e-5)


def constant_bitmap(mi, value):
    """A spatially varying texture (a bitmap) that has `value` everywhere."""
    return {"type": "bitmap", "data": mi.TensorXf(np.full((2, 2, 1), value, dtype=np.float32)), "raw": True}


@pytest.mark.parametrize("model,textured,cov", [(CY, False, [0.5, 0.4, 0.6]), (CY, True, [0.5, 0.4, 0.6]),
                                               (MD, False, [0.5, 0.4, 0.6]), (MD, True, [0.5, 0.4, 0.6]),
                                               (CY, True, [1.0, 0.0, 1.0]), (MD, True, [1.0, 0.0, 1.0])])
def test_three_overlapping_inks_match_numpy_model(use_variant, tables, model, textured, cov):
    """R30, a diffuse ink and B30 at 50/40/60 %: all eight primaries, overprints from the provider
    (asked top first, once each); eval, delta lobe and albedo equal the NumPy model. Coverages
    as numbers (Clapper–Yule: one premixed table, `inkbsdf.premix`; Murray–Davies: one lookup
    per primary, in a loop) and as bitmaps (a loop over each lane's primaries of weight > 0,
    `inkbsdf.mixing.LoopedPrint`; with coverages 1, 0, 1 only the stack of inks 1 and 3)."""
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    paths = (tables["R30"], tables["diffuse"], tables["B30"])
    from inkbsdf.mixing import LoopedPrint

    provider = StackProvider()
    with stack_provider(provider):
        bsdf = load(mi, paths, [constant_bitmap(mi, c) for c in cov] if textured else cov, model)
    assert (bsdf.premixed is not None) == (model == CY and not textured)
    assert isinstance(bsdf._lane_model()[0], LoopedPrint) == (bsdf.premixed is None)
    if cov[1] > 0:
        assert sorted(provider.calls) == sorted([(2, 1), (3, 1), (3, 2), (3, 2, 1)])
    printed = reference(paths)
    rng = np.random.default_rng(2)
    wi, wo = directions(rng, N_LANES), directions(rng, N_LANES)
    got = plugin_eval(mi, bsdf, wi, wo)
    np.testing.assert_allclose(got, model_eval(printed, cov, wi, wo, model), rtol=3e-4, atol=2e-6)
    for deg in (0.0, 45.0, 75.0):
        s = np.radians(deg)
        np.testing.assert_allclose(delta_weight(mi, bsdf, deg),
                                   specular_reflectance(printed, cov, s, wavelengths_nm=LAMBDAS), rtol=2e-4)
        want = directional_albedo(printed, cov, 0.9, s, model, wavelengths_nm=LAMBDAS)
        np.testing.assert_allclose(quadrature_albedo(mi, bsdf, deg, LAMBDAS), want, rtol=5e-4, atol=1e-5)


def test_no_and_full_coverage_equal_murray_davies(use_variant, tables):
    """At coverages 0 and 1 the Clapper–Yule BSDF is exactly the former (Murray–Davies) one."""
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    rng = np.random.default_rng(3)
    wi, wo = directions(rng, N_LANES), directions(rng, N_LANES)
    for ink in ("Y30", "diffuse"):
        for c in (0.0, 1.0):
            one = [mi.load_dict({"type": "ink", "filename": str(tables[ink]), "coverage": c,
                                 "coverage_model": m}) for m in (CY, MD)]
            np.testing.assert_allclose(plugin_eval(mi, one[0], wi, wo), plugin_eval(mi, one[1], wi, wo),
                                       rtol=1e-6, atol=1e-9)
            np.testing.assert_allclose(delta_weight(mi, one[0], 30.0), delta_weight(mi, one[1], 30.0), rtol=1e-6)
    paths = (tables["R30"], tables["diffuse"], tables["B30"])
    with stack_provider(StackProvider()):
        for cov in ([1, 0, 1], [0, 1, 1], [1, 1, 1], [0, 0, 0]):
            pair = [load(mi, paths, [float(c) for c in cov], m) for m in (CY, MD)]
            np.testing.assert_allclose(plugin_eval(mi, pair[0], wi, wo), plugin_eval(mi, pair[1], wi, wo),
                                       rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize("model", [CY, MD])
def test_reciprocity_with_overprints(use_variant, tables, model):
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    with stack_provider(StackProvider()):
        bsdf = load(mi, (tables["Y30"], tables["diffuse"], tables["B30"]), [0.7, 0.5, 0.3], model)
    rng = np.random.default_rng(4)
    a, b = directions(rng, N_LANES), directions(rng, N_LANES)
    f_ab = plugin_eval(mi, bsdf, a, b) / b[2]
    f_ba = plugin_eval(mi, bsdf, b, a) / a[2]
    np.testing.assert_allclose(f_ab, f_ba, rtol=3e-4, atol=1e-6)
    assert np.ptp(f_ab) > 1e-3


@pytest.mark.parametrize("model", [CY, MD])
@pytest.mark.parametrize("deg", [0.0, 45.0, 80.0])
def test_white_furnace_three_clear_inks(use_variant, tables, model, deg):
    """Three lossless clear layers and their lossless stacks on white paper reflect exactly 1."""
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    with stack_provider(StackProvider()):
        bsdf = load(mi, (tables["clear700"], tables["clear1000"], tables["clear1500"]), [0.5, 0.3, 0.8],
                    model, paper=1.0)
    lam = np.random.default_rng(5).uniform(360.0, 830.0, size=(4, 1 << 17))
    mean, err = sampled_albedo(mi, bsdf, deg, lam)
    assert err < 5e-3
    assert abs(mean - 1.0) < 4.5 * err + 1e-4, (mean, err)


def test_energy_at_most_one_with_overprints(use_variant, tables):
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    paths = (tables["R30"], tables["Y30"], tables["B30"])
    lam = np.random.default_rng(6).uniform(360.0, 830.0, size=(4, 1 << 15))
    with stack_provider(StackProvider()):
        for model in (CY, MD):
            bsdf = load(mi, paths, [0.6, 0.6, 0.6], model, paper=1.0)
            for deg in (0.0, 60.0, 85.0):
                mean, err = sampled_albedo(mi, bsdf, deg, lam)
                assert 0.05 < mean <= 1.0 + 4.5 * err + 1e-4
            printed = reference(paths)
            assert directional_albedo(printed, [0.6] * 3, 1.0, np.radians(np.arange(0, 91, 5)), model).max() <= 1.0


def _bitmap(mi, tmp_path, name, img, filter_type):
    path = tmp_path / f"{name}.exr"
    mi.Bitmap(np.asarray(img, dtype=np.float32)[..., None], mi.Bitmap.PixelFormat.Y).write(str(path))
    return {"type": "bitmap", "filename": str(path), "raw": True, "filter_type": filter_type}


def test_overprints_decided_at_load(use_variant, tables, tmp_path):
    """Only overprints that can occur are evaluated: constant 0 never overlaps; bitmaps with no
    common texel need no stack (nearest), but do when bilinear filtering mixes touching texels;
    a coverage changed through traverse is analysed again."""
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    paths = (tables["R30"], tables["Y30"], tables["B30"])
    provider = StackProvider()
    with stack_provider(provider):
        bsdf = load(mi, paths, [0.5, 0.0, 0.7])
    assert provider.calls == [(3, 1)]
    assert "stacks=[3/1]" in str(bsdf)

    left, right = np.zeros((8, 8)), np.zeros((8, 8))
    left[:, :4], right[:, 4:] = 1.0, 0.6
    for filt in ("nearest", "bilinear"):
        covs = [_bitmap(mi, tmp_path, f"l{filt}", left, filt), _bitmap(mi, tmp_path, f"r{filt}", right, filt), 0.0]
        if filt == "nearest":                                   # no provider needed at all
            bsdf = load(mi, paths, covs)
            assert "stacks=[]" in str(bsdf)
        else:          # bilinear: they can overlap; the default provider builds the overprint
            bsdf = load(mi, paths, covs)
            assert "stacks=[2/1]" in str(bsdf)

    provider = StackProvider()
    with stack_provider(provider):
        bsdf = load(mi, paths, [0.5, 0.0, 0.0])
        assert provider.calls == []
        params = mi.traverse(bsdf)
        assert "coverage2.value" in params and "coverage3.value" in params
        params["coverage2.value"] = 0.4
        params.update()
    assert provider.calls == [(2, 1)]
    rng = np.random.default_rng(7)
    wi, wo = directions(rng, 512), directions(rng, 512)
    want = model_eval(reference(paths), [0.5, 0.4, 0.0], wi, wo, CY)
    np.testing.assert_allclose(plugin_eval(mi, bsdf, wi, wo), want, rtol=3e-4, atol=2e-6)


def test_numbered_parameters(use_variant, tables):
    """In-scene inks with shared and numbered parameters reach the provider as single-ink names."""
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.inks import stack_provider

    seen = []

    def provider(members):
        seen.append(members)
        return members[0].lut

    with stack_provider(provider):
        mi.load_dict({"type": "ink", "ink1": "Y15", "ink2": "B15", "thickness": 800.0, "thickness2": 1200.0,
                      "coverage1": 0.5, "coverage2": 0.5})
        mi.load_dict({"type": "ink", "filename1": str(tables["R30"]), "ink2": "B15", "coverage2": 0.5,
                      "coverage1": 0.5})
    top, bottom = seen[0]
    assert (top.index, top.label, top.params["thickness"]) == (2, "B15", 1200.0)
    assert (bottom.index, bottom.label, bottom.params["thickness"]) == (1, "Y15", 800.0)
    top, bottom = seen[1]
    assert bottom.params == {"filename": str(tables["R30"].resolve())} and bottom.label == "R30"
    assert top.params == {"ink": "B15"}


@pytest.mark.parametrize("params,message", [
    ({"filename": "R30", "filename1": "R30"}, "not both forms"),
    ({"filename1": "R30", "coverage": 0.5}, "not both forms"),
    ({"filename1": "R30", "filename3": "B30"}, "without gaps"),
    ({"filename1": "R30", "ink1": "R30"}, "ink 1: give either 'filename1' or 'ink1'"),
    ({"filename1": "R30", "coverage2": 0.5}, "'coverage2' names no ink"),
    ({"filename1": "R30", "coverage_model": "yule"}, "coverage_model must be one of clapper-yule, murray-davies"),
    ({"filename1": "R30", "bogus2": 1.0}, "unreferenced property"),
    ({"filename1": "R30", "particles": "molecular"}, "unreferenced property"),
    ({"filename1": "nowhere.npz"}, "ink BSDF, ink 1: .*not found"),
])
def test_parameter_errors(use_variant, tables, params, message):
    mi = use_variant("llvm_ad_spectral")
    for key, value in params.items():
        if key.startswith("filename") and value == "R30":
            params[key] = str(tables["R30"])
    for n in range(5):
        if f"filename{n}" in params and params[f"filename{n}"] == "B30":
            params[f"filename{n}"] = str(tables["B30"])
    with pytest.raises(Exception, match=message):
        mi.load_dict({"type": "ink", **params})


def test_coverage_bitmap_must_be_raw_and_finite(use_variant, tables, tmp_path):
    """A coverage bitmap read without raw (sRGB-decoded: a 50 % grey would print 0.21) and an
    EXR with NaN texels are refused at load, the message naming the parameter and the fix; the
    same bitmaps read raw and filled load."""
    from PIL import Image

    mi = use_variant("llvm_ad_spectral")
    Image.fromarray(np.full((4, 4), 128, np.uint8)).save(tmp_path / "grey.png")
    base = {"type": "ink", "filename": str(tables["R30"])}
    for raw in (None, False):
        tex = {"type": "bitmap", "filename": str(tmp_path / "grey.png")}
        if raw is not None:
            tex["raw"] = raw
        with pytest.raises(Exception, match=r"'coverage'.*raw missing or false.*name=\"raw\" value=\"true\""):
            mi.load_dict({**base, "coverage": tex})
    mi.load_dict({**base, "coverage": {"type": "bitmap", "filename": str(tmp_path / "grey.png"), "raw": True}})
    holes = np.full((3, 5), 0.4, np.float32)
    holes[1, 2] = np.nan
    nan_exr = _bitmap(mi, tmp_path, "holes", holes, "bilinear")
    with pytest.raises(Exception, match=r"'coverage2'.*1 NaN or infinite texel"):
        mi.load_dict({"type": "ink", "filename1": str(tables["R30"]), "filename2": str(tables["B30"]),
                      "coverage1": 0.3, "coverage2": nan_exr})
    mi.load_dict({**base, "coverage": _bitmap(mi, tmp_path, "filled", np.nan_to_num(holes), "bilinear")})


@pytest.mark.parametrize("variant", ["llvm_ad_spectral", "llvm_ad_rgb"])
def test_looped_print_equals_unrolled_on_halftones(use_variant, tables, variant):
    """Three inks as 0/1 halftone bitmaps (nearest texels, every primary somewhere, one per
    lane): the per-lane loop over non-zero primaries (`LoopedPrint`) equals the unrolled sums
    (`PrintModel`, validated above against the NumPy model; used while the paper albedo is
    being differentiated), eval and sample, lane by lane."""
    mi = use_variant(variant)
    import drjit as dr

    from inkbsdf.inks import stack_provider
    from inkbsdf.mixing import LoopedPrint, PrintModel

    rng = np.random.default_rng(5)
    maps = [{"type": "bitmap", "data": mi.TensorXf((rng.random((8, 8, 1)) < 0.5).astype(np.float32)),
             "raw": True, "filter_type": "nearest"} for _ in range(3)]
    with stack_provider(StackProvider()):
        bsdf = load(mi, (tables["R30"], tables["diffuse"], tables["B30"]), maps, CY)
    n = 2048
    wi, wo = directions(rng, n), directions(rng, n)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(*[mi.Float(c) for c in wi])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    si.uv = mi.Point2f(mi.Float(rng.random(n)), mi.Float(rng.random(n)))
    if mi.is_spectral:
        si.wavelengths = mi.Spectrum(*[mi.Float(rng.uniform(380, 780, n)) for _ in range(4)])
    u = [mi.Float(rng.random(n)) for _ in range(3)]
    ctx = mi.BSDFContext()

    def run():
        f = bsdf.eval(ctx, si, mi.Vector3f(*[mi.Float(c) for c in wo]))
        bs, w = bsdf.sample(ctx, si, u[0], mi.Point2f(u[1], u[2]))
        channels = dr.size_v(mi.Spectrum)
        return np.array([np.asarray(f[k]) for k in range(channels)] + [np.asarray(w[k]) for k in range(channels)])

    assert isinstance(bsdf._lane_model()[0], LoopedPrint)
    looped = run()
    params = mi.traverse(bsdf)
    paper = mi.Float(0.9)
    dr.enable_grad(paper)
    params["paper.value"] = paper
    params.update()
    assert isinstance(bsdf._lane_model()[0], PrintModel)
    unrolled = run()
    assert np.all(np.isfinite(looped)) and np.any(looped > 0)
    np.testing.assert_allclose(looped, unrolled, rtol=2e-5, atol=1e-7)


def test_premixed_tables_shared_between_bsdfs(use_variant, tables):
    """Two BSDFs with the same table and coverage hold one premixed table; another coverage
    makes another."""
    mi = use_variant("llvm_ad_spectral")

    a, b, c = (mi.load_dict({"type": "ink", "filename": str(tables["R30"]), "coverage": cov})
               for cov in (0.3, 0.3, 0.7))
    model = lambda bsdf: bsdf.premixed.primaries[0][1]      # noqa: E731
    assert model(a) is model(b) and model(a) is not model(c)
