"""Spheroids (solver/geometry/shapes/spheroid.py), the third shape, against analytic geometry and
independent oracles (tests/oracles.py): volumes, extents and chords of the ellipsoid equation,
the distance of two ellipsoids by constrained minimisation and Perram–Wertheim's overlap
function, depolarisation factors by their integral; a spheroid of aspect 1 is a sphere in every
stage; and the shape reaches every stage: packing, voxels, tables, figure columns, the CLI and
scene parameters."""

import math

import numpy as np
import pytest

from solver.geometry import (LayerSpec, ParticleSpecError, UnreachableConcentrationError, draw_grains, find_overlaps,
                             generate, geometry_cost, parse_particles, voxelize)
from solver.geometry.bodies import Bodies
from solver.geometry.contacts import horizontal_separation, separation
from solver.geometry.limits import reachable_limit
from solver.geometry.depolarisation import local_field_of
from solver.geometry.neighbours import neighbour_pairs
from solver.geometry.orientation import sample_orientations
from solver.geometry.shapes.sphere import Sphere
from solver.geometry.shapes.spheroid import Spheroid
from solver.geometry.statistics import wall_violations
from solver.inks import parse_ink

from oracles import depolarisation_integral, ellipsoid_distance, perram_wertheim, spheroid_matrix

ASPECTS = (0.25, 0.5, 1.0, 2.0, 4.0)


def random_bodies(aspect, n, rng, diameter=100.0):
    shape = Spheroid(aspect)
    return Bodies.of(shape, np.full(n, diameter), sample_orientations("isotropic", n, rng))


def matrix(bodies, k):
    return spheroid_matrix(bodies.radii_nm[k], bodies.half_lengths_nm[k], bodies.axes[k])


def matrices(bodies, index):
    return spheroid_matrix(bodies.radii_nm[index], bodies.half_lengths_nm[index], bodies.axes[index])


# ------------------------------------------------------------------------------ grammar
@pytest.mark.parametrize("text, label", [
    ("spheroid:200", "spheroid:200:aspect=3:isotropic"),
    ("spheroid:200:aspect=0.25:vertical", "spheroid:200:aspect=0.25:vertical"),
    ("spheroid:150:inplane:aspect=2:tilt=10:rough", "spheroid:150:aspect=2:inplane:rough=0.5:tilt=10"),
    ("Spheroid:80:aspect=1:agglutinated=2:spread=0.1", "spheroid:80:aspect=1:isotropic:agglutinated=2:spread=0.1"),
])
def test_spheroid_specs_round_trip(text, label):
    spec = parse_particles(text)
    assert spec.label == label and parse_particles(label) == spec
    assert spec.shape.name == "spheroid" and spec.shape.oriented


@pytest.mark.parametrize("text, words", [
    ("spheroid:100:aspect=10", ["aspect", "[0.25, 4]", "10"]),
    ("spheroid:100:aspect=0", ["aspect", "[0.25, 4]"]),
    ("spheroid:100:aspect", ["'aspect'", "needs a value"]),
    ("spheroid:100:aspect=flat", ["bad spheroid aspect", "flat"]),
    ("sphere:100:aspect=2", ["unknown particle modifier", "aspect=2"]),
    ("cylinder:100:aspect=2", ["unknown particle modifier"]),
    ("spheroid:100:isotropic:tilt=5", ["tilt", "inplane or vertical", "isotropic"]),
    ("sphere:100:vertical", ["applies to", "cylinders and spheroids", "not spheres"]),
])
def test_bad_spheroid_specs_give_one_clear_error(text, words):
    with pytest.raises(ParticleSpecError) as info:
        parse_particles(text)
    for word in words:
        assert word in str(info.value)


