"""Table schema (v2; a TE table, so v1's columns): round trip and one clear error for each kind of bad file."""

import json
from dataclasses import replace

import numpy as np
import pytest

from solver.inks import parse_ink
from solver.table import TableError, read_table, write_table
from solver.table.thinfilm_tier import build_thinfilm_table


@pytest.fixture()
def table():
    return build_thinfilm_table(parse_ink("Y7.5+B7.5"), 1000.0, np.arange(380.0, 781.0, 40.0),
                                np.linspace(0, np.pi / 2, 10), polarisation="te")


def test_round_trip(tmp_path, table):
    path = write_table(tmp_path / "t.npz", table)
    back = read_table(path)
    for name in ("wavelengths", "sigma", "theta", "dphi", "R", "R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below"):
        np.testing.assert_array_equal(getattr(back, name), getattr(table, name))
    assert back.meta == table.meta
    assert not list(tmp_path.glob("*.tmp"))          # atomic write leaves no temp file


def test_missing_file(tmp_path):
    with pytest.raises(TableError, match="not found"):
        read_table(tmp_path / "nope.npz")


def test_truncated_file(tmp_path, table):
    path = write_table(tmp_path / "t.npz", table)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(TableError, match="truncated or corrupt"):
        read_table(path)


def test_wrong_version(tmp_path, table):
    path = tmp_path / "v3.npz"
    arrays = {k: getattr(table, k) for k in ("wavelengths", "sigma", "theta", "dphi", "R", "R_spec",
                                               "T_coh", "Rbar", "Tbar", "Rbar_below")}
    np.savez(path, meta=np.array(json.dumps({**table.meta, "schema_version": 3})), **arrays)
    with pytest.raises(TableError, match="schema version 3 is not supported"):
        read_table(path)


def test_missing_array(tmp_path, table):
    path = tmp_path / "m.npz"
    np.savez(path, meta=np.array(json.dumps(table.meta)), wavelengths=table.wavelengths)
    with pytest.raises(TableError, match="missing arrays: sigma"):
        read_table(path)


@pytest.mark.parametrize("change, message", [
    (lambda t: replace(t, R=t.R[:, :, :1]), "'R' has shape"),
    (lambda t: replace(t, Tbar=np.where(np.arange(t.Tbar.size).reshape(t.Tbar.shape) == 3, np.nan, t.Tbar)),
     "'Tbar' has 1 non-finite"),
    (lambda t: replace(t, sigma=t.sigma[::-1]), "strictly increasing"),
    (lambda t: replace(t, sigma=t.sigma * 0.9), "must run from 0"),
    (lambda t: replace(t, R_spec=t.R_spec * 2 + 0.6), "exceeds"),
    (lambda t: replace(t, R=t.R + 0.1), "differs from R_spec"),
])
def test_invalid_tables_are_refused_with_the_reason(tmp_path, table, change, message):
    with pytest.raises(TableError, match=message):
        write_table(tmp_path / "bad.npz", change(table))
    assert not list(tmp_path.iterdir())


def _with_diffuse(table, R):
    from solver.table.integrals import diffuse_albedo

    rbar = table.R_spec + diffuse_albedo(table.theta, table.dphi, R)
    return replace(table, R=R, Rbar=rbar, Rbar_below=rbar, Tbar=np.minimum(table.Tbar, 1 - rbar))


def test_diffuse_table_must_be_reciprocal_and_azimuth_free_at_normal(tmp_path, table):
    grid = table.sigma
    shape = (table.wavelengths.size, grid.size, grid.size, 5)
    base = replace(table, theta=grid.copy(), dphi=np.linspace(0, np.pi, 5))
    good = 0.01 * np.ones(shape)
    good[:, -1] = good[:, :, -1] = 0.0               # nothing scattered at grazing incidence
    write_table(tmp_path / "good.npz", _with_diffuse(base, good))
    tilted = good.copy()
    tilted[:, 3, 5, :] += 0.01                       # R(σ3, θ5) ≠ R(θ5, σ3)
    with pytest.raises(TableError, match="not reciprocal"):
        write_table(tmp_path / "b1.npz", _with_diffuse(base, tilted))
    azim = good.copy()
    azim[:, 0, :-1, 0] += 0.01
    azim[:, :-1, 0, 0] += 0.01                       # reciprocal, but Δφ-dependent at normal incidence
    with pytest.raises(TableError, match="depends on Δφ at sigma = 0"):
        write_table(tmp_path / "b2.npz", _with_diffuse(base, azim))


def test_energy_from_below_is_checked_under_diffuse_light(tmp_path, table):
    """From below, Tbar (measured from above) is not the per-angle transmittance of an
    asymmetric layer; reciprocity equates the two only cosine-weighted over the hemisphere. A
    table whose Rbar_below + Tbar exceeds 1 at one angle but not on that average is valid; one
    exceeding 1 on the average (computed here with a fine midpoint rule) is refused."""
    s = table.sigma
    bump = np.where(np.arange(s.size) == s.size - 2, 1.0, 0.0)[None, :]     # one grazing node
    room = 1.0 - table.Tbar
    below = np.clip(table.Rbar_below + bump * (room + 0.02), 0.0, 1.0)
    per_angle = table.Tbar + below
    assert per_angle.max() > 1.01                                           # refused by a per-angle rule
    fine = np.linspace(0, np.pi / 2, 20001)
    mid = 0.5 * (fine[1:] + fine[:-1])
    mean = np.array([np.sum(np.interp(mid, s, row) * 2 * np.cos(mid) * np.sin(mid) * np.diff(fine))
                     for row in per_angle])
    assert mean.max() < 1.0
    write_table(tmp_path / "ok.npz", replace(table, Rbar_below=below))
    assert read_table(tmp_path / "ok.npz").Rbar_below.max() == pytest.approx(below.max())
    worse = np.clip(table.Rbar_below + 0.9 * room + 0.05, 0.0, 1.0)        # every angle: > 1 on average
    with pytest.raises(TableError, match="'Rbar_below' \\+ 'Tbar' exceeds 1 by .* diffuse light from below"):
        write_table(tmp_path / "bad.npz", replace(table, Rbar_below=worse))


def test_energy_from_below_allows_the_standard_errors(tmp_path, table):
    """Rbar_below and Tbar come from different solves: their sum may exceed 1 by sampling
    noise, within two standard errors, not beyond."""
    excess = 0.01
    below = np.clip(1.0 - table.Tbar + excess, 0.0, 1.0)
    noisy = {"Rbar_below": np.full_like(below, 0.004), "Tbar": np.full_like(below, 0.004)}
    write_table(tmp_path / "ok.npz", replace(table, Rbar_below=below, errors=noisy))      # 0.01 < 2 × 0.008
    quiet = {"Rbar_below": np.full_like(below, 0.001), "Tbar": np.full_like(below, 0.001)}
    with pytest.raises(TableError, match="beyond 2 standard errors"):
        write_table(tmp_path / "bad.npz", replace(table, Rbar_below=below, errors=quiet))  # 0.01 > 2 × 0.002


@pytest.mark.parametrize("content, kind", [(b"plain text\n", "not a zip archive"),
                                           (b"\x89PNG\r\n\x1a\n" + bytes(20), "a PNG image"),
                                           (b"", "empty")])
def test_non_table_files_say_what_they_are(tmp_path, content, kind):
    """Never np.load's advice to load pickles: the message says what the file is."""
    path = tmp_path / "x.npz"
    path.write_bytes(content)
    with pytest.raises(TableError) as info:
        read_table(path)
    assert kind in str(info.value) and "pickle" not in str(info.value)
