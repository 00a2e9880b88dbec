"""`ink-tables design`: the ink recipe that prints an aim colour (the inverse problem).

    ink-tables design --aim iso12647-2:PC1:cyan                 # one process colour
    ink-tables design --aim 55,-37,-50 --pigments C             # CIELAB numbers
    ink-tables design --aim iso12647-2 -o process.json          # the whole ISO 12647-2 PC1 set

The logic lives in solver.design; this module parses the options (each checked before any
work), prints each recipe with its colour, ΔE2000 and cost, and writes -o OUT.json.
"""

from __future__ import annotations

import json
import shlex
import sys
import time

from solver.colour.aims import AIM_GEOMETRY, known_aims_text, parse_aim
from solver.design.recipe import LOAD_RANGE, PROCESS_PIGMENTS, THICKNESS_RANGE_NM, DesignError, InkTemplate
from solver.paper import PAPER_ALBEDO, check_paper_albedo
from .build import add_cache_argument, cache_from_args
from .parsing import DefaultsFormatter, add_measurement_arguments, measurement_from_args, writable_output


def _pair(text: str, option: str, unit: str) -> tuple[float, float]:
    try:
        values = [float(v) for v in str(text).split(",")]
    except ValueError:
        values = []
    if len(values) == 1:
        values = values * 2
    if len(values) != 2 or not all(v == v and abs(v) != float("inf") for v in values) or values[0] > values[1]:
        raise DesignError(f"{option} {text!r}: give MIN,MAX ({unit}, MIN ≤ MAX), or one value to fix it")
    return values[0], values[1]


def add_parser(sub) -> None:
    p = sub.add_parser("design", help="find the ink recipe whose printed colour is closest to an aim (ΔE2000)",
                       formatter_class=DefaultsFormatter, description=__doc__.split("\n\n")[0])
    p.add_argument("--aim", required=True,
                   help=f"L,a,b (CIELAB) or a named aim: {known_aims_text()} (iso12647-2: the whole set)")
    p.add_argument("--pigments", default=None, metavar="LETTERS",
                   help="pigments whose loads are free, e.g. C or K+C+M (default for a process colour: "
                        + ", ".join(f"{k} {'+'.join(v)}" for k, v in PROCESS_PIGMENTS.items())
                        + "; required for L,a,b aims)")
    p.add_argument("--load-range", default=f"{100 * LOAD_RANGE[0]:g},{100 * LOAD_RANGE[1]:g}", metavar="MIN,MAX",
                   help="range of each pigment load (volume percent); one value fixes every load")
    p.add_argument("--thickness-range", default=f"{THICKNESS_RANGE_NM[0]:g},{THICKNESS_RANGE_NM[1]:g}",
                   metavar="MIN,MAX", help="range of the layer thickness (nm); one value fixes it")
    p.add_argument("--particles", default="molecular",
                   help="molecular (exact films, fast) or a particle spec (tables through the cache)")
    p.add_argument("--paper", type=float, default=None,
                   help=f"paper albedo r (default: for ISO 12647-2 aims the PC1 paper designed against its "
                        f"white, else {PAPER_ALBEDO:g})")
    lf = p.add_mutually_exclusive_group()
    lf.add_argument("--local-field", dest="local_field", action="store_true", default=None,
                    help="pigments with their grains' local field in the binder (the tables' default)")
    lf.add_argument("--no-local-field", dest="local_field", action="store_false", default=None,
                    help="pigments with their bulk permittivity (the paper's volume mix)")
    p.add_argument("--tolerance", type=float, default=None, metavar="DE2000",
                   help="ΔE2000 within which an aim counts as reached (default: 3 for ISO 12647-2 solids and "
                        "paper, 6 for its overprints, 1 for L,a,b)")
    p.add_argument("--no-joint", action="store_true",
                   help="a set: keep each solid's own best recipe (no joint refinement against the overprints)")
    add_measurement_arguments(p, geometry_default=AIM_GEOMETRY)
    p.add_argument("-o", "--output", default=None, metavar="OUT.json",
                   help='write {"aims": {NAME: {"recipe", "lab", "aim", "de2000"}}} here')
    add_cache_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    # every option checked before any work
    aims = parse_aim(args.aim)
    measurement = measurement_from_args(args, AIM_GEOMETRY)
    load_range = tuple(v / 100.0 for v in _pair(args.load_range, "--load-range", "percent"))
    thickness_range = _pair(args.thickness_range, "--thickness-range", "nm")
    if args.tolerance is not None and not args.tolerance > 0:
        raise DesignError(f"--tolerance {args.tolerance:g}: give a ΔE2000 > 0")
    if args.paper is not None:
        check_paper_albedo(args.paper, what="--paper (the paper albedo)")
    output = writable_output(args.output, ".json", "-o/--output") if args.output else None
    custom = [a for a in aims if a.kind == "custom"]
    if custom and not args.pigments:
        raise DesignError(f"--aim {args.aim}: give --pigments (the pigments to design with, e.g. C or K+C+M)")
    pigments = InkTemplate.of(args.pigments).pigments if args.pigments else ("C",)
    if args.pigments and len([a for a in aims if a.kind != "paper"]) > 1:
        raise DesignError("--pigments names the pigments of one ink: a set designs each process colour with its own "
                          "(" + ", ".join(f"{k} {'+'.join(v)}" for k, v in PROCESS_PIGMENTS.items()) + ")")
    template = InkTemplate(pigments, load_range, thickness_range, args.particles)
    if args.particles != "molecular":
        from solver.table.request import table_request

        table_request("Y10", args.particles)            # the particle spec checked now (one line)
        if any(a.kind == "overprint" for a in aims):
            raise DesignError("--particles: overprints are stacks of molecular layers only (as the ink BSDF "
                              "prints them); design particle solids one at a time")
        print(particle_tables_line(template, args.local_field), file=sys.stderr, flush=True)
    from solver.design import FilmColour, design_ink, design_process_set
    from solver.table.cache import TableCache

    cache = cache_from_args(args) if args.cache else TableCache.default()
    colour = FilmColour(PAPER_ALBEDO if args.paper is None else args.paper, measurement, cache, args.local_field)
    t0 = time.perf_counter()
    if custom:
        results = {aims[0].name: design_ink(aims[0], template, colour, args.tolerance)}
    else:
        wanted = _with_solids(aims)
        own = {a.colour: pigments for a in aims if a.kind == "solid"} if args.pigments else {}
        results, colour = design_process_set(wanted, colour, template, design_paper_white=args.paper is None,
                                             joint=not args.no_joint, pigments=own,
                                             progress=lambda line: print(f"  … {line}", file=sys.stderr))
        names = {a.colour for a in aims}
        results = {k: v for k, v in results.items() if k in names}
    seconds = time.perf_counter() - t0
    for result in results.values():
        result.tolerance = args.tolerance
        print(report_lines(result, measurement.label))
    print(f"total {seconds:.1f} s, {colour.films} film tables computed"
          + (f", {colour.wave_tables} particle tables built" if colour.wave_tables else "")
          + (f", {colour.reads} read from the cache" if colour.reads else ""))
    if output is not None:
        document = {"aims": {k: r.to_json() for k, r in results.items()},
                    "measurement": measurement.label, "command": command_line(args)}
        output.write_text(json.dumps(document, indent=2) + "\n")
        print(f"wrote {output}")
    return 0


