"""Voxel fractions: exact pigment volume, local accuracy, periodic wrap, rough top, ε mixing."""

import dataclasses

import numpy as np
import pytest

from solver.geometry import LayerSpec, eps_grid, generate, parse_particles, voxelize
from solver.geometry.voxelize import lines_per_voxel
from solver.inks import parse_ink
from solver.materials import BINDER_INDEX, pigment_eps


def make(ink, particles, seed=2, thickness=1000.0, cell=(1000.0, 1000.0)):
    return generate(LayerSpec(parse_ink(ink), parse_particles(particles), thickness, cell), seed)


def particle_volumes(real):
    r, length = real.radii_nm, real.lengths_nm
    return np.where(length > 0, np.pi * r**2 * length, 4.0 / 3.0 * np.pi * r**3)


def check_volumes(real, vox, tolerance=0.005):
    vol = particle_volumes(real)
    for code in real.population_codes:
        exact = vol[real.pigments == code].sum()
        assert abs(vox.volume_nm3(code) / exact - 1) < tolerance, code
    total = sum(vox.volume_nm3(m) for m in vox.materials)
    cell = real.period_nm[0] * real.period_nm[1] * (real.z_range_nm[1] - real.z_range_nm[0])
    assert abs(total / cell - 1) < 1e-5
    f = vox.fractions
    assert f.dtype == np.float32 and f.min() >= 0.0
    assert np.allclose(f.sum(axis=0), 1.0, atol=1e-5)


@pytest.mark.parametrize("ink, particles, grid, cell, thickness", [
    ("Y7.5+B7.5", "sphere:100", (64, 64, 64), (1000.0, 1000.0), 1000.0),
    ("R50", "sphere:30", (16, 16, 8), (600.0, 600.0), 300.0),         # 37.5-nm voxels > 30-nm grains
    ("R50", "sphere:30", (40, 40, 20), (600.0, 600.0), 300.0),
    ("Y25+B5", "sphere:100:spread=0.3", (50, 50, 50), (1000.0, 1000.0), 1000.0),
    ("B30", "cylinder:100:isotropic", (64, 64, 64), (1000.0, 1000.0), 1000.0),
    ("B30", "cylinder:100:inplane", (32, 32, 32), (1000.0, 1000.0), 1000.0),
    ("B30", "cylinder:100:vertical", (48, 48, 48), (1000.0, 1000.0), 1000.0),
    ("Y15+B15", "cylinder:100:inplane", (40, 30, 16), (1000.0, 600.0), 800.0),   # oblong voxels
])
def test_grid_pigment_volume_equals_particle_volume(ink, particles, grid, cell, thickness):
    real = make(ink, particles, cell=cell, thickness=thickness)
    vox = voxelize(real, grid)
    check_volumes(real, vox)
    assert vox.materials == ("binder", "air") + real.population_codes
    assert vox.volume_nm3("air") == 0.0                          # flat top: no air in the cell


def reference_fractions(real, index, shape, samples=24):
    """Fractions of one particle by dense point sampling (samples³ points per voxel)."""
    nx, ny, nz = shape
    lx, ly = real.period_nm
    z0, z1 = real.z_range_nm
    c, r = real.centres_nm[index], real.radii_nm[index]
    out = np.zeros(shape)
    dx, dy, dz = lx / nx, ly / ny, (z1 - z0) / nz
    sub = (np.arange(samples) + 0.5) / samples
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                x = (i + sub) * dx
                y = (j + sub) * dy
                z = z0 + (k + sub) * dz
                X, Y, Z = np.meshgrid(x - c[0], y - c[1], z - c[2], indexing="ij")
                X -= lx * np.round(X / lx)
                Y -= ly * np.round(Y / ly)
                out[i, j, k] = np.mean(X * X + Y * Y + Z * Z < r * r)
    return out


