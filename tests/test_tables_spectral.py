"""Film-guided wavelength refinement (solver/table/spectral.py, docs/tables.md "Wavelength
stride"): solve every k-th wavelength, interpolate the difference to the exact film."""

import dataclasses

import numpy as np
import pytest

from solver.geometry import VoxelFractions
from solver.table.builder import BuildOptions, build_table
from solver.table.cache import TableCache
from solver.table.request import RequestError, table_request
from solver.table.schema import validate
from solver.table.spectral import refine, solved_indices
from solver.table.thinfilm_tier import build_thinfilm_table, request_film
from solver.table.wave_ensemble import reduce_units
from solver.table.wave_tier import SolveUnit, solve_unit


def test_solved_indices_take_every_kth_and_the_last():
    assert solved_indices(5, 1) == (0, 1, 2, 3, 4)
    assert solved_indices(21, 4) == (0, 4, 8, 12, 16, 20)
    assert solved_indices(21, 3) == (0, 3, 6, 9, 12, 15, 18, 20)
    assert solved_indices(3, 7) == (0, 2)
    with pytest.raises(ValueError):
        solved_indices(5, 0)


def test_stride_is_a_checked_request_option():
    assert table_request("R15", "sphere:100", wavelength_stride=3).solved_wavelength_indices[:2] == (0, 3)
    assert table_request("R15", "sphere:100", wavelength_stride=1).key() != table_request("R15", "sphere:100").key()
    with pytest.raises(RequestError, match="--wavelength-stride"):
        table_request("R15", "sphere:100", wavelength_stride=0)


def _film(req, wl):
    return build_thinfilm_table(req.layer.ink, req.thickness_nm, wl, req.grids.sigma_rad,
                                req.layer_materials(), polarisation=req.polarisation)


@pytest.mark.parametrize("polarisation", ["unpolarised", "te"])
def test_guide_carries_fringes_and_absorption_bands(polarisation):
    """The exact film of Y9+B7.5 refined from every 4th of 41 wavelengths (40-nm steps),
    guided by the exact film of Y7.5+B7.5 (same thickness: the same fringes, nearly the same
    bands): the refined spectrum is far closer to the exact Y9+B7.5 film than linear
    interpolation of its spectrum (up to 80°), equal to it where solved, and every identity of the table
    holds (schema validation)."""
    truth_req = table_request("Y9+B7.5", "molecular", polarisation=polarisation)
    guide_req = table_request("Y7.5+B7.5", "molecular", polarisation=polarisation)
    wl = np.arange(380.0, 781.0, 10.0)
    truth, guide = _film(truth_req, wl), _film(guide_req, wl)
    solved = solved_indices(wl.size, 4)
    coarse = _film(truth_req, wl[list(solved)])
    guided = validate(refine(coarse, guide, solved))
    flat = dataclasses.replace(guide, **{k: np.zeros_like(getattr(guide, k)) for k in
                                         ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")
                                         + (("Rbar_s", "Rbar_p", "Tbar_s", "Tbar_p", "r_s", "r_p")
                                            if guide.r_s is not None else ())})
    linear = refine(coarse, flat, solved)
    solved_sigma = truth.sigma <= np.radians(80.5)          # the particle tables' solved nodes
    for name in ("Rbar", "Tbar", "R_spec", "T_coh"):
        e_guided = np.max(np.abs(getattr(guided, name) - getattr(truth, name))[:, solved_sigma])
        e_linear = np.max(np.abs(getattr(linear, name) - getattr(truth, name))[:, solved_sigma])
        assert e_guided < 0.25 * e_linear, (name, e_guided, e_linear)     # measured 0.09–0.2
        np.testing.assert_array_equal(getattr(guided, name)[list(solved)], getattr(coarse, name))


def test_homogeneous_layer_through_the_wave_path_is_the_film_at_every_wavelength():
    """The molecular limit (a homogeneous voxel grid solved by the wave tier) at the solved
    wavelengths, refined: equal to the exact film at the wavelengths never solved too."""
    req = table_request("R15", "sphere:300", wavelengths_nm=(450.0, 490.0, 530.0),
                        sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])), grid=(16, 16, 8), realizations=1,
                        azimuths=2, dphi_count=7, tier="full", wavelength_stride=2)
    ink, (nx, ny, nz) = req.layer.ink, req.wave.grid
    fractions = np.zeros((3, nx, ny, nz), np.float32)
    fractions[0], fractions[2] = 1.0 - ink.total_fraction, ink.total_fraction
    vox = VoxelFractions(("binder", "air", "R"), fractions, (req.wave.cell_nm,) * 2, (0.0, req.thickness_nm))
    solved = req.solved_wavelength_indices
    assert solved == (0, 2)
    units = [[solve_unit(SolveUnit(req, 0, li, vox)) for li in solved]]
    sub = req.with_grids(wavelengths_nm=(450.0, 530.0))
    film = request_film(req)
    table = refine(reduce_units(sub, units, {"schema_version": 2, "polarisation": req.polarisation}), film, solved)
    for name in ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_s", "Rbar_p"):
        np.testing.assert_allclose(getattr(table, name)[1], getattr(film, name)[1], atol=2e-4)
    np.testing.assert_allclose(np.abs(table.r_s[1] - film.r_s[1]), 0.0, atol=2e-3)
    # linear interpolation of the spectrum itself misses the film at 490 nm by far more
    mid = 0.5 * (film.Tbar[0] + film.Tbar[2])
    assert np.max(np.abs(mid - film.Tbar[1])) > 10 * np.max(np.abs(table.Tbar[1] - film.Tbar[1]))


