"""Particle-ink tables from the wave solver: equal to direct solves, energy, reciprocity,
the molecular limit, the cache (hit, resume after a kill, one build per ink), workers and Dask."""

import itertools
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from bsdf_probes import evaluate, hemisphere, ink_bsdf, sampled_albedo
from conftest import process_group
from oracles import reference_eval
from solver.geometry import VoxelFractions, eps_grid
from solver.inks import molecular_eps, parse_ink
from solver.materials import DISSOLVED_FIELD, default_materials
from solver.table import read_table
from solver.table.builder import BuildOptions, build_table, get_or_build
from solver.table.cache import TableCache
from solver.table.integrals import diffuse_albedo
from solver.table.request import TableRequest, table_request
from solver.table.thinfilm_tier import build_thinfilm_table
from solver.table.wave_ensemble import reduce_units
from solver.table.wave_tier import GeometryUnit, SolveUnit, azimuths, geometry_unit, samples, solve_unit
from solver.wave import Cell, Incidence, solve

COLUMNS = ("R", "R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")


def small(**kw) -> TableRequest:
    base = dict(ink="Y7.5+B7.5", particles="sphere:300", wavelengths_nm=(450.0, 700.0),
                sigma_rad=tuple(np.radians([0.0, 40.0, 90.0])), grid=(16, 16, 8), realizations=2,
                azimuths=1, dphi_count=7, tier="full")
    base.update(kw)
    return table_request(base.pop("ink"), base.pop("particles"), **base)


def opts(tmp_path, workers=1, **kw) -> BuildOptions:
    """In-process by default (tiny tables: spawning workers costs more than it saves)."""
    return BuildOptions(progress=False, cache=TableCache(tmp_path / "cache"), workers=workers, **kw)


@pytest.fixture(scope="module")
def table_and_request(tmp_path_factory):
    req = small()
    return build_table(req, opts(tmp_path_factory.mktemp("t"))), req


@pytest.mark.parametrize("polarisation", ["te", "unpolarised"])
def test_small_table_equals_direct_solves(tmp_path, polarisation):
    """One realization, one azimuth: a TE table is the TE solve; an unpolarised one is the mean
    of the TE and TM solves, with the s and p amplitudes stored (conjugated: Mitsuba's sign)."""
    req = small(realizations=1, polarisation=polarisation)
    table = build_table(req, opts(tmp_path))
    vox = geometry_unit(GeometryUnit(req, 0))
    phi = azimuths(req, 0)[0]
    pols = ("te",) if polarisation == "te" else ("te", "tm")
    for li, wl in enumerate(req.grids.wavelengths_nm):
        cell = Cell(eps_grid(vox, wl, req.layer_materials()), vox.period_nm, vox.z_range_nm)
        eps_b = complex(molecular_eps(req.layer.ink, wl, req.layer_materials()))
        for si, sigma in enumerate(req.grids.sigma_rad[:-1]):
            direct = [solve(cell, Incidence(wl, sigma, phi), tol=req.wave.solver_tol, eps_background=eps_b,
                            eps_face=eps_b, polarisation=p) for p in pols]   # faces: the layer's ε
            mean = lambda f: np.mean([f(d) for d in direct])
            assert table.Rbar[li, si] == pytest.approx(mean(lambda d: d.R), abs=1e-9)
            assert table.Tbar[li, si] == pytest.approx(mean(lambda d: d.T), abs=1e-9)
            assert table.R_spec[li, si] == pytest.approx(mean(lambda d: d.R_spec), abs=1e-9)  # one sample: coherent = |α00|²
            assert table.T_coh[li, si] == pytest.approx(mean(lambda d: d.T_coh), abs=1e-9)
            if polarisation == "unpolarised":
                assert table.Rbar_s[li, si] == pytest.approx(direct[0].R, abs=1e-9)
                assert table.Tbar_p[li, si] == pytest.approx(direct[1].T, abs=1e-9)
                for amp, d in ((table.r_s, direct[0]), (table.r_p, direct[1])):
                    assert np.conj(amp[li, si]) == pytest.approx(d.reflected.amp(0, 0), abs=1e-9)
    assert table.polarisation == polarisation


