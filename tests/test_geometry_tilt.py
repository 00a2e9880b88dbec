"""Orientation spread (`tilt=`): parsing, errors, the drawn and packed axis statistics, heights,
and the tilt-aware reachable limit."""

import math

import numpy as np
import pytest
from scipy.stats import kstest, ks_2samp

from solver.geometry import (DEFAULT_TILTS_DEG, GeometryError, LayerSpec, ParticleSpecError, find_overlaps, generate,
                             parse_particles, reachable_limit, smallest_tilt_reaching)
from solver.geometry.orientation import sample_orientations
from solver.geometry.shapes.cylinder import cylinder_radius_length
from solver.geometry.statistics import wall_violations
from solver.inks import parse_ink


@pytest.mark.parametrize("text, label, degrees", [
    ("cylinder:300:vertical:tilt=15", "cylinder:300:vertical:tilt=15", 15.0),
    ("cylinder:100:inplane:tilt=7.5", "cylinder:100:inplane:tilt=7.5", 7.5),
    ("cylinder:100:tilt=20:vertical", "cylinder:100:vertical:tilt=20", 20.0),
    ("cylinder:100:vertical:tilt=0", "cylinder:100:vertical", 0.0),
    ("cylinder:200:inplane:rough=0.3:tilt=5", "cylinder:200:inplane:rough=0.3:tilt=5", 5.0),
])
def test_tilt_parses_and_round_trips(text, label, degrees):
    spec = parse_particles(text)
    assert spec.label == label
    assert parse_particles(spec.label) == spec
    assert spec.tilt_deg == pytest.approx(degrees) and spec.tilt_rad == pytest.approx(math.radians(degrees))


@pytest.mark.parametrize("text, words", [
    ("cylinder:100:isotropic:tilt=10", ["tilt", "inplane or vertical", "isotropic"]),
    ("cylinder:100:tilt=10", ["tilt", "isotropic"]),                 # isotropic is the default
    ("sphere:100:tilt=10", ["tilt", "spheres"]),
    ("cylinder:100:vertical:tilt=90", ["tilt", "[0, 90)"]),
    ("cylinder:100:vertical:tilt=-5", ["tilt", "-5"]),
    ("cylinder:100:vertical:tilt", ["tilt", "degrees"]),
    ("cylinder:100:vertical:tilt=abc", ["bad tilt"]),
])
def test_bad_tilt_gives_one_clear_error(text, words):
    with pytest.raises(ParticleSpecError) as info:
        parse_particles(text)
    for word in words:
        assert word in str(info.value)


def rejection_sample(n, keep, rng):
    """Independent oracle: isotropic directions (normalised Gaussians), folded to a_z ≥ 0,
    kept where keep(a) holds."""
    out = []
    while sum(len(o) for o in out) < n:
        a = rng.normal(size=(4 * n, 3))
        a /= np.linalg.norm(a, axis=1)[:, None]
        a[a[:, 2] < 0] *= -1
        out.append(a[keep(a)])
    return np.concatenate(out)[:n]


@pytest.mark.parametrize("mode, tilt_deg", [("vertical", 15.0), ("vertical", 40.0), ("inplane", 15.0)])
def test_drawn_axes_are_uniform_on_the_cap_or_band(mode, tilt_deg):
    """The cap (vertical) and the band (in-plane) are the isotropic distribution restricted to
    the allowed angles: compared with rejection sampling of Gaussian directions, and with the
    closed forms (a_z uniform in [cos t, 1], resp. [0, sin t]; azimuth uniform)."""
    t = math.radians(tilt_deg)
    axes = sample_orientations(mode, 20000, np.random.default_rng(5), t)
    assert np.allclose(np.linalg.norm(axes, axis=1), 1.0) and np.all(axes[:, 2] >= 0)
    if mode == "vertical":
        assert axes[:, 2].min() >= math.cos(t) - 1e-12
        keep = lambda a: a[:, 2] >= math.cos(t)                                  # noqa: E731
        assert kstest(axes[:, 2], "uniform", args=(math.cos(t), 1 - math.cos(t))).pvalue > 1e-3
    else:
        assert axes[:, 2].max() <= math.sin(t) + 1e-12
        keep = lambda a: a[:, 2] <= math.sin(t)                                  # noqa: E731
        assert kstest(axes[:, 2], "uniform", args=(0.0, math.sin(t))).pvalue > 1e-3
    oracle = rejection_sample(20000, keep, np.random.default_rng(6))
    assert ks_2samp(axes[:, 2], oracle[:, 2]).pvalue > 1e-3
    azimuth = np.mod(np.arctan2(axes[:, 1], axes[:, 0]), 2 * np.pi) / (2 * np.pi)
    assert kstest(azimuth, "uniform").pvalue > 1e-3


