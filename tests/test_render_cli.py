"""`python -m inkbsdf.render`: one clear error line for bad input, no traceback."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from inkbsdf.render import main, scene_parameters

SCENE = str(Path(__file__).resolve().parents[1] / "scenes" / "printed_page.xml")


def test_missing_tables_folder(tmp_path, capsys):
    code = main([SCENE, "--tables", str(tmp_path / "empty"), "--spp", "1", "-o", str(tmp_path / "x.exr")])
    err = capsys.readouterr().err
    assert code == 2
    assert "not found" in err and ".npz" in err and str(tmp_path / "empty") in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.exr").exists()


def test_truncated_table(tmp_path, ink_tables, capsys):
    tables = tmp_path / "tables"
    tables.mkdir()
    for ink, path in ink_tables.items():
        data = path.read_bytes()
        (tables / path.name).write_bytes(data[:100] if ink == "G30" else data)
    code = main([SCENE, "--tables", str(tables), "--spp", "1", "-o", str(tmp_path / "x.exr")])
    err = capsys.readouterr().err
    assert code == 2 and "G30.npz" in err and "truncated" in err and "Traceback" not in err


def test_missing_scene(tmp_path, capsys):
    assert main([str(tmp_path / "nope.xml"), "-o", str(tmp_path / "x.exr")]) == 2
    assert "scene file not found" in capsys.readouterr().err


def test_scene_parameters_resolve_tables(tmp_path):
    params = scene_parameters(tables=tmp_path, width=32, spp=4)
    assert params == {"tables": str(tmp_path.resolve()), "width": "32", "spp": "4"}


def test_module_entry_point_renders(tmp_path, ink_tables):
    """The command of `make demo`, tiny: exit 0, an EXR and a PNG, the render time printed."""
    exr, png = tmp_path / "p.exr", tmp_path / "p.png"
    proc = subprocess.run([sys.executable, "-m", "inkbsdf.render", SCENE, "--tables",
                           str(ink_tables["clear"].parent), "--spp", "2", "--width", "48",
                           "--height", "40", "-o", str(exr), "--png", str(png)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "render" in proc.stdout and " s " in proc.stdout
    from inkbsdf.imageio import read_exr

    image = read_exr(exr)
    assert image.shape == (40, 48, 3) and np.all(np.isfinite(image))
    assert png.stat().st_size > 100


def test_scene_without_parameters_renders_and_says_what_it_ignored(tmp_path, ink_tables, capsys):
    """Mitsuba refuses parameters a scene does not take: the CLI passes only those it takes."""
    from inkbsdf.render import scene_parameter_names

    scene = tmp_path / "bare.xml"
    scene.write_text(f"""<scene version="3.0.0">
  <integrator type="path"/>
  <sensor type="perspective"><transform name="to_world"><lookat origin="0,0,3" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film></sensor>
  <emitter type="constant"/>
  <shape type="rectangle"><bsdf type="ink"><string name="filename" value="{ink_tables['R30']}"/></bsdf></shape>
</scene>""")
    assert scene_parameter_names(scene.read_text()) == set()
    assert scene_parameter_names(Path(SCENE).read_text()) >= {"tables", "width", "height", "spp", "paper"}
    exr = tmp_path / "bare.exr"
    with pytest.warns(UserWarning, match=r"takes no parameter \$width; ignored"):
        assert main([str(scene), "--spp", "2", "--width", "64", "-o", str(exr)]) == 0
    from inkbsdf.imageio import read_exr

    assert read_exr(exr).shape == (12, 16, 3)          # the scene's own film, not --width
    scene.write_text(scene.read_text().replace('<integrator type="path"/>', ""))
    assert main([str(scene), "--spp", "2", "-o", str(exr)]) == 2   # no integrator: one line, no traceback
    assert "No integrator" in capsys.readouterr().err
