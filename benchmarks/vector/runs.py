"""Units of work, one (case, realization, λ, σ) each, for both solvers, cached on disk.

Vector units are expensive (treams' lattice sums: minutes), so each is written to
`out/bench/vector/<geometry key>/vector_r<r>_l<λ>_s<σ>_L<lmax>_c<cutoff>.npz` as soon as it is
done; a rerun reads it.  Scalar units take seconds; they are cached the same way, keyed by the
solver's grid and tolerance (delete the folder after a change of the scalar solver).

Each unit stores, per incident polarisation (s, p): R, T (totals) and the 00 amplitudes
r00, t00 [incident pol, outgoing pol] referenced at the layer's faces.  The scalar solver is
TE (s) only until its TM (p) mode lands; then `scalar_polarisations()` reports both.
"""

from __future__ import annotations

import inspect
import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.geometry import eps_grid, voxelize
from solver.wave import Cell, Incidence, solve

from .cases import Case, host_eps, lmax_for, realization, sphere_eps

CACHE = Path("out/bench/vector")
SCALAR_VOXEL_NM = 1000.0 / 64      # ≈ λ/(18 n) at 450 nm: finer than the tables' default
SCALAR_TOL = 1e-5


@dataclass(frozen=True)
class Unit:
    """Result of one solve: arrays over incident polarisation (index 0 = s, 1 = p; NaN where a
    solver does not do that polarisation)."""

    R: np.ndarray
    T: np.ndarray
    r00: np.ndarray          # (2, 2) complex
    t00: np.ndarray
    seconds: float
    info: dict


def _save(path: Path, unit: Unit) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, R=unit.R, T=unit.T, r00=unit.r00, t00=unit.t00, seconds=unit.seconds,
             info=np.array(repr(unit.info)))
    tmp.replace(path)


def _load(path: Path) -> Unit:
    with np.load(path) as d:
        return Unit(d["R"], d["T"], d["r00"], d["t00"], float(d["seconds"]), {"info": str(d["info"])})


def _tag(x: float) -> str:
    return f"{x:g}".replace(".", "p")


def vector_path(case: Case, r: int, lam: float, sigma_deg: float, lmax: int) -> Path:
    return (CACHE / case.geometry_key /
            f"vector_r{r}_l{_tag(lam)}_s{_tag(sigma_deg)}_L{lmax}_c{_tag(case.pw_cutoff_per_nm)}.npz")


def vector_lmax(case: Case, lam: float) -> int:
    real = realization(case, 0)
    return lmax_for(float(real.radii_nm.max()), lam, sphere_eps(case, lam))


def vector_unit(case: Case, r: int, lam: float, sigma_deg: float, *, compute: bool = True,
                lmax: int | None = None) -> Unit | None:
    """The treams solve of one unit (cached); None if not cached and compute is False."""
    lmax = vector_lmax(case, lam) if lmax is None else lmax
    path = vector_path(case, r, lam, sigma_deg, lmax)
    if path.exists():
        return _load(path)
    if not compute:
        return None
    from .treams_layer import VectorSettings, solve_cell   # treams: the optional extra
    real = realization(case, r)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # treams' annotation warnings (kpar overwritten)
        res = solve_cell(real.radii_nm, real.centres_nm, sphere_eps(case, lam), lam,
                         math.radians(sigma_deg), (case.cell_nm, case.cell_nm), case.thickness_nm,
                         host_eps(), VectorSettings(lmax, case.pw_cutoff_per_nm))
    unit = Unit(res.R, res.T, res.r00, res.t00, res.seconds_total,
                dict(lmax=lmax, modes=res.n_modes, plane_waves=res.n_plane_waves,
                     lattice_s=round(res.seconds_lattice, 1), spheres=len(real.radii_nm)))
    _save(path, unit)
    return unit


def scalar_polarisations() -> tuple[str, ...]:
    """'s' always (TE); 'p' once solver.wave.solve takes polarisation='tm'."""
    return ("s", "p") if "polarisation" in inspect.signature(solve).parameters else ("s",)


def scalar_grid(case: Case) -> tuple[int, int, int]:
    n_xy = max(8, int(round(case.cell_nm / SCALAR_VOXEL_NM)))
    return n_xy, n_xy, int(round(case.thickness_nm / SCALAR_VOXEL_NM))


def scalar_path(case: Case, r: int, lam: float, sigma_deg: float, variant: str = "plain") -> Path:
    nx, _, nz = scalar_grid(case)
    pols = "".join(scalar_polarisations())
    extra = "" if variant == "plain" else f"_{variant}"
    return (CACHE / case.geometry_key /
            f"scalar_r{r}_l{_tag(lam)}_s{_tag(sigma_deg)}_g{nx}x{nz}_{pols}{extra}.npz")


def local_field_eps(eps_particle: complex, eps_host: float) -> complex:
    """Permittivity whose *scalar* contrast equals the vector dipole response of a small sphere:
    ε' − ε_h = 3ε_h(ε − ε_h)/(ε + 2ε_h) (Clausius–Mossotti local-field factor).  An experiment,
    not part of the project's scalar model: does this one correction close the gap?"""
    return eps_host + 3 * eps_host * (eps_particle - eps_host) / (eps_particle + 2 * eps_host)


VARIANTS = ("plain", "localfield")


def scalar_unit(case: Case, r: int, lam: float, sigma_deg: float, variant: str = "plain") -> Unit:
    """The project's scalar solver (solver.wave) on the same realization (cached).

    variant 'plain': the project's model (ε per voxel = volume mean of the materials, eps_grid);
    'localfield': the pigment's ε replaced by `local_field_eps`."""
    if variant not in VARIANTS:
        raise ValueError(f"scalar variant must be one of {VARIANTS}, got {variant!r}")
    path = scalar_path(case, r, lam, sigma_deg, variant)
    if path.exists():
        return _load(path)
    t0 = time.perf_counter()
    vox = voxelize(realization(case, r), scalar_grid(case))
    if variant == "plain":
        eps = eps_grid(vox, lam)
    else:
        frac = dict(zip(vox.materials, vox.fractions.astype(np.float64)))
        eps = (frac["binder"] * host_eps() + frac["air"] * 1.0
               + frac[case.pigment] * local_field_eps(sphere_eps(case, lam), host_eps()))
    cell = Cell(eps, (case.cell_nm, case.cell_nm), vox.z_range_nm)
    R, T = np.full(2, np.nan), np.full(2, np.nan)
    r00, t00 = np.full((2, 2), np.nan, complex), np.full((2, 2), np.nan, complex)
    for i, pol in enumerate(("s", "p")):
        if pol not in scalar_polarisations():
            continue
        kwargs = {"polarisation": "te" if pol == "s" else "tm"} if len(scalar_polarisations()) == 2 else {}
        res = solve(cell, Incidence(lam, math.radians(sigma_deg)), tol=SCALAR_TOL, on_fail="raise", **kwargs)
        R[i], T[i] = res.R, res.T
        r00[i, i], t00[i, i] = res.reflected.amp(0, 0), res.transmitted.amp(0, 0)
        r00[i, 1 - i] = t00[i, 1 - i] = 0.0          # a scalar field keeps its polarisation
    unit = Unit(R, T, r00, t00, time.perf_counter() - t0, dict(grid=scalar_grid(case)))
    _save(path, unit)
    return unit