def test_a_strided_build_solves_only_its_wavelengths_and_equals_the_full_build_there(tmp_path):
    base = dict(wavelengths_nm=(450.0, 500.0, 550.0), sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])),
                grid=(16, 16, 8), realizations=2, azimuths=2, dphi_count=7, tier="full")
    opts = BuildOptions(progress=False, cache=TableCache(tmp_path / "cache"), workers=1)
    full = build_table(table_request("Y7.5+B7.5", "sphere:300", wavelength_stride=1, **base), opts)
    strided = build_table(table_request("Y7.5+B7.5", "sphere:300", wavelength_stride=2, **base), opts)
    validate(strided)
    assert strided.meta["solved_wavelengths_nm"] == [450.0, 550.0]
    assert strided.meta["solver_stats"]["solves"] == full.meta["solver_stats"]["solves"] * 2 // 3
    for name in ("R", "R_spec", "Rbar", "Tbar", "Rbar_below", "r_s", "Tbar_p"):
        np.testing.assert_array_equal(getattr(strided, name)[[0, 2]], getattr(full, name)[[0, 2]])
    # between them: the refined value is within a few standard errors of the solved one
    for name in ("Rbar", "Tbar"):
        gap = np.abs(getattr(strided, name)[1] - getattr(full, name)[1])
        assert np.all(gap <= 0.02 + 3 * full.errors[name][1]), (name, gap)


def test_a_deep_guide_never_breaks_energy():
    """A guide whose band is far deeper than the ink's (R50 guiding R5, every 4th of 41
    wavelengths solved): interpolated alone, the transmittance puts R̄ + T̄ above 1 between the
    solved wavelengths; capped at 1 − R̄ (the loss is never negative) nothing breaks energy, so
    no wavelength is named for solving, and the refined table holds every identity."""
    from solver.table.schema import energy_excess
    from solver.table.spectral import unsolved_breaking_energy

    truth_req = table_request("R5", "molecular")
    wl = np.arange(380.0, 781.0, 10.0)
    guide = _film(table_request("R50", "molecular"), wl)
    solved = solved_indices(wl.size, 4)
    sw = wl[list(solved)]
    coarse = _film(truth_req, sw)
    refined = refine(coarse, guide, solved)
    excess = energy_excess(refined)
    assert all(np.all(e <= 0) for e in excess.values()), {k: e.max() for k, e in excess.items()}
    assert unsolved_breaking_energy(refined, solved) == []
    validate(refined)
    # the cap did work here: the plainly guided transmittance exceeds 1 − R̄ somewhere
    diff = coarse.Tbar - guide.Tbar[list(solved)]
    plain = guide.Tbar + np.stack([np.interp(wl, sw, diff[:, j]) for j in range(diff.shape[1])], axis=1)
    assert np.max(plain + refined.Rbar - 1.0) > 1e-3


def test_flattening_has_duysens_limits():
    """The package effect of the guide: a thin grain absorbs as the dissolved pigment (→ 1 as
    αℓ → 0, first correction −3αℓ/8 from the sphere's chord distribution), a black one by its
    cross-section (Q → 1, so the ratio → 3/(2αℓ)); in between it falls monotonically."""
    from solver.table.spectral import flattening

    assert flattening(0.0) == 1.0
    assert flattening(0.01) == pytest.approx(1.0 - 3 * 0.01 / 8, rel=1e-4)
    assert flattening(200.0) == pytest.approx(3.0 / (2 * 200.0), rel=1e-2)
    x = np.linspace(0.01, 50.0, 200)
    assert np.all(np.diff(flattening(x)) < 0)


def test_a_wavelength_whose_refinement_breaks_energy_is_solved(tmp_path, monkeypatch):
    """The builder's guard: where the film-guided refinement still broke energy (here forced at
    the one interpolated wavelength: T̄ = 1 there), that wavelength is solved by the wave
    ensemble too, so the table is the fully solved one — never the broken numbers."""
    from solver.table import spectral

    base = dict(wavelengths_nm=(450.0, 500.0, 550.0), sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])),
                grid=(16, 16, 8), realizations=2, azimuths=2, dphi_count=7, tier="full")
    opts = BuildOptions(progress=False, cache=TableCache(tmp_path / "cache"), workers=1)
    full = build_table(table_request("Y7.5+B7.5", "sphere:300", wavelength_stride=1, **base), opts)
    real = spectral.refine

    def breaking(coarse, film, solved, meta=None):
        table = real(coarse, film, solved, meta)
        if 1 not in solved:
            table.Tbar[1] = 1.0
        return table

    monkeypatch.setattr(spectral, "refine", breaking)
    guarded = build_table(table_request("Y7.5+B7.5", "sphere:300", wavelength_stride=2, **base), opts)
    assert "solved_wavelengths_nm" not in guarded.meta
    for name in ("Rbar", "Tbar", "R"):
        np.testing.assert_array_equal(getattr(guarded, name), getattr(full, name))
