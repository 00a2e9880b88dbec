"""Spheres and cylinders give the same grains and voxels for the same seed as before the shapes
became objects (docs/geometry.md, "Shapes"): a few small cells of each shape, orientation and
modifier, generated and voxelised, compared exactly with the arrays the code wrote before that
refactor (tests/data/shape_cells.npz, made by `python -m tests.test_geometry_regression` on the
old code, commit 91f76af).  Cached tables of spheres and cylinders stay right only if this holds.
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
ARRAYS = ("centres_nm", "axes", "radii_nm", "lengths_nm", "population", "protrusion")


def cell_arrays(ink: str, particles: str, cell: float, thickness: float, seed: int) -> dict[str, np.ndarray]:
    layer = LayerSpec(parse_ink(ink), parse_particles(particles), thickness, (cell, cell))
    real = generate(layer, seed)
    out = {name: np.asarray(getattr(real, name)) for name in ARRAYS}
    out["z_range_nm"] = np.asarray(real.z_range_nm)
    out["fractions"] = voxelize(real, GRID).fractions
    return out


def _key(index: int, name: str) -> str:
    return f"{index}/{name}"


def _values(case) -> tuple:
    return case.values[0] if hasattr(case, "values") else case


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[0]}-{c[1]}")
def test_same_grains_and_voxels_as_before_the_refactor(case):
    stored = np.load(FIXTURE)
    index = stored["cases"].tolist().index(repr(case))
    for name, value in cell_arrays(*case).items():
        np.testing.assert_array_equal(value, stored[_key(index, name)], err_msg=f"{case}: {name}")


if __name__ == "__main__":
    cases = [_values(c) for c in CASES]
    arrays = {"cases": np.array([repr(c) for c in cases])}
    for k, case in enumerate(cases):
        for name, value in cell_arrays(*case).items():
            arrays[_key(k, name)] = value
    np.savez_compressed(FIXTURE, **arrays)
    print(f"wrote {FIXTURE} ({FIXTURE.stat().st_size} bytes)")
