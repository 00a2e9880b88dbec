"""Pair separations of parallel cylinders (exact) and the linearised contact solve of the packer."""

import numpy as np
import pytest

from solver.geometry.contact_solve import BodyRows, Contacts, solve_contacts, wall_rows
from solver.geometry.bodies import Bodies
from solver.geometry.contacts import separation
from solver.geometry.separating_axis import support_gap
from solver.geometry.shapes.cylinder import Cylinder

CYLINDER = Cylinder()


def test_parallel_cylinders_are_separated_exactly():
    """Parallel cylinders differ by a cylinder of radius r_i + r_j and half length h_i + h_j:
    the signed distance of d to it is written out here independently, and a brute-force
    maximisation of the separating-axis gap over 40 000 directions never beats the library."""
    rng = np.random.default_rng(3)
    n = 2000
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    axis *= np.sign(axis[2])
    r, h = rng.uniform(10, 40, 2 * n), rng.uniform(20, 120, 2 * n)
    bodies = Bodies(CYLINDER, r, h, np.tile(axis, (2 * n, 1)))
    d = rng.normal(size=(n, 3)) * rng.uniform(0, 200, (n, 1))
    centres = np.concatenate([np.full((n, 3), 5000.0), 5000.0 + d])
    sep = separation(bodies, centres, np.arange(n), np.arange(n, 2 * n), (1e5, 1e5), margin_nm=1e9)
    z = np.abs(d @ axis)
    rho = np.linalg.norm(d - np.outer(d @ axis, axis), axis=1)
    big_r, big_h = r[:n] + r[n:], h[:n] + h[n:]
    outside = (rho > big_r) & (z > big_h)
    exact = np.where(outside, np.hypot(rho - big_r, z - big_h), np.maximum(rho - big_r, z - big_h))
    assert np.abs(sep.gap_nm - exact).max() < 1e-9
    assert (outside.sum() > 100) and ((exact < 0).sum() > 100)
    dirs = rng.normal(size=(40000, 3))
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    for p in range(0, n, 40):
        brute = support_gap(CYLINDER.width, dirs[None], d[p][None], axis[None], axis[None], r[p:p + 1], r[n + p:n + p + 1],
                            h[p:p + 1], h[n + p:n + p + 1]).max()
        assert brute <= sep.gap_nm[p] + 1e-9


def sphere_gaps(c, r, i, j):
    return np.linalg.norm(c[j] - c[i], axis=1) - r[i] - r[j]


def test_contact_solve_separates_overlapping_spheres():
    """For translations the linearised gap n·(c_j − c_i) − r_i − r_j is a lower bound of the new
    distance, so after the solve every pair is at least target − tolerance apart, exactly."""
    rng = np.random.default_rng(11)
    n = 400
    c = rng.uniform(0, 260, size=(n, 3))
    r = rng.uniform(8, 12, n)
    i, j = np.triu_indices(n, 1)
    gap = sphere_gaps(c, r, i, j)
    near = gap < 3.0
    i, j = i[near], j[near]
    d = c[j] - c[i]
    normal = d / np.linalg.norm(d, axis=1)[:, None]
    assert (gap[near] < -2.0).sum() > 100
    target = 0.5
    empty = BodyRows(np.zeros(0, dtype=int), np.zeros((0, 3)), None, np.zeros(0))
    moves = solve_contacts(Contacts(i, j, normal, gap[near]), empty, 1.0 / r**3, None, target, sweeps=3000,
                           tolerance_nm=1e-3)
    assert moves.residual_nm <= 1e-3
    after = sphere_gaps(c + moves.shift_nm, r, i, j)
    assert after.min() >= target - 1e-3 - 1e-6
    # Minimal moves: nothing moves far, untouched spheres do not move at all.
    assert np.abs(moves.shift_nm).max() < 20.0
    alone = np.setdiff1d(np.arange(n), np.concatenate([i, j]))
    assert np.all(moves.shift_nm[alone] == 0.0)