@pytest.fixture(scope="module")
def alternating(tmp_path_factory):
    req = small(realizations=4)
    return build_table(req, opts(tmp_path_factory.mktemp("alt"))), req


def test_one_azimuth_alternates_polarisation_over_realizations(alternating):
    """Four realizations of one azimuth: TE in realizations 0 and 2, TM in 1 and 3, each solve
    its own cell; the unpolarised Rbar is the mean of the TE and TM means and its standard
    error the independent groups' sqrt(SE_TE² + SE_TM²)/2 with N − 2 degrees of freedom
    (written out here from the units, not through the reduction's code)."""
    table, req = alternating
    assert [p for r in range(4) for _, p in samples(req, r)] == [0, 1, 0, 1]
    units = [[solve_unit(SolveUnit(req, r, li, geometry_unit(GeometryUnit(req, r))))
              for li in range(2)] for r in range(4)]
    solved = np.flatnonzero(req.grids.solved_mask)
    for li in range(2):
        te = np.array([units[r][li]["Rbar"][:, 0] for r in (0, 2)])
        tm = np.array([units[r][li]["Rbar"][:, 0] for r in (1, 3)])
        np.testing.assert_allclose(table.Rbar[li, solved], (te.mean(0) + tm.mean(0)) / 2, atol=1e-12)
        se = np.sqrt(te.var(0, ddof=1) / 2 + tm.var(0, ddof=1) / 2) / 2
        np.testing.assert_allclose(table.errors["Rbar"][li, solved], se, atol=1e-12)
        np.testing.assert_allclose(table.Rbar_s[li, solved], te.mean(0), atol=1e-12)
    assert table.meta["errors"]["se_dof"] == 2
    assert table.meta["solver_stats"]["solves"] == 4 * 2 * solved.size     # one solve per cell and σ
    # the jackknife's strata are the TE and TM cells: its Rbar replicas give the groups' SE too
    assert table.meta["jackknife_groups"] == [0, 1, 0, 1]
    from solver.table import jackknife
    loo = [r["Rbar"] for r in jackknife.replicas(table)]
    np.testing.assert_allclose(jackknife.standard_error(loo, [0, 1, 0, 1]), table.errors["Rbar"], atol=1e-6)


@pytest.mark.parametrize("which", ["table_and_request", "alternating"])
def test_energy_closure_with_independently_computed_absorption(which, request):
    """R̄ + T̄ + A = 1, A the absorptance by quadrature of ∫ Im ε |u|² (solve(..., exact_energy=True):
    independent of the table's R and T) for the realizations, azimuths and polarisations the
    table averaged, averaged the same way (per polarisation over the realizations that solved it,
    then over TE/TM): `alternating` has TE in realizations 0, 2 and TM in 1, 3.
    The layer absorbs a lot (A ≈ 0.4–0.55): the closure is not R̄ + T̄ ≈ 1 by luck."""
    table, req = request.getfixturevalue(which)
    solved = np.flatnonzero(req.grids.solved_mask)
    absorbed = {0: [], 1: []}                            # polarisation → per-realization [λ, σ]
    for r in range(req.wave.realizations):
        vox, phis = geometry_unit(GeometryUnit(req, r)), azimuths(req, r)
        todo = samples(req, r)                           # (azimuth index, polarisation) per solve
        for pol in {p for _, p in todo}:
            a_r = np.zeros((len(req.grids.wavelengths_nm), solved.size))
            mine = [j for j, p in todo if p == pol]
            for li, wl in enumerate(req.grids.wavelengths_nm):
                cell = Cell(eps_grid(vox, wl, req.layer_materials()), vox.period_nm, vox.z_range_nm)
                eps_b = complex(molecular_eps(req.layer.ink, wl, req.layer_materials()))
                for (k, si), j in itertools.product(enumerate(solved), mine):
                    res = solve(cell, Incidence(wl, req.grids.sigma_rad[si], phis[j]), tol=req.wave.solver_tol,
                                eps_background=eps_b, polarisation=("te", "tm")[pol], exact_energy=True)
                    assert res.energy_check == "quadrature"
                    a_r[li, k] += res.absorbed / len(mine)
            absorbed[pol].append(a_r)
    a = np.mean([np.mean(absorbed[p], axis=0) for p in (0, 1)], axis=0)
    assert req.polarisation == "unpolarised" and a.min() > 0.3
    np.testing.assert_allclose(table.Rbar[:, solved] + table.Tbar[:, solved] + a, 1.0, atol=2e-4)
    grazing = ~req.grids.solved_mask                    # σ = 90°: mirrored, nothing enters
    np.testing.assert_array_equal(table.Rbar[:, grazing] + table.Tbar[:, grazing], 1.0)
    assert table.meta["errors"]["energy_closure_max"] < 1e-3     # the build's own closure, reported


