"""One ink prints a monotone (solver/apps/separation/monotone.py, docs/printing.md "One ink: a
monotone"): each pixel's L*, black-point compensated onto the ink's ramp (paper white to solid),
printed as the coverage whose printed L* equals it. The references here are the print model's
own ramp at coverage 0 and 1 and a bisection of its L* per target, not the module's table."""

from types import SimpleNamespace

import numpy as np
import pytest

from solver.apps.separation import (PrintColourModel, SeparationLUT, Separator, delta_e76, printed_inks,
                                   separate_image, srgb8_to_lab)
from solver.apps.separation.monotone import MonotoneError, MonotoneRamp


@pytest.fixture(scope="module")
def b30():
    return PrintColourModel.build(printed_inks(("B30",)), 0.9, "clapper-yule")


@pytest.fixture(scope="module")
def b30_separator(b30):
    return Separator.build(b30)


def _compensated(model, source_l):
    """The target L*: source L* 0…100 linearly onto the ink's solid…paper L* (the model's own)."""
    paper, solid = model.lab(np.zeros(1))[0], model.lab(np.ones(1))[0]
    return solid + np.asarray(source_l) * (paper - solid) / 100.0


def _bisect_coverage(model, target_l, steps=40):
    """The coverage printing L* `target_l` [N], by bisection on the model (L* falls with coverage)."""
    lo, hi = np.zeros(len(target_l)), np.ones(len(target_l))
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        darker = model.lab(mid[:, None])[:, 0] < target_l
        lo, hi = np.where(darker, lo, mid), np.where(darker, mid, hi)
    return 0.5 * (lo + hi)


def test_grey_ramp_prints_its_compensated_lightness(b30, b30_separator):
    grey = np.linspace(0, 255, 64).round().astype(np.uint8)
    ramp = np.repeat(grey[:, None], 3, axis=1)[None]                       # black → white
    sep = separate_image(b30_separator, ramp)
    source_l = srgb8_to_lab(ramp[0])[:, 0]
    printed = sep.printed_lab[0].astype(np.float64)
    target = _compensated(b30, source_l)
    assert np.all(np.diff(printed[:, 0]) > 0.0), np.diff(printed[:, 0])     # monotone in the source's L*
    assert np.max(np.abs(printed[:, 0] - target)) < 0.5                     # ΔE76 in L* alone
    assert printed[0, 0] == pytest.approx(b30.lab(np.ones(1))[0], abs=1e-3)    # black: the solid
    assert sep.coverages[0, -1, 0] == pytest.approx(0.0, abs=1e-6)          # white: bare paper
    # the coverage is the model's own inverse at that L* (a bisection, not the module's table)
    np.testing.assert_allclose(sep.coverages[0, :, 0], _bisect_coverage(b30, target), atol=1e-4)


def test_mapped_colour_is_the_printed_colour(b30, b30_separator):
    rgb = np.random.default_rng(5).integers(0, 256, (500, 3))
    sep, source = b30_separator.separate_srgb(rgb / 255.0)
    assert np.max(sep.delta_e76) < 1e-9 and not sep.out_of_gamut.any()
    np.testing.assert_allclose(b30_separator.targets(source), sep.printed_lab, atol=1e-9)
    np.testing.assert_allclose(sep.printed_lab, b30.lab(sep.coverages), atol=1e-9)   # the ink's own colour
    # coloured pixels too: their L* alone decides, monotone and on target
    order = np.argsort(source[:, 0])
    assert np.all(np.diff(sep.printed_lab[order, 0]) >= -1e-9)
    assert np.max(np.abs(sep.printed_lab[:, 0] - _compensated(b30, source[:, 0]))) < 0.5


def test_report_says_monotone_and_nothing_missed(b30_separator):
    rgb = np.random.default_rng(6).integers(0, 256, (40, 30, 3)).astype(np.uint8)
    report = separate_image(b30_separator, rgb).report
    lines = report.lines()
    assert report.residual_pixels == 0 and report.mapped_pixels == 0 and report.residual_max_de76 < 1e-9
    assert len(lines) == 2 and "a monotone of the image's lightness in B30" in lines[1], lines
    assert not any("out of gamut" in x or "miss" in x for x in lines), lines
    black, white = report.lightness_range
    assert white == pytest.approx(100.0, abs=1e-6) and f"{black:.1f} solid" in lines[1]


def test_table_and_direct_paths_agree(b30):
    """More distinct colours than the table's nodes: still separated directly (exact), and a
    table built from the same separator interpolates the same monotone."""
    separator = Separator.build(b30, lut_nodes=5)                          # 125 nodes
    rgb = np.random.default_rng(7).integers(0, 256, (20, 20, 3)).astype(np.uint8)
    result = separate_image(separator, rgb)
    assert result.report.lut_nodes == 0 and result.report.residual_pixels == 0
    flat = rgb.reshape(-1, 3) / 255.0
    lut, nodes = SeparationLUT.build(separator, 33)
    assert np.max(nodes.delta_e76) < 1e-9                                  # its nodes are exact too
    via_table = b30.lab(lut(flat))
    assert np.max(delta_e76(via_table, result.printed_lab.reshape(-1, 3))) < 0.5


def test_clip_and_two_inks_are_not_monotones(b30):
    assert Separator.build(b30, mapping="clip").few_inks is None             # clip: the closest colour
    two = PrintColourModel.build(printed_inks(("Y30", "B30")), 0.9, "clapper-yule")
    separator = Separator.build(two)
    assert not isinstance(separator.few_inks, MonotoneRamp)                  # a surface: tests/test_duotone.py
    grey = np.repeat(np.linspace(0, 255, 12).round().astype(np.uint8)[:, None], 3, axis=1)[None]
    lines = separate_image(separator, grey).report.lines()
    assert lines[1].startswith("two inks") and not any("monotone" in x for x in lines), lines


def test_an_ink_whose_lightness_turns_back_is_refused():
    """An ink whose L* falls to 60 at 40 % coverage and then rises again (past the paper's): its
    tones cannot carry the image's lightness — one clear line naming the ink and the turn."""
    def lab(c):
        c = np.asarray(c, dtype=np.float64)[..., 0]
        L = 100.0 - 200.0 * c + 250.0 * c ** 2
        return np.stack([L, np.zeros_like(L), -30.0 * c], -1)

    meta = SimpleNamespace(meta={"ink": "W20"})
    fake = SimpleNamespace(n_inks=1, lab=lab, predictor=SimpleNamespace(printed=SimpleNamespace(inks=(meta,))))
    with pytest.raises(MonotoneError, match=r"one ink \(W20\): its printed L\* does not fall steadily") as err:
        MonotoneRamp.build(fake)
    assert "\n" not in str(err.value) and "40.0 %" in str(err.value)


def test_print_command_refuses_such_an_ink_in_one_line(tmp_path, capsys, monkeypatch):
    from PIL import Image

    from conftest import run_main
    from inkbsdf.apps.print import main
    from solver.apps.separation import separate

    def refuse(model):
        raise MonotoneError("one ink (B30): its printed L* does not fall steadily with coverage")

    monkeypatch.setattr(separate.MonotoneRamp, "build", refuse)
    Image.fromarray(np.full((4, 6, 3), 128, np.uint8)).save(tmp_path / "grey.png")
    status, _, err = run_main(main, [tmp_path / "grey.png", "--inks", "B30", "-o", tmp_path / "p.xml"], capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and lines[0].startswith("python -m inkbsdf.print: error: --inks: one ink"), err
    assert not (tmp_path / "p.xml").exists()