def single_sphere(real, centre, radius):
    return dataclasses.replace(real, centres_nm=np.array([centre], dtype=float), radii_nm=np.array([radius]),
                               lengths_nm=np.zeros(1), axes=np.array([[0.0, 0.0, 1.0]]),
                               population=np.zeros(1, dtype=int), protrusion=np.zeros(1))


def test_sub_voxel_fractions_match_dense_sampling_and_wrap_periodically():
    base = make("B15", "sphere:100", cell=(400.0, 400.0), thickness=200.0)
    shape = (16, 16, 8)                                        # 25-nm voxels
    # A sphere straddling the x and y boundaries.
    one = single_sphere(base, (390.0, 7.0, 93.0), 41.0)
    vox = voxelize(one, shape)
    pig = vox.fractions[2]
    ref = reference_fractions(one, 0, shape)
    assert np.abs(pig - ref).max() < 0.03                      # no staircase: close to exact
    assert pig[0].sum() > 0 and pig[-1].sum() > 0 and pig[:, 0].sum() > 0 and pig[:, -1].sum() > 0
    check_volumes(one, vox, tolerance=1e-5)
    # Translation by whole voxels (through the boundary) only rolls the grid.
    moved = single_sphere(base, (390.0 + 5 * 25.0 - 400.0, 7.0 + 3 * 25.0, 93.0), 41.0)
    rolled = np.roll(np.roll(pig, 5, axis=0), 3, axis=1)
    assert np.abs(voxelize(moved, shape).fractions[2] - rolled).max() < 1e-5


def test_grain_smaller_than_a_voxel_counts_in_full():
    base = make("B15", "sphere:100", cell=(400.0, 400.0), thickness=200.0)
    for centre in [(12.0, 13.0, 50.0), (25.0, 25.0, 25.0), (199.9, 0.1, 100.0)]:
        one = single_sphere(base, centre, 15.0)
        vox = voxelize(one, (8, 8, 4))                          # 50-nm voxels, 30-nm grain
        assert vox.volume_nm3("B") == pytest.approx(4 / 3 * np.pi * 15.0**3, rel=1e-5)
        assert vox.fractions[2].max() < 0.5
    assert 50.0 / lines_per_voxel(50.0, 15.0) <= 15.0 / 3        # line spacing ≤ r/3


def test_rough_top_voxels_above_the_binder_are_air():
    real = make("G30", "sphere:300:rough", cell=(2000.0, 2000.0))
    vox = voxelize(real, (64, 64, 48))
    check_volumes(real, vox)
    z_top, z_bottom = vox.z_range_nm
    assert z_top < 0 and vox.volume_nm3("air") > 0
    dz = (z_bottom - z_top) / 48
    air = vox.fractions[1]
    # The top voxel row starts at the highest grain's apex: air, and that grain's cap.
    assert np.mean(air[:, :, 0]) > 0.99 and vox.fractions[0, :, :, 0].max() < 0.02
    # Below z = 0 there is no air.
    below = int(np.ceil(-z_top / dz)) + 1
    assert air[:, :, below:].max() < 1e-6
    # Air volume: cell above the flat top minus what grains and menisci fill there.
    assert vox.volume_nm3("air") < 2000.0 * 2000.0 * (-z_top)


def test_eps_grid_is_the_linear_mix():
    real = make("Y15+B15", "sphere:100", cell=(600.0, 600.0), thickness=500.0)
    vox = voxelize(real, (24, 24, 20))
    wl = 550.0
    eps = eps_grid(vox, wl)
    assert eps.shape == vox.shape and np.iscomplexobj(eps)
    f = vox.fractions.astype(float)
    expect = f[0] * BINDER_INDEX**2 + f[1] * 1.0 + f[2] * pigment_eps("Y", wl) + f[3] * pigment_eps("B", wl)
    assert np.allclose(eps, expect)
    pure_binder = f[0] > 1 - 1e-7
    assert np.allclose(eps[pure_binder], BINDER_INDEX**2)
    assert np.all(eps.imag >= 0)
    assert not np.allclose(eps_grid(vox, 450.0), eps)          # pigments are dispersive
