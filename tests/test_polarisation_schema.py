"""Table schema v2: polarisation in meta, the optional s/p arrays, version 1 files still read,
and files with complex or text where numbers belong refused with a clear message."""

import json
from dataclasses import replace

import numpy as np
import pytest

from solver.inks import parse_ink
from solver.table import InkTable, TableError, read_table, validate, write_table
from solver.table.schema import COLUMNS, GRIDS, SCHEMA_VERSION
from solver.table.thinfilm_tier import build_thinfilm_table

WL = np.arange(380.0, 781.0, 50.0)
SIGMA = np.linspace(0, np.pi / 2, 8)
SP = ("r_s", "r_p", "Rbar_s", "Rbar_p", "Tbar_s", "Tbar_p")


@pytest.fixture()
def table():
    return build_thinfilm_table(parse_ink("Y7.5+B7.5"), 1000.0, WL, SIGMA, polarisation="unpolarised")


def _arrays(t: InkTable) -> dict:
    out = {k: getattr(t, k) for k in GRIDS + COLUMNS + ("R",)}
    out.update(t.sp_arrays)
    out["meta"] = np.array(json.dumps(t.meta))
    return out


def test_v2_round_trip_keeps_complex_amplitudes_and_s_p_columns(tmp_path, table):
    assert SCHEMA_VERSION == 2 and table.meta["schema_version"] == 2
    back = read_table(write_table(tmp_path / "t.npz", table))
    assert back.polarisation == "unpolarised" and back.meta == table.meta
    for name in GRIDS + COLUMNS + ("R",) + SP:
        np.testing.assert_array_equal(getattr(back, name), getattr(table, name), err_msg=name)
    assert back.r_s.dtype == np.complex128 and np.any(back.r_p.imag != 0)
    assert back.Rbar_s.dtype == np.float64


def test_te_table_round_trip_has_no_s_p_arrays(tmp_path):
    te = build_thinfilm_table(parse_ink("R15"), 1000.0, WL, SIGMA, polarisation="te")
    back = read_table(write_table(tmp_path / "te.npz", te))
    assert back.polarisation == "te" and back.sp_arrays == {}
    with np.load(tmp_path / "te.npz") as npz:
        assert not set(SP) & set(npz.files)


def test_version_1_file_still_reads_as_te(tmp_path):
    te = build_thinfilm_table(parse_ink("R15"), 1000.0, WL, SIGMA, polarisation="te")
    meta = {k: v for k, v in te.meta.items() if k != "polarisation"}
    meta["schema_version"] = 1
    arrays = _arrays(te)
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "v1.npz", **arrays)
    back = read_table(tmp_path / "v1.npz")
    assert back.polarisation == "te" and back.meta["schema_version"] == 1 and back.sp_arrays == {}
    np.testing.assert_array_equal(back.R_spec, te.R_spec)
    # a version 1 file cannot carry polarisation data
    arrays["r_s"], arrays["r_p"] = np.zeros_like(te.R_spec, complex), np.zeros_like(te.R_spec, complex)
    np.savez(tmp_path / "v1sp.npz", **arrays)
    with pytest.raises(TableError, match="v1sp.npz: a schema version 1 table has no polarisation data"):
        read_table(tmp_path / "v1sp.npz")


@pytest.mark.parametrize("change, message", [
    (lambda a: a.update(Rbar=a["Rbar"] + 0j), "'Rbar' is complex .* must be real"),
    (lambda a: a.update(R_spec=a["R_spec"] * (1 + 1e-3j)), "'R_spec' is complex"),
    (lambda a: a.update(Rbar_s=a["Rbar_s"] + 1e-9j), "'Rbar_s' is complex"),
    (lambda a: a.update(Tbar=a["Tbar"].astype(str)), "'Tbar' holds text"),
    (lambda a: a.update(sigma=a["sigma"].astype("S20")), "'sigma' holds text"),
    (lambda a: a.update(r_p=a["r_p"].astype(str)), "'r_p' holds text"),
    (lambda a: a.update(Rbar_below=a["Rbar_below"] > 0.1), "'Rbar_below' has dtype bool"),
    (lambda a: a.update(meta=np.array([1.0, 2.0])), "'meta' must be one JSON string"),
])
def test_complex_or_text_arrays_are_refused(tmp_path, table, change, message):
    arrays = _arrays(table)
    change(arrays)
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(TableError, match="bad.npz: " + message):
        read_table(tmp_path / "bad.npz")


