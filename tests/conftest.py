"""Shared fixtures and helpers: ink tables built into a temporary folder, Mitsuba variant
selection, synthetic tables (a diffuse lobe; one binder face), the paper's inks, the scene
scripts of scenes/, and the processes of a process group.

Oracles (independent reference formulas) live in oracles.py, BSDF probing in bsdf_probes.py,
printing tables in printing_tables.py."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from benchmarks.bench_interrupts import process_group  # noqa: F401  (tests import it from here)

THICKNESS_NM = 1000.0
ROOT = Path(__file__).resolve().parents[1]
N_BINDER = 1.558                          # the binder's refractive index (docs/design.md §2)
E_BINDER = N_BINDER**2
DEMO_SCENE = str(ROOT / "scenes" / "printed_page.xml")
BREWSTER_DEG = float(np.degrees(np.arctan(N_BINDER)))
# the inks of the paper's figures (rows of Fig. 7)
PAPER_INKS = ["R15", "Y15", "Y12.5+B2.5", "Y7.5+B7.5", "G15", "Y2.5+B12.5", "B15", "R30", "Y30",
              "Y25+B5", "Y15+B15", "G30", "Y5+B25", "B30", "R50", "Y50", "Y42+B8", "Y25+B25", "G50",
              "Y8+B42", "B50"]


@pytest.fixture(scope="session", autouse=True)
def _private_table_cache(tmp_path_factory):
    """Tests never read or write the user's table cache: $INKBSDF_CACHE → a session temp dir."""
    import os

    old = os.environ.get("INKBSDF_CACHE")
    os.environ["INKBSDF_CACHE"] = str(tmp_path_factory.mktemp("inkbsdf_cache"))
    yield
    if old is None:
        os.environ.pop("INKBSDF_CACHE", None)
    else:
        os.environ["INKBSDF_CACHE"] = old


#: the available memory every test sees (solver.host): no test depends on the machine it runs on
HOST_MEMORY_BYTES = 64e9


@pytest.fixture(autouse=True)
def _fixed_host_memory(monkeypatch):
    """solver.host.available_memory_bytes → HOST_MEMORY_BYTES (a test that needs another figure
    patches it again)."""
    from solver import host

    monkeypatch.setattr(host, "available_memory_bytes", lambda: HOST_MEMORY_BYTES)


@pytest.fixture(scope="session")
def ink_tables(tmp_path_factory):
    """{ink: path} of the demo inks' tables (built once per test session, ~0.1 s each)."""
    from inkbsdf.apps.demo_tables import build_tables

    return build_tables(tmp_path_factory.mktemp("tables"))


@pytest.fixture()
def single_blas_thread():
    """NumPy's BLAS on one thread for the test (solver.wave.vecops.one_blas_thread): the RCWA
    oracle's dense 121×121 eigenproblems took ~4 s each on a threaded OpenBLAS on a busy
    2-core machine, ~0.05 s on one thread."""
    from solver.wave.vecops import one_blas_thread

    with one_blas_thread():
        yield


@pytest.fixture()
def use_variant():
    """Call with a variant name: sets it and registers the `ink` BSDF; restores afterwards."""
    import mitsuba as mi

    previous = mi.variant()

    def _use(name: str):
        import inkbsdf

        mi.set_variant(name)
        inkbsdf.register()
        return mi

    yield _use
    if previous is not None and mi.variant() != previous:
        mi.set_variant(previous)      # registrations are per variant and persist


def diffuse_layer_table(lossless=True, n_lambda=9, n_angle=10, n_dphi=7, strength=0.3):
    """A synthetic table with a diffuse lobe (R ≠ 0, reciprocal, anisotropic in Δφ).

    R(λ, σ, θ, Δφ) = a(λ)·g(σ)·g(θ)·(1 + ½ sin σ sin θ cos Δφ) on equal σ and θ grids (Δφ-free
    where σ or θ is 0, as the convention requires), R_spec half a clear
    film's, Rbar = R_spec + ∫R (schema identity); lossless: Tbar = 1 − Rbar; else 80 % of it.
    """
    from solver.inks import parse_ink
    from solver.table import InkTable, validate
    from solver.table.integrals import diffuse_albedo
    from solver.table.thinfilm_tier import build_thinfilm_table

    wl = np.linspace(380.0, 780.0, n_lambda)
    grid = np.linspace(0.0, np.pi / 2, n_angle)
    dphi = np.linspace(0.0, np.pi, n_dphi)
    film = build_thinfilm_table(parse_ink("clear"), THICKNESS_NM, wl, grid)
    a = strength * (0.5 + 0.5 * (wl - wl[0]) / (wl[-1] - wl[0]))
    g = np.sqrt(np.cos(grid).clip(0.0))
    sin = np.sin(grid)
    R = (a[:, None, None, None] * g[None, :, None, None] * g[None, None, :, None]
         * (1.0 + 0.5 * sin[None, :, None, None] * sin[None, None, :, None]
            * np.cos(dphi)[None, None, None, :]))
    r_spec = 0.5 * film.R_spec
    rbar = r_spec + diffuse_albedo(grid, dphi, R)
    tbar = (1.0 - rbar) * (1.0 if lossless else 0.8)
    meta = dict(film.meta, tier="synthetic", particles="synthetic diffuse lobe", ink="synthetic")
    return validate(InkTable(wavelengths=wl, sigma=grid, theta=grid.copy(), dphi=dphi, R=R,
                             R_spec=r_spec, T_coh=0.7 * tbar, Rbar=rbar, Tbar=tbar,
                             Rbar_below=rbar.copy(), meta=meta))


