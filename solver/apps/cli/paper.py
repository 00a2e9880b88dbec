"""`ink-tables paper fig7|fig8|fig9`: the paper's figures, each from one command.

    ink-tables paper fig8 --accuracy preview --report fig8.md -o fig8.png      # + fig8.csv
    ink-tables paper fig7 --rows R15,Y7.5+B7.5 --columns molecular,sphere:100 -o part.png

Every missing table is built through the cache (an interrupted run resumes), the estimated
time is printed before the work starts and a progress bar shows the ETA; docs/figures.md says
what each figure and each CSV column shows.
"""

from __future__ import annotations

import warnings

from ..figures import FIGURES, FigureSettings, make_figure, parse_columns, parse_rows
from ..figures.models import DEFAULT_MODEL, MODELS, parse_model
from solver.table.request import ACCURACY
from solver.table.request_checks import ignored_on_molecular
from .build import add_request_arguments, add_run_arguments, given_options, options_from_args

#: the request options a figure takes as overrides of its preset (every cell gets them)
FIGURE_OVERRIDES = ("wavelengths_nm", "sigma_rad", "grid", "realizations", "azimuths", "cell_nm", "tier", "seed")
from .parsing import PARTICLE_GRAMMAR, DefaultsFormatter, add_measurement_arguments, measurement_from_args, writable_outputs


def add_parser(sub) -> None:
    p = sub.add_parser("paper", help="reproduce the paper's Fig. 7, Fig. 8 or Fig. 9 (PNG + CSV)",
                       formatter_class=DefaultsFormatter)
    p.add_argument("figure", choices=tuple(FIGURES), help="which figure")
    p.add_argument("-o", "--output", required=True, help="the figure (.png); the cells' colours go to the same "
                   "name with .csv")
    p.add_argument("--accuracy", choices=tuple(ACCURACY), default="default",
                   help="preset of the particle tables (default: default; docs/tables.md: error and cost of each)")
    p.add_argument("--rows", default=None, metavar="INKS",
                   help="ink specs separated by commas, e.g. R15,Y7.5+B7.5 (default: the figure's rows)")
    p.add_argument("--columns", default=None, metavar="GRAINS",
                   help="particle specs separated by commas, e.g. molecular,sphere:100,cylinder:200:inplane "
                        f"(default: the figure's columns); each molecular or {PARTICLE_GRAMMAR}")
    p.add_argument("--model", default=DEFAULT_MODEL, choices=tuple(MODELS),
                   help="paper = the model as published (TE light, bulk pigment ε, the strip without the coherent "
                        "mirror); default = this project's (unpolarised, local field, every order)")
    add_measurement_arguments(p)
    p.add_argument("--report", default=None, metavar="OUT.md",
                   help="also test the paper's §3.3 findings on every row/column pair and write them here")
    add_request_arguments(p, names=FIGURE_OVERRIDES, group="overrides of the preset (quick drafts; every cell gets them)")
    add_run_arguments(p)
    p.set_defaults(func=run, resumes=True)            # an interrupt keeps finished work units


def settings_from_args(args) -> FigureSettings:
    overrides = tuple((name, value) for name, value in given_options(args).items() if name in FIGURE_OVERRIDES)
    model = parse_model(args.model)
    measurement = measurement_from_args(args, model.measurement.geometry.name)
    return FigureSettings(args.accuracy, overrides, model,
                          None if measurement == model.measurement else measurement)


def run(args) -> int:
    if args.workers is not None and args.scheduler:
        raise ValueError("--workers and --scheduler exclude each other: the scheduler's workers do the work")
    rows = parse_rows(args.rows, args.figure)
    columns = parse_columns(args.columns, args.figure)
    settings = settings_from_args(args)
    ignored = settings.particle_only()
    if ignored and all(column.molecular for column in columns):
        warnings.warn(ignored_on_molecular("every column", ignored))
    opts = options_from_args(args)
    outputs = [(args.output, ".png", "-o")] + ([(args.report, ".md", "--report")] if args.report else [])
    out, report = (writable_outputs(outputs, make_folders=True) + [None])[:2]
    output = make_figure(args.figure, rows, columns, settings, opts, out, report)
    # cells that cannot exist (no table to plan, e.g. an unreachable concentration) are part of a
    # complete figure; a table that failed to build is a failure of this run: exit status 1
    return 1 if any(not r.ok and r.cache_key for r in output.records) else 0
