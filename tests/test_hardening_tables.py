"""Faults and ordinary failures of table builds: one clear line and no traceback, nothing left
behind (temp files, processes), broken cache parts recomputed, files readable by others."""

import logging
import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

from conftest import run_main
from solver.apps.cli import main
from solver.table.builder import BuildOptions, build_table, get_or_build
from solver.table.cache import TableCache
from solver.table.request import table_request

CLI = [sys.executable, "-m", "solver.apps.cli"]
SMALL = ["--ink", "Y7.5+B7.5", "--particles", "sphere:300", "--wavelengths", "400:700:20", "--angles", "4",
         "--grid", "24", "24", "12", "--realizations", "1", "--azimuths", "2", "--tier", "full", "--no-progress"]


def _small_request():
    return table_request("Y7.5+B7.5", "sphere:300", wavelengths_nm=(450.0, 650.0),
                         sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])), grid=(16, 16, 8), realizations=1,
                         azimuths=1, tier="full")


def test_a_part_holding_nan_is_recomputed(tmp_path, caplog):
    req, cache = _small_request(), TableCache(tmp_path / "cache")
    opts = BuildOptions(workers=1, progress=False, cache=cache)
    first = build_table(req, opts)                                # build_table keeps the parts
    part = cache.parts_dir(req) / "full_r0_l1.npz"
    with np.load(part) as npz:
        arrays = {k: npz[k] for k in npz.files}
    arrays["Rbar"] = np.full_like(arrays["Rbar"], np.nan)
    np.savez(part, **arrays)
    with caplog.at_level(logging.WARNING, logger="inkbsdf.tables"):
        again = build_table(req, opts)
    assert any("full_r0_l1.npz" in r.message and "non-finite" in r.message for r in caplog.records)
    np.testing.assert_array_equal(again.Rbar, first.Rbar)


def test_cached_tables_are_readable_by_the_team(tmp_path):
    old = os.umask(0o022)
    try:
        _, path, _ = get_or_build(table_request("R15"), BuildOptions(progress=False, cache=TableCache(tmp_path)))
    finally:
        os.umask(old)
    for p in (path, path.replace(".npz", ".json")):
        assert stat.S_IMODE(os.stat(p).st_mode) == 0o644


@pytest.fixture()
def read_only(monkeypatch):
    """Call with a folder: it becomes read-only — its modes (for a user) and os.access refusing
    writes under it (root writes whatever the modes say; a shared read-only mount refuses)."""
    from pathlib import Path

    folders, real_access = [], os.access

    def access(path, mode, *args, **kw):
        if mode & os.W_OK and any(Path(path).resolve().is_relative_to(f) for f in folders):
            return False
        return real_access(path, mode, *args, **kw)

    def _make(folder):
        folders.append(Path(folder).resolve())
        for p in [folder, *Path(folder).rglob("*")]:
            p.chmod(p.stat().st_mode & ~0o222)

    monkeypatch.setattr(os, "access", access)
    yield _make
    for folder in folders:
        for p in [folder, *folder.rglob("*")]:
            p.chmod(p.stat().st_mode | 0o200)


