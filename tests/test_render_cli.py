"""`python -m inkbsdf.render`: one clear error line for bad input, no traceback."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import DEMO_SCENE
from inkbsdf.apps.render import main, scene_parameters

SCENE = DEMO_SCENE


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


@pytest.mark.render
def test_module_entry_point_renders(tmp_path, ink_tables):
    """The command of `make demo`, tiny: exit 0, an EXR and a PNG, the render time printed."""
    exr, png = tmp_path / "p.exr", tmp_path / "p.png"
    proc = subprocess.run([sys.executable, "-m", "inkbsdf.render", SCENE, "--tables",
                           str(ink_tables["clear"].parent), "--spp", "2", "--width", "48",
                           "--height", "40", "-o", str(exr), "--png", str(png)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "render" in proc.stdout and " s " in proc.stdout
    from inkbsdf.apps.imageio import read_exr

    image = read_exr(exr)
    assert image.shape == (40, 48, 3) and np.all(np.isfinite(image))
    assert png.stat().st_size > 100


@pytest.mark.render
def test_scene_without_parameters_renders_and_says_what_it_ignored(tmp_path, ink_tables, capsys):
    """Mitsuba refuses parameters a scene does not take: the CLI passes only those it takes."""
    from inkbsdf.apps.render import scene_parameter_names

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
    assert main([str(scene), "--spp", "2", "--width", "64", "-o", str(exr)]) == 0
    assert capsys.readouterr().err == f"warning: {scene} takes no parameter $width; ignored\n"
    from inkbsdf.apps.imageio import read_exr

    assert read_exr(exr).shape == (12, 16, 3)          # the scene's own film, not --width
    png = tmp_path / "only.png"                        # a PNG alone: no EXR asked, none written
    assert main([str(scene), "--spp", "2", "--png", str(png)]) == 0 and png.stat().st_size > 50
    assert sorted(p.name for p in tmp_path.glob("*.exr")) == ["bare.exr"]
    capsys.readouterr()
    scene.write_text(scene.read_text().replace('<integrator type="path"/>', ""))
    assert main([str(scene), "--spp", "2", "-o", str(exr)]) == 2   # no integrator: one line, no traceback
    assert "No integrator" in capsys.readouterr().err


# ------------------------------------------------------------------ hardening: bad input
BARE_SCENE = """<scene version="3.0.0">
  {defaults}
  <integrator type="path"/>
  <sensor type="perspective"><transform name="to_world"><lookat origin="0,0,3" target="0,0,0" up="0,1,0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
    <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="10"/></film></sensor>
  <emitter type="constant"/>
  <shape type="rectangle"><bsdf type="ink">{bsdf}</bsdf></shape>
