"""Builds that cannot fit this machine are refused before any work, with the estimate and the
limit in one line; long ones are warned about; --force / force=true overrides."""

import logging
import time

import pytest
from conftest import run_main

from solver.apps.cli import main
from solver import host
from solver.table import preflight
from solver.table.builder import BuildOptions, get_or_build
from solver.table.cache import TableCache
from solver.table.request import MAX_ANGLES, RequestError, table_request


@pytest.mark.parametrize("args", [
    ["--ink", "Y15", "--particles", "sphere:100", "--grid", "4096", "4096", "2048"],
    ["--ink", "Y15", "--particles", "sphere:100", "--grid", "4096", "4096", "16"],
    ["--ink", "R15", "--particles", "sphere:100", "--thickness", "1e9"],
])
def test_impossible_builds_refused_before_any_work(args, tmp_path, capsys):
    t0 = time.perf_counter()
    status, out, err = run_main(main, ["build", *args, "--cache", tmp_path / "c", "--no-progress",
                                       "-o", tmp_path / "t.npz"], capsys)
    assert status == 2
    line = err.strip().splitlines()[-1]
    assert "refused before starting" in line and "memory" in line and "--force" in line
    assert "GB per worker" in line and "available" in line       # the estimate and the limit
    assert time.perf_counter() - t0 < 20
    assert not (tmp_path / "c" / "parts").exists() or not any((tmp_path / "c" / "parts").iterdir())
    assert not (tmp_path / "t.npz").exists()


def test_too_many_angles_refused(tmp_path, capsys):
    status, _, err = run_main(main, ["build", "--ink", "R15", "--angles", "1000000", "--cache", tmp_path / "c",
                                     "-o", tmp_path / "t.npz"], capsys)
    assert status == 2 and "--angles" in err and str(MAX_ANGLES) in err
    with pytest.raises(RequestError, match="--angles"):
        table_request("R15", sigma_rad=tuple(float(i) for i in range(MAX_ANGLES + 1)))


def test_force_skips_the_refusal_but_keeps_the_estimate(tmp_path):
    request = table_request("R15", "sphere:100", grid=(4096, 4096, 16))
    with pytest.raises(preflight.PreflightError):
        preflight.check(request, 1, tmp_path)
    est = preflight.check(request, 1, tmp_path, force=True)
    assert est.worker_bytes > host.available_memory_bytes()


def test_estimate_grows_with_what_is_asked():
    base = preflight.estimate(table_request("R15", "sphere:100"))
    finer = preflight.estimate(table_request("R15", "sphere:100", grid=(128, 128, 64)))
    more = preflight.estimate(table_request("R15", "sphere:100", realizations=12))
    assert finer.worker_bytes > base.worker_bytes and finer.seconds > base.seconds
    assert more.solves == 2 * base.solves and more.seconds > base.seconds
    # the default: 6 realizations of one azimuth, TE and TM alternating: 6 solves per (λ, σ);
    # two azimuths solve TE and TM in every realization: 12
    assert base.solves == 6 * 11 * 7
    assert preflight.estimate(table_request("R15", "sphere:100", azimuths=2)).solves == 2 * base.solves
    assert preflight.estimate(table_request("R15", "sphere:100"), workers=2).seconds < base.seconds
    # grains: volume fraction × layer volume / grain volume (an independent count, not the model's)
    import math
    expected = 0.15 * 2000.0 ** 2 * 1000.0 / (math.pi / 6 * 100.0 ** 3)
    assert 0.6 * expected < base.grains < 1.6 * expected


def test_stack_estimate_counts_both_layers():
    one = preflight.estimate(table_request("Y15", "sphere:100"))
    stack = preflight.estimate(table_request("Y15/B15", "sphere:100"))
    assert 1.6 * one.grains < stack.grains < 2.4 * one.grains
    assert stack.solves >= 2 * one.solves          # solved from above and from below


def test_molecular_estimate_is_small_and_passes(tmp_path):
    est = preflight.check(table_request("R15"), 2, tmp_path)
    assert est.grains == 0 and est.solves == 0 and est.seconds < 5 and est.worker_bytes < 1e9


def test_long_build_and_unresolved_grains_warned(tmp_path, caplog, monkeypatch):
    monkeypatch.setattr(host, "available_memory_bytes", lambda: 1e15)    # warned, not refused
    with caplog.at_level(logging.WARNING, logger="inkbsdf.tables"):
        preflight.check(table_request("R15", "sphere:5"), 2, tmp_path)
    assert "much smaller than" in caplog.text and "voxels" in caplog.text
    caplog.clear()
    est = preflight.estimate(table_request("R15", "sphere:100"), 2)
    monkeypatch.setattr(preflight, "LONG_BUILD_S", 0.5 * est.seconds)
    with caplog.at_level(logging.WARNING, logger="inkbsdf.tables"):
        preflight.check(table_request("R15", "sphere:100"), 2, tmp_path)
    assert "will take long" in caplog.text and "grains per cell" in caplog.text
    assert "much smaller than" not in caplog.text


def test_refusal_happens_inside_get_or_build(tmp_path):
    opts = BuildOptions(cache=TableCache(tmp_path / "c"), workers=1, progress=False)
    with pytest.raises(preflight.PreflightError, match="refused before starting"):
        get_or_build(table_request("R15", "sphere:100", thickness_nm=1e9), opts)


