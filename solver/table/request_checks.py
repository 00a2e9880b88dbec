"""Refusing meaningless table requests before any work, with one line naming the option
(`request.table_request` calls `validate` on every request it makes), and the names and limits
it checks against."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..geometry.stacking import split_cells
from ..seeds import checked_seed
from .options import OPTION
from .schema import POLARISATIONS

if TYPE_CHECKING:
    from .request import TableRequest


class RequestError(ValueError):
    """A table request that cannot be computed as asked; the message names the option."""


class ThinLayerWarning(UserWarning):
    """A layer thinner than THIN_LAYER_NM: valid, but most likely µm typed as nm."""


def parsed_option(name: str, given, parse, part=None):
    """parse(part) (part: `given` itself by default) for the request option `name`, a grammar
    error told with the option and what was given (`--ink 'R-5': negative concentration …`)."""
    try:
        return parse(given if part is None else part)
    except ValueError as exc:
        raise RequestError(f"{OPTION[name]} {given!r}: {exc}") from None


#: most incidence angles a table may have: 0.02° steps, far finer than any film or grain feature
#: the linear interpolation in σ needs (a molecular table at 4096 angles is ~16 MB)
MAX_ANGLES = 4096
TIERS = ("auto", "thin-film", "effective-medium", "born", "full")
MIN_GRID = (8, 8, 4)
#: layers thinner than this are most likely µm typed as nm (a printed ink layer is ~1000 nm)
THIN_LAYER_NM = 50.0


def _finite_positive(value, what: str) -> None:
    if not (isinstance(value, (int, float, np.floating, np.integer)) and math.isfinite(value) and value > 0):
        raise RequestError(f"{what} must be a positive finite number, got {value!r}")


def refuse_grains_without_pigment(ink, particles) -> None:
    """Grains (`particles`, None: molecular) need pigment to be made of: 'clear' has none."""
    if particles is not None and not ink.components:
        raise RequestError(f"--particles {particles.label}: 'clear' has no pigment to make grains "
                           "of; use --particles molecular")


def checked_layer(ink, particles, thickness_nm: float, cell_nm: tuple[float, float]):
    """The geometry.LayerSpec of a particle layer, its refusal (a grain taller than the layer,
    or spanning half the cell) told with the options and the fix."""
    from ..geometry.spec import GeometryError, LayerSpec

    try:
        return LayerSpec(ink, particles, thickness_nm=thickness_nm, cell_nm=cell_nm)
    except GeometryError as exc:
        tall = particles.max_height_nm(particles.max_diameter_nm) > thickness_nm
        fix = f"a thicker {OPTION['thickness_nm']}" if tall else f"a larger {OPTION['cell_nm']}"
        raise RequestError(f"{OPTION['particles']}: {exc}: give a smaller grain or {fix}") from None


def ignored_on_molecular(what: str, options) -> str:
    """The warning that options of particle inks (`options`, CLI names) mean nothing where every
    layer is molecular (an exact thin film); `what` names the ink(s)."""
    return f"{what} is molecular (an exact thin film): {', '.join(options)} ignored"


def thin_layers_warning(thicknesses_nm, option: str = OPTION["thickness_nm"]) -> str | None:
    """A warning for layers thinner than THIN_LAYER_NM (µm typed as nm?), or None; `option`
    names where the thicknesses were given (`ink-tables design` says --thickness-range)."""
    thin = [t for t in thicknesses_nm if t < THIN_LAYER_NM]
    if not thin:
        return None
    return (f"{option} {', '.join(f'{t:g}' for t in thin)}: a layer thinner than "
            f"{THIN_LAYER_NM:g} nm, while a printed ink layer is ~1000 nm (1 µm): thicknesses are in nm")


#: the wavelength steps (nm) fringe_aliasing_warning offers, coarsest first (each divides 400 nm)
FRINGE_STEPS_NM = (5.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.2, 0.1)


def fringe_aliasing_warning(thickness_nm: float, wavelengths_nm, binder_index: float) -> str | None:
    """A warning when a film's interference fringes are finer than the table's wavelength step
    (less than one sample per fringe at the blue end: the colour is aliased), or None.  Fringe
    spacing at normal incidence (the finest): Δλ = λ²/(2 n d) at the shortest λ, d the whole
    film (a stack's layers together).  Measured on clear binder films, 45:0/D50 on paper, the
    10-nm step against 0.5 nm: ΔE2000 ≤ 0.31 up to d = 5000 nm (Δλ 9.3 nm at 380 nm), 4.2 at
    6500 nm (7.1 nm), 2.3–2.6 at 10–20 µm — the boundary is one sample per fringe."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    if wl.size < 2:
        return None
    step = float(np.max(np.diff(wl)))
    spacing = float(wl[0]) ** 2 / (2.0 * binder_index * float(thickness_nm))
    if step <= spacing:
        return None
    said = (f"{OPTION['thickness_nm']}: a {thickness_nm:g}-nm film's interference fringes "
            f"are {spacing:.3g} nm apart at {wl[0]:g} nm, and the table samples every {step:g} nm: its colour is "
            f"aliased; ")
    fine = next((s for s in FRINGE_STEPS_NM if s <= spacing / 2.0), None)
    if fine is None:          # no step we offer resolves them: only the layer can change
        return said + (f"no wavelength step down to {FRINGE_STEPS_NM[-1]:g} nm resolves them: use a "
                       f"thinner layer (ink layers are ~1000 nm)")
    return said + (f"sample finer ({OPTION['wavelengths_nm']} {wl[0]:g}:{wl[-1]:g}:{fine:g}) or use a "
                   f"thinner layer")


def validate(req: TableRequest) -> None:
    """Refuse meaningless requests with one line naming the option (before any work)."""
    if not req.layers:
        raise RequestError("a table needs at least one layer (--ink)")
    for layer in req.layers:
        _finite_positive(layer.thickness_nm, f"{OPTION['thickness_nm']} (layer thickness, nm)")
        refuse_grains_without_pigment(layer.ink, layer.particles)
    wl = np.asarray(req.grids.wavelengths_nm)
    if wl.size < 2 or not np.all(np.isfinite(wl)) or np.any(np.diff(wl) <= 0):
        raise RequestError(f"{OPTION['wavelengths_nm']}: need ≥ 2 strictly increasing finite wavelengths (nm)")
    try:
        req.materials.check_range(wl, OPTION["wavelengths_nm"])
    except ValueError as exc:
        raise RequestError(str(exc)) from None
    s = np.asarray(req.grids.sigma_rad)
    if s.size > MAX_ANGLES:
        raise RequestError(f"{OPTION['sigma_rad']}: {s.size:,} incidence angles; at most {MAX_ANGLES} "
                           "(finer than the tables' interpolation needs, and the table grows with them)")
    if s.size < 2 or not np.all(np.isfinite(s)) or abs(s[0]) > 1e-12 or abs(s[-1] - np.pi / 2) > 1e-12 \
            or np.any(np.diff(s) <= 0):
        raise RequestError(f"{OPTION['sigma_rad']}: incidence angles must increase strictly from 0° to 90°")
    if not (isinstance(req.grids.dphi_count, (int, np.integer)) and req.grids.dphi_count >= 3):
        raise RequestError(f"{OPTION['dphi_count']} must be an integer ≥ 3, got {req.grids.dphi_count!r}")
    if req.polarisation not in POLARISATIONS:
        raise RequestError(f"{OPTION['polarisation']} {req.polarisation!r}: choose one of {', '.join(POLARISATIONS)}")
    if not isinstance(req.local_field, (bool, np.bool_)):
        raise RequestError(f"{OPTION['local_field']} is on or off (a boolean), got {req.local_field!r}; "
                           "in a scene write <boolean name=\"local_field\" value=\"false\"/>")
    if req.wave is None:
        return
    w = req.wave
    if len(req.layers) > 1:
        if req.has_rough_top:
            raise RequestError(f"--particles {req.particles_label}: a rough top inside a stack is not modelled; "
                               "give the stacked particle layers flat faces")
        try:
            split_cells([layer.thickness_nm for layer in req.layers], int(w.grid[2]))
        except ValueError as exc:
            raise RequestError(str(exc)) from None
    _finite_positive(w.cell_nm, f"{OPTION['cell_nm']} (cell period, nm)")
    for layer in req.layers:
        if layer.particles is not None:
            checked_layer(layer.ink, layer.particles, layer.thickness_nm, (w.cell_nm, w.cell_nm))
    if len(w.grid) != 3 or any(not isinstance(n, (int, np.integer)) for n in w.grid) \
            or any(n < m for n, m in zip(w.grid, MIN_GRID)):
        raise RequestError(f"{OPTION['grid']} {' '.join(map(str, w.grid))}: need at least "
                           f"{' '.join(map(str, MIN_GRID))} voxels (NX NY NZ) for a meaningful table")
    for name in ("realizations", "azimuths", "wavelength_stride"):
        value = getattr(w, name)
        if not isinstance(value, (int, np.integer)) or value < 1:
            raise RequestError(f"{OPTION[name]} must be an integer ≥ 1, got {value!r}")
    if not (isinstance(w.solver_tol, (int, float)) and math.isfinite(w.solver_tol) and 0 < w.solver_tol < 0.5):
        raise RequestError(f"{OPTION['solver_tol']} (wave solver relative residual) must lie in (0, 0.5), "
                           f"got {w.solver_tol!r}")
    if not (isinstance(w.tolerance, (int, float)) and math.isfinite(w.tolerance) and 0 < w.tolerance <= 1):
        raise RequestError(f"{OPTION['tolerance']} (allowed model error when choosing the tier) must lie in "
                           f"(0, 1], got {w.tolerance!r}")
    if w.target_se is not None and not (isinstance(w.target_se, (int, float)) and math.isfinite(w.target_se)
                                        and 0 < w.target_se < 1):
        raise RequestError(f"{OPTION['target_se']} (wanted standard error of Rbar and Tbar) must lie in (0, 1), "
                           f"got {w.target_se!r}")
    if not isinstance(w.max_realizations, (int, np.integer)) or w.max_realizations < w.realizations:
        raise RequestError(f"{OPTION['max_realizations']} must be an integer ≥ --realizations "
                           f"({w.realizations}), got {w.max_realizations!r}")
    checked_seed(w.seed, OPTION["seed"], RequestError)
    if w.tier not in TIERS:
        raise RequestError(f"{OPTION['tier']} {w.tier!r}: choose one of {', '.join(TIERS)}")
    if w.tier == "thin-film":
        raise RequestError(f"{OPTION['tier']} thin-film is for molecular inks; with particles use "
                           "'effective-medium' for the mean-ε film")