</scene>"""


def bare_scene(folder, bsdf, spp="4", defaults="", name="scene.xml"):
    path = folder / name
    path.write_text(BARE_SCENE.format(bsdf=bsdf, spp=spp, defaults=defaults))
    return path


def table_param(path):
    return f'<string name="filename" value="{path}"/>'


@pytest.fixture()
def unwritable_dir(tmp_path):
    """A folder this process cannot create files in (root ignores permission bits: /sys)."""
    import os
    import tempfile

    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    if os.geteuid() == 0:
        folder = Path("/sys")
    with pytest.raises(OSError):
        tempfile.mkstemp(dir=folder)
    yield folder
    (tmp_path / "ro").chmod(0o755)


def _bad_cases(tmp, tables, unwritable):
    """(argv, needle the one error line must contain) for each class of bad input."""
    r30 = table_param(tables / "R30.npz")
    scene, exr = str(SCENE), str(tmp / "x.exr")
    base = [scene, "--tables", str(tables), "-o", exr]
    return {
        "width 0": (base + ["--width", "0"], "--width"),
        "height <0": (base + ["--height", "-3"], "--height"),
        "spp 0": (base + ["--spp", "0"], "--spp"),
        "spp text": (base + ["--spp", "many"], "--spp"),
        # Mitsuba's sampler seed is a UInt32: outside it nanobind's raw type error, not this line
        "seed < 0": (base + ["--seed", "-1"], "--seed: give an integer in [0, 2^32), got -1"),
        "seed ≥ 2^32": (base + ["--seed", "4294967296"], "--seed: give an integer in [0, 2^32), got 4294967296"),
        "exposure nan": (base + ["--exposure", "nan", "--png", str(tmp / "x.png")], "--exposure"),
        "exposure inf": (base + ["--exposure", "inf", "--png", str(tmp / "x.png")], "--exposure"),
        "output not exr": ([scene, "--tables", str(tables), "-o", str(tmp / "x.png")], ".exr"),
        "too many samples": (base + ["--width", "2", "--height", "2", "--spp", "1100000000"], "2^32"),
        # the size is checked before any table is read or built (a folder without tables here)
        "image too large": ([scene, "--tables", str(tmp / "no tables"), "-o", exr, "--width", "100000",
                             "--height", "100000"], "lower --width/--height"),
        "too many samples at the scene's spp": ([scene, "--tables", str(tmp / "no tables"), "-o", exr,
                                                 "--width", "9000", "--height", "9000"], "2^32"),
        "png not png": (base + ["--png", str(tmp / "x.jpg")], "--png"),
        "no output": ([scene, "--tables", str(tables)], "give -o OUT.exr"),
        "output in a file": ([scene, "-o", str(tables / "R30.npz" / "x.exr")], "not a folder"),
        "output read-only": ([scene, "-o", str(unwritable / "x.exr")], "cannot write in"),
        "png read-only": (base + ["--png", str(unwritable / "x.png")], "--png"),
        "variant bogus": (base + ["--variant", "bogus"], "llvm_ad_spectral"),
        "param type": ([str(bare_scene(tmp, r30 + '<string name="paper" value="white"/>', name="t.xml")),
                        "-o", exr], "parameter 'paper'"),
        "param value": ([str(bare_scene(tmp, '<string name="ink" value="R30"/><string name="thickness" '
                                             'value="thick"/>', name="v.xml")), "-o", exr],
                        "parameter 'thickness'"),
        "unknown param": ([str(bare_scene(tmp, r30 + '<float name="papr" value="0.5"/>', name="u.xml")),
                           "-o", exr], "'papr'"),
        "cache is a file": ([str(bare_scene(tmp, '<string name="ink" value="R30"/><string name="cache" '
                                                 f'value="{tables / "R30.npz"}"/>', name="c.xml")),
                             "-o", exr], "is a file, not a folder"),
        "cache read-only": ([str(bare_scene(tmp, '<string name="ink" value="R30"/><string name="cache" '
                                                 f'value="{unwritable / "cache"}"/>', name="r.xml")),
                             "-o", exr], "writable folder with parameter 'cache'"),
    }


@pytest.mark.render
def test_a_scene_loads_table_build_says_so_and_more_with_verbose(tmp_path):
    """By default a user sees the render's own lines and warnings; an instant (molecular) table
    the scene load builds says nothing; -v adds what a build computes and reuses (INFO of
    inkbsdf.tables, the build's first and last line among them), as in `ink-tables` (one logging
    setup).  A slow build's lines show without -v: the next test."""
    scene = bare_scene(tmp_path, '<string name="ink" value="Y30"/>', spp="1")
    for extra, verbose in (([], False), (["-v"], True)):
        env = {**os.environ, "INKBSDF_CACHE": str(tmp_path / f"cache{int(verbose)}")}   # built each time
        proc = subprocess.run([sys.executable, "-m", "inkbsdf.render", str(scene), "-o", str(tmp_path / "y.exr"),
                               *extra], capture_output=True, text=True, timeout=120, env=env)
        assert proc.returncode == 0, proc.stderr
        assert "render" in proc.stdout and " s " in proc.stdout
        lines = proc.stderr.splitlines()
        if verbose:
            assert any("computing table: Y30" in line for line in lines), proc.stderr
            assert any("table ready in" in line for line in lines), proc.stderr
        else:
            assert lines == [], proc.stderr                     # nothing without -v


def test_a_slow_build_says_its_first_and_last_line_without_verbose(tmp_path, monkeypatch, caplog):
    """A build the preflight expects to take ≥ QUIET_BUILD_S logs on the builds logger (shown by
    render and print without -v: a long scene load is not silent); an instant one does not."""
    import dataclasses
    import logging

    from solver.table import builder, preflight
    from solver.table.cache import TableCache
    from solver.table.request import table_request

    opts = lambda name: builder.BuildOptions(cache=TableCache(tmp_path / name))   # noqa: E731
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        builder.get_or_build(table_request("Y30"), opts("instant"))
    assert not [r for r in caplog.records if r.name == builder.BUILDS_LOGGER]
    assert any("computing table" in r.message for r in caplog.records)      # with -v
    caplog.clear()
    real = preflight.check
    monkeypatch.setattr(preflight, "check", lambda *a, **k: dataclasses.replace(real(*a, **k), seconds=40.0))
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        builder.get_or_build(table_request("R30"), opts("slow"))
    said = [r.getMessage() for r in caplog.records if r.name == builder.BUILDS_LOGGER]
    assert len(said) == 2 and "(estimated 40 s" in said[0] and said[1].startswith("table ready in"), said


