"""geometry_cost (estimates before any work) and the progress callback of generate."""

import math

import numpy as np
import pytest

from solver.geometry import GENERATE_STAGES, LayerSpec, generate, geometry_cost, parse_particles
from solver.inks import parse_ink


@pytest.mark.parametrize("ink, particles, cell", [
    ("Y7.5+B7.5", "sphere:100", 1000.0),
    ("R30", "sphere:100", 1000.0),
    ("Y25+B25", "cylinder:100:vertical", 1000.0),
    ("G15", "cylinder:200:inplane:tilt=10", 2000.0),
    ("B15", "sphere:300:rough", 2000.0),
])
def test_grain_count_is_the_generated_count(ink, particles, cell):
    layer = LayerSpec(parse_ink(ink), parse_particles(particles), 1000.0, (cell, cell))
    est = geometry_cost(layer, (32, 32, 16))
    assert est.grains == len(generate(layer, 3).radii_nm)
    assert math.isfinite(est.seconds) and est.seconds > 0
    assert est.peak_bytes > 0


def test_grain_count_with_a_size_spread_is_close():
    layer = LayerSpec(parse_ink("B30"), parse_particles("sphere:100:spread=0.2"), 1000.0, (1000.0, 1000.0))
    est = geometry_cost(layer, (32, 32, 16))
    assert abs(est.grains / len(generate(layer, 1).radii_nm) - 1) < 0.15


def test_huge_layer_is_estimated_without_work():
    """5-nm spheres at 15 % in 2000×2000×1000 nm: round(0.15·V / (π/6·5³)) grains, counted
    independently here; the estimate is instant and large enough to refuse."""
    layer = LayerSpec(parse_ink("R15"), parse_particles("sphere:5"))
    expect = round(0.15 * 2000.0 * 2000.0 * 1000.0 / (math.pi / 6 * 5.0**3))
    est = geometry_cost(layer, (128, 128, 64))
    assert est.grains == expect and 9.0e6 < expect < 9.4e6
    assert est.peak_bytes > 4 * 2**30 and est.seconds > 60.0
    # Estimates grow with the work: more grains, a finer grid, a higher concentration.
    small = geometry_cost(LayerSpec(parse_ink("R15"), parse_particles("sphere:30")), (128, 128, 64))
    assert small.grains < est.grains and small.seconds < est.seconds
    fine = geometry_cost(LayerSpec(parse_ink("R15"), parse_particles("sphere:30")), (256, 256, 128))
    assert fine.seconds > small.seconds and fine.peak_bytes > small.peak_bytes
    dense = geometry_cost(LayerSpec(parse_ink("R50"), parse_particles("sphere:30")), (128, 128, 64))
    assert dense.seconds / dense.grains > small.seconds / small.grains


def test_bad_grid_is_refused():
    layer = LayerSpec(parse_ink("R15"), parse_particles("sphere:100"))
    with pytest.raises(ValueError, match="voxel grid"):
        geometry_cost(layer, (128, 0, 64))


def record(events):
    return lambda stage, fraction: events.append((stage, fraction))


@pytest.mark.parametrize("ink, particles, stages", [
    ("B30", "cylinder:100:vertical", ("grains", "rsa", "packing", "check")),
    ("Y7.5+B7.5", "sphere:100:agglutinated=4", ("grains", "rsa", "agglutination", "check")),
    ("B10", "sphere:100", ("grains", "rsa", "check")),
])
def test_progress_reports_stages_in_order(ink, particles, stages):
    layer = LayerSpec(parse_ink(ink), parse_particles(particles), 1000.0, (1000.0, 1000.0))
    events = []
    real = generate(layer, 4, progress=record(events))
    seen = list(dict.fromkeys(stage for stage, _ in events))
    assert tuple(seen) == stages
    assert [GENERATE_STAGES.index(s) for s in seen] == sorted(GENERATE_STAGES.index(s) for s in seen)
    for stage in seen:
        fractions = [f for s, f in events if s == stage]
        assert all(0.0 <= f <= 1.0 for f in fractions)
        assert fractions == sorted(fractions)                     # never goes back
        if stage != "rsa":                                        # RSA may end before every grain is placed
            assert fractions[-1] == 1.0
    # Reporting changes nothing: the same arrays as without a callback.
    plain = generate(layer, 4)
    for field in ("centres_nm", "axes", "radii_nm", "population"):
        assert np.array_equal(getattr(real, field), getattr(plain, field))
