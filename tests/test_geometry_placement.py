"""Placement: concentrations, no overlaps (checked independently), periodicity, orientations,
agglutination, rough top, reproducibility."""

import dataclasses

import numpy as np
import pytest
from scipy.stats import kstest

from solver.geometry import LayerSpec, cluster_statistic, find_overlaps, generate, pair_correlation, parse_particles
from solver.geometry.bodies import Bodies
from solver.geometry.contacts import separation
from solver.geometry.orientation import sample_orientations
from solver.geometry.separating_axis import support_gap
from solver.geometry.shapes.cylinder import Cylinder
from solver.geometry.statistics import wall_violations
from solver.geometry.surface import binder_surface_nm
from solver.inks import parse_ink

CELL = (1000.0, 1000.0)


def make(ink, particles, seed=1, thickness=1000.0, cell=CELL):
    return generate(LayerSpec(parse_ink(ink), parse_particles(particles), thickness, cell), seed)


@pytest.fixture(scope="module")
def cases():
    """Realizations shared by the tests below (the slow part is built once)."""
    return {
        "sphere15": make("Y7.5+B7.5", "sphere:100", cell=(2000.0, 2000.0)),
        "sphere50": make("B50", "sphere:100"),
        "small50": make("R50", "sphere:30", thickness=300.0, cell=(600.0, 600.0)),
        "spread": make("Y25+B5", "sphere:100:spread=0.25"),
        "iso": make("B30", "cylinder:100:isotropic"),
        "inplane": make("B30", "cylinder:100:inplane"),
        "vertical": make("B30", "cylinder:100:vertical"),
        "iso_dilute": make("Y7.5+B7.5", "cylinder:100:isotropic", cell=(2000.0, 2000.0)),
        "inplane_dilute": make("Y7.5+B7.5", "cylinder:100:inplane", cell=(2000.0, 2000.0)),
        "rough": make("G30", "sphere:300:rough", cell=(2000.0, 2000.0)),
    }


def independent_volume(real):
    r, length = real.radii_nm, real.lengths_nm
    return np.where(length > 0, np.pi * r**2 * length, 4.0 / 3.0 * np.pi * r**3)


@pytest.mark.parametrize("name", ["sphere15", "sphere50", "small50", "spread", "iso", "inplane", "vertical",
                                  "rough"])
def test_achieved_fraction_within_one_percent(cases, name):
    real = cases[name]
    cell_volume = real.layer.cell_nm[0] * real.layer.cell_nm[1] * real.layer.thickness_nm
    vol = independent_volume(real)
    for code, target in real.layer.ink.components:
        achieved = vol[real.pigments == code].sum() / cell_volume
        assert abs(achieved / target - 1) < 0.01, (code, achieved, target)
    assert set(real.pigments) == {c for c, _ in real.layer.ink.components}


def test_size_spread_is_log_normal_about_the_median(cases):
    d = cases["spread"].effective_diameters_nm
    assert abs(np.median(d) / 100.0 - 1) < 0.05
    assert 0.2 < np.std(np.log(d)) < 0.3


def min_image(d, period):
    d = d.copy()
    for k in (0, 1):
        d[..., k] -= period[k] * np.round(d[..., k] / period[k])
    return d


@pytest.mark.parametrize("name", ["sphere15", "sphere50", "small50", "spread", "rough"])
def test_spheres_do_not_overlap_brute_force(cases, name):
    real = cases[name]
    c, r = real.centres_nm, real.radii_nm
    worst = np.inf
    for a in range(0, len(c), 500):
        d = min_image(c[None, :, :] - c[a:a + 500, None, :], real.period_nm)
        gap = np.linalg.norm(d, axis=-1) - r[None, :] - r[a:a + 500, None]
        gap[np.arange(len(gap)), np.arange(a, a + len(gap))] = np.inf
        worst = min(worst, gap.min())
    assert worst >= 0.0
    assert len(find_overlaps(real)) == 0
    assert len(wall_violations(real)) == 0


def cylinder_points(centre, axis, radius, half, shrink=0.0, n_len=15, n_ring=24, n_rad=5):
    """Points filling a cylinder (shrunk by `shrink` nm) — an independent sampling of it."""
    e = np.eye(3)[np.argmin(np.abs(axis))]
    u = np.cross(axis, e)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    t = np.linspace(-half + shrink, half - shrink, n_len)
    rho = np.linspace(0.0, radius - shrink, n_rad)
    ang = 2 * np.pi * np.arange(n_ring) / n_ring
    T, R, A = np.meshgrid(t, rho, ang, indexing="ij")
    pts = (T[..., None] * axis + R[..., None] * (np.cos(A)[..., None] * u + np.sin(A)[..., None] * v))
    return centre + pts.reshape(-1, 3)


