"""Particle inks from the wave solver: the work units of a table build.

Stage 1, one unit per realization: random cell → voxel fractions (reused for every λ, σ).
Stage 2, one unit per (realization, λ): for every solved incidence σ and every sample (an
incidence azimuth and a polarisation), one prepared operator and one solve from above (and one
from below when the layer is not up-down symmetric).  A unit returns small arrays (the 00
amplitudes, totals, the diffuse orders already spread onto the BRDF grid), so results travel
cheaply between processes or Dask workers and are stored for resuming.

Sampling (docs/tables.md):
- realization r uses seed SeedSequence([seed, r]); its incidence azimuths are a golden-ratio
  sequence over [0, π/2) (the square cell's symmetry), so successive samples put the discrete
  order directions at new angles;
- unpolarised light is the mean of TE and TM (docs/design.md §1).  With an even number of
  azimuths per realization, even azimuths are solved in TE and odd ones in TM: the same number
  of solves as a TE table, both polarisations sampled equally in every realization (the
  azimuth is itself a random sample of a statistically isotropic layer).  With an odd number,
  every azimuth is solved in both.
- the background slab's ε_b is the ink's nominal mean permittivity (the voxel fractions make
  each realization's mean equal to it); the TM faces' ε_f are each layer's own (face_eps: for
  one layer ε_b; a stack's faces its top and bottom layers', and its inner interfaces get the
  TM conditions), except a rough top's: its realization's mean profile (`tm_faces`).
- the scheme-exact energy identity (quadrature of ∫ Im ε |u|²) is evaluated on one solve per
  unit (the first without TM inner interfaces); every other solve closes its energy from the
  true residual (solver.wave).
- every full solve converges or the unit is refused: a solve short of its tolerance climbs the
  ladder of stronger settings (retry.py), and `retries` counts the rungs climbed per [σ, sample].
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..geometry import LayerSpec, eps_grid, generate, voxelize
from ..geometry.stacking import split_cells, stack_voxels, uniform_layer
from ..inks import molecular_eps
from ..wave import Cell, FaceLayers, prepare, solve_prepared
from ..wave.interfaces import mean_profile
from .orders_to_brdf import fold_dphi, spread_orders
from .request import TableRequest
from .retry import converged_solve

GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)
TE, TM = 0, 1


def realization_seed(request: TableRequest, realization: int) -> int:
    return int(np.random.SeedSequence([request.wave.seed, realization]).generate_state(1)[0])


def azimuths(request: TableRequest, realization: int) -> np.ndarray:
    """Incidence azimuths (rad) of one realization."""
    s = realization * request.wave.azimuths + np.arange(request.wave.azimuths)
    return 0.5 * np.pi * np.mod(s * GOLDEN, 1.0)


#: with one azimuth per realization, TE and TM alternate over the realizations from this many
#: on (each polarisation then has ≥ 2 cells, so its spread is known); fewer solve both
ALTERNATE_FROM_REALIZATIONS = 4


def alternates(request: TableRequest) -> bool:
    """Whether an unpolarised table's polarisations alternate over the global sample index
    s = r·A + j (realization r, its azimuth j of A): with an even A within every realization
    (TE, TM, TE, …), with A = 1 across the realizations (realization r solves TE if r is even,
    TM if odd: every solve its own cell, docs/tables.md "Samples") when there are at least
    ALTERNATE_FROM_REALIZATIONS.  Otherwise every azimuth is solved in both."""
    a, n = request.wave.azimuths, request.wave.realizations
    return request.polarisation != "te" and (a % 2 == 0 or (a == 1 and n >= ALTERNATE_FROM_REALIZATIONS))


def samples(request: TableRequest, realization: int = 0) -> tuple[tuple[int, int], ...]:
    """(azimuth index, polarisation) of the solves of one realization at one (λ, σ)."""
    count = request.wave.azimuths
    if request.polarisation == "te":
        return tuple((j, TE) for j in range(count))
    if alternates(request):
        return tuple((j, TE if (realization * count + j) % 2 == 0 else TM) for j in range(count))
    return tuple((j, p) for j in range(count) for p in (TE, TM))


def probe_realizations(request: TableRequest) -> tuple[int, ...]:
    """The realizations the tier probe solves: the first, and the second where the first
    solves one polarisation only (A = 1 alternating), so the probe sees TE and TM."""
    both = {p for _, p in samples(request, 0)} == ({TE} if request.polarisation == "te" else {TE, TM})
    return (0,) if both else (0, 1)


def solves_per_incidence(request: TableRequest, realizations: int | None = None) -> int:
    """Solves of `realizations` (default: the request's) at one (λ, σ), from above and below."""
    n = request.wave.realizations if realizations is None else realizations
    return sum(len(samples(request, r)) for r in range(n)) * (2 if needs_below(request) else 1)


def layer_spec(request: TableRequest, index: int = 0) -> LayerSpec:
    """The geometry of one particle layer of the request (the only one, or layer `index` of a
    stack, top first)."""
    layer = request.layers[index]
    return LayerSpec(layer.ink, layer.particles, thickness_nm=layer.thickness_nm,
                     cell_nm=(request.wave.cell_nm, request.wave.cell_nm))


def needs_below(request: TableRequest) -> bool:
    """A rough top or a stack of different layers breaks the up-down symmetry: Rbar_below is
    then solved from below, with the same operator."""
    return len(request.layers) > 1 or request.has_rough_top


def layer_eps(request: TableRequest, wavelength_nm: float) -> list[complex]:
    """Each layer's molecular-mix permittivity (with its grains' local field), top first."""
    return [complex(molecular_eps(layer.ink, wavelength_nm, request.layer_materials(i)))
            for i, layer in enumerate(request.layers)]


def nominal_eps(request: TableRequest, wavelength_nm: float) -> complex:
    """The background slab's ε_b: the layers' molecular-mix permittivities, thickness-weighted."""
    total = request.thickness_nm
    return complex(sum(e * layer.thickness_nm / total
                       for e, layer in zip(layer_eps(request, wavelength_nm), request.layers)))


def face_eps(request: TableRequest, wavelength_nm: float) -> FaceLayers:
    """The TM faces' ε_f: each layer's own permittivity on its z-cells (a stack's top face the
    top layer's, its bottom face the bottom layer's, and the TM conditions between its layers:
    solver/wave/interfaces.py)."""
    cells = split_cells([layer.thickness_nm for layer in request.layers], request.wave.grid[2])
    return FaceLayers(tuple(cells), tuple(layer_eps(request, wavelength_nm)))


#: a rough top's mean profile: neighbouring z-cells within this relative |Δε̄| share one TM
#: layer (interfaces.mean_profile; 0: every z-cell its own).  Measured against RCWA and in time
#: (`python -m benchmarks.bench_vector --rough-profile`, docs/vector_referee.md).
ROUGH_PROFILE_MERGE = 0.05


def tm_faces(request: TableRequest, wavelength_nm: float, eps: np.ndarray) -> FaceLayers:
    """The TM conditions of a realization eps (nx, ny, nz): a rough top gets its mean profile
    (air between the grains' caps down to the binder, then the layer) with Maxwell's TM
    conditions between its layers (`mean_profile`, merged by ROUGH_PROFILE_MERGE); a flat
    layer or stack keeps its layers' own faces (`face_eps`), where the profile is the grains'
    ramp whose correction is not better against Maxwell (docs/wave_solver.md, "The mean
    profile in TM")."""
    if request.has_rough_top:
        return mean_profile(eps, ROUGH_PROFILE_MERGE)
    return face_eps(request, wavelength_nm)


def cell_eps(request: TableRequest, vox, wavelength_nm: float) -> np.ndarray:
    """Permittivity per voxel of a realization: each layer's z cells with that layer's material
    data (`TableRequest.layer_materials`: its grains' local field)."""
    if len(request.layers) == 1:
        return eps_grid(vox, wavelength_nm, request.layer_materials(0))
    cells = split_cells([layer.thickness_nm for layer in request.layers], vox.shape[2])
    bounds = np.cumsum((0,) + cells)
    eps = np.empty(vox.shape, complex)
    for i in range(len(request.layers)):
        z = slice(bounds[i], bounds[i + 1])
        part = dataclasses.replace(vox, fractions=vox.fractions[..., z])
        eps[..., z] = eps_grid(part, wavelength_nm, request.layer_materials(i))
    return eps


def _stack_geometry(request: TableRequest, realization: int):
    """Voxel fractions of a stack: each layer on its share of the z cells, top first."""
    nx, ny, nz = request.wave.grid
    period = (request.wave.cell_nm, request.wave.cell_nm)
    cells = split_cells([layer.thickness_nm for layer in request.layers], nz)
    grids, z0 = [], 0.0
    for i, (layer, n) in enumerate(zip(request.layers, cells)):
        z1 = z0 + layer.thickness_nm
        if layer.molecular:
            grids.append(uniform_layer(layer.ink, (nx, ny, n), period, (z0, z1)))
        else:
            seed = int(np.random.SeedSequence([request.wave.seed, realization, i]).generate_state(1)[0])
            vox = voxelize(generate(layer_spec(request, i), seed), (nx, ny, n))
            grids.append(dataclasses.replace(vox, z_range_nm=(z0, z1)))
        z0 = z1
    return stack_voxels(grids)


@dataclass(frozen=True)
class GeometryUnit:
    request: TableRequest
    realization: int


def geometry_unit(unit: GeometryUnit):
    """Voxel fractions of one seeded realization."""
    if len(unit.request.layers) > 1:
        return _stack_geometry(unit.request, unit.realization)
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


def _operators(cell: Cell, wl: float, kx0: float, ky0: float, eps_nominal: complex,
               eps_faces: FaceLayers, polarisation: str, threads: int | None):
    """make_op(dtype) → the prepared operator of one incidence in that dtype, prepared once per
    dtype (both sides and every rung of the retry ladder share it)."""
    ops = {}

    def make_op(dtype=np.complex64):
        if dtype not in ops:
            ops[dtype] = prepare(cell, wl, kx0, ky0, eps_background=eps_nominal,
                                 eps_face=eps_faces, polarisation=polarisation,
                                 workers=threads, dtype=dtype)
        return ops[dtype]
    return make_op


def exact_identity_checked(request: TableRequest, realization: int, wavelength_index: int) -> bool:
    """Whether this unit evaluates the scheme-exact energy identity (the quadrature of ∫ Im ε |u|²,
    independent of R and T; 19 ms at 48×48×24, 4 % of a unit of seven solves) on its first
    solve: one unit per realization, at the solved wavelength r mod (their count), so every
    realization and, over the realizations, several wavelengths are checked.  Every solve
    closes its energy from its true residual anyway (solver.wave)."""
    solved = request.solved_wavelength_indices
    return wavelength_index == solved[realization % len(solved)]


def solve_unit(unit: SolveUnit) -> dict:
    """All solves of one realization at one wavelength → arrays indexed [σ, sample]."""
    req, vox = unit.request, unit.voxels
    wl = req.grids.wavelengths_nm[unit.wavelength_index]
    sig, phis, todo = req.grids.solved_sigma_rad, azimuths(req, unit.realization), samples(req, unit.realization)
    below = needs_below(req)
    cell = Cell(cell_eps(req, vox, wl), tuple(vox.period_nm), tuple(vox.z_range_nm))
    eps_nominal, eps_faces = nominal_eps(req, wl), tm_faces(req, wl, cell.eps)
    z_top, z_bottom = (float(z) for z in vox.z_range_nm)
    polar, dphi = np.asarray(req.grids.sigma_rad), req.grids.dphi_rad
    shape = (sig.size, len(todo))
    out = {k: np.zeros(shape) for k in ("Rbar", "Tbar", "A", "energy_error", "applications",
                                         "seconds", "Rbar_below", "retries")}
    out["alpha00"] = np.zeros(shape, complex)
    out["beta00"] = np.zeros(shape, complex)
    out["R"] = np.zeros(shape + (polar.size, dphi.size))
    out["polarisation"] = np.array([p for _, p in todo])
    out["energy_error_exact"] = np.zeros(1)
    k0 = 2.0 * np.pi / wl
    checked = exact_identity_checked(req, unit.realization, unit.wavelength_index)
    first_checkable = next((k for k, (_, pol) in enumerate(todo)
                            if pol == TE or not eps_faces.boundaries), None)
    for i, s in enumerate(sig):
        for k, (j, pol) in enumerate(todo):
            phi = phis[j]
            kx0, ky0 = k0 * np.sin(s) * np.cos(phi), k0 * np.sin(s) * np.sin(phi)
            make_op = _operators(cell, wl, kx0, ky0, eps_nominal, eps_faces, ("te", "tm")[pol],
                                 unit.threads)
            # the sampled exact identity, on the unit's first solve it can weigh (not a TM solve
            # across inner interfaces: solver/wave/energy.py)
            exact = i == 0 and k == first_checkable and checked and unit.method != "born"
            for from_below in ((False, True) if below else (False,)):
                if unit.method == "born":      # first order by design: truncated on purpose
                    res = solve_prepared(make_op(), from_below, tol=req.wave.solver_tol,
                                         method="born", maxiter=1, on_fail="truncate")
                    apps = res.applications
                else:
                    where = (f"{req.describe()}, realization {unit.realization}, λ {wl:g} nm, "
                             f"σ {np.degrees(s):.4g}°, azimuth {np.degrees(phi):.4g}°, "
                             f"{('TE', 'TM')[pol]}, from {'below' if from_below else 'above'}")
                    res, rungs, apps = converged_solve(make_op, from_below, tol=req.wave.solver_tol,
                                                       where=where,
                                                       exact_energy=exact and not from_below)
                    out["retries"][i, k] += rungs
                out["applications"][i, k] += apps
                out["seconds"][i, k] += res.seconds
                if from_below:
                    out["Rbar_below"][i, k] = res.R
                    continue
                if exact:
                    out["energy_error_exact"][0] = res.energy_error
                kz = k0 * np.cos(s)
                # re-reference the 00 amplitudes to the planes z = 0 and z = H (flat binder faces)
                out["alpha00"][i, k] = res.reflected.amp(0, 0) * np.exp(2j * kz * z_top)
                out["beta00"][i, k] = res.transmitted.amp(0, 0) * np.exp(
                    1j * kz * (z_top - z_bottom + req.thickness_nm))
                out["Rbar"][i, k], out["Tbar"][i, k] = res.R, res.T
                out["A"][i, k], out["energy_error"][i, k] = res.absorbed, res.energy_error
                refl = res.reflected
                keep = refl.propagating & ~((refl.m == 0) & (refl.n == 0))
                out["R"][i, k] = spread_orders(polar, dphi, refl.theta_rad[keep],
                                               fold_dphi(phi + np.pi, refl.phi_rad[keep]), refl.power[keep])
            if not below:
                out["Rbar_below"][i, k] = out["Rbar"][i, k]
    return out

