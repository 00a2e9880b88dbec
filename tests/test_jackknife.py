"""The jackknife over a wave table's realizations (solver/table/jackknife.py) and the colour's
standard error from it (solver/colour/table_colour.py; docs/figures.md "The colour's standard
error")."""

import dataclasses

import numpy as np
import pytest

from conftest import diffuse_layer_table
from solver.colour import measurement as M
from solver.colour.table_colour import table_colour, transmitted_colour
from solver.table import jackknife
from solver.table.builder import BuildOptions, build_table
from solver.table.cache import TableCache
from solver.table.integrals import diffuse_albedo
from solver.table.request import table_request
from solver.table.schema import JACKKNIFE_COLUMNS, TableError, read_table, validate, write_table
from solver.table.wave_ensemble import reduce_units


def test_jackknife_of_a_mean_is_the_standard_error_of_the_mean():
    """For a mean the leave-one-out formula is exactly s/√N (the textbook identity)."""
    x = np.random.default_rng(3).normal(size=(5, 7))
    loo = np.array([rest for rest in (np.mean(r, axis=0) for r in jackknife.leave_one_out(list(x)))])
    np.testing.assert_allclose(jackknife.standard_error(loo), x.std(axis=0, ddof=1) / np.sqrt(5), rtol=1e-12)
    with pytest.raises(ValueError, match="at least 2"):
        jackknife.leave_one_out([x[0]])


def test_stratified_jackknife_of_a_mean_of_group_means_is_its_standard_error():
    """TE and TM on separate cells (6 realizations alternating): the quantity is the mean of the
    two groups' means, whose variance is s_TE²/(4 n_TE) + s_TM²/(4 n_TM); the stratified
    jackknife gives exactly that, with N − 2 degrees of freedom (the pooled form would not)."""
    rng = np.random.default_rng(5)
    x = rng.normal(size=(6, 4)) * np.array([1.0, 2.0, 0.5, 3.0])
    groups = [0, 1, 0, 1, 0, 1]
    g = np.asarray(groups)
    theta = lambda rows, gs: 0.5 * (rows[gs == 0].mean(axis=0) + rows[gs == 1].mean(axis=0))
    loo = np.array([theta(np.delete(x, k, axis=0), np.delete(g, k)) for k in range(6)])
    exact = np.sqrt(sum(x[g == p].var(axis=0, ddof=1) / (4 * 3) for p in (0, 1)))
    np.testing.assert_allclose(jackknife.standard_error(loo, groups), exact, rtol=1e-12)
    assert not np.allclose(jackknife.standard_error(loo), exact, rtol=0.05)
    assert jackknife.degrees_of_freedom(6, groups) == 4 and jackknife.degrees_of_freedom(6) == 5
    with pytest.raises(ValueError, match="each group"):
        jackknife.standard_error(loo[:3], [0, 1, 0])


def test_the_colour_reads_only_jackknife_columns():
    assert set(M.REFLECTANCE_COLUMNS) <= set(JACKKNIFE_COLUMNS)


def _ensemble(base, rng, n, lobe=True):
    """n synthetic realizations of `base`: every column the colour reads perturbed by a part
    shared by all λ and σ (the same random cell) and by node-wise noise; R's noise (lobe) moves
    power between neighbouring θ bins (anti-correlated, as diffraction orders do)."""
    out = []
    for _ in range(n):
        shared = rng.normal(size=3)
        cols = {
            "Tbar": base.Tbar * (1.0 + 0.03 * shared[0] + 0.02 * rng.normal(size=base.Tbar.shape)),
            "Rbar_below": base.Rbar_below * (1.0 + 0.03 * shared[1] + 0.02 * rng.normal(size=base.Rbar.shape)),
            "R_spec": base.R_spec * (1.0 + 0.05 * rng.normal(size=base.R_spec.shape)),
        }
        swing = 0.3 * rng.normal(size=base.R.shape[:3] + (1,)) * np.where(np.arange(base.R.shape[2]) % 2, 1.0, -1.0)[
            None, None, :, None]
        cols["R"] = base.R * (1.0 + 0.05 * shared[2] + swing) if lobe else base.R
        out.append(cols)
    return out


def _table_of(base, realizations):
    mean = {k: np.mean([r[k] for r in realizations], axis=0) for k in realizations[0]}
    mean["Rbar"] = mean["R_spec"] + diffuse_albedo(base.theta, base.dphi, mean["R"])    # the schema's identity
    return dataclasses.replace(base, **mean)


