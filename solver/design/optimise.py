"""Minimise ΔE2000 (CIEDE2000, colour-science's delta_E) between a recipe's colour and an aim.

The free parameters (solver.design.recipe) are scaled to the unit box; ΔE2000² is minimised
by L-BFGS-B (finite-difference gradients) from the best points of a coarse grid, so a local
minimum of one start does not decide. The result says which parameters sit at a bound: an aim
out of reach is answered with the best recipe, its ΔE2000 and the bound that stops it.
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from ..colour.cie import delta_e2000
from .colour import FilmColour
from .recipe import PAPER_RANGE, InkTemplate, Recipe

#: ΔE2000 within which an aim counts as reached: CIELAB numbers, about one just-noticeable
#: difference; the standard's paper and solids, and its overprints: issue 21's numbers
REACHED_DE2000 = 1.0
SOLID_TARGET = 3.0
OVERPRINT_TARGET = 6.0


def default_tolerance(aim) -> float:
    """The ΔE2000 within which `aim` counts as reached (by its kind)."""
    return {"paper": SOLID_TARGET, "solid": SOLID_TARGET, "overprint": OVERPRINT_TARGET}.get(aim.kind, REACHED_DE2000)
#: a parameter closer than this (share of its range) to a bound sits at that bound: L-BFGS-B
#: with finite differences stops short of an active bound in a shallow valley (a cyan load of
#: 2.99 % against a 3 % cap: 0.3 % of the range), so a thousandth of the range missed bounds
AT_BOUND = 0.01
#: a particle ink's search stops when no free parameter moves more than this share of its range
STILL = 1e-3
#: a particle ink's design reads (or builds) at most this many wave-optics tables
PARTICLE_TABLES = 4
#: the coarse grid's size (points in all) and how many of its best points start a local search
GRID_SIZE = 100
STARTS = 3


@dataclass
class DesignResult:
    """The best recipe for an aim: its colour, ΔE2000, the parameters at a bound, the cost."""

    aim: object                                   # solver.colour.aims.Aim
    recipe: Recipe | None                         # None for the paper white and an overprint
    lab: np.ndarray
    de2000: float
    at_bounds: list[str] = field(default_factory=list)   # free parameters at a bound (`bound_names`)
    paper: float | None = None                    # the paper albedo (designed for the paper white)
    seconds: float = 0.0
    films: int = 0
    evaluations: int = 0
    stack: tuple[Recipe, ...] = ()                # an overprint's inks, top first
    tolerance: float | None = None                # ΔE2000 of "reached" (None: default_tolerance)
    particle_tables: int = 0                      # wave-optics tables built or read (particle inks)
    fixed: list[str] = field(default_factory=list)  # parameters the user fixed (`InkTemplate.fixed`)

    @property
    def limits(self) -> list[str]:
        """What stops a recipe short of its aim: the fixed parameters, then those at a bound."""
        return list(self.fixed) + list(self.at_bounds)

    @property
    def recipe_label(self) -> str:
        if self.stack:
            return " / ".join(r.label for r in self.stack)
        return f"paper albedo {self.paper:.4f}" if self.recipe is None else self.recipe.label

    @property
    def reached(self) -> bool:
        return self.de2000 <= (default_tolerance(self.aim) if self.tolerance is None else self.tolerance)

    def to_json(self) -> dict:
        if self.stack:
            recipe = {"overprint": [r.to_json() for r in self.stack], "order": "top first"}
        elif self.recipe is None:
            recipe = {"paper_albedo": round(float(self.paper), 6)}
        else:
            recipe = self.recipe.to_json()
        return {"recipe": recipe, "lab": [round(float(v), 3) for v in self.lab],
                "aim": [float(v) for v in self.aim.lab], "de2000": round(float(self.de2000), 4),
                "at_bounds": list(self.at_bounds), "fixed": list(self.fixed)}


def bound_names(names, x, bounds) -> list[str]:
    """'load C = 2.99 % (upper bound 3 %)' for each parameter within AT_BOUND of its range
    from a bound."""
    out = []
    for name, v, (lo, hi) in zip(names, x, bounds):
        span = hi - lo
        scale, unit = (100.0, " %") if name.startswith("load") else (1.0, " nm" if name.endswith("_nm") else "")
        for side, edge, near in (("lower", lo, v <= lo + AT_BOUND * span), ("upper", hi, v >= hi - AT_BOUND * span)):
            if near:
                out.append(f"{name} = {scale * v:.4g}{unit} ({side} bound {scale * edge:g}{unit})")
                break
    return out


def minimise_de(colour_of, aim_lab, bounds: np.ndarray, feasible=lambda x: True,
                tol: float = 1e-10, start=None) -> tuple[np.ndarray, float, int]:
    """(x, ΔE2000, evaluations) minimising ΔE2000(colour_of(x), aim) over the box `bounds`."""
    aim = np.asarray(aim_lab, dtype=float)
    lo, span = bounds[:, 0], bounds[:, 1] - bounds[:, 0]
    count = [0]
    if not len(lo):                                   # every parameter fixed: the one recipe
        x = lo.copy()
        value = float(delta_e2000(colour_of(x), aim)) if feasible(x) else np.inf
        return x, value, 1

    def de(u):
        x = lo + np.clip(u, 0.0, 1.0) * span
        if not feasible(x):
            return 1e6
        count[0] += 1
        value = float(delta_e2000(colour_of(x), aim))
        if not np.isfinite(value):              # never expected: a film is finite by construction
            raise ArithmeticError(f"ΔE2000 is {value} at parameters {x}: a bug in the colour of a recipe")
        return value

    def objective(u):
        return de(u) ** 2

    # the grid spans the box's faces too: an aim out of reach is often best met at a bound
    # (bare paper at load 0 for an aim no amount of this pigment nears)
    inner = np.linspace(0.05, 0.95, int(np.clip(np.floor(GRID_SIZE ** (1.0 / len(lo)) + 1e-9), 3, 9)))
    grid = np.concatenate([[0.0], inner, [1.0]])
    if start is None:
        starts = sorted(((de(np.array(u)), np.array(u)) for u in itertools.product(grid, repeat=len(lo))),
                        key=lambda t: t[0])[:STARTS]
    else:                                    # polish from one point (a particle ink's next step)
        starts = [(0.0, (np.asarray(start, dtype=float) - lo) / span)]
    best_u, best = None, np.inf
    for _, u0 in starts:
        res = minimize(objective, u0, method="L-BFGS-B", bounds=[(0.0, 1.0)] * len(lo),
                       options={"ftol": tol, "gtol": 1e-9, "eps": 1e-6, "maxiter": 200})
        value = de(res.x)
        if value < best:
            best_u, best = np.clip(res.x, 0.0, 1.0), value
    return lo + best_u * span, best, count[0]


def design_ink(aim, template: InkTemplate, colour: FilmColour, tolerance: float | None = None) -> DesignResult:
    """The recipe of `template`'s free parameters whose solid on the paper is closest to the aim
    (a particle ink: `design_particle_ink`)."""
    if template.particles != "molecular":
        return design_particle_ink(aim, template, colour, tolerance=tolerance)
    t0, films0 = time.perf_counter(), colour.films
    x, de, n = minimise_de(lambda v: colour.lab(template.recipe(v)), aim.lab, template.bounds(),
                           template.feasible)
    recipe = template.recipe(x)
    return DesignResult(aim, recipe, colour.lab(recipe), de, bound_names(template.names, x, template.bounds()),
                        colour.paper, time.perf_counter() - t0, colour.films - films0, n, fixed=template.fixed)


def design_particle_ink(aim, template: InkTemplate, colour: FilmColour,
                        max_tables: int = PARTICLE_TABLES, tolerance: float | None = None) -> DesignResult:
    """A particle ink: each recipe costs a wave-optics table (through the cache), so the search
    runs on the molecular ink of the same recipe (exact films, milliseconds) corrected by the
    grains' colour offset Δ = Lab_particles(x) − Lab_molecular(x) measured at the current recipe:
    x_{i+1} = argmin ΔE2000(Lab_molecular(x) + Δ_i, aim), one table per step (a fixed-point
    iteration: Δ changes slowly with the recipe). Stops at the tolerance, when the recipe no
    longer moves, or after `max_tables` tables; returns the best recipe measured with particles.
    tolerance: the ΔE2000 that ends the search (None: `default_tolerance(aim)`)."""
    from dataclasses import replace

    t0, films0, reads0, waves0 = time.perf_counter(), colour.films, colour.reads, colour.wave_tables
    molecular = replace(template, particles="molecular")
    bounds = template.bounds()
    offset, x, evaluations, best = np.zeros(3), None, 0, None
    tolerance = default_tolerance(aim) if tolerance is None else tolerance
    for _ in range(max_tables):
        x_new, _, n = minimise_de(lambda v: colour.lab(molecular.recipe(v)) + offset, aim.lab, bounds,
                                  template.feasible, start=x)
        evaluations += n
        if x is not None and np.all(np.abs(x_new - x) <= STILL * (bounds[:, 1] - bounds[:, 0])):
            break
        x = x_new
        lab = colour.lab(template.recipe(x))
        de = float(delta_e2000(lab, np.asarray(aim.lab)))
        if best is None or de < best[1]:
            best = (x, de, lab)
        if de <= tolerance:
            break
        offset = lab - colour.lab(molecular.recipe(x))
    x, de, lab = best
    return DesignResult(aim, template.recipe(x), lab, de, bound_names(template.names, x, bounds), colour.paper,
                        time.perf_counter() - t0, colour.films - films0, evaluations,
                        particle_tables=colour.wave_tables + colour.reads - waves0 - reads0, fixed=template.fixed)


def design_paper(aim, colour: FilmColour, wavelengths_nm, albedo_range=PAPER_RANGE) -> DesignResult:
    """The flat paper albedo whose colour is closest to the aim (a flat spectrum is neutral:
    only L* can be matched; an aim's a*, b* are the part out of reach)."""
    from dataclasses import replace

    t0 = time.perf_counter()
    wl = np.asarray(wavelengths_nm, dtype=float)

    def de(r):
        return float(delta_e2000(replace(colour, paper=float(r)).paper_lab(wl), np.asarray(aim.lab)))

    res = minimize_scalar(de, bounds=albedo_range, method="bounded", options={"xatol": 1e-7})
    r = float(res.x)
    paper = replace(colour, paper=r)
    return DesignResult(aim, None, paper.paper_lab(wl), de(r),
                        bound_names(("paper albedo",), [r], [albedo_range]), r,
                        time.perf_counter() - t0, 0, int(res.nfev))