@pytest.mark.parametrize("particles", ["cylinder:100:vertical:tilt=15", "cylinder:100:inplane:tilt=15"])
def test_packed_layer_keeps_the_spread(particles):
    """Tilted vertical cylinders keep their drawn axes; in-plane ones turn about z only, so
    a_z keeps its distribution exactly; no overlaps, inside the walls, exact fractions."""
    layer = LayerSpec(parse_ink("B30"), parse_particles(particles), 1000.0, (1000.0, 1000.0))
    real = generate(layer, 2)
    t = math.radians(15.0)
    az = real.axes[:, 2]
    if "vertical" in particles:
        assert az.min() >= math.cos(t) - 1e-9
        assert kstest(az, "uniform", args=(math.cos(t), 1 - math.cos(t))).pvalue > 1e-3
    else:
        assert az.max() <= math.sin(t) + 1e-9
        assert kstest(az, "uniform", args=(0.0, math.sin(t))).pvalue > 1e-3
        azimuth = np.mod(np.arctan2(real.axes[:, 1], real.axes[:, 0]), np.pi) / np.pi
        assert kstest(azimuth, "uniform").pvalue > 1e-3
    assert len(find_overlaps(real)) == 0 and len(wall_violations(real)) == 0
    assert real.achieved_fractions["B"] == pytest.approx(0.30, rel=1e-9)


def test_tilt_counts_in_the_particle_height():
    """A 300-nm cylinder (r = 90.9, L = 545 nm) in the plane is 182 nm high; with ±45° it can be
    L sin 45° + 2r cos 45° = 514 nm high (brute force over angles), too high for 400 nm."""
    r, length = cylinder_radius_length(300.0)
    angles = np.radians(np.linspace(45.0, 90.0, 2001))
    height = np.max(length * np.cos(angles) + 2 * r * np.sin(angles))
    assert 500.0 < height < 520.0
    LayerSpec(parse_ink("R15"), parse_particles("cylinder:300:inplane"), thickness_nm=400)
    with pytest.raises(GeometryError, match="larger than the layer"):
        LayerSpec(parse_ink("R15"), parse_particles("cylinder:300:inplane:tilt=45"), thickness_nm=400)
    LayerSpec(parse_ink("R15"), parse_particles("cylinder:300:inplane:tilt=45"), thickness_nm=height + 1)


def test_vertical_limit_with_tilt_follows_the_midplane_estimate():
    """All 300-nm cylinders within 45° of the vertical are more than 500 nm high, so they all
    cross the mid-plane of a 1000-nm layer, with elliptic sections of area πr²/cos θ: a spread
    up to 45° lowers the limit (by the mean 1/cos θ over the cap), it cannot raise it."""
    def limit(tilt):
        text = "cylinder:300:vertical" + (f":tilt={tilt}" if tilt else "")
        return reachable_limit(LayerSpec(parse_ink("B50"), parse_particles(text)))

    _, length = cylinder_radius_length(300.0)
    bound = math.pi / math.sqrt(12) * length / 1000.0
    untilted = limit(0)
    assert untilted == pytest.approx(0.9 * bound)
    for tilt in (15, 30, 45):
        t = math.radians(tilt)
        mean_sec = -math.log(math.cos(t)) / (1 - math.cos(t))            # mean of 1/u, u = cos θ ∈ [cos t, 1]
        assert limit(tilt) <= bound / mean_sec
    assert limit(15) < untilted and limit(45) < limit(15)


def test_smallest_tilt_reaching():
    vertical300 = lambda ink: LayerSpec(parse_ink(ink), parse_particles("cylinder:300:vertical"))  # noqa: E731
    assert smallest_tilt_reaching(vertical300("B40")) == 0.0              # reachable without spread
    # 50 % of vertical 300-nm cylinders in 1000 nm: the mid-plane bound (49.4 %) holds for every
    # spread up to ~48°, so no spread of the default list reaches it.
    assert 45.0 in DEFAULT_TILTS_DEG and smallest_tilt_reaching(vertical300("B50")) is None
    # The function tries the list in increasing order and returns the first that reaches.
    assert smallest_tilt_reaching(vertical300("B44")) == 0.0
    assert smallest_tilt_reaching(vertical300("B44.45"), (20, 0, 5)) == 0.0
    assert smallest_tilt_reaching(vertical300("B44.6"), (0, 5, 10)) is None
    # Spheres and isotropic cylinders have no spread: 0.0 when reachable, else None.
    assert smallest_tilt_reaching(LayerSpec(parse_ink("B50"), parse_particles("sphere:100"))) == 0.0
    assert smallest_tilt_reaching(LayerSpec(parse_ink("B55"), parse_particles("cylinder:100:isotropic"))) is None


def test_aligned_column_bound_is_hexagonal_packing_of_one_tier():
    """Vertical cylinders longer than half the layer stand one per column: their fraction is at
    most the hexagonal disc packing π/√12 times length / thickness (computed here from the
    cylinder's volume and aspect, not from the module's constants); shorter ones stack."""
    from solver.geometry import aligned_column_bound

    r, length = cylinder_radius_length(300.0)
    assert math.pi * r ** 2 * length == pytest.approx(math.pi / 6 * 300.0 ** 3, rel=1e-9)
    layer = LayerSpec(parse_ink("R50"), parse_particles("cylinder:300:vertical"), 1000.0, (2000.0, 2000.0))
    hexagonal = (math.pi * r ** 2) / (2 * math.sqrt(3) * r ** 2) * length / 1000.0
    assert aligned_column_bound(layer) == pytest.approx(hexagonal, rel=1e-9)
    assert aligned_column_bound(layer) < 0.5 and reachable_limit(layer) <= aligned_column_bound(layer)
    short = LayerSpec(parse_ink("R50"), parse_particles("cylinder:100:vertical"), 1000.0, (2000.0, 2000.0))
    assert aligned_column_bound(short) is None
    assert aligned_column_bound(LayerSpec(parse_ink("R50"), parse_particles("sphere:300"), 1000.0,
                                          (2000.0, 2000.0))) is None
