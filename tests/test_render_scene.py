"""The demo scene rendered through the CLI: a finite image whose patches have the inks' hues."""


import numpy as np
import pytest

from conftest import DEMO_SCENE
from inkbsdf.apps.demo_tables import DEMO_INKS

pytestmark = pytest.mark.render
SCENE = DEMO_SCENE
WIDTH, HEIGHT, SPP = 240, 192, 32
ERODE_PX = 2

# CIELAB hue angle (degrees) expected for each patch, seen relative to the paper's white.
HUE_RANGES = {"R30": (320.0, 400.0),      # magenta to red (wraps through 0)
              "Y30": (60.0, 105.0),       # yellow
              "B30": (180.0, 290.0),      # cyan to blue
              "G30": (110.0, 175.0),      # green
              "Y25+B5": (80.0, 135.0)}    # yellow-green


def patch_id(ink):
    return "patch_" + ink.replace("+", "_")


def shape_masks(mi, scene, width, height):
    """{shape id: bool [H, W]} of the shape seen through each pixel centre (ray cast)."""
    import drjit as dr

    idx = dr.arange(mi.UInt32, width * height)
    x, y = mi.Float(idx % width) + 0.5, mi.Float(idx // width) + 0.5
    ray, _ = scene.sensors()[0].sample_ray(0.0, 0.5, mi.Point2f(x / width, y / height), mi.Point2f(0.5, 0.5))
    hit = scene.ray_intersect(ray)
    return {s.id(): np.asarray(hit.shape == mi.ShapePtr(s)).reshape(height, width) for s in scene.shapes()}


def erode(mask, px):
    out = mask.copy()
    for axis in (0, 1):
        for shift in range(1, px + 1):
            for sign in (-1, 1):
                out &= np.roll(mask, sign * shift, axis=axis)
    return out


def lab_relative_to(rgb, white_rgb):
    """CIELAB of linear sRGB colours with the paper's colour as reference white."""
    import colour

    cs = colour.RGB_COLOURSPACES["sRGB"]
    to_xyz = lambda c: colour.RGB_to_XYZ(c, cs, apply_cctf_decoding=False)   # noqa: E731
    white = to_xyz(white_rgb)
    return colour.XYZ_to_Lab(to_xyz(rgb) / white[1], colour.XYZ_to_xy(white))


@pytest.fixture(scope="module")
def rendered(tmp_path_factory, ink_tables):
    from inkbsdf.apps.imageio import read_exr
    from inkbsdf.apps.render import main

    out = tmp_path_factory.mktemp("render")
    tables = ink_tables["clear"].parent
    args = [SCENE, "--tables", str(tables), "--spp", str(SPP), "--width", str(WIDTH),
            "--height", str(HEIGHT), "-o", str(out / "page.exr"), "--png", str(out / "page.png")]
    assert main(args) == 0
    assert (out / "page.png").stat().st_size > 1000
    return read_exr(out / "page.exr"), tables


def test_render_is_finite(rendered):
    image, _ = rendered
    assert image.shape == (HEIGHT, WIDTH, 3)
    assert np.all(np.isfinite(image))
    luminance = image @ np.array([0.2126, 0.7152, 0.0722])      # channels may dip < 0 out of gamut
    assert luminance.min() > -1e-3
    assert 0.05 < float(np.median(image)) < 2.0


def test_patch_hues(rendered, use_variant):
    image, tables = rendered
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.apps.render import load_scene

    masks = shape_masks(mi, load_scene(SCENE, tables=tables, width=WIDTH, height=HEIGHT), WIDTH, HEIGHT)
    paper = np.median(image[erode(masks["page"], ERODE_PX)], axis=0)
    lab = {}
    for ink in DEMO_INKS:
        m = erode(masks[patch_id(ink)], ERODE_PX)
        assert m.sum() > 100, f"patch {ink} hardly visible ({m.sum()} px)"
        lab[ink] = lab_relative_to(image[m], paper)
    mean = {k: lab_relative_to(image[erode(masks[patch_id(k)], ERODE_PX)].mean(axis=0), paper)
            for k in DEMO_INKS}
    hue = {k: np.degrees(np.arctan2(v[2], v[1])) % 360.0 for k, v in mean.items()}
    chroma = {k: float(np.hypot(v[1], v[2])) for k, v in mean.items()}
    report = {k: (round(hue[k]), round(chroma[k], 1), round(float(mean[k][0]), 1)) for k in mean}
    for ink, (lo, hi) in HUE_RANGES.items():
        h = hue[ink] + (360.0 if hue[ink] < lo else 0.0)
        assert lo <= h <= hi, f"{ink}: hue {hue[ink]:.0f}° outside [{lo:g}, {hi:g}] {report}"
        assert chroma[ink] > 10.0, f"{ink}: chroma {chroma[ink]:.1f} too low {report}"
    assert hue["Y30"] < hue["Y25+B5"] < hue["G30"], report          # blue pulls yellow to green
    assert mean["B30"][0] < mean["Y30"][0] and mean["G30"][0] < mean["Y25+B5"][0], report
    # Clear varnish: the softbox's mirror image (the sheen) lies on part of the patch; elsewhere
    # it is paper seen through a clear layer: near-neutral and about as light as the paper.
    clear = lab["clear"]
    sheen = clear[:, 0] > 110.0
    plain = clear[clear[:, 0] < 104.0]
    assert 0.1 < sheen.mean() < 0.9, f"sheen on {sheen.mean():.0%} of the clear patch"
    assert len(plain) > 50
    plain_mean = plain.mean(axis=0)
    assert np.hypot(plain_mean[1], plain_mean[2]) < 6.0, f"clear varnish not neutral: {plain_mean}"
    assert 85.0 < plain_mean[0] < 104.0, plain_mean
