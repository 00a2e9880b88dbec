"""`--dpi` too coarse for the halftone: refused before any work, one line naming --dpi and
--dots and the smallest resolution that draws a dot; a resolution at that bound prints."""

import numpy as np
import pytest

from conftest import run_main
from inkbsdf.apps.print import main
from solver.apps.separation import DotsError, parse_dots
from solver.apps.separation.halftone import (AM_MIN_TEXELS_PER_CELL, FM_MIN_DPI, TexelGrid, check_dpi,
                                        min_dpi)


@pytest.fixture(scope="module")
def small_image(tmp_path_factory):
    from PIL import Image

    path = tmp_path_factory.mktemp("img") / "grey.png"
    Image.fromarray(np.full((6, 8, 3), 128, dtype=np.uint8)).save(path)
    return path


COARSE = [
    (["--dots", "AM:20", "--dpi", "5"], "--dpi 80 or more"),      # 0.25 texel per period
    (["--dots", "AM:20", "--dpi", "79.9"], "--dpi 80 or more"),   # just under 4 per period
    (["--dots", "AM:0.5", "--dpi", "1"], "--dpi 2 or more"),
    (["--dots", "FM", "--dpi", "1"], f"--dpi {FM_MIN_DPI:g} or more"),
]


@pytest.mark.parametrize("extra,fix", COARSE, ids=[" ".join(c[0]) for c in COARSE])
def test_too_coarse_dpi_refused_in_one_line(small_image, tmp_path, capsys, extra, fix):
    status, _, err = run_main(main, [small_image, "--inks", "R30", *extra, "-o", tmp_path / "page.xml"],
                              capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1, err
    assert lines[0].startswith("python -m inkbsdf.print: error: --dpi:") and "--dots" in lines[0] and fix in lines[0], err
    assert not (tmp_path / "page.xml").exists() and not (tmp_path / "page_textures").exists()


def test_refused_before_the_image_is_read(tmp_path, capsys):
    status, _, err = run_main(main, [tmp_path / "missing.png", "--inks", "R30", "--dots", "FM", "--dpi", "1",
                                     "-o", tmp_path / "page.xml"], capsys)
    assert status == 2 and "--dpi" in err and "missing.png" not in err, err


@pytest.mark.parametrize("dots,dpi", [("AM:20", 80), ("FM", FM_MIN_DPI)])
def test_smallest_resolution_that_works_prints(small_image, tmp_path, capsys, dots, dpi):
    from PIL import Image

    status, out, err = run_main(main, [small_image, "--inks", "R30", "--dots", dots, "--dpi", str(dpi),
                                       "--size", "2", "-o", tmp_path / "page.xml", "--quiet"], capsys)
    assert status == 0, err
    texture = np.asarray(Image.open(tmp_path / "page_textures" / "ink_1_R30.png"))
    assert texture.shape == (round(1.5 / 2.54 * dpi), round(2 / 2.54 * dpi))


def test_min_dpi_and_check():
    assert min_dpi(parse_dots("AM:150")) == AM_MIN_TEXELS_PER_CELL * 150
    assert min_dpi(parse_dots("FM")) == FM_MIN_DPI and min_dpi(parse_dots("none")) == 0.0
    check_dpi(parse_dots("none"), 1.0)                  # continuous textures take any resolution
    check_dpi(parse_dots("AM:150"), 600.0)
    with pytest.raises(DotsError, match=r"^dpi: .*--dots AM:150"):
        check_dpi(parse_dots("AM:150"), 599.0)


def test_texel_grid_refuses_coarse_dpi_too():
    """The library's own entry point keeps the bound (not only the command line)."""
    with pytest.raises(DotsError, match="--dpi"):
        TexelGrid.for_print((12.0, 9.0), (90, 120), parse_dots("AM:20"), dpi=5.0)
    assert TexelGrid.for_print((12.0, 9.0), (90, 120), parse_dots("none"), dpi=5.0).shape == (18, 24)
