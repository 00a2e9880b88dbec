"""Particle inks from the wave solver: the work units of a table build.

Stage 1, one unit per realization: random cell → voxel fractions (reused for every λ, σ).
Stage 2, one unit per (realization, λ): for every solved incidence σ and `azimuths` incidence
azimuths, one prepared operator and one solve from above (and one from below when the layer is
not up-down symmetric).  A unit returns small arrays (order amplitudes of the 00 orders, totals,
the diffuse orders already spread onto the BRDF grid), so results travel cheaply between
processes or Dask workers and are stored for resuming.

Sampling: realization r uses seed SeedSequence([seed, r]); its incidence azimuths are a
golden-ratio sequence over [0, π/2) (the square cell's symmetry), so successive samples put the
discrete order directions at new angles.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from ..geometry import LayerSpec, eps_grid, generate, parse_particles, voxelize
from ..inks import parse_ink
from ..wave import Cell, prepare, solve_prepared
from .reduce import fold_dphi, spread_orders
from .request import TableRequest

GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)


def solved_mask(request: TableRequest) -> np.ndarray:
    """Which σ nodes are solved: all except grazing 90°, which is set analytically."""
    return np.asarray(request.sigma_rad) < np.pi / 2 - 1e-9


def solved_sigma(request: TableRequest) -> np.ndarray:
    """Incidence angles that are solved, rad."""
    return np.asarray(request.sigma_rad)[solved_mask(request)]


def dphi_grid(request: TableRequest) -> np.ndarray:
    return np.linspace(0.0, np.pi, request.dphi_count)


def realization_seed(request: TableRequest, realization: int) -> int:
    return int(np.random.SeedSequence([request.seed, realization]).generate_state(1)[0])


def azimuths(request: TableRequest, realization: int) -> np.ndarray:
    s = realization * request.azimuths + np.arange(request.azimuths)
    return 0.5 * np.pi * np.mod(s * GOLDEN, 1.0)


def layer_spec(request: TableRequest) -> LayerSpec:
    return LayerSpec(parse_ink(request.ink), parse_particles(request.particles),
                     thickness_nm=request.thickness_nm, cell_nm=(request.cell_nm, request.cell_nm))


def needs_below(request: TableRequest) -> bool:
    """Only a rough top breaks the layer's statistical up-down symmetry here."""
    return parse_particles(request.particles).rough_top > 0


@dataclass(frozen=True)
class GeometryUnit:
    request: TableRequest
    realization: int


def geometry_unit(unit: GeometryUnit):
    """Voxel fractions of one seeded realization."""
    real = generate(layer_spec(unit.request), realization_seed(unit.request, unit.realization))
    return voxelize(real, unit.request.grid)


@dataclass(frozen=True)
class SolveUnit:
    request: TableRequest
    realization: int
    wavelength_index: int
    voxels: object                      # VoxelFractions of this realization
    method: str = "full"                # "full": converged solve; "born": first order (DWBA)


def _workers() -> int:
    return int(os.environ.get("INKBSDF_THREADS", "0")) or max(1, min(os.cpu_count() or 1, 8))


def solve_unit(unit: SolveUnit) -> dict:
    """All solves of one realization at one wavelength → arrays indexed [σ, azimuth]."""
    req, vox = unit.request, unit.voxels
    wl = req.wavelengths_nm[unit.wavelength_index]
    sig, phis = solved_sigma(req), azimuths(req, unit.realization)
    below = needs_below(req)
    cell = Cell(eps_grid(vox, wl), tuple(vox.period_nm), tuple(vox.z_range_nm))
    z_top, z_bottom = (float(z) for z in vox.z_range_nm)
    polar, dphi = np.asarray(req.sigma_rad), dphi_grid(req)
    shape = (sig.size, phis.size)
    out = {k: np.zeros(shape) for k in ("Rbar", "Tbar", "A", "energy_error", "applications",
                                         "seconds", "Rbar_below")}
    out["alpha00"] = np.zeros(shape, complex)
    out["beta00"] = np.zeros(shape, complex)
    out["R"] = np.zeros(shape + (polar.size, dphi.size))
    kw = dict(tol=req.solver_tol, method="born" if unit.method == "born" else "auto")
    if unit.method == "born":              # first order by design: not a convergence failure
        kw.update(maxiter=1, on_fail="ignore")
    k0 = 2.0 * np.pi / wl
    for i, s in enumerate(sig):
        for j, phi in enumerate(phis):
            kx0, ky0 = k0 * np.sin(s) * np.cos(phi), k0 * np.sin(s) * np.sin(phi)
            op = prepare(cell, wl, kx0, ky0, workers=_workers())
            sides = (False, True) if below else (False,)
            for from_below in sides:
                res = solve_prepared(op, from_below, **kw)
                out["applications"][i, j] += res.applications
                out["seconds"][i, j] += res.seconds
                if from_below:
                    out["Rbar_below"][i, j] = res.R
                    continue
                kz = k0 * np.cos(s)
                # re-reference the 00 amplitudes to the planes z = 0 and z = H (flat binder faces)
                out["alpha00"][i, j] = res.reflected.amp(0, 0) * np.exp(2j * kz * z_top)
                out["beta00"][i, j] = res.transmitted.amp(0, 0) * np.exp(
                    1j * kz * (z_top - z_bottom + req.thickness_nm))
                out["Rbar"][i, j], out["Tbar"][i, j] = res.R, res.T
                out["A"][i, j], out["energy_error"][i, j] = res.absorbed, res.energy_error
                refl = res.reflected
                keep = refl.propagating & ~((refl.m == 0) & (refl.n == 0))
                out["R"][i, j] = spread_orders(polar, dphi, refl.theta_rad[keep],
                                               fold_dphi(phi + np.pi, refl.phi_rad[keep]), refl.power[keep])
            if not below:
                out["Rbar_below"][i, j] = out["Rbar"][i, j]
    return out