def test_bad_input_one_line_exit_2_before_any_work(tmp_path, ink_tables, unwritable_dir, capsys):
    """Every class of bad input: exit 2, one line on stderr naming the option or parameter,
    nothing rendered (no 'rendering…' line) and nothing written."""
    cases = _bad_cases(tmp_path, ink_tables["R30"].parent, unwritable_dir)
    for name, (argv, needle) in cases.items():
        code = main(argv)
        out, err = capsys.readouterr()
        lines = err.strip().splitlines()
        assert code == 2, (name, err)
        assert len(lines) == 1 and lines[0].startswith("python -m inkbsdf.render: error: ") and needle in lines[0], (name, err)
        assert "rendering" not in out, name
        assert not (tmp_path / "x.exr").exists() and not (tmp_path / "x.png").exists(), name


def _start_cli(argv):
    """`python -m inkbsdf.render argv` in a subprocess with SIGINT at its default (Python then
    turns it into KeyboardInterrupt even when the test runner itself ignores it)."""
    import signal

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)   # exec resets it to default
    try:
        return subprocess.Popen([sys.executable, "-m", "inkbsdf.render", *argv], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
    finally:
        signal.signal(signal.SIGINT, previous)


def test_entry_point_bad_input_has_no_traceback(tmp_path, ink_tables, unwritable_dir):
    """The real command, a subprocess per class (run side by side): exit 2, one line, no traceback."""
    cases = _bad_cases(tmp_path, ink_tables["R30"].parent, unwritable_dir)
    chosen = ["width 0", "output read-only", "variant bogus", "param type"]
    procs = {name: _start_cli(cases[name][0]) for name in chosen}
    try:
        for name, proc in procs.items():
            _, err = proc.communicate(timeout=120)
            assert proc.returncode == 2, (name, err)
            assert "Traceback" not in err, (name, err)
            assert len(err.strip().splitlines()) == 1 and cases[name][1] in err, (name, err)
    finally:
        for proc in procs.values():
            proc.kill()
            proc.wait()


# ----------------------------------------------------------------------- samples per pixel
@pytest.mark.render
def test_spp_defaults_to_the_scenes_own(tmp_path, ink_tables, capsys):
    """Without --spp the scene's sample count is used (and said): the image equals an explicit
    render at that count with the same seed, and differs from one at the old fixed 64."""
    from inkbsdf.apps.imageio import read_exr

    r30 = table_param(ink_tables["R30"])
    scene = bare_scene(tmp_path, r30, spp="$spp", defaults='<default name="spp" value="3"/>')
    images = {}
    for label, extra in {"default": [], "3": ["--spp", "3"], "64": ["--spp", "64"]}.items():
        assert main([str(scene), "-o", str(tmp_path / f"{label}.exr")] + extra) == 0
        images[label] = read_exr(tmp_path / f"{label}.exr")
        out = capsys.readouterr().out
        if label == "default":
            assert "3 spp (the scene's default)" in out
    assert np.array_equal(images["default"], images["3"])
    assert not np.array_equal(images["default"], images["64"])
    sampler_only = bare_scene(tmp_path, r30, spp="5", name="sampler.xml")    # no <default>: the sampler's
    assert main([str(sampler_only), "-o", str(tmp_path / "s.exr")]) == 0
    assert "5 spp (the scene's default)" in capsys.readouterr().out


# -------------------------------------------------------------------------------- Ctrl-C
def _children(pid):
    from pathlib import Path as P

    kids = set()
    for task in P(f"/proc/{pid}/task").glob("*"):
        try:
            kids |= {int(k) for k in (task / "children").read_text().split()}
        except OSError:
            pass
    return kids


def _wait_for(stream, text, proc, timeout_s):
    """Read lines of `stream` until one contains `text` (the process is killed on timeout)."""
    import threading

    timer = threading.Timer(timeout_s, proc.kill)
    timer.start()
    try:
        seen = []
        for line in stream:
            seen.append(line)
            if text in line:
                return "".join(seen)
        raise AssertionError(f"never saw {text!r}: {''.join(seen)[-2000:]}")
    finally:
        timer.cancel()


def _interrupted(argv, stream, text, settle=lambda proc: None, sig=None):
    """Start the CLI, wait for `text` on its stdout or stderr (`stream`), call settle(proc),
    send `sig` (SIGINT by default): exit 128 + sig (130 for SIGINT) within 3 s, one line
    "interrupted" (SIGTERM: "terminated") and no traceback on stderr. Returns what settle
    returned."""
    import signal
    import time

    sig = signal.SIGINT if sig is None else sig
    proc = _start_cli(argv)
    try:
        _wait_for(getattr(proc, stream), text, proc, 120)
        state = settle(proc)
        t0 = time.perf_counter()
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=30)
        seconds = time.perf_counter() - t0
    finally:
        proc.kill()
        proc.wait()
    word = "terminated" if sig == signal.SIGTERM else "interrupted"
    assert proc.returncode == 128 + sig, err
    assert "Traceback" not in err and f"python -m inkbsdf.render: {word}: stopped" in err, err
    assert seconds < 3.0, f"took {seconds:.1f} s to stop"
    return state