def test_contact_solve_respects_the_walls():
    """A sphere pressed against a wall by its neighbour moves sideways or the neighbour moves:
    the wall row keeps the centre in its allowed range."""
    c = np.array([[0.0, 0.0, 10.0], [3.0, 0.0, 25.0]])
    r = np.array([10.0, 10.0])
    d = c[1] - c[0]
    normal = (d / np.linalg.norm(d))[None]
    gap = np.array([np.linalg.norm(d) - r.sum()])
    lo, hi = np.array([10.0, 10.0]), np.array([90.0, 90.0])
    walls = wall_rows(c[:, 2], lo, hi, 1.0)
    moves = solve_contacts(Contacts(np.array([0]), np.array([1]), normal, gap), walls, np.ones(2), None, 0.0,
                           sweeps=2000, tolerance_nm=1e-6)
    new = c + moves.shift_nm
    assert new[0, 2] >= 10.0 - 1e-4
    assert np.linalg.norm(new[1] - new[0]) >= 20.0 - 1e-4


def test_contact_solve_with_candidate_rows_and_no_wall_rows():
    """Kink rows that join only when violated (primary False) and no one-particle rows at all
    (in-plane rods of an agglutinated layer away from the walls): the active-set round still
    solves, and the row that joins is satisfied too."""
    normal = np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    lever = np.array([[0.0, 0.0, 5.0], [0.0, 0.0, -5.0]])
    rows = Contacts(np.array([0, 0]), np.array([1, 1]), normal, np.array([-2.0, -4.0]), lever, -lever,
                    primary=np.array([True, False]))
    empty = BodyRows(np.zeros(0, dtype=int), np.zeros((0, 3)), None, np.zeros(0))
    moves = solve_contacts(rows, empty, np.ones(2), np.full(2, 0.01), 0.5, sweeps=2000, tolerance_nm=1e-4)
    assert moves.residual_nm <= 1e-3
    du = moves.shift_nm[1] - moves.shift_nm[0]
    for k in range(2):
        predicted = rows.gap_nm[k] + normal[k] @ du + lever[k] @ (-moves.turn[1] - moves.turn[0])
        assert predicted >= 0.5 - 1e-3


@pytest.mark.parametrize("seed", [0, 1])
def test_linearised_rotation_rows_predict_small_turns(seed):
    """In-plane rods turning about z: the candidate rows (both ends of a side contact) bound the
    true separating-axis gap after a small turn from below, to second order."""
    from solver.geometry.motion import contact_rows, turn_axes

    rng = np.random.default_rng(seed)
    n = 200
    phi = rng.uniform(0, 2 * np.pi, 2 * n)
    axes = np.stack([np.cos(phi), np.sin(phi), np.zeros(2 * n)], axis=1)
    bodies = Bodies(CYLINDER, np.full(2 * n, 10.0), np.full(2 * n, 30.0), axes)
    d = rng.normal(size=(n, 3)) * np.array([40.0, 40.0, 5.0])
    xyz = np.concatenate([np.zeros((n, 3)), d]).T.copy()
    i, j = np.arange(n), np.arange(n, 2 * n)
    sep = separation(bodies, xyz.T, i, j, (1e5, 1e5), margin_nm=1e9)
    rows = contact_rows(bodies, xyz, i, j, sep.normal, sep.gap_nm, (1e5, 1e5), "z")
    turn = np.zeros((2 * n, 3))
    turn[:, 2] = rng.uniform(-0.02, 0.02, 2 * n)
    moved = bodies.turned(turn_axes(axes, turn, "z"))
    # g(n) at the same normal after the turn, from the support function (no search).
    g_after = support_gap(CYLINDER.width, sep.normal[:, None, :], d, moved.axes[i], moved.axes[j], moved.radii_nm[i],
                          moved.radii_nm[j], moved.half_lengths_nm[i], moved.half_lengths_nm[j])[:, 0]
    predicted = rows.gap_nm - np.einsum("pc,pc->p", rows.lever_i, turn[rows.i]) + \
        np.einsum("pc,pc->p", rows.lever_j, turn[rows.j])
    worst_row = np.full(n, np.inf)
    np.minimum.at(worst_row, rows.i, predicted)
    second_order = 0.5 * 0.02**2 * 2 * (30.0 + 10.0)            # |Δ| ≤ ½ w² (h + r) per body
    assert np.all(g_after >= worst_row - second_order - 1e-9)