def test_a_read_only_cache_serves_the_tables_it_holds(tmp_path, read_only, use_variant, capsys):
    """A shared cache nobody may write: `build` and an in-scene ink take the table it holds (no
    file written there), a table it lacks is refused in one line (exit 2) before any work."""
    cache = tmp_path / "shared"
    assert run_main(main, ["build", "--ink", "R15", "--cache", cache, "-o", tmp_path / "a.npz"], capsys)[0] == 0
    read_only(cache)
    before = sorted(cache.rglob("*"))
    code, out, err = run_main(main, ["build", "--ink", "R15", "--cache", cache, "-o", tmp_path / "b.npz"], capsys)
    assert code == 0 and "from cache" in out, err
    assert np.array_equal(np.load(tmp_path / "a.npz")["Rbar"], np.load(tmp_path / "b.npz")["Rbar"])
    mi = use_variant("scalar_spectral")
    bsdf = mi.load_dict({"type": "ink", "ink": "R15", "cache": str(cache)})
    assert bsdf is not None
    code, out, err = run_main(main, ["build", "--ink", "Y15", "--cache", cache, "-o", tmp_path / "c.npz"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "is not writable" in err, err
    assert sorted(cache.rglob("*")) == before


def _run(args, **kw):
    return subprocess.run(CLI + args, capture_output=True, text=True, timeout=120, **kw)


def test_ordinary_failures_are_one_line_without_traceback(tmp_path, monkeypatch, capsys):
    """Exit 2 and one line on stderr, promptly: in this process for each class of failure, as
    the installed command for the two whose libraries could also write there (an unreachable
    Dask scheduler; the first class, as the entry point's check)."""
    a_file = tmp_path / "not_a_folder"
    a_file.write_text("x")
    cases = [
        (["--ink", "R15", "-o", str(tmp_path / "t.npz")], {"INKBSDF_CACHE": str(a_file)}, "is a file, not a folder"),
        (["--ink", "R15", "--cache", "/proc/inkbsdf_cache", "-o", str(tmp_path / "t.npz")], None,
         "cannot be created"),
        (["--ink", "R15", "--cache", "/proc", "-o", str(tmp_path / "t.npz")], None,   # exists, not writable
         "/proc is not writable"),
        (SMALL + ["--scheduler", "tcp://127.0.0.1:9", "-o", str(tmp_path / "t.npz")], None,
         "cannot reach the Dask scheduler"),
        (["--ink", "R15", "--grid", "1", "1", "1", "--particles", "sphere:100", "-o", "x.npz"], None, "--grid"),
        (["--ink", "R15", "--solver-tol", "0", "--particles", "sphere:100", "-o", "x.npz"], None, "--solver-tol"),
        (["--ink", "R15", "--seed", "-1", "--particles", "sphere:100", "-o", "x.npz"], None, "--seed"),
        (["--ink", "clear", "--particles", "sphere:100", "-o", "x.npz"], None, "clear"),
        (["--ink", "R15", "--wavelengths", "300:800:10", "-o", "x.npz"], None, "pigment data"),
        (["--ink", "R15", "--thickness", "inf", "-o", "x.npz"], None, "--thickness"),
        (["--ink", "R15", "-o", "/proc/nowhere/t.npz"], None, "/proc/nowhere"),
    ]
    for i, (args, env, words) in enumerate(cases):
        t0 = time.perf_counter()
        with monkeypatch.context() as patch:
            for name, value in (env or {}).items():
                patch.setenv(name, value)
            status, _, err = run_main(main, ["build"] + args, capsys)
        assert status == 2, (args, err)
        assert "Traceback" not in err and err.count("\n") == 1, (args, err)
        assert words in err, (args, err)
        assert time.perf_counter() - t0 < 30
        if i in (0, 2):
            res = _run(["build"] + args, env=dict(os.environ, **(env or {})))
            assert res.returncode == 2, (args, res.stderr)
            assert "Traceback" not in res.stderr and res.stderr.count("\n") == 1, (args, res.stderr)
            assert words in res.stderr, (args, res.stderr)


def test_show_into_a_closed_pipe_is_quiet(tmp_path, capsys):
    out = tmp_path / "t.npz"
    assert run_main(main, ["build", "--ink", "R15", "--cache", tmp_path / "c", "-o", out], capsys)[0] == 0
    proc = subprocess.Popen(CLI + ["show", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.readline()
    proc.stdout.close()                                           # like `| head -1`
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 0 and "Traceback" not in err, err


@pytest.mark.slow
def test_interrupts_at_random_moments_under_load_exit_promptly_and_leave_nothing(tmp_path):
    """SIGINT and SIGTERM at random moments of a build (loading, spawning workers, geometry,
    solves) under CPU load: each exits within 5 s with its one line and 130 / 143, no traceback,
    no temp file, no output, no process (benchmarks/bench_interrupts.py runs 50)."""
    from benchmarks.bench_interrupts import stress

    outcomes = stress(5, seed=1, latest_s=3.5, load=2, folder=tmp_path)
    hit = [o for o in outcomes if not o.finished_first]
    assert len(hit) >= 3 and {o.signal for o in hit} == {signal.SIGINT, signal.SIGTERM}
    assert not [o.problems() for o in hit if o.problems()]


@pytest.mark.parametrize("how", ["file", "stdin"])
def test_a_script_without_main_guard_builds_in_one_process(tmp_path, how):
    """Spawned workers re-run a script's top level: without a `__main__` guard that would build
    again in every worker (a deadlock or a broken pool), and a script read from standard input
    cannot be re-run at all; detected, one process, a warning."""
    text = (
        "import numpy as np\n"
        "from solver.table.builder import BuildOptions, build_table\n"
        "from solver.table.cache import TableCache\n"
        "from solver.table.request import table_request\n"
        "req = table_request('Y7.5+B7.5', 'sphere:300', wavelengths_nm=(450.0, 650.0), grid=(16, 16, 8),\n"
        "                    sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])), realizations=2, tier='full')\n"
        f"t = build_table(req, BuildOptions(workers=2, progress=False, cache=TableCache({str(tmp_path / 'c')!r})))\n"
        "print('built', t.Rbar.shape)\n")
    if how == "file":
        script = tmp_path / "unguarded.py"
        script.write_text(text)
        res = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    else:
        res = subprocess.run([sys.executable, "-"], input=text, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "built (2, 3)" in res.stdout and "guard" in res.stderr and "Traceback" not in res.stderr
