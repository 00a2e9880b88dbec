"""One list of request options (solver/table/options.py): the CLI, the scene parameters and the
messages derive from it, and every option round-trips through a table file
(TableRequest.from_meta) — an overprint's inks keep their settings."""

import dataclasses
import warnings

import numpy as np
import pytest

from solver.table import read_table, write_table
from solver.table.builder import build_table
from solver.table.meta import table_meta
from solver.table.options import OPTION, OPTIONS, SCENE_PARAMS, WAVE_OPTIONS
from solver.table.request import RequestError, TableRequest, WaveSettings, table_request

#: one request per line, each option set off its default somewhere
CASES = [
    dict(ink="R30"),
    dict(ink="G30", thickness_nm=700.0, polarisation="te", local_field=True, accuracy="preview"),
    dict(ink="Y15/B15", thickness_nm=(800.0, 600.0), wavelengths_nm=(400.0, 550.0, 700.0),
         sigma_rad=tuple(np.linspace(0, np.pi / 2, 5)), dphi_count=7),
    dict(ink="Y7.5+B7.5", particles="sphere:300", accuracy="preview", realizations=3, seed=7, local_field=False),
    dict(ink="R15", particles="cylinder:100:vertical:tilt=15", polarisation="te", target_se=0.01,
         max_realizations=9, grid=(16, 16, 8), cell_nm=1500.0, solver_tol=1e-4, tolerance=0.02, tier="full",
         azimuths=3, wavelength_stride=1),
    dict(ink="Y15/B15", particles="sphere:100/molecular", accuracy="fine"),
]