def test_jackknife_colour_se_matches_the_spread_of_synthetic_ensembles():
    """Known variance: many ensembles of 4 synthetic realizations; the spread of their colour
    across ensembles is the truth, and the jackknife's SE (root mean square over the
    ensembles) agrees with it within the sampling noise (400 ensembles: ≈ 4 % on each)."""
    base = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    rng = np.random.default_rng(11)
    labs, se2, methods = [], [], set()
    for _ in range(400):
        real = _ensemble(base, rng, 4)
        table = jackknife.attach(_table_of(base, real), [_table_of(base, rest) for rest in jackknife.leave_one_out(real)])
        colour = table_colour(table, 0.9)
        labs.append(colour.lab)
        se2.append(colour.se ** 2)
        methods.add((colour.method, colour.dof))
    assert methods == {("jackknife", 3.0)}
    truth = np.std(labs, axis=0, ddof=1)
    np.testing.assert_allclose(np.sqrt(np.mean(se2, axis=0)), truth, rtol=0.12)
    assert np.all(truth > 0.05)            # the test can fail: the spread is well resolved


def test_transmitted_colour_uses_the_jackknife():
    base = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    real = _ensemble(base, np.random.default_rng(2), 3)
    table = jackknife.attach(_table_of(base, real), [_table_of(base, rest) for rest in jackknife.leave_one_out(real)])
    through = transmitted_colour(table)
    labs = [M.DEFAULT.lab_of_spectra(base.wavelengths, r["Tbar"][:, 0]) for r in real]
    assert through.method == "jackknife"
    # a colour of three realizations: its jackknife SE is about the SE of the mean of their colours
    np.testing.assert_allclose(through.se, np.std(labs, axis=0, ddof=1) / np.sqrt(3), rtol=0.05)


def test_tables_without_jackknife_load_and_keep_the_propagated_bound(tmp_path):
    """An old table (no `_jack` arrays: exactly what the previous writer wrote) reads with
    jackknife None and its colour's SE is the propagated bound; one with them round-trips
    (float32) and gives the same colour SE."""
    base = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    real = _ensemble(base, np.random.default_rng(5), 3, lobe=False)       # R reciprocal, as a table's
    table = jackknife.attach(_table_of(base, real), [_table_of(base, rest) for rest in jackknife.leave_one_out(real)])
    errors = {k: np.std([r[k] for r in real], axis=0, ddof=1) / np.sqrt(3) for k in ("R_spec", "Tbar", "Rbar_below", "R")}
    old = dataclasses.replace(table, jackknife=None, errors=errors, meta=dict(table.meta, tier="full", realizations_used=3))
    path = write_table(tmp_path / "old.npz", old)
    with np.load(path) as npz:
        assert not any(k.endswith("_jack") for k in npz.files)
    back = read_table(path)
    assert back.jackknife is None and table_colour(back, 0.9).method == "propagated"
    new = read_table(write_table(tmp_path / "new.npz", dataclasses.replace(old, jackknife=table.jackknife)))
    assert set(new.jackknife) == set(JACKKNIFE_COLUMNS) and new.jackknife["R"].dtype == np.float32
    np.testing.assert_array_equal(new.jackknife["Tbar"], table.jackknife["Tbar"])
    np.testing.assert_allclose(table_colour(new, 0.9).se, table_colour(table, 0.9).se, rtol=1e-5)


def test_bad_jackknife_arrays_are_refused():
    table = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    one = {"Tbar": table.Tbar[None].astype(np.float32)}
    with pytest.raises(TableError, match="replica count ≥ 2"):
        validate(dataclasses.replace(table, jackknife=one))
    with pytest.raises(TableError, match="'Tbar_jack' has shape"):
        validate(dataclasses.replace(table, jackknife={"Tbar": np.zeros((2, 3), np.float32)}))
    with pytest.raises(TableError, match="unknown jackknife column 'T_s_jack'"):
        validate(dataclasses.replace(table, jackknife={"T_s": np.zeros((2,) + table.Tbar.shape)}))


