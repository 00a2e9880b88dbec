"""`ink-tables geometry`: build one random cell of an ink layer, summarise it, draw its sections.

    ink-tables geometry --ink Y7.5+B7.5 --particles sphere:100:agglutinated --png out/geometry/agg.png

Lengths in nm; concentrations in percent in the ink spec.  The picture shows horizontal and
vertical sections like the paper's Figs. 3–5 (binder grey, air white, pigments in colour), cut
exactly through the particles and through the voxel grid the wave solver uses.
"""

from __future__ import annotations

from solver.inks import parse_ink
from solver.seeds import checked_seed
from solver.table.preflight import GEOMETRY_FIX, check_geometry
from solver.table.request import WaveSettings
from solver.table.request_checks import checked_layer, parsed_option, refuse_grains_without_pigment
from .parsing import PARTICLE_GRAMMAR, PARTICLE_GRAMMAR_KEY, DefaultsFormatter, writable_output

#: the voxel grid of a geometry picture (finer than a table's, for the sections)
PICTURE_GRID = (128, 128, 64)


def add_parser(sub) -> None:
    p = sub.add_parser("geometry", help="generate one random layer cell; summary and section pictures",
                       formatter_class=DefaultsFormatter)
    p.add_argument("--ink", required=True, help="ink, e.g. R15, Y7.5+B7.5, G30 (volume percent)")
    p.add_argument("--particles", required=True,
                   help=f"{PARTICLE_GRAMMAR} ({PARTICLE_GRAMMAR_KEY})")
    p.add_argument("--thickness", type=float, default=1000.0, help="layer thickness, nm")
    p.add_argument("--cell", type=float, nargs="+", default=[2000.0], metavar="NM",
                   help="cell period in x (and y), nm")
    seeds = p.add_mutually_exclusive_group()
    seeds.add_argument("--seed", type=int, default=None,
                       help="random seed of the generator (default 0)")
    seeds.add_argument("--realization", type=int, default=None, metavar="K",
                       help="draw realization K (from 0) of the tables `build` makes for this ink, with the "
                            "seed those tables derive from --table-seed (one-layer inks)")
    p.add_argument("--table-seed", type=int, default=None,
                   help=f"with --realization: the tables' --seed (default {WaveSettings().seed})")
    p.add_argument("--grid", type=int, nargs=3, default=None, metavar=("NX", "NY", "NZ"),
                   help=f"voxel grid (default {' '.join(map(str, PICTURE_GRID))}; with --realization the "
                        f"default tables' {' '.join(map(str, WaveSettings().grid))}, the cell they solved)")
    p.add_argument("--png", help="write the section pictures here")
    p.add_argument("--z", type=float, default=None, help="depth of the horizontal section, nm (default: middle)")
    p.add_argument("--y", type=float, default=None, help="y of the vertical section, nm (default: middle)")
    p.add_argument("--progress", action="store_true", help="show a progress bar of the generation stages")
    p.add_argument("--force", action="store_true",
                   help="generate even what the estimate says cannot fit this machine's memory")
    p.set_defaults(func=run, memory_hint=GEOMETRY_FIX)


def progress_bar():
    """A tqdm bar fed by generate's progress(stage, fraction); returns (callback, close)."""
    from tqdm import tqdm

    from solver.geometry import GENERATE_STAGES

    bar = tqdm(total=len(GENERATE_STAGES), unit="stage", bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed}")

    def update(stage: str, fraction: float) -> None:
        bar.set_description(stage)
        bar.n = GENERATE_STAGES.index(stage) + fraction
        bar.refresh()

    return update, bar.close


def generator_seed(args, ink, particles, cell) -> tuple[int, str]:
    """(seed of the generator, how to say it): --seed as given, or the seed the tables of this
    ink give realization --realization (`wave_tier.realization_seed`, the one rule)."""
    if args.realization is None:
        if args.table_seed is not None:
            raise ValueError("--table-seed goes with --realization K (the tables' realization to draw)")
        seed = 0 if args.seed is None else checked_seed(args.seed, "--seed")
        return seed, f"seed {seed}"
    if args.realization < 0:
        raise ValueError(f"--realization {args.realization}: realizations count from 0")
    if args.table_seed is not None:
        checked_seed(args.table_seed, "--table-seed")
    from solver.table.request import table_request
    from solver.table.wave_tier import realization_seed

    kw = {} if args.table_seed is None else {"seed": args.table_seed}
    request = table_request(ink, particles, thickness_nm=args.thickness, cell_nm=cell[0], **kw)
    if cell[0] != cell[1]:
        raise ValueError("--realization: tables use square cells; give one --cell length")
    seed = realization_seed(request, args.realization)
    return seed, (f"realization {args.realization} of the tables built with seed {request.wave.seed} "
                  f"(--table-seed; generator seed {seed})")


def run(args) -> int:
    from solver.geometry import generate, parse_particles, voxelize
    from solver.geometry.render import draw_sections
    from solver.geometry.report import summary

    if "/" in args.ink:
        raise ValueError(f"--ink {args.ink}: geometry draws one layer; give one ink of the stack, e.g. "
                         f"--ink {args.ink.split('/')[0]}")
    ink = parsed_option("ink", args.ink, parse_ink)
    particles = parsed_option("particles", args.particles, parse_particles)
    if particles is None:
        raise ValueError(f"--particles {args.particles}: a molecular ink is one homogeneous layer, with no "
                         "particle geometry to generate; give grains, e.g. sphere:100")
    refuse_grains_without_pigment(ink, particles)
    if len(args.cell) > 2:
        raise ValueError(f"--cell takes one or two lengths, got {len(args.cell)}")
    cell = (args.cell[0], args.cell[-1])
    grid = tuple(args.grid) if args.grid is not None else (
        WaveSettings().grid if args.realization is not None else PICTURE_GRID)
    if min(grid) < 1:
        raise ValueError(f"--grid {' '.join(map(str, grid))}: voxel counts are integers ≥ 1")
    for option, value, top in (("--z", args.z, args.thickness), ("--y", args.y, cell[1])):
        if value is not None and not 0.0 <= value <= top:
            raise ValueError(f"{option} {value:g}: the section must lie inside the layer cell, 0 … {top:g} nm")
    seed, seed_text = generator_seed(args, ink, particles, cell)
    layer = checked_layer(ink, particles, args.thickness, cell)
    if args.png:
        writable_output(args.png, ".png", "--png", make_folder=True)
    check_geometry(layer, grid, force=args.force)
    update, close = progress_bar() if args.progress else (None, lambda: None)
    try:
        real = generate(layer, seed, progress=update)
    finally:
        close()
    vox = voxelize(real, grid)
    print(summary(real, vox))
    if args.realization is not None:
        print(seed_text + ("" if args.grid is not None else
                           f", on the default tables' voxel grid {'×'.join(map(str, grid))}"))
    if args.png:
        title = f"{ink.label}, {particles.label}, H = {args.thickness:g} nm, {seed_text}"
        draw_sections(real, vox, args.png, title, z_nm=args.z, y_nm=args.y)
        print(f"wrote {args.png}")
    return 0