def test_scene_ink_gets_the_same_check(use_variant, tmp_path):
    mi = use_variant("scalar_spectral")
    with pytest.raises(Exception, match="refused before starting.*parameter 'force'"):
        mi.load_dict({"type": "ink", "ink": "R15", "particles": "sphere:100", "thickness": 1e9,
                      "cache": str(tmp_path / "c")})
    with pytest.raises(Exception, match="'force' must be a boolean"):
        mi.load_dict({"type": "ink", "ink": "R15", "force": "yes", "cache": str(tmp_path / "c")})


def test_a_long_geometry_unit_is_announced_with_its_estimate(tmp_path, caplog, monkeypatch):
    """A geometry unit's bar moves only when a realization is done: a long one says up front
    how long it will take (the estimate), so a silent bar is not mistaken for a hang."""
    request = table_request("R15", "sphere:300", grid=(16, 16, 8), realizations=1)
    est = preflight.estimate(request, 1)
    assert est.geometry_seconds > 0
    monkeypatch.setattr(preflight, "GEOMETRY_NOTE_S", 0.5 * est.geometry_seconds)
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        preflight.check(request, 1, tmp_path)
    assert "per realization (estimate" in caplog.text and f"{est.grains:,} grains" in caplog.text
    caplog.clear()
    monkeypatch.setattr(preflight, "GEOMETRY_NOTE_S", 2.0 * est.geometry_seconds)
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        preflight.check(request, 1, tmp_path)
    assert "per realization" not in caplog.text


def test_estimate_counts_the_solves_of_the_solved_wavelengths_at_the_measured_cost(monkeypatch):
    """Solves: realizations × solved wavelengths (every stride-th and the last) × solved σ ×
    azimuths (× 2 sides for a rough top); each at the measured CPU cost per application
    (preflight's coefficients, docs/tables.md), a rough top's at ROUGH_TOP_SOLVE_FACTOR."""
    import math

    monkeypatch.setattr(preflight, "POOL_START_S", 0.0)
    kw = dict(wavelengths_nm=tuple(float(w) for w in range(400, 701, 20)), grid=(32, 32, 16), realizations=3,
              tier="full", solver_tol=1e-3)
    every = preflight.estimate(table_request("R15", "sphere:300", wavelength_stride=1, **kw))
    third = preflight.estimate(table_request("R15", "sphere:300", wavelength_stride=3, **kw))
    rough = preflight.estimate(table_request("R15", "sphere:300:rough", wavelength_stride=3, **kw))
    assert every.solves == 3 * 16 * 7 * 2 and third.solves == 3 * 6 * 7 * 2   # 400, 460, … 700 (6 of 16)
    assert rough.solves == 2 * third.solves
    voxels = 32 * 32 * 16
    per_solve = (preflight.QUIET_MACHINE_FACTOR * preflight.APPLICATIONS_PER_SOLVE * preflight.SECONDS_PER_VOXEL_LOG
                 * voxels * math.log2(voxels))
    geometry = third.geometry_seconds * 3
    assert third.seconds == pytest.approx(geometry + third.solves * per_solve, rel=1e-9)
    assert rough.seconds - rough.geometry_seconds * 3 == pytest.approx(
        rough.solves * per_solve * preflight.ROUGH_TOP_SOLVE_FACTOR, rel=1e-9)
    # a looser solver tolerance: fewer applications, 27 % per decade (the measured slope)
    loose = preflight.estimate(table_request("R15", "sphere:300", wavelength_stride=3, **dict(kw, solver_tol=1e-2)))
    assert loose.seconds - geometry == pytest.approx((1 - 0.27) * (third.seconds - geometry), rel=1e-9)
    monkeypatch.setattr(preflight, "SECONDS_PER_VOXEL_LOG", 2 * preflight.SECONDS_PER_VOXEL_LOG)
    doubled = preflight.estimate(table_request("R15", "sphere:300", wavelength_stride=3, **kw))
    assert doubled.seconds - geometry == pytest.approx(2 * (third.seconds - geometry), rel=1e-9)
    # grains another ink drew already (geometry_store.py): only the solves are left
    drawn = preflight.estimate(table_request("R15", "sphere:300", wavelength_stride=3, **kw), geometry_drawn=True)
    assert third.geometry_seconds > 0 and drawn.seconds == pytest.approx(doubled.seconds - geometry, rel=1e-9)


def test_auto_tier_estimate_weighs_the_tiers_the_probe_picks():
    """Tier auto: small grains mostly end in Born or the effective medium (the probe, then a
    Born solve per sample: far cheaper than full), large grains and rough tops in the full solve
    (its cost plus the probe's Born solves)."""
    kw = dict(grid=(32, 32, 16), realizations=3)
    small = preflight.estimate(table_request("R15", "sphere:30", **kw))
    small_full = preflight.estimate(table_request("R15", "sphere:30", tier="full", **kw))
    large = preflight.estimate(table_request("R15", "sphere:450", **kw))
    large_full = preflight.estimate(table_request("R15", "sphere:450", tier="full", **kw))
    assert preflight.full_tier_share(table_request("R15", "sphere:30")) == 0.0
    assert preflight.full_tier_share(table_request("R15", "sphere:200")) == pytest.approx(0.5)
    assert preflight.full_tier_share(table_request("R15", "sphere:100:rough")) == 1.0
    solving = lambda est: est.seconds - 3 * est.geometry_seconds       # one worker: no pool to start
    assert solving(small) < 0.5 * solving(small_full)
    assert solving(large_full) < solving(large) < 1.1 * solving(large_full)
