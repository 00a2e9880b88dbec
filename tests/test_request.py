"""One request, one table: every entry point makes the same typed request for the same ink, the
cache key covers everything that changes the numbers (material data, code), bad options are
refused before any work with a message naming the option."""

import argparse
import math

import numpy as np
import pytest

from solver.materials import default_materials, load_material_data
from solver.table.fingerprint import file_digest
from solver.apps.cli.parsing import wavelength_range
from solver.table.request import RequestError, table_request, thin_layers_warning


def _cli_request(*argv):
    from solver.apps.cli.build import add_parser, request_from_args

    parser = argparse.ArgumentParser()
    add_parser(parser.add_subparsers())
    return request_from_args(parser.parse_args(["build", *argv, "-o", "unused.npz"]))


class Props(dict):
    """The part of mitsuba.Properties that inkbsdf.source reads."""

    def get(self, name, default=None):
        return self[name] if name in self else default


@pytest.mark.parametrize("ink, particles", [("R30", "molecular"), ("Y7.5+B7.5", "sphere:300")])
def test_every_entry_point_makes_the_same_request(ink, particles):
    from inkbsdf.source import table_request as scene_request

    library = table_request(ink, particles)
    cli = _cli_request("--ink", ink, "--particles", particles)
    scene = scene_request(Props(ink=ink, particles=particles))
    assert library == cli == scene
    assert library.key() == cli.key() == scene.key()
    # the molecular default is one grid everywhere (it used to be 21 λ in scenes, 41 at the CLI)
    if particles == "molecular":
        assert len(library.grids.wavelengths_nm) == 41 and len(library.grids.sigma_rad) == 46
    # the local field the same way from each: default, off, and te's default
    off = table_request(ink, particles, local_field=False)
    assert off == _cli_request("--ink", ink, "--particles", particles, "--no-local-field") \
        == scene_request(Props(ink=ink, particles=particles, local_field=False))
    te = table_request(ink, particles, polarisation="te")
    assert not te.local_field and te == scene_request(Props(ink=ink, particles=particles, polarisation="te")) \
        == _cli_request("--ink", ink, "--particles", particles, "--polarisation", "te")


def test_demo_tables_are_the_cli_tables(tmp_path):
    from inkbsdf.apps.demo_tables import build_tables
    from solver.table import read_table

    table = read_table(build_tables(tmp_path, ["G30"])["G30"])
    assert table.meta["cache_key"] == _cli_request("--ink", "G30").key()


def test_make_tables_rebuilds_demo_tables_of_another_request(tmp_path, capsys):
    """`make tables` keeps a current table, rebuilds one another request (or older code) made."""
    from inkbsdf.apps.demo_tables import DEMO_INKS, build_tables, main
    from solver.table import read_table

    build_tables(tmp_path)
    build_tables(tmp_path, ["R30"], polarisation="te")          # e.g. an old TE-only table
    before = {ink: (tmp_path / f"{ink}.npz").stat().st_mtime_ns for ink in DEMO_INKS}
    assert main([str(tmp_path)]) == 0
    assert "rebuilding" in capsys.readouterr().out
    after = {ink: (tmp_path / f"{ink}.npz").stat().st_mtime_ns for ink in DEMO_INKS}
    assert [ink for ink in DEMO_INKS if after[ink] != before[ink]] == ["R30"]
    assert read_table(tmp_path / "R30.npz").meta["cache_key"] == table_request("R30").key()


def test_key_follows_what_changes_the_numbers():
    base = table_request("Y7.5+B7.5", "sphere:300")
    assert table_request("G30").key() == table_request("Y15+B15").key()          # one material
    assert table_request("G30", "sphere:100").key() != table_request("Y15+B15", "sphere:100").key()
    for other in (table_request("Y7.5+B7.5", "sphere:300", realizations=5),
                  table_request("Y7.5+B7.5", "sphere:300", seed=2),
                  table_request("Y7.5+B7.5", "sphere:300", thickness_nm=900),
                  table_request("Y7.5+B7.5", "sphere:300", polarisation="te"),
                  table_request("Y7.5+B7.5", "sphere:300", accuracy="preview")):
        assert other.key() != base.key()
    assert table_request("Y15/B15").key() != table_request("B15/Y15").key()
    assert table_request("Y15/B15").key() != table_request("Y15+B15").key()


