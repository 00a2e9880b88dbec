"""Not converged is not a result (issue 22 item 4): solve() raises short of its tolerance, a
table's solve climbs the ladder of stronger settings (solver/table/retry.py) and otherwise
refuses the cell with the reason; a sweep of random hard cells returns no iterate whose explicit
residual (recomputed in complex128, not the solver's estimate) exceeds the tolerance."""
from __future__ import annotations

import numpy as np
import pytest

from solver.table.retry import LADDER, Attempt, SolveRefused, converged_solve
from solver.wave import Incidence, WaveSolverError, bloch_vector, prepare, solve
from solver.wave.validation import explicit_residual, hard_cells, random_layer
from conftest import run_main


def _stagnating(shape=(12, 12, 6)):
    """Lossless n = 3 spheres at 30 % (issue 22): GMRES(60) stagnates, BiCGStab blows up."""
    cell = random_layer(3.0, fraction=0.3, shape=shape)
    kx0, ky0 = bloch_vector(cell, Incidence(500.0, 0.3))
    return cell, lambda dtype=np.complex64: prepare(cell, 500.0, kx0, ky0, dtype=dtype)


def test_the_ladder_converges_the_stagnating_cell():
    """Rung 0 (the default GMRES(60)) stagnates; rung 1 (GMRES without restarts, complex128,
    tol/10) converges: a lossless layer then conserves energy."""
    _, make_op = _stagnating()
    res, rung, apps = converged_solve(make_op, False, tol=1e-3, where="the stagnating cell")
    assert rung == 1 and res.converged and res.method == "gmres"
    assert res.residual <= 1e-4 and apps > res.applications      # rung 0's applications counted
    assert abs(res.R + res.T - 1) < 5e-3                          # lossless (δ artefact ~1e-3)


def test_a_cell_no_rung_converges_is_refused_with_every_attempt():
    _, make_op = _stagnating()
    short = (Attempt("auto", 40, None, np.complex64), Attempt("bicgstab", 40, None, np.complex64))
    with pytest.raises(SolveRefused, match="no converged solve for the stagnating cell") as err:
        converged_solve(make_op, False, tol=1e-3, where="the stagnating cell", ladder=short)
    msg = str(err.value)
    assert "table refused" in msg and "auto, complex64, tol 0.001, ≤ 40 applications" in msg
    assert "bicgstab" in msg and msg.count("stopped at relative residual") == 2


def test_the_default_ladder_is_stronger_rung_by_rung():
    """Each rung allows at least as many applications, as fine a dtype and as tight a
    tolerance as the one before, and the first rung is the solver's default."""
    assert LADDER[0] == Attempt("auto", 500, None, np.complex64, 1.0)
    for a, b in zip(LADDER, LADDER[1:]):
        assert b.maxiter >= a.maxiter and b.tol_factor <= a.tol_factor
        assert np.dtype(b.dtype).itemsize >= np.dtype(a.dtype).itemsize
    assert {a.method for a in LADDER} >= {"auto", "gmres", "bicgstab"}


def test_sweep_of_hard_cells_returns_no_unconverged_result():
    """24 random hard cells (n 1–3.5, k 0–1.5, 5–50 %, σ 0–85°, λ 380–780, TE/TM) with a
    budget of 40 applications, so that some must fail: every returned result's explicit
    residual is within its tolerance, every other one raised."""
    tol, returned, refused = 1e-3, 0, 0
    for case in hard_cells(24, shape=(8, 8, 4)):
        try:
            res = solve(case.cell, case.incidence, polarisation=case.polarisation, maxiter=40,
                        tol=tol)
        except WaveSolverError:
            refused += 1
            continue
        returned += 1
        assert res.converged and explicit_residual(case, res) <= tol * 1.001, case.describe()
        assert abs(res.energy_error) <= 1e-3, case.describe()
    assert returned >= 10 and refused >= 3           # the sweep exercises both outcomes


def _tiny_request():
    from solver.table.request import table_request

    return table_request("Y7.5+B7.5", "sphere:300", wavelengths_nm=(450.0, 700.0),
                         sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])), grid=(8, 8, 4),
                         realizations=1, azimuths=2, dphi_count=5, tier="full")


def _opts(tmp_path):
    from solver.table.builder import BuildOptions
    from solver.table.cache import TableCache

    return BuildOptions(progress=False, cache=TableCache(tmp_path / "cache"), workers=1)


def test_a_table_retries_a_failed_solve_and_records_it(tmp_path, monkeypatch):
    """A first rung that cannot converge (1 application) is retried on the next: the table
    equals the one built without retries, and its meta counts every retried solve."""
    from solver.table import retry
    from solver.table.builder import build_table

    plain = build_table(_tiny_request(), _opts(tmp_path / "a"))
    assert plain.meta["solver_stats"]["solves_retried"] == 0
    monkeypatch.setattr(retry, "LADDER", (Attempt("auto", 1, None, np.complex64),) + LADDER[:1])
    again = build_table(_tiny_request(), _opts(tmp_path / "b"))
    stats = again.meta["solver_stats"]
    assert stats["solves_retried"] == stats["solves"] == 8        # 2 λ × 2 σ × (TE, TM)
    for name in ("R", "R_spec", "Rbar", "Tbar"):
        np.testing.assert_array_equal(getattr(again, name), getattr(plain, name))


def test_a_table_refuses_a_cell_no_rung_converges(tmp_path, monkeypatch, capsys):
    """Refused with the reason (which solve, every attempt), nothing cached as a result; the
    command line says it in one line."""
    from solver.apps.cli import main
    from solver.table import retry
    from solver.table.builder import get_or_build

    monkeypatch.setattr(retry, "LADDER", (Attempt("auto", 2, None, np.complex64),))
    opts = _opts(tmp_path)
    with pytest.raises(SolveRefused, match=r"no converged solve for Y7.5\+B7.5.*λ 450 nm, σ 0°.*"
                                           r"table refused: auto, complex64"):
        get_or_build(_tiny_request(), opts)
    assert opts.cache.load(_tiny_request()) is None
    status, out, err = run_main(main, ["build", "--ink", "Y7.5+B7.5", "--particles", "sphere:300",
                                       "--wavelengths", "450:700:250", "--angles", "3", "--grid", 8, 8, 4,
                                       "--realizations", 1, "--azimuths", 2, "--tier", "full",
                                       "--workers", 1, "-o", tmp_path / "t.npz"], capsys)
    assert status == 1 and "error: no converged solve for" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1 and not (tmp_path / "t.npz").exists()