# ------------------------------------------------------------------------------ one grain, N grains
@pytest.mark.parametrize("aspect", ASPECTS)
def test_volume_axes_extents_and_span(aspect):
    """(4/3)π r²h = (π/6)D³ with h = A·r; each half extent is √M_kk of the shape matrix and the
    span twice its largest semi-axis; the largest height over an orientation range is the
    largest √M_zz over axes in it."""
    rng = np.random.default_rng(1)
    bodies = random_bodies(aspect, 50, rng, diameter=200.0)
    np.testing.assert_allclose(bodies.volumes_nm3, math.pi / 6 * 200.0**3, rtol=1e-12)
    np.testing.assert_allclose(bodies.half_lengths_nm / bodies.radii_nm, aspect, rtol=1e-12)
    for k in range(50):
        m = matrix(bodies, k)
        for axis in range(3):
            assert bodies.half_extent_nm(axis)[k] == pytest.approx(math.sqrt(m[axis, axis]), rel=1e-12)
    shape = Spheroid(aspect)
    r, h = shape.dimensions(200.0)
    assert shape.span_nm(200.0) == pytest.approx(2 * math.sqrt(np.linalg.eigvalsh(spheroid_matrix(r, h, [0, 0, 1])).max()))
    for mode, tilt in (("vertical", 0.0), ("vertical", 0.4), ("inplane", 0.0), ("inplane", 0.3), ("isotropic", 0.0)):
        spec = parse_particles(f"spheroid:200:aspect={aspect}:{mode}" + (f":tilt={math.degrees(tilt)}" if tilt else ""))
        lo, hi = {"vertical": (0.0, tilt), "inplane": (math.pi / 2 - tilt, math.pi / 2),
                  "isotropic": (0.0, math.pi / 2)}[mode]
        brute = max(2 * math.sqrt(spheroid_matrix(r, h, [math.sin(t), 0.0, math.cos(t)])[2, 2])
                    for t in np.linspace(lo, hi, 201))
        assert spec.max_height_nm(200.0) == pytest.approx(brute, rel=1e-9)


@pytest.mark.parametrize("aspect", ASPECTS)
def test_chords_solve_the_ellipsoid_equation(aspect):
    """Each chord's ends lie on xᵀM⁻¹x = 1, its middle inside; a line reported missing never
    enters (the minimum of xᵀM⁻¹x along it is ≥ 1); the chords integrate to the volume."""
    rng = np.random.default_rng(2)
    bodies = random_bodies(aspect, 20, rng)
    dx = rng.uniform(-1, 1, (20, 400)) * bodies.half_extent_nm(0)[:, None]      # the grains' shadows' boxes
    dy = rng.uniform(-1, 1, (20, 400)) * bodies.half_extent_nm(1)[:, None]
    lo, hi = bodies.shape.z_chords(bodies, dx, dy)
    hit = hi > lo
    assert 0.5 < hit.mean() < 0.95
    for k in range(20):
        inv = np.linalg.inv(matrix(bodies, k))
        for z, on in ((lo[k], 1.0), (hi[k], 1.0), (0.5 * (lo[k] + hi[k]), None)):
            pts = np.stack([dx[k], dy[k], z], axis=1)[hit[k]]
            q = np.einsum("pi,ij,pj->p", pts, inv, pts)
            if on is None:
                assert np.all(q < 1.0)
            else:
                np.testing.assert_allclose(q, 1.0, atol=1e-9)
        miss = ~hit[k]
        a = inv[2, 2]
        b = 2 * (dx[k] * inv[0, 2] + dy[k] * inv[1, 2])
        c = inv[0, 0] * dx[k] ** 2 + 2 * inv[0, 1] * dx[k] * dy[k] + inv[1, 1] * dy[k] ** 2
        assert np.all((c - b * b / (4 * a))[miss] >= 1.0 - 1e-12)
    # the chords of a fine lattice of lines add up to the volume
    one = bodies.take([0])
    span = float(one.bounding_radii_nm[0])
    step = 0.5
    grid = np.arange(-span, span, step) + 0.5 * step
    gx, gy = np.meshgrid(grid, grid, indexing="ij")
    lo, hi = one.shape.z_chords(one, gx.ravel()[None], gy.ravel()[None])
    assert np.sum(np.clip(hi - lo, 0, None)) * step * step == pytest.approx(one.volumes_nm3[0], rel=2e-4)