def inside_cylinder(points, centre, axis, radius, half):
    d = points - centre
    t = d @ axis
    return (np.abs(t) <= half) & (np.sum(d * d, axis=1) - t * t <= radius * radius)


@pytest.mark.parametrize("name", ["iso", "inplane", "vertical"])
def test_cylinders_do_not_overlap(cases, name):
    """Every pair is certified apart by the library (gap >= 0), and for the 150 closest pairs,
    independently: (1) sample points of the two cylinders project to disjoint intervals on the
    returned separating axis (checked from points, not from the support formula); (2) no point
    of one cylinder shrunk by 0.5 nm lies in the other shrunk by 0.5 nm (9 × 16 × 3 points)."""
    real = cases[name]
    assert len(find_overlaps(real)) == 0
    assert len(wall_violations(real)) == 0
    c, a, r, h = real.centres_nm, real.axes, real.radii_nm, 0.5 * real.lengths_nm
    reach = 2 * np.hypot(r, h).max()
    i, j = np.triu_indices(len(c), 1)
    d = min_image(c[j] - c[i], real.period_nm)
    close = np.linalg.norm(d, axis=1) < reach
    i, j, d = i[close], j[close], d[close]
    sep = separation(real.bodies, c, i, j, real.period_nm)
    assert np.all(sep.gap_nm >= 0)
    for p in np.argsort(sep.gap_nm)[:150]:                       # the closest pairs
        pi_ = cylinder_points(np.zeros(3), a[i[p]], r[i[p]], h[i[p]])
        pj = cylinder_points(d[p], a[j[p]], r[j[p]], h[j[p]])
        n = sep.normal[p]
        assert (pi_ @ n).max() <= (pj @ n).min() + 1e-6
        shrunk = cylinder_points(d[p], a[j[p]], r[j[p]], h[j[p]], shrink=0.5, n_len=9, n_ring=16, n_rad=3)
        assert not inside_cylinder(shrunk, np.zeros(3), a[i[p]], r[i[p]] - 0.5, h[i[p]] - 0.5).any()


def test_separating_axis_search_agrees_with_point_sampling():
    """The cylinder separation never certifies an overlapping pair, and finds the overlap of
    pairs that interpenetrate deeply (points of one inside the other)."""
    rng = np.random.default_rng(7)
    n = 400
    r, h = np.full(n, 30.0), np.full(n, 90.0)
    bodies = Bodies(Cylinder(), np.concatenate([r, r]), np.concatenate([h, h]),
                    sample_orientations("isotropic", 2 * n, rng))
    d = rng.normal(size=(n, 3))
    d *= rng.uniform(10, 220, n)[:, None] / np.linalg.norm(d, axis=1)[:, None]
    centres = np.concatenate([np.full((n, 3), 500.0), 500.0 + d])
    i, j = np.arange(n), np.arange(n, 2 * n)
    sep = separation(bodies, centres, i, j, (1e4, 1e4))
    a = bodies.axes
    for p in range(n):
        pts = cylinder_points(d[p], a[j[p]], 30.0, 90.0, n_len=21, n_ring=32, n_rad=6)
        shared = inside_cylinder(pts, np.zeros(3), a[i[p]], 30.0, 90.0).any()
        if sep.gap_nm[p] >= 0:
            assert not shared
        # the returned axis separates the projections by at least the gap (a lower bound)
        g = support_gap(bodies.shape.width, sep.normal[p][None, None, :], d[p][None], a[i[p]][None], a[j[p]][None],
                        r[:1], r[:1], h[:1], h[:1])[0, 0]
        assert g >= sep.gap_nm[p] - 1e-6
        deep = inside_cylinder(cylinder_points(d[p], a[j[p]], 28.0, 88.0, n_len=5, n_ring=8, n_rad=2),
                               np.zeros(3), a[i[p]], 28.0, 88.0).any()
        if deep:
            assert sep.gap_nm[p] < 0


