"""`python -m inkbsdf.print` as a press: images as files hold them (transparency, 16 bits, grey,
embedded ICC profiles), the CGATS characterisation chart, black-generation options and their
bad values (one line, exit 2)."""

import struct
import zlib

import numpy as np
import pytest

from conftest import run_main
from inkbsdf.apps.print import main
from solver.apps.separation import ImageWarning, read_image
from test_separation_press import read_cgats


def run(args, capsys):
    return run_main(main, args, capsys)


def png16(path, rgb16):
    """The test's own 16-bit RGB PNG writer (PNG spec: colour type 2, bit depth 16, filter 0)."""
    h, w, _ = rgb16.shape
    raw = b"".join(b"\x00" + np.asarray(rgb16[r], dtype=">u2").tobytes() for r in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 2, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    return path


def test_transparency_composited_over_paper(tmp_path):
    from PIL import Image

    rgba = np.zeros((2, 2, 4), dtype=np.uint8)
    rgba[..., :3] = (200, 40, 10)
    rgba[..., 3] = ((255, 0), (128, 255))
    Image.fromarray(rgba, "RGBA").save(tmp_path / "a.png")
    image = read_image(tmp_path / "a.png")
    a = rgba[..., 3:4] / 255.0
    want = np.round(rgba[..., :3] * a + 255 * (1 - a))
    np.testing.assert_array_equal(image.rgb8, want)
    assert len(image.notes) == 1 and "paper white" in image.notes[0] and "50.0%" in image.notes[0]


def test_sixteen_bit_colour_and_grey(tmp_path):
    from PIL import Image

    rgb16 = np.random.default_rng(2).integers(0, 65536, (3, 4, 3))
    image = read_image(png16(tmp_path / "c16.png", rgb16))
    assert np.abs(image.rgb8.astype(float) - rgb16 / 257.0).max() <= 1.0
    assert any("16-bit" in n for n in image.notes)
    grey = np.array([[0, 1000, 32896], [40000, 65535, 12345]], dtype=np.uint16)
    Image.fromarray(grey).save(tmp_path / "g16.png")
    image = read_image(tmp_path / "g16.png")
    np.testing.assert_array_equal(image.rgb8[..., 0], np.round(grey / 65535 * 255))
    assert np.all(image.rgb8[..., 0] == image.rgb8[..., 2]) and any("16-bit grey" in n for n in image.notes)


def test_embedded_icc_profile_is_honoured(tmp_path):
    """A CIELAB TIFF with its CIELAB (D50) profile: ImageCms's sRGB agrees with colour-science's
    conversion of the same CIELAB (Bradford D50 → D65) within 2 codes."""
    import colour
    from PIL import Image, ImageCms

    lab = np.array([[50.0, 20.0, -30.0], [70.0, -20.0, 40.0], [30.0, 10.0, 10.0], [85.0, 0.0, 0.0]])
    enc = np.stack([np.round(lab[:, 0] * 255 / 100), np.round(lab[:, 1]) % 256, np.round(lab[:, 2]) % 256], -1)
    im = Image.fromarray(enc.reshape(1, 4, 3).astype(np.uint8), "LAB")
    path = tmp_path / "lab.tif"
    im.save(path, icc_profile=ImageCms.ImageCmsProfile(ImageCms.createProfile("LAB")).tobytes())
    image = read_image(path)
    d50 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D50"]
    lab_q = np.stack([enc[:, 0] * 100 / 255, (enc[:, 1] + 128) % 256 - 128, (enc[:, 2] + 128) % 256 - 128], -1)
    want = colour.XYZ_to_sRGB(colour.Lab_to_XYZ(lab_q, d50), illuminant=d50, chromatic_adaptation_transform="Bradford")
    assert np.abs(image.rgb8[0].astype(float) - 255 * np.clip(want, 0, 1)).max() <= 2.0
    assert any("ICC profile" in n for n in image.notes)


def test_unusable_icc_profile_warns(tmp_path):
    from PIL import Image

    Image.fromarray(np.full((2, 2, 3), 90, np.uint8)).save(tmp_path / "bad.png", icc_profile=b"not a profile" * 20)
    with pytest.warns(ImageWarning, match="cannot be applied"):
        image = read_image(tmp_path / "bad.png")
    assert np.all(image.rgb8 == 90)


def test_notes_printed_and_bad_image_one_line(tmp_path, capsys):
    from PIL import Image

    rgba = np.full((6, 8, 4), 255, np.uint8)
    rgba[..., 3] = 0
    Image.fromarray(rgba, "RGBA").save(tmp_path / "clear.png")
    status, out, err = run([tmp_path / "clear.png", "--inks", "R30", "--lut", "0", "-o", tmp_path / "p.xml"], capsys)
    assert status == 0 and "transparency composited over paper white" in out
    (tmp_path / "broken.jpg").write_bytes(b"\xff\xd8\xff\xe0 truncated")
    status, _, err = run([tmp_path / "broken.jpg", "--inks", "R30", "-o", tmp_path / "q.xml"], capsys)
    assert status == 2 and len(err.strip().splitlines()) == 1 and "broken.jpg" in err, err


def test_characterisation_written_alone(tmp_path, capsys):
    out_file = tmp_path / "chart" / "press.txt"
    status, out, err = run(["--characterisation", out_file, "--inks", "R30,Y30,B30"], capsys)
    assert status == 0, err
    keywords, fields, rows = read_cgats(out_file.read_text())
    assert fields[:4] == ["SAMPLE_ID", "3CLR_1", "3CLR_2", "3CLR_3"] and fields[-3:] == ["LAB_L", "LAB_A", "LAB_B"]
    assert int(keywords["NUMBER_OF_SETS"]) == len(rows) == 9 ** 3
    assert f"{len(rows):,} patches" in out


BAD = [(["--tac", "50"], "--tac"), (["--black-strength", "2"], "--black-strength"),
       (["--black-start", "1"], "--black-start"), (["--black-ink", "Y30"], "--black-ink"),
       (["--black-ink", "K"], "--black-ink 'K' must be an ink spec of --inks (R30, B30) or none: K is a pigment "
                              "letter without its volume percent; no ink of --inks is made of K"),
       (["--black-ink", "B"], "--black-ink 'B' must be an ink spec of --inks (R30, B30) or none: B is a pigment "
                              "letter without its volume percent; the ink of --inks made of it is B30"),
       (["--black-ink", "Q"], "--black-ink 'Q' must be an ink spec of --inks (R30, B30) or none: bad ink term 'Q'"),
       (["--lut", "1"], "--lut"), (["--gamut-knee", "1.5"], "--gamut-knee"), (["--black", "max"], "--black")]


@pytest.mark.parametrize("extra,word", BAD, ids=[" ".join(b[0]) for b in BAD])
def test_bad_press_options_one_line(tmp_path, capsys, extra, word):
    from PIL import Image

    Image.fromarray(np.zeros((4, 4, 3), np.uint8)).save(tmp_path / "i.png")
    status, _, err = run([tmp_path / "i.png", "--inks", "R30,B30", *extra, "-o", tmp_path / "p.xml"], capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and word in lines[0], err
    assert not (tmp_path / "p.xml").exists()


BAD_BLACK = [(["--black-strength", "2"], "--black-strength: give a share in [0, 1], got 2"),
             (["--black-strength", "-0.1"], "--black-strength: give a share in [0, 1], got -0.1"),
             (["--black-start", "1"], "--black-start: give a share in [0, 1), got 1"),
             (["--tac", "50"], "--tac: give a total area coverage limit in [100, 400] percent, got 50"),
             (["--tac", "450"], "--tac: give a total area coverage limit in [100, 400] percent, got 450")]


@pytest.mark.parametrize("extra,message", BAD_BLACK, ids=[" ".join(b[0]) for b in BAD_BLACK])
def test_bad_black_values_name_option_range_and_value(tmp_path, capsys, extra, message):
    """The rule (black.py) says which field failed; the command names its option, the range in
    the option's unit (percent for --tac) and the value given."""
    from PIL import Image

    Image.fromarray(np.zeros((4, 4, 3), np.uint8)).save(tmp_path / "i.png")
    status, _, err = run([tmp_path / "i.png", "--inks", "R30,B30", *extra, "-o", tmp_path / "p.xml"], capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and lines[0].endswith(message), err


def test_black_ranges_live_in_the_rule_alone(monkeypatch):
    """The command has no copy of the ranges: move them in black.py and the options follow."""
    import argparse

    from inkbsdf.apps.print import UsageError, black_rule
    from solver.apps.separation import black

    def args(**kw):
        base = dict(black="gcr", black_strength=0.7, black_start=0.2, tac=300.0)
        return argparse.Namespace(**{**base, **kw})

    monkeypatch.setattr(black, "TAC_BOUNDS", black.Bounds(1.0, 5.0))
    assert black_rule(args(tac=450.0)).tac == pytest.approx(4.5)
    monkeypatch.setattr(black, "STRENGTH_BOUNDS", black.Bounds(0.0, 0.5))
    with pytest.raises(UsageError, match=r"^--black-strength: give a share in \[0, 0.5\], got 0.6$"):
        black_rule(args(black_strength=0.6))
    with pytest.raises(UsageError, match=r"^--black: give one of gcr, ucr, got 'max'$"):
        black_rule(args(black="max"))


def test_ink_thickness_in_the_ink_list(tmp_path, capsys):
    """'R30@500': the tables (ink and overprints) are films of 500 nm, the scene names the
    thickness for the BSDF; a bad thickness is one line."""
    from solver.apps.separation import parse_ink_list, printed_inks
    from solver.apps.separation.printset import InkListError, ink_requests
    from solver.colour.measurement import DEFAULT

    inks = parse_ink_list("R30@500nm,B30")
    assert inks == ("R30@500", "B30")
    req = ink_requests(inks)
    assert req[(0,)].layers[0].thickness_nm == 500.0 and req[(1,)].layers[0].thickness_nm == 1000.0
    assert [layer.thickness_nm for layer in req[(0, 1)].layers] == [1000.0, 500.0]      # B30 over R30
    thin, thick = printed_inks(inks).inks[0], printed_inks(("R30",)).inks[0]
    assert DEFAULT.lab(thin, 0.9)[0] > DEFAULT.lab(thick, 0.9)[0] + 3       # half the ink: lighter
    for bad in ("R30@", "R30@5", "R30@x"):
        with pytest.raises(InkListError, match="thickness in nm"):
            parse_ink_list(bad)
    from PIL import Image

    Image.fromarray(np.full((4, 6, 3), 120, np.uint8)).save(tmp_path / "i.png")
    status, out, err = run([tmp_path / "i.png", "--inks", "R30@500,B30", "--lut", "0", "-o", tmp_path / "p.xml"],
                           capsys)
    assert status == 0, err
    xml = (tmp_path / "p.xml").read_text()
    assert '<string name="ink1" value="R30"/><float name="thickness1" value="500"/>' in xml
    assert '<string name="ink2" value="B30"/>' in xml and "thickness2" not in xml


def test_default_inks_are_the_process_set(tmp_path, capsys):
    """Without --inks the command prints with the process inks K, C, M, Y (each with its
    thickness, on their paper), black generation on; the scene names all four."""
    from PIL import Image

    from solver.apps.separation.printset import process_paper_albedo, process_set

    Image.fromarray(np.full((3, 4, 3), (40, 60, 90), np.uint8)).save(tmp_path / "i.png")
    status, out, err = run([tmp_path / "i.png", "--lut", "0", "--dots", "AM:20", "-o", tmp_path / "p.xml"], capsys)
    assert status == 0, err
    xml = (tmp_path / "p.xml").read_text()
    for n, label in enumerate(process_set(), start=1):
        spec, _, nm = label.partition("@")
        assert f'<string name="ink{n}" value="{spec}"/><float name="thickness{n}" value="{nm}"/>' in xml
    assert f'<default name="paper" value="{process_paper_albedo():g}"/>' in xml
    assert "black: GCR" in out and f"{process_set()[0]} 45°" in out


def test_cmyk_file_without_profile_warns(tmp_path):
    from PIL import Image

    Image.new("CMYK", (4, 3), (0, 0, 0, 0)).save(tmp_path / "c.jpg")
    with pytest.warns(ImageWarning, match="CMYK image without a usable ICC profile"):
        image = read_image(tmp_path / "c.jpg")
    assert image.rgb8.shape == (3, 4, 3) and image.rgb8.min() >= 250          # no ink: white


def test_a_bare_process_letter_points_to_the_process_set():
    """'--inks C,M' (a user who read of the process inks C, M, Y, K): the ink-spec error says
    that the four together are 'process'; an ordinary bad term gets no such hint."""
    from solver.apps.separation import parse_ink_list
    from solver.apps.separation.printset import InkListError

    with pytest.raises(InkListError, match=r"bad ink term 'C'.*the process inks K, C, M, Y together are 'process'"):
        parse_ink_list("C,M")
    with pytest.raises(InkListError) as info:
        parse_ink_list("B3O")
    assert "process" not in str(info.value)
