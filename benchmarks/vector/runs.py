"""Units of work, one (case, realization, λ, σ) each, for both solvers, cached on disk.

Vector units are expensive (treams' lattice sums: minutes), so each is written to
`out/bench/vector/<geometry key>/vector_r<r>_l<λ>_s<σ>_L<lmax>_c<cutoff>.npz` as soon as it is
done; a rerun reads it.  Scalar units take seconds; they are cached the same way, keyed by the
solver's grid and tolerance (delete the folder after a change of the scalar solver).

Each unit stores, per incident polarisation (s, p): R, T (totals) and the 00 amplitudes
r00, t00 [incident pol, outgoing pol] referenced at the layer's faces.  The scalar side caches
TE and TM (per face-form preset, solver.wave.faces) separately, for each pigment permittivity
model (MATERIALS).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.geometry import eps_grid, voxelize
from solver.materials import default_materials
from solver.wave import DEFAULT_TM_FACES, Cell, Incidence, solve

from .cases import Case, host_eps, lmax_for, realization, sphere_eps
from .mie_matched import MODES, matched_eps

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


def scalar_grid(case: Case) -> tuple[int, int, int]:
    n_xy = max(8, int(round(case.cell_nm / SCALAR_VOXEL_NM)))
    return n_xy, n_xy, int(round(case.thickness_nm / SCALAR_VOXEL_NM))


#: Pigment permittivity models of the scalar side: 'volume' (bulk ε: ε per voxel = volume mean
#: of the materials), 'localfield' (spheres' local-field ε, the tables' default) and the two
#: Mie-matched variants that were tried (`mie_matched.MODES`).
MATERIALS = ("volume", "localfield") + MODES


def scalar_path(case: Case, r: int, lam: float, sigma_deg: float, pol_key: str,
                material: str = "volume") -> Path:
    """pol_key: 'te' or 'tm-<faces preset>'."""
    nx, _, nz = scalar_grid(case)
    extra = "" if material == "volume" else f"_{material}"
    return (CACHE / case.geometry_key /
            f"scalar_r{r}_l{_tag(lam)}_s{_tag(sigma_deg)}_g{nx}x{nz}_{pol_key}{extra}.npz")


def scalar_cell(case: Case, r: int, lam: float, material: str = "volume") -> Cell:
    """The realization voxelised on the scalar grid, ε by the material model."""
    if material not in MATERIALS:
        raise ValueError(f"scalar material model must be one of {MATERIALS}, got {material!r}")
    vox = voxelize(realization(case, r), scalar_grid(case))
    data = default_materials()
    eps = eps_grid(vox, lam, data.with_local_field() if material == "localfield" else data)
    if material in MODES:                  # the case's pigment with its Mie-matched ε'
        bulk = sphere_eps(case, lam)
        matched = matched_eps(bulk, host_eps(), case.diameter_nm / 2, lam, material)
        eps = eps + vox.fractions[vox.materials.index(case.pigment)] * (matched - bulk)
    return Cell(eps, (case.cell_nm, case.cell_nm), vox.z_range_nm)


def _scalar_pol(case: Case, r: int, lam: float, sigma_deg: float, pol: str, material: str,
                tm_faces: str) -> Unit:
    """One polarisation ('s' = TE, 'p' = TM with `tm_faces`) of a scalar unit (cached)."""
    key = "te" if pol == "s" else f"tm-{tm_faces}"
    path = scalar_path(case, r, lam, sigma_deg, key, material)
    if path.exists():
        return _load(path)
    t0 = time.perf_counter()
    i = 0 if pol == "s" else 1
    extra = {} if pol == "s" else {"polarisation": "tm", "tm_faces": tm_faces}
    res = solve(scalar_cell(case, r, lam, material), Incidence(lam, math.radians(sigma_deg)),
                tol=SCALAR_TOL, on_fail="raise", **extra)
    R, T = np.full(2, np.nan), np.full(2, np.nan)
    r00, t00 = np.full((2, 2), np.nan, complex), np.full((2, 2), np.nan, complex)
    R[i], T[i] = res.R, res.T
    r00[i, i], t00[i, i] = res.reflected.amp(0, 0), res.transmitted.amp(0, 0)
    r00[i, 1 - i] = t00[i, 1 - i] = 0.0          # a scalar field keeps its polarisation
    unit = Unit(R, T, r00, t00, time.perf_counter() - t0,
                dict(grid=scalar_grid(case), tm_faces=res.tm_faces))
    _save(path, unit)
    return unit


def scalar_unit(case: Case, r: int, lam: float, sigma_deg: float, material: str = "volume",
                tm_faces: str = DEFAULT_TM_FACES) -> Unit:
    """The project's scalar solver (solver.wave) on the same realization, s = TE and p = TM
    with the face forms `tm_faces` (a solver.wave.faces preset), each cached.

    material 'volume': the bulk pigment ε (the paper's volume mix, `--no-local-field`);
    'localfield': the spheres' local-field pigment ε (the unpolarised tables' default)."""
    s = _scalar_pol(case, r, lam, sigma_deg, "s", material, tm_faces)
    p = _scalar_pol(case, r, lam, sigma_deg, "p", material, tm_faces)
    pick = lambda a, b: np.where(np.isnan(a), b, a)   # noqa: E731
    return Unit(pick(s.R, p.R), pick(s.T, p.T), pick(s.r00, p.r00), pick(s.t00, p.t00),
                s.seconds + p.seconds, dict(grid=scalar_grid(case), tm_faces=tm_faces))
