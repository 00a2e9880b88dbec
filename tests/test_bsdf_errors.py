"""Bad input to the `ink` BSDF: one clear error naming the file (or variant) and the problem."""

import json
import zipfile
from pathlib import Path

import numpy as np
import pytest

SCENE = """<scene version="3.0.0">
  <shape type="rectangle"><bsdf type="ink"><string name="filename" value="{name}"/></bsdf></shape>
</scene>"""


def _load_scene(mi, folder, table_name):
    path = folder / "scene.xml"
    path.write_text(SCENE.format(name=table_name))
    return mi.load_file(str(path))


def _error(mi, folder, table_name):
    with pytest.raises(Exception) as info:
        _load_scene(mi, folder, table_name)
    return str(info.value)


def test_relative_filename_resolves_next_to_scene(use_variant, ink_tables, tmp_path, monkeypatch):
    mi = use_variant("llvm_ad_spectral")
    (tmp_path / "t").mkdir()
    (tmp_path / "t" / "R30.npz").write_bytes(ink_tables["R30"].read_bytes())
    monkeypatch.chdir("/")
    scene = _load_scene(mi, tmp_path, "t/R30.npz")
    assert "R30.npz" in str(scene.shapes()[0].bsdf())


def test_missing_table(use_variant, tmp_path):
    mi = use_variant("llvm_ad_spectral")
    msg = _error(mi, tmp_path, "nowhere/R30.npz")
    assert "nowhere/R30.npz" in msg and "not found" in msg


