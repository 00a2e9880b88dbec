"""The layered preconditioner (solver/wave/layered.py): a rough top's solves at ≤ 2× the
applications of the flat twin's, to the same answer — in TM with the rough top's mean profile
and its inner interfaces (the tables' TM conditions, wave_tier.tm_faces)."""

import numpy as np
import pytest

from solver.table.request import table_request
from solver.table.wave_tier import GeometryUnit, cell_eps, geometry_unit, nominal_eps, tm_faces
from solver.wave import Cell, prepare, solve_prepared
from solver.wave import layered

GRID = (24, 24, 12)
WAVELENGTH_NM = 740.0          # R15 hardly absorbs here: the slowest convergence of the rough top


def _operator(particles, sigma_deg, polarisation="te"):
    req = table_request("R15", particles, grid=GRID)
    vox = geometry_unit(GeometryUnit(req, 0))
    cell = Cell(cell_eps(req, vox, WAVELENGTH_NM), tuple(vox.period_nm), tuple(vox.z_range_nm))
    k0 = 2 * np.pi / WAVELENGTH_NM
    return prepare(cell, WAVELENGTH_NM, k0 * np.sin(np.radians(sigma_deg)), 0.0,
                   eps_background=nominal_eps(req, WAVELENGTH_NM), eps_face=tm_faces(req, WAVELENGTH_NM, cell.eps),
                   polarisation=polarisation, workers=1)


def _pair(op, preconditioner):
    """Both sides of an incidence (a rough top's table solves both): results, applications."""
    res = [solve_prepared(op, side, preconditioner=preconditioner) for side in (False, True)]
    return res, sum(r.applications for r in res)


@pytest.mark.parametrize("sigma_deg, polarisation", [(0.0, "te"), (45.0, "tm")])
def test_rough_top_within_twice_the_flat_twins_applications(sigma_deg, polarisation):
    flat_op = _operator("sphere:300", sigma_deg, polarisation)
    rough_op = _operator("sphere:300:rough", sigma_deg, polarisation)
    assert not layered.wanted(flat_op) and layered.wanted(rough_op)   # 'auto' picks the rough top only
    if polarisation == "tm":       # the rough top's profile: TM conditions at inner interfaces
        assert rough_op.interfaces is not None and flat_op.interfaces is None
    _, flat = _pair(flat_op, "none")
    plain_res, plain = _pair(rough_op, "none")
    pre_res, pre = _pair(rough_op, "auto")
    assert pre <= 2 * flat, (pre, flat)
    assert pre < 0.75 * plain, (pre, plain)
    # the same solution of the same equation: results within the solver's tolerance
    for a, b in zip(plain_res, pre_res):
        for name in ("R", "T", "R_spec", "T_coh", "absorbed"):
            assert abs(getattr(a, name) - getattr(b, name)) < 3e-4, name
        assert b.converged and b.residual <= 1e-3 and abs(b.energy_error) < 1e-3


def test_preconditioner_changes_no_answer_on_a_flat_layer():
    """Forced onto a cell where it brings nothing, the left preconditioner still solves the
    cell's own equation (P⁻¹A w = P⁻¹b has the solution of A w = b whatever P is)."""
    op = _operator("sphere:300", 45.0)
    a = solve_prepared(op, tol=1e-6, preconditioner="none")
    b = solve_prepared(op, tol=1e-6, preconditioner="layered")
    for name in ("R", "T", "R_spec", "T_coh"):
        assert abs(getattr(a, name) - getattr(b, name)) < 1e-5, name
    with pytest.raises(ValueError, match="preconditioner"):
        solve_prepared(op, preconditioner="ilu")


@pytest.mark.parametrize("dtype", [np.complex64, np.complex128])
def test_the_true_residual_from_the_arnoldi_relation_is_the_explicit_one(dtype):
    """The layered solve's residual (the convergence test and the energy closure read it) is P
    times GMRES's preconditioned residual, not an explicit b − (I − GV)w: the two agree to
    rounding, and the solve meets its tolerance in the explicit one."""
    from solver.wave.operator import Workspace, system_zmajor, to_zmajor
    from solver.wave.solve import _layered_gmres, source

    req = table_request("R15", "sphere:300:rough", grid=GRID)
    vox = geometry_unit(GeometryUnit(req, 0))
    cell = Cell(cell_eps(req, vox, WAVELENGTH_NM), tuple(vox.period_nm), tuple(vox.z_range_nm))
    k0 = 2 * np.pi / WAVELENGTH_NM
    op = prepare(cell, WAVELENGTH_NM, k0 * np.sin(np.radians(30.0)), 0.0,
                 eps_background=nominal_eps(req, WAVELENGTH_NM), eps_face=tm_faces(req, WAVELENGTH_NM, cell.eps),
                 polarisation="tm", workers=1, dtype=dtype)
    ws = Workspace(op)
    try:
        for below in (False, True):
            b = to_zmajor(source(op, below), op.fft)
            tol = 1e-3 if dtype == np.complex64 else 1e-8
            out = _layered_gmres(op, b, ws, tol=tol, maxiter=300, restart=60, x0=None, callback=None)
            explicit = b - system_zmajor(op, out.x, ws)
            bnorm = np.linalg.norm(b.ravel())
            gap = np.linalg.norm((explicit - out.residual_vector).ravel()) / bnorm
            assert gap < (1e-5 if dtype == np.complex64 else 1e-12), gap
            assert out.converged and np.linalg.norm(explicit.ravel()) / bnorm <= tol * (1 + 1e-2)
    finally:
        ws.release()