def make(case):
    case = dict(case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return table_request(case.pop("ink"), case.pop("particles", "molecular"), **case)


def test_every_option_is_set_off_its_default_by_some_case():
    default = make(dict(ink="R30", particles="sphere:100")).to_options()
    set_somewhere = {name for case in CASES for name, value in make(case).to_options().items()
                     if name in ("ink", "particles") or value != default.get(name)}
    assert set_somewhere == {o.name for o in OPTIONS}


@pytest.mark.parametrize("case", CASES, ids=lambda c: c["ink"] + "-" + c.get("particles", "mol"))
def test_every_option_round_trips_through_a_table_file(case, tmp_path):
    """The request written into a table file's meta comes back equal, with the same cache key."""
    req = make(case)
    film = build_table(make(dict(ink="R30", wavelengths_nm=(400.0, 700.0), sigma_rad=(0.0, np.pi / 2),
                                 polarisation=req.polarisation)))
    path = write_table(tmp_path / "t.npz", dataclasses.replace(film, meta=table_meta(req, "full", "test")))
    back = TableRequest.from_meta(read_table(path).meta)
    assert back == req and back.key() == req.key()
    assert make({"ink": back.to_options()["ink"], **{k: v for k, v in back.to_options().items() if k != "ink"}}) == req


def test_meta_of_another_material_or_version_is_refused():
    req = make(CASES[0])
    meta = table_meta(req, "thin-film", "test")
    other = dict(meta, settings=dict(meta["settings"], materials="0123"))
    with pytest.raises(RequestError, match="computed with other material data"):
        TableRequest.from_meta(other)
    with pytest.raises(RequestError, match="no request settings"):
        TableRequest.from_meta({"ink": "R30", "schema_version": 2})


def test_cli_options_and_scene_parameters_derive_from_the_list():
    from solver.apps.cli import make_parser
    from solver.apps.cli.build import request_from_args

    parser = make_parser()
    build = parser._subparsers._group_actions[0].choices["build"]
    flags = {s for a in build._actions for s in a.option_strings}
    assert {o.cli for o in OPTIONS} <= flags and "--no-local-field" in flags
    argv = ["build", "--ink", "R15", "--particles", "cylinder:100:vertical:tilt=15", "--polarisation", "te",
            "--target-se", "0.01", "--max-realizations", "9", "--grid", "16", "16", "8", "--cell", "1500",
            "--solver-tol", "1e-4", "--tolerance", "0.02", "--tier", "full", "--azimuths", "3",
            "--wavelength-stride", "1", "-o", "x.npz"]
    assert request_from_args(parser.parse_args(argv)) == make(CASES[4])
    argv = ["build", "--ink", "Y15/B15", "--thickness", "800,600", "--wavelengths", "400:700:150", "--angles", "5",
            "--dphi-count", "7", "-o", "x.npz"]
    assert request_from_args(parser.parse_args(argv)) == make(CASES[2])
    # scenes: every scene parameter names an option, and messages say the option's CLI name
    assert set(SCENE_PARAMS.values()) <= {o.name for o in OPTIONS}
    assert set(WAVE_OPTIONS) == set(WaveSettings.__dataclass_fields__)
    assert OPTION["thickness_nm"] == "--thickness" and OPTION["cell_nm"] == "--cell"


def test_scene_parameters_make_the_same_request():
    import mitsuba as mi

    import inkbsdf  # noqa: F401 — a variant is set
    from inkbsdf.source import table_request as scene_request

    props = mi.Properties("ink")
    props["ink"] = "R15"
    props["particles"] = "cylinder:100:vertical:tilt=15"
    props["polarisation"] = "te"
    props["target_se"] = 0.01
    props["max_realizations"] = 9
    props["solver_tol"] = 1e-4
    props["tolerance"] = 0.02
    props["tier"] = "full"
    props["azimuths"] = 3
    props["wavelength_stride"] = 1
    req = scene_request(props)
    want = make(dict(CASES[4], grid=WaveSettings().grid, cell_nm=WaveSettings().cell_nm))
    assert req == want


def test_overprint_members_keep_every_setting(tmp_path):
    """An ink given as a table file keeps what it was built with (here the bulk pigment ε of
    --no-local-field) when an overprint rebuilds its request."""
    from inkbsdf.inks import InkSource
    from inkbsdf.lut import load_lut
    from inkbsdf.source import _member_request

    req = make(dict(ink="R30", local_field=False, thickness_nm=900.0, wavelengths_nm=(400.0, 550.0, 700.0)))
    path = write_table(tmp_path / "r30.npz", build_table(req))
    member = InkSource(1, {"filename": str(path)}, load_lut(path))
    back = _member_request(member)
    assert back == req and back.local_field is False and back.key() == req.key()


def test_the_key_is_computed_once_per_request(monkeypatch):
    req = make(CASES[3])
    key = req.key()
    calls = []
    real = TableRequest.numeric_fields
    monkeypatch.setattr(TableRequest, "numeric_fields", lambda self: calls.append(1) or real(self))
    fresh = dataclasses.replace(req)
    assert fresh.key() == fresh.key() == key and len(calls) == 1


def test_a_film_made_directly_gives_its_request_back():
    """A film built by the thin-film tier itself (no request record): its ink, thickness,
    polarisation, pigment field and grids are all its numbers depend on."""
    from solver.inks import parse_ink
    from solver.materials import DISSOLVED_FIELD, default_materials
    from solver.table.thinfilm_tier import build_stack_table, build_thinfilm_table

    wl, sigma = np.arange(400.0, 701.0, 50.0), np.linspace(0, np.pi / 2, 7)
    film = build_thinfilm_table(parse_ink("R30"), 900.0, wl, sigma, polarisation="te")
    req = TableRequest.of_table(film)
    assert req == make(dict(ink="R30", thickness_nm=900.0, wavelengths_nm=tuple(wl), sigma_rad=tuple(sigma),
                            polarisation="te", local_field=False))
    np.testing.assert_array_equal(build_table(req).Tbar, film.Tbar)
    lf = build_stack_table([(parse_ink("Y15"), 800.0), (parse_ink("B15"), 600.0)], wl, sigma,
                           default_materials().with_local_field(DISSOLVED_FIELD))
    req = TableRequest.of_table(lf)
    assert req.local_field and req.ink_label == "Y15/B15" and [l.thickness_nm for l in req.layers] == [800.0, 600.0]
    np.testing.assert_allclose(build_table(req).Rbar, lf.Rbar, rtol=1e-12)
    wave = dataclasses.replace(film, meta=dict(film.meta, tier="full", particles="sphere:100"))
    with pytest.raises(RequestError, match="no request settings"):
        TableRequest.of_table(wave)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c["ink"] + "-" + c.get("particles", "mol"))
def test_overprint_member_from_a_table_file_keeps_every_option(case, tmp_path):
    """Every option of every case survives the overprint path: an ink given by its table file
    (`filename`) comes back from `_member_request` as the request that made the file."""
    from inkbsdf.inks import InkSource
    from inkbsdf.lut import load_lut
    from inkbsdf.source import _member_request

    req = make(case)
    film = build_table(make(dict(ink="R30", wavelengths_nm=(400.0, 700.0), sigma_rad=(0.0, np.pi / 2),
                                 polarisation=req.polarisation)))
    path = write_table(tmp_path / "t.npz", dataclasses.replace(film, meta=table_meta(req, "full", "test")))
    back = _member_request(InkSource(1, {"filename": str(path)}, load_lut(path)))
    assert back == req and back.key() == req.key()