def test_a_built_table_holds_its_refined_leave_one_out_ensembles(tmp_path):
    """A strided build of 3 realizations: each replica at the solved wavelengths is, bit for
    bit (float32), the reduction of the other two realizations' units; the replicas are
    refined between them like the table (film-guided, not linear); the jackknife of a mean
    column is its stored standard error (computed by another path); the table validates
    (energy, schema) and its colour's SE is the jackknife's."""
    base = dict(wavelengths_nm=(380.0, 480.0, 580.0, 680.0, 780.0), sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])),
                grid=(16, 16, 8), realizations=3, azimuths=2, dphi_count=7, tier="full")
    cache = TableCache(tmp_path / "cache")
    request = table_request("Y7.5+B7.5", "sphere:300", wavelength_stride=2, **base)
    table = validate(build_table(request, BuildOptions(progress=False, cache=cache, workers=1)))
    solved = list(request.solved_wavelength_indices)
    assert solved == [0, 2, 4] and table.meta["solved_wavelengths_nm"] == [380.0, 580.0, 780.0]
    assert {k: v.shape[0] for k, v in table.jackknife.items()} == {k: 3 for k in JACKKNIFE_COLUMNS}
    coarse = request.with_grids(wavelengths_nm=(380.0, 580.0, 780.0))
    units = [[cache.load_part(request, f"full_r{r}_l{li}") for li in solved] for r in range(3)]
    meta = {"schema_version": 2, "polarisation": request.polarisation}
    for k, rest in enumerate(jackknife.leave_one_out(units)):
        own = reduce_units(coarse, rest, meta)
        for name in JACKKNIFE_COLUMNS:
            np.testing.assert_array_equal(table.jackknife[name][k][solved], own.column(name).astype(np.float32))
        # between the solved wavelengths: refined, not a plain linear interpolation
        linear = 0.5 * (own.Tbar[0] + own.Tbar[1])
        assert np.max(np.abs(table.jackknife["Tbar"][k][1] - linear)) > 1e-3
    for name in ("Rbar", "Tbar", "Rbar_below"):
        np.testing.assert_allclose(jackknife.standard_error(table.jackknife[name][:, solved]),
                                   table.errors[name][solved], rtol=1e-3, atol=1e-6)
    colour = table_colour(table, 0.9)
    assert colour.method == "jackknife" and colour.dof == 2.0 and np.all(colour.se > 0)


def test_the_csv_records_the_method_and_reads_csvs_without_it(tmp_path):
    """se_method goes to the figures' CSV; a CSV of an earlier version (no such column) still
    reads, with the method unrecorded ("")."""
    import csv

    from solver.apps.figures.records import FIELDS, CellRecord, read_csv, write_csv

    lab = np.array([50.0, 10.0, 5.0])
    rec = CellRecord("fig7", "default", "B30", "cylinder:200:inplane", "c", "c", None, "preview", "full", "ok",
                     "45:0/D50/2°", lab, np.full(3, 0.5), "realizations", 1.0, lab, np.full(3, 0.2), "k", False,
                     1.0, se_method="jackknife")
    path = write_csv([rec], tmp_path / "new.csv")
    assert read_csv(path)[0].se_method == "jackknife"
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    old = tmp_path / "old.csv"
    with open(old, "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, [k for k in FIELDS if k != "se_method"], extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    back = read_csv(old)[0]
    assert back.se_method == "" and back.se_source == "realizations" and back.se_dof == 1.0


def test_show_names_how_the_colour_se_is_known():
    from solver.apps.cli.show import colour_lines

    base = diffuse_layer_table(lossless=False, n_lambda=9, n_angle=6)
    real = _ensemble(base, np.random.default_rng(4), 3)
    table = jackknife.attach(_table_of(base, real), [_table_of(base, rest) for rest in jackknife.leave_one_out(real)])
    line = colour_lines(table, 0.9, M.DEFAULT)[-1]
    assert line.startswith("  standard error of the * colour: L* ")
    assert "(jackknife over 3 realizations: 2 degrees of freedom)" in line
    assert "unknown (one realization)" in colour_lines(base, 0.9, M.DEFAULT)[-1]


def test_show_says_the_strata_and_counts_degrees_right():
    """Six cells, TE and TM on separate ones: 4 degrees of freedom, and the line says why."""
    from types import SimpleNamespace

    from solver.apps.cli.show import se_text

    colour = SimpleNamespace(method="jackknife", se=np.array([0.2, 0.35, 0.29]), dof=4.0, source="realizations")
    line = se_text(colour, 6, [0, 1, 0, 1, 0, 1])
    assert line.endswith("(jackknife over 6 realizations, stratified 3 TE + 3 TM cells: 4 degrees of freedom)")
    assert "1 degree of freedom)" in se_text(SimpleNamespace(method="jackknife", se=np.zeros(3), dof=1.0), 2)
