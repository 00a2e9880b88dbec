"""Scene parameters of the `ink` BSDF refused at load with one line naming the parameter and
the fix: a `paper` albedo outside [0, 1] (a float or spectrum; a texture is not read), and a
numbered parameter (`coverage2`, `thickness3`, …) without its ink."""

import numpy as np
import pytest


def _bsdf_xml(body: str) -> str:
    return f'<bsdf version="3.0.0" type="ink">{body}</bsdf>'


def _problem(mi, xml: str) -> str:
    """The one-line cause of a scene load's error, as the command line says it."""
    from inkbsdf.errors import loader_problem

    with pytest.raises(RuntimeError) as info:
        mi.load_string(xml)
    line = loader_problem(info.value)
    assert "\n" not in line and "Traceback" not in line
    return line


@pytest.mark.parametrize("paper,got", [
    ('<float name="paper" value="9"/>', "got 9"),                    # a typo for 0.9
    ('<float name="paper" value="-0.1"/>', "got -0.1"),
    ('<spectrum name="paper" value="1.5"/>', "got 1.5"),
    ('<spectrum name="paper" value="400:0.5, 550:1.2, 700:0.8"/>', "got a spectrum reaching 1.2"),
])
def test_paper_outside_unit_interval_refused(use_variant, ink_tables, paper, got):
    mi = use_variant("llvm_ad_spectral")
    line = _problem(mi, _bsdf_xml(f'<string name="filename" value="{ink_tables["R30"]}"/>{paper}'))
    assert "parameter 'paper'" in line and "[0, 1]" in line and got in line, line
    assert "clamp" not in line


def test_paper_checked_before_the_table_is_read(use_variant):
    mi = use_variant("llvm_ad_spectral")
    line = _problem(mi, _bsdf_xml('<string name="filename" value="nowhere.npz"/><float name="paper" value="9"/>'))
    assert "parameter 'paper'" in line and "not found" not in line, line


def test_paper_in_range_and_textures_load(use_variant, ink_tables, tmp_path):
    """Bounds included; a bitmap is not read at load (its values are clamped per lookup)."""
    from PIL import Image

    mi = use_variant("llvm_ad_spectral")
    table = f'<string name="filename" value="{ink_tables["R30"]}"/>'
    Image.fromarray(np.full((4, 4), 200, dtype=np.uint8)).save(tmp_path / "paper.png")
    for paper in ('<float name="paper" value="0"/>', '<float name="paper" value="1"/>',
                  '<spectrum name="paper" value="400:0.2, 700:1"/>', '<rgb name="paper" value="0.8, 0.5, 0.2"/>',
                  f'<texture type="bitmap" name="paper"><string name="filename" value="{tmp_path / "paper.png"}"/>'
                  '</texture>'):
        bsdf = mi.load_string(_bsdf_xml(table + paper))
        assert "InkBSDF" in str(bsdf), paper


@pytest.mark.parametrize("extra,number", [
    ('<float name="coverage2" value="0.5"/>', 2),                   # the new-user trial's case
    ('<float name="coverage1" value="0.5"/>', 1),
    ('<float name="thickness3" value="800"/>', 3),
])
def test_numbered_parameter_beside_single_ink_names_its_ink(use_variant, ink_tables, extra, number):
    mi = use_variant("llvm_ad_spectral")
    line = _problem(mi, _bsdf_xml(f'<string name="filename" value="{ink_tables["R30"]}"/>{extra}'))
    assert f"needs ink {number}, given as 'ink{number}' or 'filename{number}'" in line, line
    assert "takes no parameter" not in line and "one ink" in line


def test_numbered_parameter_without_its_ink_in_multi_ink_form(use_variant, ink_tables):
    mi = use_variant("llvm_ad_spectral")
    inks = (f'<string name="filename1" value="{ink_tables["R30"]}"/>'
            f'<string name="filename2" value="{ink_tables["B30"]}"/>')
    line = _problem(mi, _bsdf_xml(inks + '<float name="thickness3" value="800"/>'))
    assert "'thickness3'" in line and "needs ink 3, given as 'ink3' or 'filename3'" in line, line
    assert "inks given: 1, 2" in line


def test_unknown_numbered_name_is_still_unreferenced(use_variant, ink_tables):
    """Only the ink parameters' names are taken as numbered: a typo stays Mitsuba's report."""
    mi = use_variant("llvm_ad_spectral")
    line = _problem(mi, _bsdf_xml(f'<string name="filename" value="{ink_tables["R30"]}"/>'
                                  '<float name="covrage2" value="0.5"/>'))
    assert "takes no parameter 'covrage2'" in line, line
