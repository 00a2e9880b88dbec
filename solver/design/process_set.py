"""Design a set of process inks against a standard's paper white, solids and overprints.

    results = design_process_set(ISO12647_2_PC1.values(), FilmColour())

1. The paper white: the flat albedo closest to the paper aim (`design_paper`); the inks are then
   printed on that paper (the standard's aims are measured on its own paper).
2. Each solid alone (`design_ink`, pigments from `recipe.PROCESS_PIGMENTS`).
3. The overprints (red = M + Y, green = C + Y, blue = C + M, printed in the order K, C, M, Y) are
   measured through the print model (`FilmColour.print_lab`); then the chromatic inks that
   print them are refined together, minimising Σ (ΔE2000 / tolerance)² over their solids and
   overprints (tolerances `SOLID_TARGET`, `OVERPRINT_TARGET`: the issue's ΔE2000 3 and 6), so
   that an overprint out of tolerance can trade a little of a solid's match.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
from scipy.optimize import minimize

from ..colour.aims import PROCESS_ORDER
from ..colour.cie import delta_e2000
from .colour import FilmColour
from .optimise import OVERPRINT_TARGET, SOLID_TARGET, DesignResult, bound_names, design_ink, design_paper
from .recipe import PROCESS_PIGMENTS, InkTemplate

#: L-BFGS-B iterations of the joint refinement (each costs one film per solid and overprint
#: per free parameter: its gains flatten after a few tens)
JOINT_ITERATIONS = 30


def design_process_set(aims, colour: FilmColour, template: InkTemplate | None = None, *,
                       design_paper_white: bool = True, joint: bool = True, pigments=None,
                       progress=lambda line: None) -> tuple[dict[str, DesignResult], FilmColour]:
    """{colour name: DesignResult} for every aim (paper, solids, overprints), and the FilmColour
    (paper) the inks were designed on. `template` gives the load and thickness ranges (its
    pigments are replaced by each process colour's: `recipe.PROCESS_PIGMENTS`, or `pigments`,
    {colour: codes}, where given)."""
    aims = list(aims)
    template = template or InkTemplate(("C",))
    results: dict[str, DesignResult] = {}
    paper_aim = next((a for a in aims if a.kind == "paper"), None)
    wl = colour.wavelengths_nm
    if paper_aim is not None:
        if design_paper_white:
            results["paper"] = design_paper(paper_aim, colour, wl)
            colour = replace(colour, paper=results["paper"].paper, films=0, wave_tables=0, reads=0, _tables={})
        else:
            lab = colour.paper_lab(wl)
            results["paper"] = DesignResult(paper_aim, None, lab, float(delta_e2000(lab, np.asarray(paper_aim.lab))),
                                            paper=float(colour.paper))
        progress(f"paper: albedo {results['paper'].paper:.4f}, ΔE2000 {results['paper'].de2000:.2f}")
    solids = {a.inks[0]: a for a in aims if a.kind == "solid"}
    own = dict(PROCESS_PIGMENTS, **(pigments or {}))
    templates = {name: replace(template, pigments=tuple(own[name])) for name in solids}
    for name, aim in solids.items():
        results[name] = design_ink(aim, templates[name], colour)
        progress(f"{name}: {results[name].recipe.label}, ΔE2000 {results[name].de2000:.2f}")
    overprints = [a for a in aims if a.kind == "overprint" and all(i in solids for i in a.inks)]
    if overprints:
        if joint:
            _refine_jointly(results, templates, overprints, colour, progress)
        for aim in overprints:
            t0, films0 = time.perf_counter(), colour.films
            order = sorted(aim.inks, key=PROCESS_ORDER.index)
            lab = colour.print_lab(tuple(results[i].recipe for i in order))
            results[aim.colour] = DesignResult(aim, None, lab, float(delta_e2000(lab, np.asarray(aim.lab))),
                                               paper=colour.paper, seconds=time.perf_counter() - t0,
                                               films=colour.films - films0,
                                               stack=tuple(results[i].recipe for i in reversed(order)))
    return results, colour


def _refine_jointly(results, templates, overprints, colour: FilmColour, progress) -> None:
    """Refine the inks that print the overprints together (module docstring, step 3)."""
    names = [n for n in PROCESS_ORDER if n in templates and any(n in a.inks for a in overprints)]
    sizes = [len(templates[n].bounds()) for n in names]
    bounds = np.vstack([templates[n].bounds() for n in names])
    lo, span = bounds[:, 0], bounds[:, 1] - bounds[:, 0]
    if not len(bounds):                               # every parameter fixed: nothing to refine
        return
    x0 = np.concatenate([templates[n].params(results[n].recipe) for n in names])
    t0, films0, count = time.perf_counter(), colour.films, [0]

    def recipes(u):
        x = lo + np.clip(u, 0.0, 1.0) * span
        parts = np.split(x, np.cumsum(sizes)[:-1])
        return {n: templates[n].recipe(p) for n, p in zip(names, parts)}, parts

    def cost(u):
        count[0] += 1
        rec, parts = recipes(u)
        if not all(templates[n].feasible(p) for n, p in zip(names, parts)):
            return 1e6
        total = sum((float(delta_e2000(colour.lab(rec[n]), np.asarray(results[n].aim.lab))) / SOLID_TARGET) ** 2
                    for n in names)
        for aim in overprints:
            order = sorted(aim.inks, key=PROCESS_ORDER.index)
            lab = colour.print_lab(tuple(rec[i] for i in order))
            total += (float(delta_e2000(lab, np.asarray(aim.lab))) / OVERPRINT_TARGET) ** 2
        return total

    u0 = (x0 - lo) / span
    before = cost(u0)
    res = minimize(cost, u0, method="L-BFGS-B", bounds=[(0.0, 1.0)] * len(lo),
                   options={"ftol": 1e-8, "eps": 1e-6, "maxiter": JOINT_ITERATIONS})
    if res.fun < before:
        rec, parts = recipes(res.x)
        for n, p in zip(names, parts):
            lab = colour.lab(rec[n])
            old = results[n]
            results[n] = DesignResult(old.aim, rec[n], lab, float(delta_e2000(lab, np.asarray(old.aim.lab))),
                                      bound_names(templates[n].names, p, templates[n].bounds()), colour.paper,
                                      old.seconds, old.films, old.evaluations, fixed=templates[n].fixed)
    seconds = time.perf_counter() - t0
    for n in names:
        results[n].seconds += seconds / len(names)
        results[n].films += (colour.films - films0) // len(names)
        results[n].evaluations += count[0] // len(names)
    progress(f"joint refinement of {', '.join(names)}: cost {before:.3f} → {min(res.fun, before):.3f} "
             f"({count[0]} evaluations, {seconds:.1f} s)")