def test_truncated_table(use_variant, ink_tables, tmp_path):
    mi = use_variant("llvm_ad_spectral")
    data = ink_tables["Y30"].read_bytes()
    (tmp_path / "cut.npz").write_bytes(data[: len(data) // 2])
    msg = _error(mi, tmp_path, "cut.npz")
    assert "cut.npz" in msg and "truncated" in msg


def test_refused_bsdf_never_reaches_a_later_render(use_variant, ink_tables, tmp_path):
    """A refused `ink` (a truncated table) stays alive in its exception's reference cycles until
    the garbage collector runs; it must not be in Dr.Jit's BSDF registry, whose every member a
    render's symbolic calls traverse and call (it was: "'InkBSDF' object has no attribute
    'premixed'", flaky with the collector's timing). The collector is off here: deterministic."""
    import gc

    mi = use_variant("llvm_ad_rgb")
    data = ink_tables["Y30"].read_bytes()
    (tmp_path / "cut.npz").write_bytes(data[: len(data) // 2])
    gc.collect()
    gc.disable()
    try:
        assert "truncated" in _error(mi, tmp_path, "cut.npz")
        refused = [o for o in gc.get_objects() if type(o).__name__ == "InkBSDF"]
        assert refused, "the refused object was freed: this test no longer shows anything"
        scene = mi.load_dict({
            "type": "scene", "integrator": {"type": "path"}, "emitter": {"type": "constant"},
            "sensor": {"type": "perspective", "film": {"type": "hdrfilm", "width": 4, "height": 3},
                       "to_world": mi.ScalarTransform4f().look_at([0, 0, 3], [0, 0, 0], [0, 1, 0])},
            "shape": {"type": "rectangle", "bsdf": {"type": "ink", "filename": str(ink_tables["R30"])}}})
        image = np.asarray(mi.render(scene, spp=1))
    finally:
        gc.enable()
    assert image.shape == (3, 4, 3) and np.all(np.isfinite(image)) and image.max() > 0


def test_wrong_version_table(use_variant, ink_tables, tmp_path):
    mi = use_variant("llvm_ad_spectral")
    with np.load(ink_tables["B30"]) as npz:
        arrays = {k: npz[k] for k in npz.files}
    meta = json.loads(str(arrays["meta"]))
    meta["schema_version"] = 99
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "v99.npz", **arrays)
    assert zipfile.is_zipfile(tmp_path / "v99.npz")
    msg = _error(mi, tmp_path, "v99.npz")
    assert "v99.npz" in msg and "schema version 99" in msg


def test_missing_filename_parameter(use_variant):
    mi = use_variant("llvm_ad_spectral")
    with pytest.raises(Exception, match="needs 'filename'.*or 'ink'"):
        mi.load_dict({"type": "ink"})


def test_filename_and_ink_together_refused(use_variant, ink_tables):
    mi = use_variant("llvm_ad_spectral")
    with pytest.raises(Exception, match="either 'filename' or 'ink', not both"):
        mi.load_dict({"type": "ink", "filename": str(ink_tables["R30"]), "ink": "R30"})


def test_bad_in_scene_ink_names_the_problem(use_variant):
    mi = use_variant("llvm_ad_spectral")
    with pytest.raises(Exception, match="unknown pigment 'Q'"):
        mi.load_dict({"type": "ink", "ink": "Q5"})
    with pytest.raises(Exception, match="unknown particle shape|unknown shape|cube"):
        mi.load_dict({"type": "ink", "ink": "R15", "particles": "cube:100"})


def test_scene_load_workers_parameter_then_environment_then_one(monkeypatch):
    from inkbsdf.source import build_workers
    from solver.table import TableError

    monkeypatch.delenv("INKBSDF_WORKERS", raising=False)
    assert build_workers({}) == 1                       # in the loading process by default
    monkeypatch.setenv("INKBSDF_WORKERS", "3")
    assert build_workers({}) == 3
    assert build_workers({"workers": 2}) == 2           # the BSDF's parameter wins
    monkeypatch.setenv("INKBSDF_WORKERS", "many")
    with pytest.raises(TableError, match="INKBSDF_WORKERS='many'"):
        build_workers({})


# ------------------------------------------- library use: the cause first, not a traceback
def _load_from_depth(mi, spec, depth):
    """mi.load_dict called `depth` Python frames deep; return the error message."""
    if depth:
        return _load_from_depth(mi, spec, depth - 1)
    with pytest.raises(RuntimeError) as info:
        mi.load_dict(spec)
    return str(info.value)


@pytest.mark.parametrize("params,needle", [
    ({"paper": "white"}, "InkParameterError: ink BSDF: parameter 'paper' is a string, not a float"),
    ({"coverage": "full"}, "InkParameterError: ink BSDF: parameter 'coverage' is a string"),
    ({"ink": "R30", "thickness": "thick"}, "InkParameterError: ink BSDF: parameter 'thickness' 'thick' is not "
                                           "a number"),          # said as a scene parameter, not --thickness
    ({"ink": "R30", "accuracy": "best"}, "InkParameterError: ink BSDF: parameter 'accuracy' 'best': choose one of"),
    ({"ink": "R30", "workers": "two"}, "TableError: ink BSDF: parameter 'workers' must be an integer"),
    ({"filename": "nowhere.npz"}, "TableError: nowhere.npz: table file not found"),
    ({"ink": 15.0}, 'InkParameterError: ink BSDF: parameter \'ink\' must be a <string> (e.g. <string name="ink" '
                    'value="R15"/>)'),
    ({"ink": "R30", "particles": 3}, "InkParameterError: ink BSDF: parameter 'particles' must be a <string>"),
    ({"filename": 3.0}, "InkParameterError: ink BSDF: parameter 'filename' must be a <string>"),
    ({"coverage_model": 1.0}, "InkParameterError: ink BSDF: parameter 'coverage_model' must be a <string>"),
])
def test_library_error_is_short_with_the_cause_and_fix(use_variant, ink_tables, params, needle):
    """mi.load_dict with a bad parameter: Mitsuba's message ends, on its third line, with the
    cause naming the parameter and how to write it, however deep the caller's stack is (Mitsuba
    embeds a traceback of every caller otherwise)."""
    mi = use_variant("llvm_ad_spectral")
    spec = {"type": "ink", "filename": str(ink_tables["R30"]), **params}
    if "ink" in params:
        del spec["filename"]
    shallow, deep = (_load_from_depth(mi, spec, d) for d in (0, 40))
    for msg in (shallow, deep):
        lines = msg.splitlines()
        assert len(lines) == 3, msg
        assert lines[0].endswith("Traceback (most recent call last):")
        assert lines[2].startswith(needle), msg
        assert "_load_from_depth" not in msg
    if "paper" in params:
        assert 'write e.g. <float name="paper" value=' in deep       # the fix: how to write it
    assert "--" not in deep                                          # no ink-tables option names


def test_a_numbered_ink_error_names_the_numbered_parameter(use_variant, ink_tables):
    """Ink 2's type error speaks of 'ink2' and shows <string name="ink2" …/>, the parameter the
    scene wrote, not the single-ink name it is read under."""
    mi = use_variant("llvm_ad_spectral")
    msg = _load_from_depth(mi, {"type": "ink", "filename1": str(ink_tables["R30"]), "ink2": 3.0,
                                "coverage1": 0.5, "coverage2": 0.5}, 0)
    assert ('InkParameterError: ink BSDF, ink 2: parameter \'ink2\' must be a <string> (e.g. '
            '<string name="ink2" value="R15"/>)') in msg, msg


def test_a_thin_in_scene_ink_is_warned_of_naming_the_parameter(use_variant, tmp_path):
    """thickness=1 (µm typed as nm): the tables' thin-layer warning, worded for a scene."""
    mi = use_variant("llvm_ad_spectral")
    with pytest.warns(UserWarning) as said:
        mi.load_dict({"type": "ink", "ink": "R15", "thickness": 1.0, "cache": str(tmp_path)})
    messages = [str(w.message) for w in said]
    assert any(m.startswith("parameter 'thickness' 1: a layer thinner than 50 nm") for m in messages), messages
    assert not any("--" in m for m in messages), messages


def test_unusable_cache_names_the_setting(use_variant, ink_tables, tmp_path, monkeypatch):
    """A cache that is a file, or a read-only folder: which setting chose it, and the fix."""
    import os
    import tempfile

    mi = use_variant("llvm_ad_spectral")
    with pytest.raises(RuntimeError, match=r"CacheError: cache .*R30\.npz is a file, not a folder"):
        mi.load_dict({"type": "ink", "ink": "R30", "cache": str(ink_tables["R30"])})
    read_only = tmp_path / "ro"
    read_only.mkdir()
    read_only.chmod(0o555)
    if os.geteuid() == 0:                  # root ignores permission bits
        read_only = Path("/sys")
    with pytest.raises(OSError):
        tempfile.mkstemp(dir=read_only)
    monkeypatch.setenv("INKBSDF_CACHE", str(read_only / "inkbsdf"))
    try:
        with pytest.raises(RuntimeError, match=r"\$INKBSDF_CACHE .*inkbsdf cannot be created .*choose a "
                                               r"writable folder with parameter 'cache' or \$INKBSDF_CACHE"):
            mi.load_dict({"type": "ink", "ink": "G30"})
    finally:
        (tmp_path / "ro").chmod(0o755)


def test_bug_in_the_constructor_keeps_its_traceback(use_variant):
    """Only input errors are shortened: a bug still shows where it happened."""
    from inkbsdf.errors import plugin_factory

    mi = use_variant("llvm_ad_spectral")

    def broken_constructor(props):
        return 1 / 0

    mi.register_bsdf("ink_test_bug", plugin_factory(broken_constructor))
    with pytest.raises(RuntimeError) as info:
        mi.load_dict({"type": "ink_test_bug"})
    assert "ZeroDivisionError" in str(info.value) and "broken_constructor" in str(info.value)


def test_loader_problem_is_one_line_naming_where_and_what(use_variant, ink_tables, tmp_path):
    """Mitsuba's messages, read back for the command line: file and line, then the cause."""
    from inkbsdf.errors import loader_problem

    mi = use_variant("llvm_ad_spectral")
    scenes = {
        "paper": ('<float name="paper" value="0.5"/><string name="coverage" value="x"/>',
                  "parameter 'coverage' is a string"),
        "unknown": ('<float name="papr" value="0.5"/>',
                    "the bsdf plugin \"ink\" takes no parameter 'papr' (float 0.5): remove it or correct its name"),
    }
    for name, (extra, needle) in scenes.items():
        path = tmp_path / f"{name}.xml"
        path.write_text(SCENE.format(name=ink_tables["R30"]).replace("</bsdf>", extra + "</bsdf>"))
        with pytest.raises(RuntimeError) as info:
            mi.load_file(str(path))
        line = loader_problem(info.value)
        assert "\n" not in line and "Traceback" not in line and "parser.cpp" not in line
        assert line.startswith(f"{path} (line 2, col ") and needle in line, line


# ----------------------------------------------------------------------------- variants
def test_no_variant_says_how_to_set_one():
    import inkbsdf

    with pytest.raises(inkbsdf.VariantError, match="mitsuba.set_variant"):
        inkbsdf.check_variant(None)


def test_usable_variants_and_selection():
    import mitsuba as mi

    import inkbsdf
    from inkbsdf.variant import select_variant, usable_variants

    usable = usable_variants()
    assert "llvm_ad_spectral" in usable and "scalar_spectral" in usable
    for variant in usable:
        assert inkbsdf.check_variant(variant) == variant
    assert "llvm_ad_rgb" in usable and "llvm_ad_mono" in usable   # docs/plugin.md, "RGB and mono variants"
    assert "llvm_ad_spectral_polarized" in usable            # docs/plugin.md, "Polarized variants"
    previous = mi.variant()
    with pytest.raises(inkbsdf.VariantError, match="'bogus' is not a variant.*llvm_ad_spectral"):
        select_variant("bogus")
    assert mi.variant() == previous                 # a refused variant is not set
