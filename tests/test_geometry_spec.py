"""Particle specs, layer validation and the clear errors for bad input."""

import math

import pytest

from solver.geometry import (AGGLUTINATED_DEFAULT_KT, GeometryError, LayerSpec, ParticleSpec,
                             ParticleSpecError, UnreachableConcentrationError, generate, parse_particles,
                             reachable_limit)
from solver.geometry.shapes.cylinder import cylinder_radius_length
from solver.geometry.spec import ROUGH_DEFAULT
from solver.inks import parse_ink

PAPER_PARTICLES = ["sphere:30", "sphere:100", "sphere:100:agglutinated", "sphere:200", "sphere:300",
                   "sphere:300:rough", "sphere:450"] + [f"cylinder:{d}:{o}" for d in (100, 200, 300)
                                                       for o in ("isotropic", "inplane", "vertical")]


@pytest.mark.parametrize("text", PAPER_PARTICLES + ["sphere:100:agglutinated=2.5", "sphere:300:spread=0.2",
                                                   "sphere:300:rough=0.3:spread=0.1"])
def test_label_round_trips(text):
    spec = parse_particles(text)
    assert parse_particles(spec.label) == spec
    assert parse_particles(spec.label).label == spec.label


def test_molecular_means_no_geometry():
    assert parse_particles("molecular") is None
    assert parse_particles(" Molecular ") is None


def test_keywords_map_to_documented_defaults():
    assert parse_particles("sphere:100:agglutinated").agglutination_kT == AGGLUTINATED_DEFAULT_KT
    assert parse_particles("sphere:100:agglutinated=2.5").agglutination_kT == 2.5
    assert parse_particles("sphere:300:rough").rough_top == ROUGH_DEFAULT
    assert parse_particles("sphere:300").rough_top == 0 and parse_particles("sphere:300").size_spread == 0
    spec = parse_particles("cylinder:200:inplane")
    assert (spec.shape.name, spec.diameter_nm, spec.orientation) == ("cylinder", 200.0, "inplane")
    # Equal specs written differently have one label (the cache key).
    assert parse_particles("sphere:100:agglutinated").label == parse_particles(
        f"sphere:100.0:agglutinated={AGGLUTINATED_DEFAULT_KT}").label


def test_cylinder_has_sphere_volume_and_six_radii():
    for d in (100.0, 200.0, 300.0):
        r, length = cylinder_radius_length(d)
        assert math.isclose(length, 6 * r)
        assert math.isclose(math.pi * r * r * length, math.pi / 6 * d**3, rel_tol=1e-12)


@pytest.mark.parametrize("text, words", [
    ("cube:100", ["unknown particle shape", "cube"]),
    ("cylinder:100:diagonal", ["unknown particle modifier", "diagonal", "isotropic"]),
    ("cylinder:100:orientation=diagonal", ["unknown cylinder orientation", "diagonal"]),
    ("sphere:-30", ["negative particle size", "-30"]),
    ("sphere:0", ["positive"]),
    ("sphere", ["lacks a diameter"]),
    ("sphere:abc", ["bad diameter"]),
    ("sphere:100:vertical", ["applies to", "cylinders", "not spheres"]),
    ("sphere:100:agglutinated=-1", ["agglutination", ">= 0"]),
    ("sphere:100:rough=1.5", ["rough top"]),
    ("", ["empty"]),
])
def test_bad_particle_specs_give_one_clear_error(text, words):
    with pytest.raises(ParticleSpecError) as info:
        parse_particles(text)
    for word in words:
        assert word in str(info.value)


def test_particle_larger_than_layer_is_refused():
    with pytest.raises(GeometryError, match="larger than the layer"):
        LayerSpec(parse_ink("R15"), parse_particles("sphere:450"), thickness_nm=400)
    # A vertical cylinder of effective diameter 300 nm is 545 nm long: too tall for 500 nm ...
    with pytest.raises(GeometryError, match="larger than the layer"):
        LayerSpec(parse_ink("R15"), parse_particles("cylinder:300:vertical"), thickness_nm=500)
    # ... while lying in the plane it is only 182 nm high.
    LayerSpec(parse_ink("R15"), parse_particles("cylinder:300:inplane"), thickness_nm=500)


def test_cell_too_small_and_bad_sizes_are_refused():
    with pytest.raises(GeometryError, match="too large for a"):
        LayerSpec(parse_ink("R15"), parse_particles("sphere:300"), cell_nm=(500, 500))
    with pytest.raises(GeometryError, match="thickness"):
        LayerSpec(parse_ink("R15"), parse_particles("sphere:100"), thickness_nm=-5)
    with pytest.raises(GeometryError, match="molecular"):
        LayerSpec(parse_ink("R15"), None)
    with pytest.raises(ParticleSpecError):
        ParticleSpec("sphere", -1.0)


@pytest.mark.parametrize("ink, particles", [("B70", "sphere:100"), ("B50", "cylinder:300:vertical")])
def test_unreachable_concentration_states_the_limit(ink, particles):
    layer = LayerSpec(parse_ink(ink), parse_particles(particles))
    limit = reachable_limit(layer)
    assert limit < parse_ink(ink).total_fraction
    with pytest.raises(UnreachableConcentrationError) as info:
        generate(layer, 0)
    assert info.value.limit == limit
    assert "reachable limit" in str(info.value) and f"{100 * limit:.3g}%" in str(info.value)


def test_vertical_cylinder_limit_follows_the_midplane_bound():
    """Vertical cylinders longer than half the layer all cross its mid-plane, where their
    sections are disjoint discs: φ ≤ (π/√12)·L/H whatever the packer does."""
    layer = LayerSpec(parse_ink("B30"), parse_particles("cylinder:300:vertical"))
    _, length = cylinder_radius_length(300.0)
    assert reachable_limit(layer) <= math.pi / math.sqrt(12) * length / 1000.0
