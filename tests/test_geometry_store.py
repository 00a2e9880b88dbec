"""One geometry, many inks (solver/table/geometry_store.py): inks that put the same load of
one pigment on the same grains share their voxel fractions bit for bit, so a table reuses the
realizations another ink's table drew, and gets the numbers it would have computed itself."""

import logging

import numpy as np
import pytest

from solver.table import geometry_store
from solver.table.builder import BuildOptions, build_table
from solver.table.cache import TableCache
from solver.table.request import table_request
from solver.table.wave_tier import GeometryUnit, geometry_unit

COLUMNS = ("R", "R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")


def small(ink: str, particles: str = "sphere:300", **kw):
    base = dict(wavelengths_nm=(450.0, 700.0), sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])), grid=(16, 16, 8),
                realizations=2, azimuths=1, dphi_count=7, tier="full")
    base.update(kw)
    return table_request(ink, particles, **base)


def test_voxels_depend_on_the_grains_not_on_the_pigment():
    """The invariant the store rests on, checked by drawing the realizations, not by the key."""
    voxels = {ink: geometry_unit(GeometryUnit(small(ink, "sphere:100"), 1)) for ink in ("R15", "Y15", "G15")}
    for ink in ("Y15", "G15"):
        np.testing.assert_array_equal(voxels[ink].fractions, voxels["R15"].fractions)
        assert voxels[ink].materials == ("binder", "air", ink[0])
    mix = geometry_unit(GeometryUnit(small("Y7.5+B7.5", "sphere:100"), 1))
    assert mix.fractions.shape[0] == 4                          # binder, air, Y, B: grains of two pigments


def test_key_names_everything_the_voxels_depend_on():
    base = geometry_store.key(small("R15"), 0)
    assert geometry_store.key(small("B15"), 0) == base
    for other in (geometry_store.key(small("R15"), 1), geometry_store.key(small("R30"), 0),
                  geometry_store.key(small("Y7.5+B7.5"), 0), geometry_store.key(small("R15", "sphere:200"), 0),
                  geometry_store.key(small("R15", grid=(16, 16, 16)), 0), geometry_store.key(small("R15", seed=2), 0),
                  geometry_store.key(small("R15", thickness_nm=800.0), 0)):
        assert other != base


def test_relabel_refuses_a_geometry_with_other_pigment_count():
    vox = geometry_unit(GeometryUnit(small("Y7.5+B7.5", "sphere:100"), 0))
    with pytest.raises(ValueError, match="key is wrong"):
        geometry_store.relabel(vox, small("R15", "sphere:100"))


def test_second_ink_on_the_same_grains_draws_no_geometry(tmp_path, caplog):
    cache = TableCache(tmp_path / "shared")
    opts = BuildOptions(progress=False, cache=cache, workers=1)
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        build_table(small("R15"), opts)
        assert "geometry: 2 of 2 units to compute" in caplog.text
        caplog.clear()
        shared = build_table(small("Y15"), opts)
    assert "geometry:" not in caplog.text                     # both realizations came from R15's
    assert "shared grains: 2 of 2 realizations read from the cache" in caplog.text
    alone = build_table(small("Y15"), BuildOptions(progress=False, cache=TableCache(tmp_path / "own"), workers=1))
    for name in COLUMNS:
        np.testing.assert_array_equal(getattr(shared, name), getattr(alone, name))
    assert len(list((tmp_path / "shared" / "geometry").glob("*.npz"))) == 2


@pytest.mark.parametrize("azimuths, probed", [(2, 1), (1, 2)])
def test_an_effective_medium_table_draws_only_the_probe_realization(tmp_path, caplog, azimuths, probed):
    """Tier auto solves realization 0 to choose (0 and 1 where one azimuth per realization
    alternates TE and TM over the realizations); a film (effective medium) needs no other."""
    req = small("R15", "sphere:30", tier="auto", realizations=4, azimuths=azimuths, grid=(24, 24, 12),
                tolerance=0.05)           # the film within tolerance of both probed realizations
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        table = build_table(req, BuildOptions(progress=False, cache=TableCache(tmp_path / "c"), workers=1))
    assert table.meta["tier"] == "effective-medium", table.meta["tier"]
    assert f"geometry: {probed} of {probed} units to compute" in caplog.text
    assert len(list((tmp_path / "c" / "geometry").glob("*.npz"))) == probed