def test_inside_test_is_the_ellipsoid_equation():
    rng = np.random.default_rng(3)
    bodies = random_bodies(0.4, 10, rng)
    pts = rng.uniform(-70, 70, (10, 500, 3))
    inside = bodies.shape.contains(bodies, pts[..., 0], pts[..., 1], pts[..., 2])
    for k in range(10):
        q = np.einsum("pi,ij,pj->p", pts[k], np.linalg.inv(matrix(bodies, k)), pts[k])
        clear = np.abs(q - 1) > 1e-9
        np.testing.assert_array_equal(inside[k][clear], (q < 1)[clear])
    assert 0.05 < inside.mean() < 0.5


# ------------------------------------------------------------------------------ contacts
@pytest.mark.parametrize("aspect", [0.25, 1.7, 4.0])
def test_separation_is_the_ellipsoid_distance(aspect):
    """Apart pairs: the gap is the distance of the two ellipsoids (constrained minimisation);
    every pair: the sign agrees with Perram–Wertheim's function, and a brute-force maximum of
    |d·n| − √(nᵀAn) − √(nᵀBn) over 20 000 directions never beats the gap.  With margin 0 the
    search stops at the first certificate, never certifying an overlapping pair."""
    rng = np.random.default_rng(4)
    n = 120
    bodies = random_bodies(aspect, 2 * n, rng)
    reach = 2 * float(bodies.bounding_radii_nm.max())
    d = rng.normal(size=(n, 3))
    d *= (rng.uniform(0.2, 1.1, n) * reach / np.linalg.norm(d, axis=1))[:, None]
    centres = np.concatenate([np.full((n, 3), 500.0), 500.0 + d])
    i, j = np.arange(n), np.arange(n, 2 * n)
    full = separation(bodies, centres, i, j, (1e5, 1e5), margin_nm=1e9)
    quick = separation(bodies, centres, i, j, (1e5, 1e5))
    dirs = rng.normal(size=(20000, 3))
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    contact = perram_wertheim(d, matrices(bodies, i), matrices(bodies, j))
    apart = 0
    for p in range(n):
        ma, mb = matrix(bodies, p), matrix(bodies, n + p)
        g = full.gap_nm[p]
        assert (g > 0) == (contact[p] > 1) or abs(g) < 1e-6
        assert quick.gap_nm[p] <= g + 1e-9 and ((quick.gap_nm[p] >= 0) == (g >= 0) or abs(g) < 1e-6)
        if g > 0 and apart < 15:
            apart += 1
            assert g == pytest.approx(ellipsoid_distance(d[p], ma, mb), abs=1e-6)
        if p % 8 == 0:
            brute = (np.abs(dirs @ d[p]) - np.sqrt(np.einsum("ki,ij,kj->k", dirs, ma, dirs))
                     - np.sqrt(np.einsum("ki,ij,kj->k", dirs, mb, dirs))).max()
            assert brute <= g + 1e-9
    assert apart == 15 and (full.gap_nm < 0).sum() > 20
    # the normal points from i to j and separates the projections by the gap
    np.testing.assert_allclose(np.linalg.norm(full.normal, axis=1), 1.0, atol=1e-12)
    assert np.all(np.einsum("pc,pc->p", full.normal, d) >= 0)


def test_horizontal_separation_is_a_horizontal_certificate():
    """The horizontal axis is horizontal, its gap at most the true one; moving the pair apart
    along it by its overlap (and a hair) leaves them apart (Perram–Wertheim)."""
    rng = np.random.default_rng(5)
    n = 40
    bodies = random_bodies(3.0, 2 * n, rng)
    d = rng.normal(size=(n, 3)) * 40.0
    centres = np.concatenate([np.full((n, 3), 500.0), 500.0 + d])
    i, j = np.arange(n), np.arange(n, 2 * n)
    flat = horizontal_separation(bodies, centres, i, j, (1e5, 1e5))
    full = separation(bodies, centres, i, j, (1e5, 1e5), margin_nm=1e9)
    assert np.all(flat.normal[:, 2] == 0.0) and np.all(flat.gap_nm <= full.gap_nm + 1e-9)
    moved = d + np.maximum(0.0, 1e-6 - flat.gap_nm)[:, None] * flat.normal
    assert np.all(perram_wertheim(moved, matrices(bodies, i), matrices(bodies, j)) >= 1.0 - 1e-9)