def test_periodic_images_are_seen_across_the_boundary(cases):
    real = cases["sphere15"]
    lx = real.period_nm[0]
    two = dataclasses.replace(real, centres_nm=np.array([[5.0, 500.0, 500.0], [lx - 5.0, 500.0, 500.0]]),
                              radii_nm=np.array([20.0, 20.0]), lengths_nm=np.zeros(2),
                              axes=np.tile([0.0, 0.0, 1.0], (2, 1)), population=np.zeros(2, dtype=int),
                              protrusion=np.zeros(2))
    assert find_overlaps(two).tolist() == [[0, 1]]           # 10 nm apart through the boundary
    apart = dataclasses.replace(two, centres_nm=np.array([[25.0, 500.0, 500.0], [lx - 25.0, 500.0, 500.0]]))
    assert len(find_overlaps(apart)) == 0                    # 50 nm apart: touching would be 40
    # Placement near the boundary: particles sit on both sides of x = 0 without overlapping.
    c = cases["sphere50"].centres_nm
    r = cases["sphere50"].radii_nm
    assert (c[:, 0] < r).sum() > 0 and (c[:, 0] > cases["sphere50"].period_nm[0] - r).sum() > 0


def test_orientation_statistics_match_the_mode(cases):
    for name in ("iso", "iso_dilute"):
        az = np.abs(cases[name].axes[:, 2])
        n = len(az)
        assert abs(az.mean() - 0.5) < 5 * 0.29 / np.sqrt(n) + 0.02, (name, az.mean())
        assert kstest(az, "uniform").pvalue > 1e-3                 # |a_z| uniform on [0, 1]
    for name in ("inplane", "inplane_dilute"):
        a = cases[name].axes
        assert np.all(a[:, 2] == 0)
        azimuth = np.mod(np.arctan2(a[:, 1], a[:, 0]), np.pi) / np.pi
        assert kstest(azimuth, "uniform").pvalue > 1e-3
    assert np.all(cases["vertical"].axes == [0.0, 0.0, 1.0])
    assert np.allclose(np.linalg.norm(cases["iso"].axes, axis=1), 1.0)


def test_agglutination_raises_the_cluster_statistic():
    stats = []
    for strength in (0.0, 2.0, 4.0, 8.0):
        real = make("Y7.5+B7.5", f"sphere:100:agglutinated={strength:g}" if strength else "sphere:100",
                    seed=3, cell=(1500.0, 1500.0))
        assert len(find_overlaps(real)) == 0 and len(wall_violations(real)) == 0
        stats.append(cluster_statistic(real))
        if strength == 8.0:
            r, g = pair_correlation(real, 300.0, bins=30)
    sizes = [s.mean_cluster_size for s in stats]
    bonds = [s.bonds_per_particle for s in stats]
    assert all(b > a for a, b in zip(sizes, sizes[1:])), sizes
    assert all(b > a for a, b in zip(bonds, bonds[1:])), bonds
    assert sizes[-1] > 5 * sizes[0]
    assert g[np.argmin(np.abs(r - 105.0))] > 3.0                  # contact peak of g(r)


def test_rough_top_lets_particles_stand_out(cases):
    real = cases["rough"]
    hz = real.radii_nm
    top = real.centres_nm[:, 2] - hz
    assert real.z_range_nm[0] == pytest.approx(top.min()) and top.min() < 0
    assert np.all(top >= -2 * real.protrusion * hz - 1e-9)         # within each grain's allowance
    assert np.all(real.protrusion <= real.layer.particles.rough_top)
    # The binder surface is flat (0) far from grains and reaches each protruding grain's apex.
    out = np.flatnonzero(top < -1.0)
    surf = binder_surface_nm(real.bodies, real.centres_nm, real.period_nm, real.centres_nm[out, 0],
                             real.centres_nm[out, 1])
    assert np.allclose(surf, top[out])
    flat = make("G30", "sphere:300", cell=(2000.0, 2000.0))
    assert flat.z_range_nm == (0.0, 1000.0)
    assert np.all(flat.centres_nm[:, 2] - flat.radii_nm >= -1e-9)


def test_same_seed_same_realization_other_seed_differs():
    a = make("Y25+B5", "cylinder:100:inplane", seed=11, cell=(800.0, 800.0))
    b = make("Y25+B5", "cylinder:100:inplane", seed=11, cell=(800.0, 800.0))
    c = make("Y25+B5", "cylinder:100:inplane", seed=12, cell=(800.0, 800.0))
    for field in ("centres_nm", "axes", "radii_nm", "lengths_nm", "population", "protrusion"):
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    assert a.seed == 11 and a.z_range_nm == b.z_range_nm
    assert not np.array_equal(a.centres_nm, c.centres_nm)
