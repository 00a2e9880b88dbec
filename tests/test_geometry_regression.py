"""Spheres and cylinders give the same grains and voxels for the same seed as before the shapes
became objects (docs/geometry.md, "Shapes"): a few small cells of each shape, orientation and
modifier, generated and voxelised, compared exactly with the arrays the code wrote before that
refactor (tests/data/shape_cells.npz, made by `python -m tests.test_geometry_regression` on the
old code, commit 91f76af).  Cached tables of spheres and cylinders stay right only if this holds.

"The same" up to the last bits of floating point: NumPy picks its vectorised exp/sin/cos for the
CPU it runs on (AVX-512 or AVX2 paths differ in the last ulp), so positions are compared to
1e-9 relative, not bit for bit. Agglutination is a Metropolis walk: an ulp decides an accept
now and then, after which the walk goes elsewhere (1e-5 nm on one host became 34 nm on another),
so agglutinated cells are compared by what the walk cannot change: the grains drawn (sizes,
populations, count) and the pigment volume the voxels hold.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from solver.geometry import LayerSpec, generate, parse_particles, voxelize
from solver.inks import parse_ink

FIXTURE = Path(__file__).parent / "data" / "shape_cells.npz"

#: (ink, particles, cell nm, thickness nm, seed): RSA, packing (each rotation mode), agglutination,
#: rough top, size spread, tilt
CASES = (
    ("Y7.5+B7.5", "sphere:100", 800.0, 500.0, 1),
    ("R35", "sphere:80", 600.0, 400.0, 2),
    ("R10", "sphere:100:agglutinated", 700.0, 500.0, 3),
    ("B15", "sphere:120:rough:spread=0.2", 800.0, 600.0, 4),
    ("B10", "cylinder:100:isotropic", 700.0, 500.0, 5),
    ("B30", "cylinder:90:inplane", 600.0, 400.0, 6),
    ("B30", "cylinder:90:isotropic", 600.0, 400.0, 7),
    ("B22", "cylinder:80:vertical:tilt=15", 600.0, 400.0, 8),
    ("R12", "cylinder:120:isotropic:rough", 800.0, 600.0, 9),
    ("B20", "cylinder:80:vertical", 500.0, 400.0, 11),
    pytest.param(("B6", "cylinder:80:isotropic:agglutinated", 500.0, 400.0, 10), marks=pytest.mark.slow),
)
GRID = (16, 16, 8)
#: layers whose limits, cost estimate and local field are compared too: (ink, particles, thickness nm, cell nm)
LAYERS = tuple((ink, particles, 1000.0, 2000.0) for ink in ("R15", "Y25+B25")
               for particles in ("sphere:100", "sphere:30:spread=0.3", "sphere:300:rough:agglutinated",
                                 "cylinder:100:isotropic", "cylinder:200:inplane:tilt=10",
                                 "cylinder:300:vertical", "cylinder:300:vertical:tilt=40:rough",
                                 "cylinder:100:isotropic:agglutinated=2:spread=0.1"))
#: what a Metropolis walk moves (compared only where no walk ran)
WALKED = ("centres_nm", "axes", "protrusion", "z_range_nm")
ARRAYS = ("centres_nm", "axes", "radii_nm", "lengths_nm", "population", "protrusion")


def cell_arrays(ink: str, particles: str, cell: float, thickness: float, seed: int) -> dict[str, np.ndarray]:
    layer = LayerSpec(parse_ink(ink), parse_particles(particles), thickness, (cell, cell))
    real = generate(layer, seed)
    out = {name: np.asarray(getattr(real, name)) for name in ARRAYS}
    out["z_range_nm"] = np.asarray(real.z_range_nm)
    out["fractions"] = voxelize(real, GRID).fractions
    return out


def layer_numbers(ink: str, particles: str, thickness: float, cell: float) -> np.ndarray:
    """Reachable limit, cost estimate (grains, bytes, seconds), local-field pairs, height and span."""
    from solver.geometry import geometry_cost, reachable_limit
    from solver.geometry.depolarisation import local_field_of

    layer = LayerSpec(parse_ink(ink), parse_particles(particles), thickness, (cell, cell))
    cost = geometry_cost(layer, (128, 128, 64))
    field = [x for pair in local_field_of(layer.particles).pairs for x in pair]
    return np.array([reachable_limit(layer), cost.grains, cost.peak_bytes, cost.seconds] + field)


def _key(index: int, name: str) -> str:
    return f"{index}/{name}"


def _values(case) -> tuple:
    return case.values[0] if hasattr(case, "values") else case


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[0]}-{c[1]}")
def test_same_grains_and_voxels_as_before_the_refactor(case):
    stored = np.load(FIXTURE)
    index = stored["cases"].tolist().index(repr(case))
    walk = "agglutinated" in case[1]
    for name, value in cell_arrays(*case).items():
        old = stored[_key(index, name)]
        if walk and name in WALKED:
            continue
        if walk and name == "fractions":
            assert value.sum() == pytest.approx(old.sum(), rel=0.02), f"{case}: pigment volume in voxels"
            continue
        np.testing.assert_allclose(value, old, rtol=1e-9, atol=1e-9, err_msg=f"{case}: {name}")


def test_same_limits_costs_and_local_fields_as_before_the_refactor():
    stored = np.load(FIXTURE)
    assert stored["layers"].tolist() == [repr(c) for c in LAYERS]
    for k, layer in enumerate(LAYERS):
        np.testing.assert_array_equal(layer_numbers(*layer), stored[f"layer/{k}"], err_msg=str(layer))
        assert parse_particles(layer[1]).label == str(stored["labels"][k])


if __name__ == "__main__":
    cases = [_values(c) for c in CASES]
    arrays = {"cases": np.array([repr(c) for c in cases])}
    for k, case in enumerate(cases):
        for name, value in cell_arrays(*case).items():
            arrays[_key(k, name)] = value
    arrays["layers"] = np.array([repr(c) for c in LAYERS])
    arrays["labels"] = np.array([parse_particles(c[1]).label for c in LAYERS])
    for k, layer in enumerate(LAYERS):
        arrays[f"layer/{k}"] = layer_numbers(*layer)
    np.savez_compressed(FIXTURE, **arrays)
    print(f"wrote {FIXTURE} ({FIXTURE.stat().st_size} bytes)")