# ------------------------------------------------------------------------------ a sphere in disguise
def test_aspect_one_is_a_sphere_everywhere():
    """Chords, volumes, extents, gaps and the local field of spheroids of aspect 1 are the
    sphere's; a layer of them is the sphere layer's, grain for grain and voxel for voxel."""
    rng = np.random.default_rng(6)
    ball = Bodies.of(Spheroid(1.0), np.full(30, 90.0), sample_orientations("isotropic", 30, rng))
    sphere = Bodies.of(Sphere(), np.full(30, 90.0), np.tile([0.0, 0.0, 1.0], (30, 1)))
    dx, dy = rng.uniform(-50, 50, (2, 30, 50))
    (lo_a, hi_a), (lo_b, hi_b) = ball.shape.z_chords(ball, dx, dy), sphere.shape.z_chords(sphere, dx, dy)
    hit = hi_b > lo_b
    np.testing.assert_array_equal((hi_a > lo_a)[np.abs(dx**2 + dy**2 - 45.0**2) > 1e-6], hit[np.abs(dx**2 + dy**2 - 45.0**2) > 1e-6])
    np.testing.assert_allclose(lo_a[hit], lo_b[hit], atol=1e-6)
    np.testing.assert_allclose(hi_a[hit], hi_b[hit], atol=1e-6)
    np.testing.assert_allclose(ball.volumes_nm3, sphere.volumes_nm3, rtol=1e-12)
    np.testing.assert_allclose(ball.half_extent_nm(2), 45.0, rtol=1e-12)
    c = rng.uniform(0, 300, (30, 3))
    i, j = neighbour_pairs(c, 200.0, (1e5, 1e5))
    np.testing.assert_allclose(separation(ball, c, i, j, (1e5, 1e5), margin_nm=1e9).gap_nm,
                               np.linalg.norm(c[j] - c[i], axis=1) - 90.0, atol=1e-9)
    field = local_field_of(parse_particles("spheroid:90:aspect=1"))
    assert all(factor == pytest.approx(1 / 3) for _, factor in field.pairs)
    for ink, cell in (("B15", 700.0), ("B35", 600.0)):             # RSA alone; RSA and packing
        real = [generate(LayerSpec(parse_ink(ink), parse_particles(p), 400.0, (cell, cell)), 3)
                for p in ("sphere:80", "spheroid:80:aspect=1:vertical")]
        np.testing.assert_allclose(real[0].centres_nm, real[1].centres_nm, atol=1e-9)
        np.testing.assert_allclose(voxelize(real[0], (16, 16, 8)).fractions, voxelize(real[1], (16, 16, 8)).fractions,
                                   atol=1e-6)


# ------------------------------------------------------------------------------ optics
@pytest.mark.parametrize("aspect", [0.25, 0.6, 2.5, 4.0])
def test_local_field_is_the_depolarisation_integral(aspect):
    """Vertical axes under an in-plane field see only the equatorial factor; in-plane axes see
    the polar and the equatorial one equally; both from the ellipsoid's integral."""
    polar, equatorial = depolarisation_integral(aspect, 1.0, 1.0), depolarisation_integral(1.0, aspect, 1.0)
    vertical = local_field_of(parse_particles(f"spheroid:100:aspect={aspect}:vertical")).pairs
    assert vertical[0][0] == pytest.approx(0.0, abs=1e-15) and vertical[1] == pytest.approx((1.0, equatorial), rel=1e-7)
    inplane = local_field_of(parse_particles(f"spheroid:100:aspect={aspect}:inplane")).pairs
    assert [x for pair in inplane for x in pair] == pytest.approx([0.5, polar, 0.5, equatorial], rel=1e-7)


