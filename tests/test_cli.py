"""The `ink-tables` command line: build, show, and its error messages."""

import subprocess
import sys

import numpy as np
import pytest

from conftest import run_main
from solver.cli import main
from solver.cli.parsing import wavelength_range
from solver.table import read_table


def test_build_and_show(tmp_path, capsys):
    out = tmp_path / "G30.npz"
    assert main(["build", "--ink", "G30", "--wavelengths", "400:700:50", "--angles", "7", "-o", str(out)]) == 0
    table = read_table(out)
    np.testing.assert_array_equal(table.wavelengths, [400, 450, 500, 550, 600, 650, 700])
    assert table.sigma.size == 7 and table.meta["ink"] == "G30" and table.meta["thickness_nm"] == 1000
    png, plot = tmp_path / "g.png", tmp_path / "new" / "s.png"          # a folder made for it
    assert main(["show", str(out), "--png", str(png), "--plot", str(plot)]) == 0
    text = capsys.readouterr().out
    assert "ink G30" in text and "hue" in text and "pigment ε local field" in text
    te = tmp_path / "te.npz"
    assert main(["build", "--ink", "G30", "--wavelengths", "400:700:50", "--angles", "7", "--polarisation", "te",
                 "-o", str(te)]) == 0
    assert read_table(te).meta["local_field"] is False
    capsys.readouterr()
    assert main(["show", str(te)]) == 0 and "pigment ε bulk" in capsys.readouterr().out
    import matplotlib.image
    image = matplotlib.image.imread(png)
    assert image.shape[0] > 256 and image.shape[1] > 64 + 256       # Fig. 6 with axes and a caption
    assert plot.stat().st_size > 0


@pytest.mark.parametrize("args, words", [
    (["build", "--ink", "Q5", "-o", "x.npz"], "unknown pigment 'Q'"),
    (["build", "--ink", "R5", "--thickness", "0", "-o", "x.npz"], "thickness"),
    (["build", "--ink", "R70+Y40", "-o", "x.npz"], "exceeds 100%"),
    (["show", "missing.npz"], "not found"),
    (["build", "--ink", "G30", "--local-field", "--no-local-field", "-o", "x.npz"], "not allowed with"),
    (["geometry", "--ink", "Y15", "--particles", "sphere:100", "--z", "5000"], "section must lie inside"),
])
def test_bad_input_is_one_line(tmp_path, monkeypatch, capsys, args, words):
    monkeypatch.chdir(tmp_path)
    status, _, err = run_main(main, args, capsys)
    assert status == 2, err
    assert words in err and err.count("\n") == 1, err
    assert not (tmp_path / "x.npz").exists()


def test_console_script_reports_bad_input(tmp_path):
    """The installed entry point: exit 2, one line on stderr."""
    res = subprocess.run([sys.executable, "-m", "solver.cli", "build", "--ink", "Q5", "-o", str(tmp_path / "x.npz")],
                         capture_output=True, text=True)
    assert res.returncode == 2, res.stderr
    assert "unknown pigment 'Q'" in res.stderr and res.stderr.count("\n") == 1, res.stderr


def test_wavelength_range():
    wl = wavelength_range("380:780:10")
    assert (wl[0], wl[-1], len(wl)) == (380.0, 780.0, 41) and wavelength_range("500") == (500.0,)
    with pytest.raises(ValueError, match="STEP"):
        wavelength_range("780:380:10")


@pytest.mark.parametrize("argv", [
    ["build", "--ink", "R30", "--accuracy", "ultra", "-o", "x.npz"],
    ["build", "--ink", "R30", "--grid", "64", "64", "-o", "x.npz"],
    ["build", "-o", "x.npz"],
    ["paper", "fig10", "-o", "x.png"],
])
def test_usage_errors_are_one_line(argv, capsys):
    status, _, err = run_main(main, argv, capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and "usage:" not in err and "see --help" in lines[0]


@pytest.mark.parametrize("command", [["build"], ["paper"], ["show"], ["geometry"]])
def test_help_states_no_empty_default(command, capsys):
    with pytest.raises(SystemExit):
        main(command + ["--help"])
    out = capsys.readouterr().out
    assert "(default: None)" not in out and "(default: False)" not in out
    flat = " ".join(out.split())
    assert ") (default: ... " not in flat and "(default: middle) (default" not in flat


@pytest.mark.parametrize("where", ["proc", "under_a_file"])
def test_unwritable_outputs_refused_before_any_work(where, tmp_path, capsys):
    """Writability is probed by creating a file (os.access says yes to root everywhere): a
    pseudo file system or a path under a file is refused up front, naming the option."""
    from conftest import run_main

    if where == "proc":
        target = "/proc/inkbsdf-test/t.npz"
    else:
        (tmp_path / "plain").write_text("x")
        target = str(tmp_path / "plain" / "t.npz")
    status, _, err = run_main(main, ["build", "--ink", "R30", "--particles", "sphere:100", "--cache",
                                     tmp_path / "c", "-o", target], capsys)
    assert status == 2 and "-o" in err and "cannot write" in err
    assert not (tmp_path / "c" / "tables").exists() or not any((tmp_path / "c" / "tables").iterdir())