def particle_tables_line(template: InkTemplate, local_field) -> str:
    """What a particle design will build, said before it starts: the preflight estimate of one
    table (the starting recipe's; solver/table/preflight.py) and the most tables an ink's design
    reads or builds (solver.design.optimise.PARTICLE_TABLES); tables in the cache are only read."""
    from solver.design.optimise import PARTICLE_TABLES
    from solver.table.executor import default_workers
    from solver.table.preflight import estimate
    from solver.table.request import table_request

    recipe = template.recipe(template.start())
    workers = default_workers()                       # as FilmColour builds them (BuildOptions' default)
    est = estimate(table_request(recipe.ink, recipe.particles, thickness_nm=recipe.thickness_nm,
                                 local_field=local_field), workers)
    return (f"--particles {template.particles}: up to {PARTICLE_TABLES} particle tables per ink (those in the "
            f"cache are read), each estimated {est.describe()} on {workers} worker{'s' if workers != 1 else ''}")


def command_line(args) -> str:
    """The command that made a result (the options given, output and cache left out)."""
    parts = ["ink-tables", "design", "--aim", args.aim]
    for option, value, default in (
            ("--pigments", args.pigments, None),
            ("--load-range", args.load_range, f"{100 * LOAD_RANGE[0]:g},{100 * LOAD_RANGE[1]:g}"),
            ("--thickness-range", args.thickness_range, f"{THICKNESS_RANGE_NM[0]:g},{THICKNESS_RANGE_NM[1]:g}"),
            ("--particles", args.particles, "molecular"), ("--paper", args.paper, None),
            ("--geometry", args.geometry, AIM_GEOMETRY), ("--illuminant", args.illuminant, "D50"),
            ("--observer", args.observer, "2")):
        if value is not None and str(value) != str(default):
            parts += [option, str(value)]
    if args.local_field is not None:
        parts.append("--local-field" if args.local_field else "--no-local-field")
    if args.no_joint:
        parts.append("--no-joint")
    return " ".join(shlex.quote(p) for p in parts)


def _with_solids(aims):
    """The aims with the paper and the solids their overprints need (designed, not reported)."""
    from solver.colour.aims import ISO12647_2_PC1

    names = {a.name for a in aims}
    extra = [a for a in ISO12647_2_PC1.values()
             if a.name not in names and (a.kind == "paper" or any(a.kind == "solid" and a.inks[0] in b.inks
                                                                  for b in aims if b.kind == "overprint"))]
    return extra + list(aims)


def report_lines(result, measurement_label: str) -> str:
    """Recipe, colour, ΔE2000, cost; for an aim out of reach, what limits it: the parameters the
    user fixed and those at their bounds."""
    lab, aim = result.lab, result.aim.lab
    lines = [f"{result.aim.name}: aim L*a*b* ({aim[0]:.1f}, {aim[1]:.1f}, {aim[2]:.1f}), {measurement_label}",
             f"  recipe  {result.recipe_label}" + (f"  on paper albedo {result.paper:.4f}"
                                                   if result.recipe is not None or result.stack else ""),
             f"  colour  L*a*b* ({lab[0]:.2f}, {lab[1]:.2f}, {lab[2]:.2f})  ΔE2000 {result.de2000:.2f}",
             (f"  cost    {result.seconds:.2f} s, {result.films} film tables, {result.evaluations} evaluations"
              + (f", {result.particle_tables} particle tables (cache)" if result.particle_tables else ""))
             if not result.stack else "  cost    measured with its inks' designs (the total below)"]
    if not result.reached:
        if result.stack:
            lines.append(f"  out of reach: ΔE2000 {result.de2000:.2f} (an overprint has no parameters of its own: "
                         "its inks' absorption bands set it)")
        else:
            why = "; ".join(result.limits) if result.limits else \
                "none (no parameter fixed or at a bound: the pigments' absorption bands cannot make this colour)"
            lines.append(f"  out of reach: best ΔE2000 {result.de2000:.2f}; limited by: {why}")
    return "\n".join(lines)