# ------------------------------------------------------------------------------ layers
@pytest.mark.parametrize("particles", ["spheroid:80:aspect=4", "spheroid:80:aspect=0.25:vertical",
                                       "spheroid:80:aspect=3:inplane", "spheroid:80:aspect=0.3:inplane:tilt=20",
                                       "spheroid:80:aspect=2:rough"])
def test_packed_spheroid_layers_do_not_overlap(particles):
    """B35 (RSA and packing): no pair overlaps by Perram–Wertheim, nothing crosses a wall, the
    fraction is exact, the voxel grid holds the grains' volume, the axes keep their statistics."""
    layer = LayerSpec(parse_ink("B35"), parse_particles(particles), 400.0, (500.0, 500.0))
    real = generate(layer, 2)
    assert real.stats.method == "rsa+packing" and len(find_overlaps(real)) == 0
    assert len(wall_violations(real)) == 0
    assert real.achieved_fractions["B"] == pytest.approx(0.35, rel=1e-12)
    bodies = real.bodies
    i, j = neighbour_pairs(real.centres_nm, 2 * float(bodies.bounding_radii_nm.max()), real.period_nm)
    d = real.centres_nm[j] - real.centres_nm[i]
    d[:, :2] -= np.array(real.period_nm) * np.round(d[:, :2] / np.array(real.period_nm))
    assert len(i) > 100 and perram_wertheim(d, matrices(bodies, i), matrices(bodies, j)).min() >= 1.0
    vox = voxelize(real, (20, 20, 16))
    assert sum(vox.volume_nm3(c) for c in real.population_codes) == pytest.approx(real.volumes_nm3.sum(), rel=1e-5)
    az = np.abs(real.axes[:, 2])
    spec = layer.particles
    if spec.orientation == "vertical":
        assert np.all(az == 1.0)
    elif spec.orientation == "inplane":
        assert az.max() <= math.sin(spec.tilt_rad) + 1e-12
    else:
        assert abs(az.mean() - 0.5) < 5 / math.sqrt(12 * len(az)) + 0.03
    if spec.rough_top:
        assert real.z_range_nm[0] < 0 and np.allclose(vox.fractions.sum(axis=0), 1.0, atol=1e-6)


@pytest.mark.parametrize("particles", ["spheroid:100:aspect=4", "spheroid:100:aspect=0.25:inplane:tilt=10",
                                       "spheroid:150:aspect=2:vertical:agglutinated:rough"])
def test_cost_estimate_counts_the_grains(particles):
    layer = LayerSpec(parse_ink("B30"), parse_particles(particles), 500.0, (700.0, 700.0))
    cost = geometry_cost(layer, (32, 32, 16))
    assert cost.grains == len(draw_grains(layer, 0)) and cost.seconds > 0 and cost.peak_bytes > 0


def test_tall_vertical_needles_are_refused_before_any_work():
    """Needles too tall to stack two in the layer cannot pack as densely: B50 is refused at once,
    with the limit, and their tilted or shorter kin are accepted higher."""
    tall = LayerSpec(parse_ink("B50"), parse_particles("spheroid:300:aspect=4:vertical"))
    with pytest.raises(UnreachableConcentrationError) as info:
        generate(tall, 0)
    assert "reachable limit" in str(info.value) and info.value.limit < 0.5
    short = LayerSpec(parse_ink("B50"), parse_particles("spheroid:100:aspect=4:vertical"))
    assert reachable_limit(short) > info.value.limit


