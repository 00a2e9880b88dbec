"""`python -m inkbsdf.print`: an image becomes coverage textures and a page scene that renders;
bad input gives one line and exit status 2 before any work; the demo page's photograph."""

import subprocess
import sys

import numpy as np
import pytest

from bsdf_probes import surface_interaction
from conftest import ROOT, run_main, scene_script
from inkbsdf.apps.print import main


@pytest.fixture(scope="module")
def tiny_image(tmp_path_factory):
    """16 × 12 px: a hue sweep over a lightness ramp, a white and a black corner."""
    from PIL import Image

    h, w = 12, 16
    y, x = np.mgrid[0:h, 0:w]
    rgb = np.stack([0.5 + 0.5 * np.cos(x / w * 2 * np.pi), 0.5 + 0.5 * np.cos(x / w * 2 * np.pi - 2.1),
                    0.5 + 0.5 * np.cos(x / w * 2 * np.pi + 2.1)], -1) * (0.3 + 0.7 * y[..., None] / h)
    img = np.round(255 * rgb).astype(np.uint8)
    img[:3, :3] = 255
    img[-3:, -3:] = 0
    path = tmp_path_factory.mktemp("img") / "tiny.png"
    Image.fromarray(img).save(path)
    return path


def run(args, capsys):
    return run_main(main, args, capsys)


@pytest.mark.parametrize("dots", ["AM:60", "FM", "none"])
def test_prints_textures_and_scene(tiny_image, tmp_path, capsys, dots):
    from PIL import Image

    status, out, err = run([tiny_image, "--inks", "R30,Y30,B30", "--dots", dots, "--size", "4x3",
                            "-o", tmp_path / "page.xml", "--quiet"], capsys)
    assert status == 0, err
    folder = tmp_path / "page_textures"
    names = ["ink_1_R30.png", "ink_2_Y30.png", "ink_3_B30.png"]
    assert all((folder / n).is_file() for n in names) and (folder / "proof.png").is_file()
    xml = (tmp_path / "page.xml").read_text()
    for n, ink in enumerate(("R30", "Y30", "B30"), start=1):
        assert f'<string name="ink{n}" value="{ink}"/>' in xml and f"page_textures/{names[n - 1]}" in xml
    dpi = {"AM:60": 8 * 60, "FM": 600}.get(dots)         # 8 texels per screen period; FM 600 dpi
    expected_shape = (12, 16) if dpi is None else (round(3 / 2.54 * dpi), round(4 / 2.54 * dpi))
    textures = [np.asarray(Image.open(folder / n)) for n in names]
    assert all(t.shape == expected_shape and t.dtype == np.uint8 for t in textures)
    if dots != "none":
        assert all(set(np.unique(t)) <= {0, 255} for t in textures)
        assert 'filter_type" value="nearest"' in xml and "coverage_model" not in xml
    else:
        assert '<string name="coverage_model" value="clapper-yule"/>' in xml
    assert "distinct colours" in out and "wrote" in out


@pytest.mark.render
def test_printed_page_renders(tiny_image, tmp_path, capsys):
    """The scene of a printed image renders (few spp) to a finite image."""
    from inkbsdf.apps.imageio import read_exr
    from inkbsdf.apps.render import main as render

    assert run([tiny_image, "--inks", "R30,Y30,B30", "--dots", "AM:60", "--size", "4",
                "-o", tmp_path / "page.xml", "--quiet"], capsys)[0] == 0
    assert render([str(tmp_path / "page.xml"), "--spp", "8", "--width", "64", "--height", "48",
                   "-o", str(tmp_path / "page.exr")]) == 0
    image = read_exr(tmp_path / "page.exr")
    assert image.shape == (48, 64, 3) and np.all(np.isfinite(image))
    lum = image @ np.array([0.2126, 0.7152, 0.0722])
    assert lum.min() > -1e-3 and 0.2 < lum.max() < 50.0


def test_coverage_model_and_intent_options(tiny_image, tmp_path, capsys):
    status, out, _ = run([tiny_image, "--inks", "B30", "--coverage-model", "murray-davies", "--intent",
                          "absolute", "--paper", "0.8", "-o", tmp_path / "p.xml", "--quiet"], capsys)
    assert status == 0
    xml = (tmp_path / "p.xml").read_text()
    assert '<string name="coverage_model" value="murray-davies"/>' in xml
    assert '<default name="paper" value="0.8"/>' in xml
    assert "a monotone of the image's lightness in B30" in out      # one ink: its tones, not the hues
    assert "out of gamut" not in out and "miss" not in out


BAD = [
    (["--inks", "Q30"], "--inks"),
    (["--inks", "R30,Y30,B30,G30,R15"], "--inks"),
    (["--inks", "R30,,B30"], "--inks"),
    (["--inks", "R30,R30"], "--inks"),
    (["--inks", "R30", "--dots", "AM:abc"], "--dots"),
    (["--inks", "R30", "--dots", "AM:0"], "--dots"),
    (["--inks", "R30", "--paper", "1.5"], "--paper"),
    (["--inks", "R30", "--size", "-3x2"], "--size"),
    (["--inks", "R30", "--size", "big"], "--size"),
    (["--inks", "R30", "--dpi", "0"], "--dpi"),
    (["--inks", "R30", "--coverage-model", "yule"], "--coverage-model"),
    (["--inks", "R30", "--dots", "AM:300", "--size", "150x150"], "texels"),
]


