"""Bad input to the `ink` BSDF: one clear error naming the file (or variant) and the problem."""

import json
import zipfile

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


@pytest.mark.parametrize("variant,needle", [("scalar_rgb", "spectral"), ("llvm_ad_mono", "spectral"),
                                            ("scalar_spectral_polarized", "unpolarized")])
def test_rgb_variant_refused(use_variant, variant, needle):
    import mitsuba as mi

    import inkbsdf

    use_variant("scalar_spectral")            # remember a good variant to return to
    mi.set_variant(variant)
    with pytest.raises(inkbsdf.VariantError, match=needle):
        inkbsdf.register()


def test_import_sets_a_default_variant_and_registers(ink_tables):
    """In a fresh interpreter `import inkbsdf` picks cuda/llvm_ad_spectral and registers `ink`."""
    import subprocess
    import sys

    code = ("import mitsuba as mi, inkbsdf; "
            f"b = mi.load_dict({{'type': 'ink', 'filename': {str(ink_tables['R30'])!r}}}); "
            "print(mi.variant(), inkbsdf.default_variant())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    variant, default = out.stdout.split()
    assert variant == default and variant in ("llvm_ad_spectral", "cuda_ad_spectral")


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