def test_edited_pigment_data_gives_a_new_key(tmp_path):
    text = (tmp_path / "orig.csv")
    from importlib import resources

    text.write_text(resources.files("solver.data").joinpath("pigments_nk.csv").read_text())
    same = load_material_data(text)
    assert same.fingerprint == default_materials().fingerprint
    lines = text.read_text().splitlines()
    row = next(i for i, ln in enumerate(lines) if ln.startswith("550.0,"))
    cols = lines[row].split(",")
    cols[2] = f"{float(cols[2]) * 1.01:.6f}"                  # yellow k at 550 nm, +1 %
    lines[row] = ",".join(cols)
    edited_path = tmp_path / "edited.csv"
    edited_path.write_text("\n".join(lines) + "\n")
    edited = load_material_data(edited_path)
    assert edited.fingerprint != same.fingerprint
    assert table_request("Y30", materials=edited).key() != table_request("Y30", materials=same).key()
    assert table_request("Y30", materials=same).key() == table_request("Y30").key()
    # and the numbers follow the data the request carries
    from solver.table.builder import build_table

    a = build_table(table_request("Y30", materials=same))
    b = build_table(table_request("Y30", materials=edited))
    assert np.max(np.abs(a.Tbar - b.Tbar)) > 0 and b.meta["materials"]["fingerprint"] == edited.fingerprint


def test_code_fingerprint_ignores_docstrings_and_comments(tmp_path):
    code = 'def f(x):\n    """Doc."""\n    return 2 * x  # twice\n'
    paths = {}
    for name, text in (("a", code), ("b", code.replace("Doc.", "Other words.").replace("# twice", "")),
                       ("c", code.replace("2 * x", "3 * x"))):
        paths[name] = tmp_path / f"{name}.py"
        paths[name].write_text(text)
    digest = {k: file_digest(str(p), 0) for k, p in paths.items()}
    assert digest["a"] == digest["b"] != digest["c"]


def test_code_fingerprint_hashes_the_solver_not_its_test_oracles():
    """The wave key covers every solver module a table runs (operator, krylov, …) and leaves out
    the independent references the tests use; leaving them out is safe only because no hashed
    module imports them (checked on the syntax trees)."""
    import ast
    from solver.table.fingerprint import WAVE_MODULES, _source_files

    hashed = [p for name in WAVE_MODULES for p in _source_files(name)]
    names = {p.name for p in hashed if p.parent.name == "wave"}
    assert {"operator.py", "krylov.py", "zkernels.py", "solve.py"} <= names
    assert {"sphere.py", "cylinder.py"} <= {p.name for p in hashed if p.parent.name == "shapes"}   # sub-packages too
    assert not {"oracles.py", "validation.py"} & names
    for path in hashed:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                assert not {"oracles", "validation"} & set((node.module or "").split(".")), path
                assert not {"oracles", "validation"} & {a.name for a in node.names}, path


@pytest.mark.parametrize("kwargs, option", [
    (dict(grid=(1, 1, 1)), "--grid"), (dict(grid=(3, 3, 3)), "--grid"),
    (dict(tolerance=-1.0), "--tolerance"), (dict(tolerance=math.nan), "--tolerance"),
    (dict(solver_tol=0.0), "--solver-tol"), (dict(seed=-1), "--seed"),
    (dict(seed=2**32), r"--seed: give an integer in \[0, 2\^32\), got 4294967296"),
    (dict(realizations=0), "--realizations"), (dict(thickness_nm=math.inf), "--thickness"),
    (dict(thickness_nm=-5.0), "--thickness"), (dict(wavelengths_nm=(300.0, 500.0)), "--wavelengths"),
    (dict(wavelengths_nm=(400.0, 900.0)), "--wavelengths"), (dict(tier="thin-film"), "--tier"),
    (dict(polarisation="circular"), "--polarisation"), (dict(accuracy="ultra"), "--accuracy"),
    (dict(bogus=1), "bogus"),
])
def test_meaningless_settings_are_refused_naming_the_option(kwargs, option):
    with pytest.raises(RequestError, match=option.replace("-", r"\-")):
        table_request("Y7.5+B7.5", "sphere:300", **kwargs)


def test_clear_with_particles_and_molecular_tiers_are_refused():
    with pytest.raises(RequestError, match="clear"):
        table_request("clear", "sphere:100")
    with pytest.raises(RequestError, match="--tier"):
        table_request("R30", tier="full")
    with pytest.warns(UserWarning, match="--grid"):
        table_request("R30", grid=(64, 64, 32))


def test_wavelength_range_refuses_absurd_counts():
    with pytest.raises(RequestError, match="--wavelengths"):
        wavelength_range("400:700:1e-6")
    with pytest.raises(RequestError, match="--wavelengths"):
        wavelength_range("400:nan:10")


def test_stacks_parse_into_layers():
    req = table_request("Y15/B15", thickness_nm=(800.0, 1000.0))
    assert [l.ink.label for l in req.layers] == ["Y15", "B15"]
    assert [l.thickness_nm for l in req.layers] == [800.0, 1000.0] and req.thickness_nm == 1800.0
    with pytest.raises(RequestError, match="--thickness"):
        table_request("Y15/B15", thickness_nm=(800.0, 900.0, 1000.0))