def test_binder_over_a_protruding_spheroid_of_aspect_one_is_the_spheres():
    """The binder lifted by a spheroid (its top where lines meet it, sampled surface points on
    the meniscus cone): for aspect 1, tilted, exact on the cap and within 1.5 nm of the sphere's
    exact cone (never below it: the envelope of fewer points)."""
    dx, dy = np.meshgrid(np.linspace(-200, 200, 41), np.linspace(-200, 200, 41))
    exact = Sphere().meniscus_nm(100.0, 0.0, np.array([0.0, 0.0, 1.0]), 30.0, dx.ravel(), dy.ravel(), np.radians(45))
    sampled = Spheroid(1.0).meniscus_nm(100.0, 100.0, np.array([0.6, 0.0, 0.8]), 30.0, dx.ravel(), dy.ravel(),
                                        np.radians(45))
    assert np.all(sampled >= exact - 1e-9) and np.max(sampled - exact) < 1.5
    cap = np.hypot(dx, dy).ravel() < 100.0 * np.sin(np.radians(45)) - 1.0
    np.testing.assert_allclose(sampled[cap], exact[cap], atol=1e-9)


# ------------------------------------------------------------------------------ everywhere
def test_spheroids_reach_requests_figures_cli_and_scenes(capsys):
    from solver.apps.cli import main
    from solver.apps.figures.paper_grid import parse_columns
    from solver.table.request import table_request
    from solver.table.wave_tier import layer_spec

    req = table_request("B15", "spheroid:100:aspect=0.25:vertical")
    assert req.layer.particles_label == "spheroid:100:aspect=0.25:vertical"
    assert layer_spec(req).particles.shape == Spheroid(0.25)
    assert req.layer_materials() != table_request("B15", "sphere:100").layer_materials()   # its own local field
    columns = parse_columns("molecular,spheroid:200:aspect=0.25:vertical,spheroid:200:aspect=4:inplane", "fig7")
    assert (columns[1].group, columns[1].sub, columns[1].across) == ("flakes D_eff = 200 nm, aspect 0.25",
                                                                     "lying flat", True)
    assert (columns[2].group, columns[2].sub) == ("needles D_eff = 200 nm, aspect 4", "horiz aligned")
    assert main(["geometry", "--ink", "B15", "--particles", "spheroid:100:aspect=0.25:vertical", "--seed", "1",
                 "--cell", "800", "--thickness", "500", "--grid", "32", "32", "20"]) == 0
    out = capsys.readouterr().out
    assert "overlapping pairs: 0" in out and "<|a_z|> = 1.000" in out and "(spheroid)" in out
    with pytest.raises(SystemExit):
        main(["build", "--help"])
    assert "spheroid:D[:aspect=A]" in "".join(capsys.readouterr().out.split())
    from inkbsdf import source

    scene = source.table_request({"ink": "B15", "particles": "spheroid:100:aspect=3:inplane"})
    assert scene.layer.particles_label == "spheroid:100:aspect=3:inplane"


def test_spheroid_tables_build(tmp_path):
    """A table of flakes builds and conserves energy (lossy: R̄ + T̄ < 1 wherever solved); its
    pigment enters with the flakes' local field, which for aspect 1 is the sphere's."""
    from solver.table.builder import BuildOptions, build_table
    from solver.table.cache import TableCache
    from solver.table.request import table_request

    def request(particles):
        return table_request("B15", particles, wavelengths_nm=(450.0, 650.0), sigma_rad=(0.0, 0.7, math.pi / 2),
                             grid=(16, 16, 8), realizations=1, azimuths=1, dphi_count=5, tier="full", cell_nm=800.0)

    flakes = build_table(request("spheroid:150:aspect=0.25:vertical"),
                         BuildOptions(progress=False, cache=TableCache(tmp_path / "cache"), workers=1))
    solved = flakes.sigma < math.pi / 2 - 1e-9
    assert np.all(flakes.Rbar[:, solved] + flakes.Tbar[:, solved] < 1.0) and np.all(flakes.Rbar > 0)
    assert flakes.meta["particles"] == "spheroid:150:aspect=0.25:vertical"
    eps = {p: request(p).layer_materials().pigment_eps("B", 550.0)
           for p in ("sphere:150", "spheroid:150:aspect=1:vertical", "spheroid:150:aspect=0.25:vertical")}
    assert eps["spheroid:150:aspect=1:vertical"] == pytest.approx(eps["sphere:150"], rel=1e-12)
    assert abs(eps["spheroid:150:aspect=0.25:vertical"] - eps["sphere:150"]) > 1e-3
