"""The `ink-tables` command line: build, show, and its error messages."""

import subprocess
import sys

import numpy as np
import pytest

from conftest import run_main
from solver.apps.cli import main
from solver.apps.cli.parsing import wavelength_range
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
    (["build", "--ink", "R-5", "-o", "x.npz"], "--ink 'R-5': negative concentration"),
    (["build", "--ink", "R15//Y15", "-o", "x.npz"], "--ink 'R15//Y15': empty ink spec"),
    (["build", "--ink", "R15", "--particles", "sphere:abc", "-o", "x.npz"], "--particles 'sphere:abc': bad diameter"),
    (["geometry", "--ink", "R-5", "--particles", "sphere:100"], "--ink 'R-5': negative concentration"),
    (["build", "--ink", "R5", "--thickness", "0", "-o", "x.npz"], "thickness"),
    (["build", "--ink", "R70+Y40", "-o", "x.npz"], "exceeds 100%"),
    (["show", "missing.npz"], "not found"),
    (["build", "--ink", "G30", "--local-field", "--no-local-field", "-o", "x.npz"], "not allowed with"),
    (["geometry", "--ink", "Y15", "--particles", "sphere:100", "--z", "5000"], "section must lie inside"),
    (["build", "--ink", "R30", "--particles", "sphere:5000", "-o", "x.npz"],
     "--particles: particle sphere:5000 is 5000 nm high in its orientation, larger than the layer (1000 nm): "
     "give a smaller grain or a thicker --thickness"),
    (["geometry", "--ink", "R30", "--particles", "sphere:600", "--cell", "1000"],
     "--particles: particle sphere:600 spans 600 nm, too large for a 1000x1000 nm cell (needs less than half the "
     "cell side): give a smaller grain or a larger --cell"),
    (["geometry", "--ink", "R30", "--particles", "sphere:1500"], "a smaller grain or a thicker --thickness"),
    (["build", "--ink", "Y15/B15", "--thickness", "800,600,400", "-o", "x.npz"],
     "--thickness gives 3 values for 2 layers: give one value for all layers or 2, one per layer"),
    (["build", "--ink", "R15", "--thickness", "1000,2000", "-o", "x.npz"],
     "--thickness gives 2 values for 1 layer: give one value (nm)"),
])
def test_bad_input_is_one_line(tmp_path, monkeypatch, capsys, args, words):
    monkeypatch.chdir(tmp_path)
    status, _, err = run_main(main, args, capsys)
    assert status == 2, err
    assert words in err and err.count("\n") == 1, err
    assert not (tmp_path / "x.npz").exists()