@pytest.mark.slow
@pytest.mark.render
def test_ctrl_c_during_render_exits_130_promptly(tmp_path, ink_tables):
    """SIGINT while the kernel runs (a render of tens of seconds): exit 130 within ~1 s, no
    traceback, nothing written. (Before: the render ran to its end, ~9 s.)"""
    import time

    exr = tmp_path / "long.exr"
    _interrupted([SCENE, "--tables", str(ink_tables["R30"].parent), "--spp", "4096", "--width", "160",
                  "--height", "128", "-o", str(exr)], "stdout", "rendering", lambda proc: time.sleep(0.5))
    assert not exr.exists()


@pytest.mark.slow
def test_sigterm_during_scene_load_stops_table_workers(tmp_path):
    """SIGTERM (SIGINT's path: the render test above) while a scene load builds a particle
    table on 2 worker processes: exit 143 promptly, one line, no traceback (neither ours nor
    the workers'), and no worker left running."""
    import os
    import signal
    import time

    def workers_started(proc):
        deadline = time.monotonic() + 60
        while len(_children(proc.pid)) < 2 and time.monotonic() < deadline:
            time.sleep(0.1)
        children = _children(proc.pid)
        assert len(children) >= 2
        return children

    bsdf = ('<string name="ink" value="Y7.5+B7.5"/><string name="particles" value="sphere:300"/>'
            f'<string name="cache" value="{tmp_path / "cache"}"/>')
    children = _interrupted([str(bare_scene(tmp_path, bsdf)), "--workers", "2", "-o", str(tmp_path / "x.exr"),
                             "-v"], "stderr", "computing table", workers_started, sig=signal.SIGTERM)   # -v: its INFO line
    deadline = time.monotonic() + 10
    while any(os.path.exists(f"/proc/{c}") for c in children) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(os.path.exists(f"/proc/{c}") for c in children), "a worker outlived the command"


# ------------------------------------------------------------------------------- imageio
def test_png_warns_with_the_count_of_non_finite_pixels(tmp_path):
    from inkbsdf.apps.imageio import NonFiniteWarning, write_png

    image = np.full((4, 5, 3), 0.5, dtype=np.float32)
    image[0, 0, 1] = np.nan
    image[1, 2] = np.inf
    image[3, 4, 0] = -np.inf
    with pytest.warns(NonFiniteWarning, match=r"3 of 20 pixels are NaN or infinite"):
        write_png(tmp_path / "bad.png", image)
    assert (tmp_path / "bad.png").stat().st_size > 0
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_png(tmp_path / "good.png", np.full((4, 5, 3), 0.5, dtype=np.float32))


@pytest.mark.parametrize("stops", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_exposure_refused(tmp_path, stops):
    from inkbsdf.apps.imageio import srgb_encode, write_png

    image = np.full((2, 2, 3), 0.5, dtype=np.float32)
    with pytest.raises(ValueError, match="exposure must be a finite"):
        srgb_encode(image, stops)
    with pytest.raises(ValueError, match="exposure must be a finite"):
        write_png(tmp_path / "x.png", image, stops)
    assert not (tmp_path / "x.png").exists()


def test_image_writers_check_the_extension(tmp_path):
    from inkbsdf.apps.imageio import write_exr, write_png

    image = np.zeros((2, 2, 3), dtype=np.float32)
    with pytest.raises(ValueError, match=r"must end in \.exr"):
        write_exr(tmp_path / "x.png", image)
    with pytest.raises(ValueError, match=r"must end in \.png"):
        write_png(tmp_path / "x.exr", image)
    assert write_exr(tmp_path / "UPPER.EXR", image).exists()


def test_cli_says_non_finite_pixels_in_one_warning_line(tmp_path, ink_tables, monkeypatch, capsys):
    """A render with NaN pixels (a stand-in for a broken scene): the PNG is written, and stderr
    says how many pixels, in one `warning:` line (no source-line echo)."""
    import inkbsdf.apps.render as render

    def broken_render(scene, spp=None, seed=0):
        image = np.full((10, 12, 3), 0.25, dtype=np.float32)
        image[2:4, 5] = np.nan
        return image, 0.0

    monkeypatch.setattr(render, "render_loaded", broken_render)
    r30 = table_param(ink_tables["R30"])
    code = main([str(bare_scene(tmp_path, r30)), "-o", str(tmp_path / "n.exr"), "--png", str(tmp_path / "n.png")])
    err = capsys.readouterr().err
    assert code == 0 and (tmp_path / "n.png").exists()
    assert err.strip().splitlines() == [f"warning: {tmp_path / 'n.png'}: 2 of 120 pixels are NaN or infinite "
                                        "(NaN written black, ±inf clipped): the render has a problem"]