def test_rbar_is_specular_plus_diffuse_albedo(table_and_request):
    """The reduction's bookkeeping: R̄ = R_spec + ∫R cos θ dω/π (the incoherent part of the 00
    order placed in R), and R̄ + T̄ ≤ 1."""
    table, _ = table_and_request
    np.testing.assert_allclose(table.Rbar, table.R_spec + diffuse_albedo(table.theta, table.dphi, table.R),
                               atol=1e-12)
    assert np.all(table.Rbar + table.Tbar <= 1 + 1e-3)


def test_lossless_particles_conserve_energy(tmp_path):
    # F8BT (Y) is transparent at 650–700 nm: a lossless particle layer, R + T = 1.  (The scheme
    # sees the background's fictitious loss only through an O(h⁴) z-term: nz = 16 keeps it < 2e-4.)
    table = build_table(small(ink="Y30", wavelengths_nm=(680.0, 700.0), realizations=1, grid=(16, 16, 16)),
                        opts(tmp_path))
    np.testing.assert_allclose((table.Rbar + table.Tbar)[:, :-1], 1.0, atol=2e-3)


def test_reciprocity_after_symmetrisation(table_and_request):
    table, _ = table_and_request
    np.testing.assert_allclose(table.R, np.swapaxes(table.R, 1, 2), atol=1e-15)
    assert table.has_diffuse and np.all(table.R >= 0)


def test_molecular_ink_through_the_wave_path_equals_the_exact_tier():
    """A homogeneous voxel grid (the molecular mix) through solve_unit + reduce = the thin film."""
    req = small(ink="R15", realizations=1, wavelengths_nm=(450.0, 530.0))
    ink = req.layer.ink
    nx, ny, nz = req.wave.grid
    fractions = np.zeros((3, nx, ny, nz), np.float32)
    fractions[0], fractions[2] = 1.0 - ink.total_fraction, ink.total_fraction
    vox = VoxelFractions(("binder", "air", "R"), fractions, (req.wave.cell_nm,) * 2, (0.0, req.thickness_nm))
    units = [[solve_unit(SolveUnit(req, 0, li, vox)) for li in range(2)]]
    table = reduce_units(req, units, {"schema_version": 1})
    film = build_thinfilm_table(ink, req.thickness_nm, req.grids.wavelengths_nm, req.grids.sigma_rad,
                                req.layer_materials(),            # the same ε: the spheres' local field
                                polarisation=req.polarisation)    # TE and TM faces in the wave path
    for name in ("R_spec", "T_coh", "Rbar", "Tbar"):
        np.testing.assert_allclose(getattr(table, name), getattr(film, name), atol=2e-4)
    assert np.max(table.R) < 1e-6          # a homogeneous layer scatters nothing diffusely


def test_molecular_request_is_the_exact_tier(tmp_path):
    """Unpolarised (default): dissolved pigment with the Lorentz sphere's local field."""
    table, _, built = get_or_build(table_request("Y12.5+B2.5"), opts(tmp_path))
    film = build_thinfilm_table(parse_ink("Y12.5+B2.5"), 1000.0, table.wavelengths, table.sigma,
                                default_materials().with_local_field(DISSOLVED_FIELD),
                                polarisation=table.polarisation)
    assert built and table.meta["tier"] == "thin-film"
    for name in COLUMNS:
        np.testing.assert_array_equal(getattr(table, name), getattr(film, name))
    te, _, _ = get_or_build(table_request("Y12.5+B2.5", polarisation="te"), opts(tmp_path))
    film_te = build_thinfilm_table(parse_ink("Y12.5+B2.5"), 1000.0, te.wavelengths, te.sigma,
                                   polarisation="te")          # the paper's model: bulk ε, volume mix
    for name in COLUMNS:
        np.testing.assert_array_equal(getattr(te, name), getattr(film_te, name))
    # the local field enhances the field inside the (optically thinner) pigment: more absorption
    plain, _, _ = get_or_build(table_request("Y12.5+B2.5", local_field=False), opts(tmp_path))
    assert np.all(table.Tbar[:, 0] <= plain.Tbar[:, 0] + 1e-12) and (plain.Tbar - table.Tbar)[:, 0].max() > 0.01