def test_local_field_default_follows_the_polarisation_and_is_in_the_key():
    from solver.materials import local_field_eps

    lf, plain = table_request("G15", "sphere:100"), table_request("G15", "sphere:100", local_field=False)
    te = table_request("G15", "sphere:100", polarisation="te")
    assert lf.local_field and not plain.local_field and not te.local_field     # te: the paper's model
    assert lf.key() != plain.key() and lf.materials == plain.materials          # bulk data, one fingerprint
    assert table_request("G15", "sphere:100", polarisation="te", local_field=True).local_field
    wl = np.array([450.0, 600.0])
    bulk = plain.materials
    binder = bulk.binder_eps(wl)
    # a G grain is the molecular Y–B mix, corrected once as a grain (a sphere: L = 1/3)
    want = local_field_eps(0.5 * (bulk.pigment_eps("Y", wl) + bulk.pigment_eps("B", wl)), binder)
    np.testing.assert_allclose(lf.layer_materials().pigment_eps("G", wl), want, rtol=1e-12)
    np.testing.assert_allclose(plain.layer_materials().pigment_eps("G", wl),
                               0.5 * (bulk.pigment_eps("Y", wl) + bulk.pigment_eps("B", wl)), rtol=1e-12)
    with pytest.raises(RequestError, match="--local-field"):
        table_request("G15", "sphere:100", local_field="yes")
    assert "local-field pigment ε" in lf.describe() and "bulk pigment ε" in plain.describe()
    # nothing to correct without pigment: clear varnish is one table either way
    assert not table_request("clear").local_field
    assert table_request("clear").key() == table_request("clear", local_field=False).key() \
        == table_request("clear", local_field=np.bool_(True)).key()


def test_local_field_of_each_layer_of_a_stack():
    """Every layer gets its own grains' local field; dissolved pigment the Lorentz sphere's."""
    from solver.geometry.depolarisation import local_field_of
    from solver.materials import DISSOLVED_FIELD, SPHERE_FIELD

    req = table_request("Y15/Y15/B15", "cylinder:100:vertical/sphere:100/molecular", grid=(16, 16, 12))
    fields = [req.layer_materials(i).local_field for i in range(3)]
    assert fields[1] == SPHERE_FIELD and fields[2] == DISSOLVED_FIELD
    assert fields[0] == local_field_of(req.layers[0].particles) != SPHERE_FIELD
    wl = np.array([450.0])
    y = [req.layer_materials(i).pigment_eps("Y", wl)[0] for i in range(2)]
    assert y[0] != y[1]


def test_a_thin_layer_is_warned_of_by_the_request_itself_after_validation():
    """Every caller (CLI, scene, figure) gets the warning: table_request is its one home; an
    invalid thickness is refused without it."""
    import warnings

    with pytest.warns(UserWarning, match="--thickness 1: a layer thinner than 50 nm"):
        table_request("Y15/B15", thickness_nm=(1.0, 1000.0))
    assert thin_layers_warning([0.5, 2.0], "--thickness-range").startswith(
        "--thickness-range 0.5, 2: a layer thinner than 50 nm")           # one rule, any option
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        table_request("G30", thickness_nm=50.0)
        with pytest.raises(RequestError, match="--thickness"):
            table_request("G30", thickness_nm=-1.0)


def test_a_thick_film_whose_fringes_the_default_step_misses_is_warned_about():
    """Fringes of a film of thickness d are λ²/(2 n d) apart (n the binder's 1.558): a 20-µm
    varnish's are 2.3 nm apart at 380 nm, so the default 10-nm step aliases its colour (a new
    user's neutral varnish came out with a* 1.8); a print layer's (1 µm: 46 nm) and four
    overprinted process inks' (2.4 µm: 19 nm) are sampled."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table_request("clear", thickness_nm=20000.0)
        thick = [str(w.message) for w in caught]
        caught.clear()
        table_request("clear", thickness_nm=1000.0)
        table_request("clear", thickness_nm=2412.0)      # four process inks overprinted: 19 nm apart
        table_request("clear", thickness_nm=20000.0, wavelengths_nm=tuple(range(380, 781)))   # sampled finely
        assert not caught, [str(w.message) for w in caught]
    assert len(thick) == 1 and "2.32 nm apart at 380 nm" in thick[0] and "--wavelengths 380:780:1)" in thick[0]


def test_fringes_finer_than_any_offered_step_ask_for_a_thinner_layer():
    """A 10-mm 'layer' (µm typed as nm twice): fringes 0.0046 nm apart; no step the warning
    could offer (down to 0.1 nm) resolves them, so it asks for a thinner layer, not a step that
    would not help."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table_request("clear", thickness_nm=1e7)
    said = [str(w.message) for w in caught if "fringes" in str(w.message)]
    assert len(said) == 1 and "0.00463 nm apart" in said[0], said
    assert "use a thinner layer" in said[0] and "--wavelengths" not in said[0], said