def test_console_script_reports_bad_input(tmp_path):
    """The installed entry point: exit 2, one line on stderr."""
    res = subprocess.run([sys.executable, "-m", "solver.apps.cli", "build", "--ink", "Q5", "-o", str(tmp_path / "x.npz")],
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
    ["show", "a.npz", "b.npz"],
    ["build", "--ink", "R30", "-o", "x.npz", "extra"],
])
def test_usage_errors_are_one_line(argv, capsys):
    """…prefixed with the subcommand, as its other errors are (arguments left over too)."""
    status, _, err = run_main(main, argv, capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and "usage:" not in err and "see --help" in lines[0]
    assert lines[0].startswith(f"ink-tables {argv[0]}: error: "), lines


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


# ---------------------------------------------------------------- from a new-user trial (CLI problems)
TINY = ["--wavelengths", "400:700:100", "--angles", "3"]


def _warnings(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("warning:")]


def test_paper_makes_its_output_folders_and_counts_what_this_run_did(tmp_path, capsys):
    """-o and --report in folders that do not exist yet: made before any work; a rerun says
    its cells came from the cache, on the console and in the report alike."""
    png, report = tmp_path / "fig" / "f.png", tmp_path / "notes" / "deep" / "f.md"
    argv = ["paper", "fig7", "--rows", "R15", "--columns", "molecular", *TINY, "--no-progress",
            "--cache", tmp_path / "cache", "-o", png, "--report", report]
    status, out, err = run_main(main, argv, capsys)
    assert status == 0, err
    assert png.exists() and png.with_suffix(".csv").exists() and report.exists()
    assert "= 1 cell," in out and "1 cells" not in out and not _warnings(err)
    assert "1 cell: 1 drawn (1 computed by this run, 0 from the cache), 0 failed" in out
    status, out, _ = run_main(main, argv, capsys)
    again = "1 cell: 1 drawn (0 computed by this run, 1 from the cache), 0 failed"
    assert status == 0 and again in out and again in report.read_text()


@pytest.mark.parametrize("option", ["-o", "--report"])
def test_paper_refuses_an_output_folder_it_cannot_make_before_any_work(option, tmp_path, capsys):
    (tmp_path / "plain").write_text("x")
    outputs = {"-o": tmp_path / "new" / "f.png", "--report": tmp_path / "other" / "f.md"}
    outputs[option] = tmp_path / "plain" / "sub" / outputs[option].name
    status, _, err = run_main(main, ["paper", "fig7", "--rows", "R15", "--columns", "molecular", *TINY,
                                     "--cache", tmp_path / "cache", "-o", outputs["-o"],
                                     "--report", outputs["--report"]], capsys)
    assert status == 2 and err.count("\n") == 1 and f"{option} '" in err and "cannot write" in err, err
    assert not (tmp_path / "cache" / "tables").exists() or not any((tmp_path / "cache" / "tables").iterdir())
    assert not (tmp_path / "new").exists() and not (tmp_path / "other").exists()   # no folder made either


def test_particle_options_on_a_molecular_ink_are_one_warning_line(tmp_path, capsys):
    status, _, err = run_main(main, ["build", "--ink", "G30", *TINY, "--realizations", "3", "--accuracy", "fine",
                                     "--cache", tmp_path / "cache", "-o", tmp_path / "g.npz"], capsys)
    assert status == 0, err
    assert _warnings(err) == ["warning: G30 is molecular (an exact thin film): --accuracy, --realizations ignored"]
    assert "UserWarning" not in err and "build.py" not in err and "return table_request" not in err


@pytest.mark.parametrize("columns, warned", [("molecular", True), ("molecular,sphere:100", False)])
def test_paper_warns_of_particle_options_only_without_particle_columns(columns, warned, tmp_path, capsys):
    """The warning comes before any work: an unwritable -o stops the run right after it."""
    status, _, err = run_main(main, ["paper", "fig7", "--rows", "R15", "--columns", columns, "--grid", "8", "8", "8",
                                     "--cache", tmp_path / "cache", "-o", "/proc/inkbsdf-test/f.png"], capsys)
    assert status == 2 and "cannot write" in err
    expected = ["warning: every column is molecular (an exact thin film): --grid ignored"] if warned else []
    assert _warnings(err) == expected


def test_verbose_before_or_after_the_subcommand_adds_debug_lines(tmp_path):
    from solver.apps.cli import make_parser

    argv = ["build", "--ink", "G30", *TINY, "--cache", str(tmp_path / "cache"), "-o", str(tmp_path / "g.npz")]
    assert [make_parser().parse_args(a).verbose for a in (argv, ["-v"] + argv, argv + ["-v"], argv + ["--verbose"])] \
        == [False, True, True, True]
    for extra, debug in (([], False), (["-v"], True)):          # as a user sees it: the installed entry point
        res = subprocess.run([sys.executable, "-m", "solver.apps.cli", *argv, *extra], capture_output=True, text=True)
        assert res.returncode == 0, res.stderr
        assert ("DEBUG ink-tables: request G30" in res.stderr) == debug, res.stderr
        assert "cache key" in res.stderr if debug else "DEBUG" not in res.stderr
        # what a build computes or reuses (INFO) only with -v: by default warnings and the result line
        assert ("INFO inkbsdf.tables: " in res.stderr) == debug, res.stderr
        assert debug or res.stderr == "", res.stderr
        assert res.stdout.startswith(f"{tmp_path / 'g.npz'}: ink G30"), res.stdout


def test_help_says_verbose_after_the_subcommand(capsys):
    with pytest.raises(SystemExit):
        main(["build", "--help"])
    flat = " ".join(capsys.readouterr().out.split())
    assert "-v, --verbose also log what is computed and reused, and debug details" in flat
    assert "before or after the subcommand" in flat


@pytest.mark.parametrize("argv", [["--version"], ["build", "--version"], ["show", "--version"]])
def test_version(argv, capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"ink-tables {version('inkbsdf')}"


@pytest.mark.parametrize("command", ["build", "geometry"])
def test_help_marks_the_cylinder_orientation_optional(command, capsys):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    flat = "".join(capsys.readouterr().out.split())
    assert "cylinder:D[:isotropic|inplane|vertical]" in flat and "cylinder:D:isotropic" not in flat


def test_one_thickness_applies_to_every_layer_and_show_adds_them(tmp_path, capsys):
    out = tmp_path / "s.npz"
    status, _, err = run_main(main, ["build", "--ink", "Y15/B15", "--thickness", "800", *TINY,
                                     "--cache", tmp_path / "cache", "-o", out], capsys)
    assert status == 0 and not _warnings(err), err
    assert list(read_table(out).meta["thickness_nm"]) == [800, 800]
    status, text, _ = run_main(main, ["show", out], capsys)
    assert status == 0 and "thickness 800 + 800 nm" in text
    with pytest.raises(SystemExit):
        main(["build", "--help"])
    assert "one value for every layer" in " ".join(capsys.readouterr().out.split())


def test_a_layer_thinner_than_50_nm_is_warned_of(tmp_path, capsys):
    """µm typed as nm: built (a thin film is legal), with one warning line."""
    status, _, err = run_main(main, ["build", "--ink", "G30", "--thickness", "1", *TINY,
                                     "--cache", tmp_path / "cache", "-o", tmp_path / "g.npz"], capsys)
    assert status == 0, err
    (line,) = _warnings(err)
    assert line.startswith("warning: --thickness 1:") and "50 nm" in line and "µm" in line


def test_cell_failures_show_the_message_of_a_refusal():
    from solver.apps.figures.cells import failure_reason

    assert failure_reason(ValueError("cylinder:300:vertical cannot\n hold R50")) == \
        "cylinder:300:vertical cannot hold R50"
    assert failure_reason(KeyError("tier")) == "KeyError: 'tier'"           # a bug keeps its class


def test_show_finds_a_cached_table_by_its_request_or_key_and_computes_nothing(tmp_path, capsys):
    cache, out = tmp_path / "cache", tmp_path / "y.npz"
    grids = ["--wavelengths", "400:700:100", "--angles", "4"]
    assert main(["build", "--ink", "Y15", *grids, "--cache", str(cache), "-o", str(out)]) == 0
    capsys.readouterr()
    status, by_file, _ = run_main(main, ["show", out], capsys)
    assert status == 0
    status, by_request, _ = run_main(main, ["show", "--ink", "Y15", *grids, "--cache", cache], capsys)
    key = read_table(out).meta["cache_key"]
    assert status == 0 and by_request.splitlines()[0] == f"cached table {cache / 'tables' / key}.npz"
    assert by_request.splitlines()[1:] == by_file.splitlines()          # the same table, summarised alike
    status, by_key, _ = run_main(main, ["show", key, "--cache", cache], capsys)
    assert status == 0 and by_key == by_request
    before = sorted(p.name for p in (cache / "tables").iterdir())
    # another request (a thickness nobody built): one line naming the option and the fix, nothing built
    status, _, err = run_main(main, ["show", "--ink", "Y15", "--thickness", "900", *grids, "--cache", cache], capsys)
    assert status == 2 and "no cached table" in err and "ink-tables build" in err and len(err.splitlines()) == 1
    status, _, err = run_main(main, ["show", "0123456789abcdef01234567", "--cache", cache], capsys)
    assert status == 2 and "no cached tables whose key starts so" in err
    assert sorted(p.name for p in (cache / "tables").iterdir()) == before
    for argv, words in ((["show"], "--ink INK with the build's options"), (["show", out, "--ink", "Y15"], "not with it")):
        status, _, err = run_main(main, argv, capsys)
        assert status == 2 and words in err


def test_show_refuses_request_options_beside_a_file_or_without_ink_and_finds_a_key_by_its_start(tmp_path, capsys):
    cache, out = tmp_path / "cache", tmp_path / "g.npz"
    assert main(["build", "--ink", "G30", "--wavelengths", "400:700:100", "--angles", "3", "--cache", str(cache),
                 "-o", str(out)]) == 0
    capsys.readouterr()
    key = read_table(out).meta["cache_key"]
    for argv, words in ((["show", out, "--particles", "sphere:100"], "--particles describes a cached table"),
                        (["show", out, "--ink", "G30"], "--ink describes a cached table"),
                        (["show", "--particles", "sphere:100"], "--particles needs --ink"),
                        (["show", key[:4] + "zz", "--cache", cache], "table file not found")):
        status, _, err = run_main(main, argv, capsys)
        assert status == 2 and words in err and err.count("\n") == 1, (argv, err)
    for name in (key[:8], key + ".npz"):
        status, text, _ = run_main(main, ["show", name, "--cache", cache], capsys)
        assert status == 0 and text.startswith(f"cached table {cache / 'tables' / key}.npz"), name
    (cache / "tables" / f"{key[:8]}ffff.npz").write_bytes(b"")        # a second key starting alike
    status, _, err = run_main(main, ["show", key[:8], "--cache", cache], capsys)
    assert status == 2 and "2 cached tables" in err and "give more of the key" in err


def test_max_realizations_alone_is_one_warning_and_the_same_table(tmp_path, capsys):
    from solver.table.request import table_request

    base = dict(accuracy="preview", grid=(16, 16, 8), realizations=2)
    with pytest.warns(UserWarning, match="--max-realizations is the cap of --target-se: ignored without it"):
        capped = table_request("R15", "sphere:100", max_realizations=10, **base)
    assert capped.key() == table_request("R15", "sphere:100", **base).key()
    with_target = table_request("R15", "sphere:100", max_realizations=10, target_se=0.01, **base)
    assert with_target.wave.max_realizations == 10 and "--max-realizations 10" in with_target.describe()
    other = table_request("R15", "sphere:100", seed=3, tolerance=0.02, **base)
    # what tells two requests apart is in their one-line description (the build log, show's refusal)
    assert "--seed 3" in other.describe() and "--tolerance 0.02" in other.describe()
    assert "--seed" not in capped.describe() and "16×16×8" in capped.describe()


@pytest.mark.parametrize("command, argv, option", [
    ("ink-tables", ["build", "--ink", "R15", "--ink", "Y15", "-o", "t.npz"], "--ink"),
    ("ink-tables", ["build", "--ink", "R15", "--grid", "8", "8", "8", "--grid", "16", "16", "16", "-o", "t.npz"],
     "--grid"),
    ("ink-tables", ["build", "--ink", "R15", "-o", "a.npz", "--output", "b.npz"], "-o/--output"),
    ("ink-tables", ["show", "t.npz", "--paper", "0.8", "--paper", "0.9"], "--paper"),
    ("ink-tables", ["geometry", "--ink", "R15", "--particles", "sphere:100", "--particles", "sphere:200"],
     "--particles"),
    ("ink-tables", ["paper", "fig7", "--rows", "R15", "--rows", "Y15", "-o", "f.png"], "--rows"),
    ("render", ["scene.xml", "-o", "x.exr", "--spp", "4", "--spp", "8"], "--spp"),
    ("print", ["photo.png", "--inks", "R30", "--inks", "Y30", "-o", "p.xml"], "--inks"),
])
def test_a_single_value_option_given_twice_is_refused(tmp_path, monkeypatch, capsys, command, argv, option):
    """`--ink R15 --ink Y15` kept the last silently: every command refuses it, one line naming
    the option and both values, exit 2, before any work."""
    import inkbsdf.apps.print as print_app
    import inkbsdf.apps.render as render_app

    monkeypatch.chdir(tmp_path)
    entry = {"ink-tables": main, "render": render_app.main, "print": print_app.main}[command]
    code, out, err = run_main(entry, argv, capsys)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "given twice" in lines[0] and option in lines[0], err
    assert not list(tmp_path.iterdir())                      # nothing written


def test_the_build_summary_says_what_a_born_tables_energy_closure_is(tmp_path, capsys):
    """A Born table's closure R+T+A−1 is the first-order model's own imbalance (docs/tables.md,
    'Energy'): the summary says so and names what vouches for it — the probe's measured
    deviation from full solves (as stored in meta), or that none ran; a full table's closure is
    the solver's residual."""
    small = ["--ink", "R30", "--particles", "sphere:100", "--wavelengths", "500:560:30", "--angles", "2", "--grid",
             "8", "8", "4", "--realizations", "2", "--azimuths", "2", "--no-progress", "--workers", "1",
             "--cache", str(tmp_path / "cache")]

    def closure_line(*extra):
        out_path = tmp_path / f"t{len(list(tmp_path.glob('*.npz')))}.npz"
        assert main(["build", *small, *extra, "-o", str(out_path)]) == 0
        lines = [l.strip() for l in capsys.readouterr().out.splitlines() if "closure" in l]
        assert len(lines) == 1 and "energy_closure" not in lines[0], lines
        return lines[0], read_table(out_path).meta

    line, meta = closure_line("--tier", "born")
    assert meta["tier"] == "born"
    assert line.startswith(f"energy closure {meta['errors']['energy_closure_max']:.2g} (first-order Born")
    assert "not a solver residual" in line and "no probe measured its error" in line
    line, meta = closure_line("--tier", "auto", "--tolerance", "0.001")   # the probe chooses Born here
    assert meta["tier"] == "born", meta["tier_probe"]
    assert "first-order Born" in line
    assert f"within {meta['tier_probe']['deviation']['born']:.2g} of full solves (tolerance 0.001)" in line
    line, meta = closure_line("--tier", "full")
    assert "solver's residual" in line and "Born" not in line


@pytest.mark.parametrize("module", ["inkbsdf.print", "inkbsdf.render"])
def test_print_and_render_say_their_version(module, capsys):
    """Every command of the package answers --version with the installed package's version."""
    import importlib
    from importlib.metadata import version

    app = importlib.import_module(module.replace("inkbsdf.", "inkbsdf.apps."))
    with pytest.raises(SystemExit) as exc:
        app.build_parser().parse_args(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"{module} {version('inkbsdf')}"


def _command(name: str):
    """(main, build_parser) of a command: ink-tables, inkbsdf.render or inkbsdf.print."""
    import importlib

    if name == "ink-tables":
        from solver.apps.cli import make_parser
        return main, make_parser
    app = importlib.import_module(f"inkbsdf.apps.{name}")
    return app.main, app.build_parser


@pytest.mark.parametrize("command, argv, program", [
    ("ink-tables", ["build", "--ink", "Q5", "-o", "x.npz"], "ink-tables build"),        # bad input
    ("ink-tables", ["show", "--bogus"], "ink-tables show"),                            # argparse
    ("render", ["missing.xml", "-o", "x.exr"], "python -m inkbsdf.render"),
    ("render", ["scene.xml", "--spp", "0", "-o", "x.exr"], "python -m inkbsdf.render"),
    ("render", ["scene.xml"], "python -m inkbsdf.render"),                             # usage, raised by the command
    ("print", ["missing.png", "-o", "page.xml"], "python -m inkbsdf.print"),
    ("print", ["--bogus"], "python -m inkbsdf.print"),
])
def test_every_commands_error_line_names_the_program(command, argv, program, tmp_path, monkeypatch, capsys):
    """argparse's form `PROG: error: …` for every error of every command, PROG as the usage line
    says it (a bare `error:` left the user guessing which program of a pipeline spoke)."""
    monkeypatch.chdir(tmp_path)
    run, parser = _command(command)
    status, _, err = run_main(run, argv, capsys)
    assert status == 2 and err.count("\n") == 1, err
    assert err.startswith(f"{program}: error: "), err
    usage = parser().format_usage() if command != "ink-tables" else ""
    assert usage.startswith(f"usage: {program} ") or command == "ink-tables", usage


def test_print_names_itself_when_interrupted(monkeypatch, capsys):
    """The interrupt line names the program too (render's: test_render_cli.py, by a signal)."""
    from inkbsdf.apps import print as app

    def interrupted(argv):
        raise KeyboardInterrupt

    monkeypatch.setattr(app, "_main", interrupted)
    assert app.main([]) == 130
    assert capsys.readouterr().err == "\npython -m inkbsdf.print: interrupted: stopped\n"


@pytest.mark.parametrize("command", ["ink-tables", "render", "print"])
def test_every_command_takes_verbose(command, capsys):
    _, parser = _command(command)
    with pytest.raises(SystemExit):
        parser().parse_args(["--help"])
    flat = " ".join(capsys.readouterr().out.split())
    assert "-v, --verbose also log what is computed and reused" in flat, flat


def test_verbose_logging_is_set_in_one_place_for_every_command():
    """The level of this package's loggers follows -v, whichever command set it last (a library
    scene load had set inkbsdf.tables to INFO: its lines showed without -v)."""
    import logging

    from solver.apps.cli.logs import LineFormatter, configure_logging

    tables = logging.getLogger("inkbsdf.tables")
    previous = {name: logging.getLogger(name).level for name in ("inkbsdf", "inkbsdf.tables", "ink-tables")}
    try:
        tables.setLevel(logging.INFO)                          # as inkbsdf.source.show_build_log does
        configure_logging(False)
        assert not tables.isEnabledFor(logging.INFO) and tables.isEnabledFor(logging.WARNING)
        configure_logging(True)
        assert tables.isEnabledFor(logging.DEBUG) and logging.getLogger("ink-tables").isEnabledFor(logging.DEBUG)
        assert not logging.getLogger("numpy").isEnabledFor(logging.INFO)     # never the libraries'
    finally:
        for name, level in previous.items():
            logging.getLogger(name).setLevel(level)
    record = logging.LogRecord("inkbsdf.tables", logging.WARNING, "", 0, "part %s unreadable", ("p",), None)
    assert LineFormatter().format(record) == "warning: part p unreadable"       # as warnings.warn's lines
    record = logging.LogRecord("inkbsdf.tables", logging.INFO, "", 0, "cache hit", (), None)
    assert LineFormatter().format(record) == "INFO inkbsdf.tables: cache hit"


def test_show_usage_names_the_three_ways_to_give_the_table(capsys):
    """`ink-tables show`'s usage line: the table (a file, a cache key, or --ink with the build's
    options) first, one way per line — argparse's listed 30 options and `[file]` last."""
    with pytest.raises(SystemExit):
        main(["show", "--help"])
    usage = capsys.readouterr().out.split("\n\n")[0].splitlines()
    assert [line.split()[:3] if i == 0 else line.split()[:2] for i, line in enumerate(usage)] == [
        ["usage:", "ink-tables", "show"], ["ink-tables", "show"], ["ink-tables", "show"]], usage
    assert [line.split("show ", 1)[1].split()[0] for line in usage] == ["FILE.npz", "KEY", "--ink"], usage
    assert all("--png PNG" in line and "[options]" in line for line in usage), usage
    status, _, err = run_main(main, ["show"], capsys)              # a bad call: what to give, one line
    assert status == 2 and err.count("\n") == 1 and err.startswith("ink-tables show: error: "), err
    assert all(word in err for word in ("FILE.npz", "KEY", "--ink INK", "see --help")), err


def test_the_commands_load_no_numpy_before_their_interrupt_handling():
    """ink-tables imports its package (and the logging setup) before main() installs its SIGINT
    and SIGTERM handling; what loads NumPy or SciPy comes inside it, so an interrupt while they
    load is one line and exit 130, not a traceback (tests/test_hardening_tables.py)."""
    code = ("import sys; import solver.apps.cli; "
            "print(sorted(m for m in ('numpy', 'scipy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stdout + out.stderr


def test_realizations_above_the_default_cap_set_the_cap_when_it_is_not_given():
    """--realizations alone never blames --max-realizations (the cap of --target-se, which the
    user did not give): a cap not given follows it; one given with --target-se still binds."""
    from solver.table.request import RequestError, WaveSettings, table_request

    req = table_request("R15", "sphere:100", realizations=100)
    assert req.wave.realizations == 100 and req.wave.max_realizations == 100
    assert table_request("R15", "sphere:100", realizations=100, target_se=0.01).wave.max_realizations == 100
    assert table_request("R15", "sphere:100").wave.max_realizations == WaveSettings().max_realizations
    with pytest.warns(UserWarning, match="ignored without it"):      # the cap, written out, then means nothing
        assert table_request(**req.to_options()) == req               # round-trips through a table's meta
    with pytest.raises(RequestError, match=r"--max-realizations must be an integer ≥ --realizations \(100\)"):
        table_request("R15", "sphere:100", realizations=100, target_se=0.01, max_realizations=50)


def test_an_uncreatable_cache_does_not_claim_to_serve_tables(tmp_path, capsys, monkeypatch):
    """A cache folder that does not exist serves nothing: the error does not say it does."""
    from solver.table.cache import CacheError, TableCache

    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(CacheError) as info:
        TableCache(blocker / "cache").check()                 # under a file: cannot be created
    assert "cannot be created" in str(info.value) and "still served" not in str(info.value)