def test_cache_hit_computes_nothing(tmp_path, monkeypatch):
    o = opts(tmp_path)
    req = small(realizations=1, wavelengths_nm=(500.0, 600.0))
    first, path, built = get_or_build(req, o)
    assert built
    import solver.table.wave_tier as wt

    def boom(*a, **k):
        raise AssertionError("computed on a cache hit")

    monkeypatch.setattr(wt, "solve_unit", boom)
    monkeypatch.setattr(wt, "geometry_unit", boom)
    again, path2, built2 = get_or_build(req, o)
    assert not built2 and path2 == path
    for name in COLUMNS:
        np.testing.assert_array_equal(getattr(again, name), getattr(first, name))


def test_tier_choice_is_measured_and_recorded(tmp_path):
    # 300-nm grains are far from the effective medium: the probe must see it
    table = build_table(small(tier="auto", realizations=1), opts(tmp_path))
    probe = table.meta["tier_probe"]
    assert table.meta["tier"] in ("born", "full")
    assert probe["deviation"]["effective-medium"] > probe["tolerance"]
    # tiny, dilute grains: the mean-ε film is within tolerance and no table solve is run
    tiny = build_table(small(tier="auto", particles="sphere:30", ink="Y5", realizations=1,
                             tolerance=0.02), opts(tmp_path))
    assert tiny.meta["tier"] == "effective-medium", tiny.meta["tier_probe"]
    assert tiny.meta["tier_probe"]["deviation"]["effective-medium"] <= 0.02


@pytest.mark.slow
def test_identical_for_any_number_of_workers_and_on_dask(tmp_path):
    import dask.config
    from distributed import LocalCluster

    req = small(azimuths=2)
    serial = build_table(req, opts(tmp_path / "a"))
    pool = build_table(req, opts(tmp_path / "b", workers=2))
    scratch = tmp_path / "dask-scratch"      # the workers' scratch space stays in the test's folder
    with dask.config.set({"temporary-directory": str(scratch)}), \
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                         local_directory=str(scratch)) as cluster:
        dask = build_table(req, opts(tmp_path / "c", scheduler=cluster.scheduler_address))
    assert scratch.is_dir()
    for other in (pool, dask):
        for name in COLUMNS:
            np.testing.assert_array_equal(getattr(other, name), getattr(serial, name))


