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
from dataclasses import dataclass

import numpy as np

from ..geometry import LayerSpec, eps_grid, generate, voxelize
from ..wave import Cell, prepare, solve_prepared
from .orders_to_brdf import fold_dphi, spread_orders
from .request import RequestError, TableRequest

GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)


def realization_seed(request: TableRequest, realization: int) -> int:
    return int(np.random.SeedSequence([request.wave.seed, realization]).generate_state(1)[0])


def azimuths(request: TableRequest, realization: int) -> np.ndarray:
    """Incidence azimuths (rad) of one realization."""
    s = realization * request.wave.azimuths + np.arange(request.wave.azimuths)
    return 0.5 * np.pi * np.mod(s * GOLDEN, 1.0)


def layer_spec(request: TableRequest) -> LayerSpec:
    if len(request.layers) != 1:
        raise RequestError(f"{request.ink_label}: stacks with particle layers are not solved yet; "
                           "give molecular layers for an exact multilayer film")
    layer = request.layer
    return LayerSpec(layer.ink, layer.particles, thickness_nm=layer.thickness_nm,
                     cell_nm=(request.wave.cell_nm, request.wave.cell_nm))


def needs_below(request: TableRequest) -> bool:
    """Only a rough top breaks the layer's statistical up-down symmetry here."""
    return any(layer.particles is not None and layer.particles.rough_top > 0 for layer in request.layers)


@dataclass(frozen=True)
class GeometryUnit:
    request: TableRequest
    realization: int


def geometry_unit(unit: GeometryUnit):
    """Voxel fractions of one seeded realization."""
    real = generate(layer_spec(unit.request), realization_seed(unit.request, unit.realization))
    return voxelize(real, unit.request.wave.grid)


@dataclass(frozen=True)
class SolveUnit:
    request: TableRequest
    realization: int
    wavelength_index: int
    voxels: object                      # VoxelFractions of this realization
    method: str = "full"                # "full": converged solve; "born": first order (DWBA)
    threads: int | None = None          # FFT threads (None: the solver's default)


def solve_unit(unit: SolveUnit) -> dict:
    """All solves of one realization at one wavelength → arrays indexed [σ, azimuth]."""
    req, vox = unit.request, unit.voxels
    wl = req.grids.wavelengths_nm[unit.wavelength_index]
    sig, phis = req.grids.solved_sigma_rad, azimuths(req, unit.realization)
    below = needs_below(req)
    cell = Cell(eps_grid(vox, wl, req.materials), tuple(vox.period_nm), tuple(vox.z_range_nm))
    z_top, z_bottom = (float(z) for z in vox.z_range_nm)
    polar, dphi = np.asarray(req.grids.sigma_rad), req.grids.dphi_rad
    shape = (sig.size, phis.size)
    out = {k: np.zeros(shape) for k in ("Rbar", "Tbar", "A", "energy_error", "applications",
                                         "seconds", "Rbar_below")}
    out["alpha00"] = np.zeros(shape, complex)
    out["beta00"] = np.zeros(shape, complex)
    out["R"] = np.zeros(shape + (polar.size, dphi.size))
    kw = dict(tol=req.wave.solver_tol, method="born" if unit.method == "born" else "auto")
    if unit.method == "born":              # first order by design: not a convergence failure
        kw.update(maxiter=1, on_fail="ignore")
    k0 = 2.0 * np.pi / wl
    for i, s in enumerate(sig):
        for j, phi in enumerate(phis):
            kx0, ky0 = k0 * np.sin(s) * np.cos(phi), k0 * np.sin(s) * np.sin(phi)
            op = prepare(cell, wl, kx0, ky0, workers=unit.threads)
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