@pytest.mark.parametrize("extra,word", BAD, ids=[" ".join(b[0]) for b in BAD])
def test_bad_options_one_line_exit_2(tiny_image, tmp_path, capsys, extra, word):
    status, out, err = run([tiny_image, *extra, "-o", tmp_path / "page.xml"], capsys)
    assert status == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("python -m inkbsdf.print: error: ") and word in lines[0], err
    assert not (tmp_path / "page.xml").exists() and not (tmp_path / "page_textures").exists()


def test_bad_image_and_output_one_line_exit_2(tiny_image, tmp_path, capsys):
    fake = tmp_path / "fake.png"
    fake.write_text("not a png")
    cases = [([tmp_path / "missing.png"], "not found"), ([fake], "not an image"),
             ([tiny_image, "-o", tmp_path / "page.txt"], ".xml"),
             ([tiny_image, "-o", tmp_path / "no" / "dir" / "page.xml"], None)]
    for args, word in cases:
        out_args = [] if "-o" in [str(a) for a in args] else ["-o", tmp_path / "page.xml"]
        status, _, err = run([*args, "--inks", "R30", *out_args], capsys)
        if word is None:                          # a new folder is fine: created at write time
            assert status == 0
            continue
        assert status == 2 and len(err.strip().splitlines()) == 1 and word in err, err
        assert not (tmp_path / "page.xml").exists()


def test_command_line_entry_point(tiny_image, tmp_path):
    """As a module (`python -m inkbsdf.print`): exit 2 and one stderr line, no traceback."""
    proc = subprocess.run([sys.executable, "-m", "inkbsdf.print", str(tiny_image), "--inks", "R30",
                           "--dots", "XY", "-o", str(tmp_path / "p.xml")], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


def test_demo_photograph_textures_are_current():
    """The committed photograph textures are what `scenes/make_assets.py` makes from the
    committed photograph with today's tables: binary, the layout's size, and (separated and
    screened again here) differing in fewer than 0.1 % of the texels — a change of the tables'
    defaults (e.g. their polarisation) moves about 1 %."""
    from PIL import Image

    from solver.apps.separation import PrintSettings, parse_dots, print_image, printed_inks, read_srgb8

    ma = scene_script("make_assets")

    photo = ma.PRINTED_PAGE.photo
    settings = PrintSettings(inks=photo.inks, dots=parse_dots(photo.dots), size_cm=ma.photo_size_cm(photo))
    source = read_srgb8(ROOT / "scenes" / "textures" / "printed_page_photo.png")
    assert source.shape == (ma.PHOTO_SIZE_PX[1], ma.PHOTO_SIZE_PX[0], 3)
    fresh = print_image(source, settings, printed_inks(photo.inks)).textures
    for name, want in zip(ma.photo_texture_files(ma.PRINTED_PAGE), fresh):
        tex = np.asarray(Image.open(ROOT / "scenes" / name))
        assert tex.shape == want.shape and set(np.unique(tex)) <= {0, 255}, name
        assert np.mean(tex != want) < 1e-3, f"run `python scenes/make_assets.py`: {name} is stale"


def test_bsdf_over_binary_dots_shows_murray_davies(use_variant, tmp_path):
    """The `ink` BSDF averaged over AM dot textures of coverages c̄ equals the NumPy model's
    Murray–Davies BRDF at c̄ (to the 1 % the dot areas match Demichel's), not Clapper–Yule's:
    the reason `auto` separates binary dots with murray-davies."""
    import drjit as dr

    from solver.printing import brdf_smooth
    from solver.apps.separation import TexelGrid, halftone_ink, parse_dots, printed_inks, write_grey_png

    mi = use_variant("llvm_ad_spectral")
    cov = (0.35, 0.5, 0.25)
    d = parse_dots("AM:25")
    grid = TexelGrid.for_print((2.0, 2.0), (4, 4), d)
    bsdf = {"type": "ink", "paper": 0.9}
    for i, (ink, c, angle) in enumerate(zip(("R30", "Y30", "B30"), cov, (75.0, 0.0, 15.0)), start=1):
        path = write_grey_png(tmp_path / f"{ink}.png", halftone_ink(np.full((4, 4), c), grid, d, angle, i))
        bsdf[f"ink{i}"] = ink
        bsdf[f"coverage{i}"] = {"type": "bitmap", "filename": str(path), "raw": True, "filter_type": "nearest"}
    bsdf = mi.load_dict(bsdf)
    n = 1 << 17
    lam = np.array([450.0, 530.0, 600.0, 650.0])
    theta = np.radians(30.0)
    si = surface_interaction(mi, np.tile([[0.0], [0.0], [1.0]], (1, n)), np.tile(lam[:, None], (1, n)))
    rng = np.random.default_rng(4)
    si.uv = mi.Point2f(*[mi.Float(a) for a in rng.random((2, n))])
    wo = mi.Vector3f(float(np.sin(theta)), 0.0, float(np.cos(theta)))
    value = bsdf.eval(mi.BSDFContext(), si, wo)
    dr.eval(value)
    mean = np.asarray(value).reshape(4, n).mean(axis=1) / np.cos(theta)       # f, 1/sr
    printed = printed_inks(("R30", "Y30", "B30"))
    args = (printed, cov, 0.9, 0.0, theta, 0.0)
    md = brdf_smooth(*args, coverage_model="murray-davies", wavelengths_nm=lam)
    cy = brdf_smooth(*args, coverage_model="clapper-yule", wavelengths_nm=lam)
    np.testing.assert_allclose(mean, md, rtol=0.02)
    assert np.all(np.abs(mean / cy - 1.0) > 0.05), (mean, md, cy)
