"""Shared fixtures: ink tables built into a temporary folder, and Mitsuba variant selection."""

from __future__ import annotations

from pathlib import Path

import pytest

THICKNESS_NM = 1000.0


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


@pytest.fixture(scope="session")
def ink_tables(tmp_path_factory):
    """{ink: path} of the demo inks' tables (built once per test session, ~0.1 s each)."""
    from inkbsdf.demo_tables import build_tables

    return build_tables(tmp_path_factory.mktemp("tables"))


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
    import numpy as np

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


def surface_interaction(mi, wi, wavelengths_nm):
    """A SurfaceInteraction3f for N lanes: wi [3, N] (local frame), wavelengths [4, N] in nm."""
    import drjit as dr
    import numpy as np

    wi = np.asarray(wi, dtype=np.float64)
    si = dr.zeros(mi.SurfaceInteraction3f, wi.shape[1])
    si.wi = mi.Vector3f(*[mi.Float(c) for c in wi])
    si.wavelengths = mi.Spectrum(*[mi.Float(c) for c in np.asarray(wavelengths_nm, dtype=np.float64)])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    return si


def process_group(pgid: int) -> list[str]:
    """Command lines of the live (non-zombie) processes in a process group (Linux /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            if int(fields[2]) == pgid and fields[0] != "Z":
                found.append((stat.parent / "cmdline").read_bytes().replace(b"\0", b" ").decode()[:120])
        except (OSError, IndexError, ValueError):
            continue
    return found


def ink_bsdf(mi, path, paper=0.9, coverage=1.0):
    """Load an `ink` BSDF with uniform paper albedo and coverage."""
    return mi.load_dict({"type": "ink", "filename": str(path), "paper": paper, "coverage": coverage})