@pytest.mark.slow
def test_killed_build_resumes_from_finished_units(tmp_path):
    cache = tmp_path / "cache"
    args = [sys.executable, "-m", "solver.apps.cli", "-v", "build", "--ink", "Y7.5+B7.5", "--particles", "sphere:300",
            "--wavelengths", "400:700:20", "--angles", "4", "--grid", "24", "24", "12", "--realizations", "1",
            "--azimuths", "2", "--tier", "full", "--wavelength-stride", "1", "--cache", str(cache), "--no-progress",
            "-o", str(tmp_path / "t.npz")]
    # a session of its own: every process the build starts (pool workers, the resource tracker)
    # carries its process-group id, so we can see whether any outlives the kill
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    parts = lambda: sorted(cache.glob("parts/*/full_*.npz"))
    deadline = time.time() + 120
    while len(parts()) < 3 and time.time() < deadline and proc.poll() is None:
        time.sleep(0.02)
    assert len(process_group(proc.pid)) >= 2, "the build was meant to run on a pool of workers"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = len(parts())
    assert 3 <= done < 16, f"the kill must land mid-build ({done} of 16 units finished)"
    deadline = time.time() + 10
    while process_group(proc.pid) and time.time() < deadline:
        time.sleep(0.05)
    assert not process_group(proc.pid), f"processes outlived the killed build: {process_group(proc.pid)}"
    res = subprocess.run(args, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert f"solve (full): {16 - done} of 16 units to compute ({done} reused)" in res.stderr, res.stderr
    assert "geometry: " not in res.stderr            # the realization's voxels were reused too
    resumed = read_table(tmp_path / "t.npz")
    fresh = build_table(table_request("Y7.5+B7.5", "sphere:300",
                                      wavelengths_nm=tuple(np.arange(400.0, 701.0, 20.0)),
                                      sigma_rad=tuple(np.linspace(0, np.pi / 2, 4)), grid=(24, 24, 12),
                                      realizations=1, azimuths=2, tier="full", wavelength_stride=1),
                       opts(tmp_path / "fresh"))
    for name in COLUMNS:
        np.testing.assert_array_equal(getattr(resumed, name), getattr(fresh, name))
    assert not list(cache.glob("parts/*/*.npz"))      # a finished build clears its parts


def test_scene_naming_two_inks_builds_exactly_two_tables(tmp_path, use_variant, caplog):
    import logging

    mi = use_variant("llvm_ad_spectral")
    cache = tmp_path / "scene_cache"
    ink = lambda spec, **kw: {"type": "ink", "ink": spec, "cache": str(cache), **kw}
    rect = lambda x, bsdf: {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([x, 0, 0]), "bsdf": bsdf}
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        mi.load_dict({"type": "scene", "a": rect(-3, ink("R30")), "b": rect(0, ink("G30")),
                      "c": rect(3, ink("G30", coverage=0.5)), "d": rect(6, ink("R30", paper=0.8))})
    assert len(list((cache / "tables").glob("*.npz"))) == 2
    assert sum("computing table" in r.message for r in caplog.records) == 2


def test_wave_table_in_the_bsdf(use_variant, table_and_request, tmp_path):
    """A real particle table through the plugin: eval = the reference formula, reciprocal, and
    the sampled albedo on white paper stays ≤ 1."""
    from solver.table import write_table

    mi = use_variant("llvm_ad_spectral")
    table, _ = table_and_request
    path = write_table(tmp_path / "wave.npz", table)
    bsdf = ink_bsdf(mi, path, paper=1.0)
    rng = np.random.default_rng(11)
    a, b = hemisphere(rng, 2048), hemisphere(rng, 2048)
    lam = rng.uniform(420.0, 720.0, size=(4, 2048))
    f_ab = evaluate(mi, bsdf, a, b, lam)
    np.testing.assert_allclose(f_ab, reference_eval(read_table(path), a, b, lam, 1.0, 1.0), rtol=2e-4, atol=2e-6)
    np.testing.assert_allclose(f_ab / b[2], evaluate(mi, bsdf, b, a, lam) / a[2], rtol=2e-4, atol=1e-6)
    for deg in (0.0, 40.0, 75.0):
        mean, err = sampled_albedo(mi, bsdf, deg, rng.uniform(430.0, 700.0, size=(4, 1 << 15)))
        assert 0.05 < mean <= 1.0 + 4.5 * err + 1e-4


def test_target_se_adds_realizations_until_met_or_capped(tmp_path, caplog):
    import logging

    loose = build_table(small(target_se=0.5), opts(tmp_path / "a"))
    assert loose.meta["realizations_used"] == 2 and len(loose.meta["seeds"]) == 2
    caplog.clear()              # only the tight build's lines (an earlier test may have left INFO on)
    with caplog.at_level(logging.INFO, logger="inkbsdf.tables"):
        tight = build_table(small(target_se=1e-6, max_realizations=3), opts(tmp_path / "b"))
    assert tight.meta["realizations_used"] == 3 and tight.errors["Rbar"].shape == tight.Rbar.shape
    # the third realization's units were the only new ones: 2 λ, nothing recomputed
    solves = [r.message for r in caplog.records if r.message.startswith("solve (full)")]
    assert solves == ["solve (full): 4 of 4 units to compute (0 reused)",
                      "solve (full): 2 of 2 units to compute (0 reused)"], solves
    same = build_table(small(realizations=3), opts(tmp_path / "c"))
    np.testing.assert_array_equal(tight.Rbar, same.Rbar)


@pytest.mark.parametrize("polarisation", ["te", "unpolarised"])
def test_a_stack_through_the_wave_path_equals_the_exact_multilayer_film(polarisation):
    """Two homogeneous layers stacked on one grid (Y15 over B15), solved by the wave tier from
    above and below, equal the exact stack film — the background is their mean, so the
    contrast is not zero and the test exercises the stacked geometry and the solves from below;
    in TM each face takes its layer's ε and the inner interface its TM condition
    (solver/wave/interfaces.py), so the unpolarised table is exact too."""
    from solver.geometry.stacking import stack_voxels, uniform_layer
    from solver.table.thinfilm_tier import request_film

    req = small(ink="Y15/B15", particles="sphere:300/molecular", grid=(8, 8, 32), realizations=1, solver_tol=1e-3,
                wavelengths_nm=(450.0, 610.0), polarisation=polarisation,
                sigma_rad=tuple(np.radians([0.0, 40.0, 70.0, 85.0, 90.0])))
    nx, ny, nz = req.wave.grid
    period = (req.wave.cell_nm,) * 2
    vox = stack_voxels([uniform_layer(req.layers[0].ink, (nx, ny, nz // 2), period, (0.0, 1000.0)),
                        uniform_layer(req.layers[1].ink, (nx, ny, nz // 2), period, (1000.0, 2000.0))])
    table = reduce_units(req, [[solve_unit(SolveUnit(req, 0, li, vox)) for li in range(2)]], {"schema_version": 2})
    film = request_film(req, polarisation=req.polarisation)
    names = ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")
    if polarisation == "unpolarised":
        names += ("Rbar_s", "Rbar_p", "Tbar_s", "Tbar_p")
    for name in names:        # tol 1e-3 (the default's 3e-3: 5e-4) and 16 cells per layer: not the ≤ 1e-5 of
        np.testing.assert_allclose(getattr(table, name), getattr(film, name), atol=1e-4,
                                   err_msg=name)              # tests/test_wave_stacks.py
    assert np.max(np.abs(table.Rbar_below - table.Rbar)) > 1e-3       # a stack is not up-down symmetric


def test_stacks_need_whole_cells_per_layer():
    from solver.table.request import RequestError

    with pytest.raises(RequestError, match="NZ = 36"):
        small(ink="Y15/B15", particles="sphere:300", thickness_nm=(800.0, 1000.0), grid=(16, 16, 32))
    assert small(ink="Y15/B15", particles="sphere:300", thickness_nm=(800.0, 1000.0),
                 grid=(16, 16, 9)).wave.grid[2] == 9
    # the preset's cell height kept: two 1000-nm layers get twice the preset's z cells
    assert table_request("Y15/B15", "sphere:300").wave.grid[2] == 2 * table_request("R15", "sphere:300").wave.grid[2]
    with pytest.raises(RequestError, match="rough top"):
        small(ink="Y15/B15", particles="sphere:300:rough")


def test_the_exact_energy_identity_is_checked_once_per_realization(table_and_request):
    """One unit per realization evaluates the scheme-exact identity (rotating over the solved
    wavelengths), and the built table records its result."""
    from solver.table.wave_tier import exact_identity_checked

    req = table_request("R15", "sphere:300")
    solved = req.solved_wavelength_indices
    for r in range(req.wave.realizations):
        assert [li for li in solved if exact_identity_checked(req, r, li)] == [solved[r % len(solved)]]
    table, _ = table_and_request
    assert 0 < table.meta["errors"]["energy_closure_exact_sampled_max"] < 1e-3


def test_the_brdf_standard_error_follows_the_brdf(alternating):
    """R's standard error comes from its leave-one-out replicas, which went through the same
    normal-incidence average and reciprocity as R: zero where R is zero in every replica
    (grazing directions), equal to the stratified jackknife of the replicas elsewhere."""
    from solver.table import jackknife

    table, _ = alternating
    zero = np.all(table.jackknife["R"] == 0, axis=0) & (table.R == 0)
    assert zero.any() and np.all(table.errors["R"][zero] == 0)
    np.testing.assert_allclose(table.errors["R"],
                               jackknife.standard_error(table.jackknife["R"], table.meta["jackknife_groups"]))