@pytest.mark.parametrize("version, message", [
    ("2", "schema version '2' is a str; expected an integer 1 or 2"),
    (True, "schema version True is a bool"),
    (2.5, "schema version 2.5 is not supported"),
    (None, "schema version None is not supported"),
])
def test_schema_version_must_be_an_integer_we_read(tmp_path, table, version, message):
    arrays = _arrays(table)
    arrays["meta"] = np.array(json.dumps({**table.meta, "schema_version": version}))
    np.savez(tmp_path / "v.npz", **arrays)
    with pytest.raises(TableError, match=message):
        read_table(tmp_path / "v.npz")


def _meta(t, **changes):
    return {**t.meta, **changes}


@pytest.mark.parametrize("change, message", [
    (lambda t: replace(t, meta={k: v for k, v in t.meta.items() if k != "polarisation"}),
     "a 'te' table cannot hold s/p arrays"),                 # unstated means te
    (lambda t: replace(t, meta=_meta(t, polarisation="tm")),
     "meta 'polarisation' is 'tm'; expected one of 'unpolarised', 'te'"),
    (lambda t: replace(t, meta=_meta(t, polarisation=None)), "meta 'polarisation' is None"),
    (lambda t: replace(t, meta=_meta(t, polarisation="te")), "a 'te' table cannot hold s/p arrays"),
    (lambda t: replace(t, r_p=None), "'r_s' and 'r_p' come in pairs; only 'r_s' given"),
    (lambda t: replace(t, Tbar_s=None), "'Tbar_s' and 'Tbar_p' come in pairs; only 'Tbar_p' given"),
    (lambda t: replace(t, r_s=t.r_s[:, :-1]), "'r_s' has shape"),
    (lambda t: replace(t, r_s=np.abs(t.r_s)), "'r_s' must be complex"),
    (lambda t: replace(t, Rbar_p=t.Rbar_p + 0j), "'Rbar_p' must be real"),
    (lambda t: replace(t, r_p=np.where(np.arange(t.r_p.size).reshape(t.r_p.shape) == 4, np.nan, t.r_p)),
     "'r_p' has 1 non-finite"),
    (lambda t: replace(t, r_s=1.2 * t.r_s / np.abs(t.r_s).max()), r"'r_s' \|·\|² is outside \[0, 1\]"),
    (lambda t: replace(t, r_s=t.r_s * 0.99), r"\(\|r_s\|² \+ \|r_p\|²\)/2 differs from 'R_spec'"),
    (lambda t: replace(t, Rbar_s=t.Rbar_s * 0.9), r"\(Rbar_s \+ Rbar_p\)/2 differs from 'Rbar'"),
    (lambda t: replace(t, Tbar_p=t.Tbar_p * 0.99), r"\(Tbar_s \+ Tbar_p\)/2 differs from 'Tbar'"),
    (lambda t: replace(t, Rbar_s=t.Rbar_s + 0.01, Rbar_p=t.Rbar_p - 0.01),
     "'|r_p|²' exceeds 'Rbar_p'"),
])
def test_inconsistent_polarisation_data_is_refused(tmp_path, table, change, message):
    bad = change(table)
    with pytest.raises(TableError, match=message):
        write_table(tmp_path / "bad.npz", bad)
    assert not list(tmp_path.iterdir())


def test_s_p_arrays_are_optional_in_an_unpolarised_table(table):
    plain = replace(table, **{k: None for k in SP})
    assert validate(plain).polarisation == "unpolarised" and plain.sp_arrays == {}


def test_unstated_polarisation_is_te(table):
    """Tables of the scalar wave tiers carry no key: they are TE."""
    te = build_thinfilm_table(parse_ink("R15"), 1000.0, WL, SIGMA, polarisation="te")
    bare = replace(te, meta={k: v for k, v in te.meta.items() if k != "polarisation"})
    assert validate(bare).polarisation == "te"