@pytest.fixture(scope="session")
def diffuse_tables(tmp_path_factory):
    """{'lossless': path, 'absorbing': path} of synthetic tables with a diffuse lobe."""
    from solver.table import write_table

    folder = tmp_path_factory.mktemp("diffuse_tables")
    return {name: write_table(folder / f"{name}.npz", diffuse_layer_table(lossless=(name == "lossless")))
            for name in ("lossless", "absorbing")}


def run_main(main, argv, capsys):
    """A command's main(argv) in this process: (exit status, stdout, stderr); argparse's
    SystemExit counts as its exit status."""
    try:
        status = main([str(a) for a in argv])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


def interface_table(sigma_deg, wavelengths_nm=(360.0, 830.0)):
    """A table of one air → binder face (no film): the face's s, p amplitudes from
    solver.thinfilm in Mitsuba's convention, R_spec their mean power, everything else transmitted."""
    from solver.table import InkTable, validate
    from solver.table.builder import build_table
    from solver.table.request import table_request
    from solver.thinfilm import stack, to_mitsuba_convention

    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    sigma = np.radians(np.asarray(sigma_deg, dtype=np.float64))
    amp = {p: to_mitsuba_convention(stack([], [], wl[:, None], sigma[None, :], polarisation=p,
                                          eps_out=N_BINDER**2).r) for p in ("te", "tm")}
    r = 0.5 * (np.abs(amp["te"]) ** 2 + np.abs(amp["tm"]) ** 2)
    like = build_table(table_request("clear", polarisation="unpolarised"))
    meta = dict(like.meta, ink="binder face", tier="synthetic", tier_reason="test: one face")
    return validate(InkTable(wavelengths=wl, sigma=sigma, theta=like.theta, dphi=like.dphi,
                             R=np.zeros((wl.size, sigma.size) + like.R.shape[2:]), R_spec=r,
                             T_coh=1.0 - r, Rbar=r.copy(), Tbar=1.0 - r, Rbar_below=r.copy(),
                             meta=meta, r_s=amp["te"], r_p=amp["tm"]))


def slab_against_airy(cell, inc, n_in, eta, n_out, thickness, polarisation="te", tol=1e-4, **kw):
    """Solve a homogeneous slab (tol 1e-8, energy by quadrature) and assert r, t (complex, on
    their reference faces), R and T within `tol` of oracles.airy_slab and the energy identity
    within 1e-6. Returns the solver's result."""
    from oracles import airy_slab
    from solver.wave import solve

    res = solve(cell, inc, tol=1e-8, polarisation=polarisation, exact_energy=True, **kw)
    r, t, big_r, big_t = airy_slab(n_in, eta, n_out, thickness, inc.wavelength_nm, inc.polar_rad, polarisation)
    errs = (abs(res.reflected.amp(0, 0) - r), abs(res.transmitted.amp(0, 0) - t),
            abs(res.R - big_r), abs(res.T - big_t))
    assert max(errs) <= tol, errs
    assert res.converged and res.energy_check == "quadrature" and abs(res.energy_error) < 1e-6
    assert res.polarisation == polarisation
    return res


def reciprocal_order_pairs(cell, lam_nm, polarisation="te", sigma=0.3, phi=0.4,
                           orders=((1, 0), (-1, 1), (0, -1))):
    """Reciprocal pairs of diffraction orders of a cell: for each order (m, n), reflected (R)
    and transmitted (T) under incidence (σ, φ) from above (a → b), the solve from that order's
    reversed direction (b̄ → ā: from above for R, from below for T) and its order (m, n), which
    must point back along the first incidence. Returns [((m, n, side), amp(a → b)/k_z,a,
    amp(b̄ → ā)/k_z,b, ε_a, ε_b)]."""
    from solver.wave import Incidence, solve

    k0 = 2 * math.pi / lam_nm
    eps_above, eps_below = complex(cell.eps_above).real, complex(cell.eps_below).real
    res_a = solve(cell, Incidence(lam_nm, sigma, phi), tol=1e-8, polarisation=polarisation)
    kz_a = k0 * math.sqrt(eps_above) * math.cos(sigma)
    pairs = []
    for (m, n) in orders:
        for side in ("R", "T"):
            out = res_a.reflected if side == "R" else res_a.transmitted
            i = out.index(m, n)
            assert out.propagating[i]
            kx, ky, kz_b = out.kx[i], out.ky[i], out.kz[i].real
            eps_b = eps_above if side == "R" else eps_below
            back = Incidence(lam_nm, math.asin(math.hypot(kx, ky) / (k0 * math.sqrt(eps_b))),
                             math.atan2(ky, kx) + math.pi, from_below=(side == "T"))
            res_b = solve(cell, back, tol=1e-8, polarisation=polarisation)
            other = res_b.reflected if side == "R" else res_b.transmitted
            j = other.index(m, n)
            assert abs(other.kx[j] + res_a.kx0) < 1e-12 and abs(other.ky[j] + res_a.ky0) < 1e-12
            pairs.append(((m, n, side), out.amplitude[i] / kz_a, other.amplitude[j] / kz_b,
                          eps_above, eps_b))
    return pairs


def scene_script(name: str):
    """The module scenes/<name>.py (a script folder, not a package), imported once by path."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / "scenes" / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]
