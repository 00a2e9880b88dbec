"""`ink-tables`: build, inspect and picture ink tables and layer geometry.

Each subcommand lives in its own module exposing `add_parser(subparsers)`; the parser sets
`func(args) -> int`.  Angles are in degrees and concentrations in percent at this level only.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
import warnings

from ...interrupts import Terminated, deferred, exit_status, raising
from .logs import add_verbose, configure_logging

# .parsing (NumPy, the request's grammar) is imported inside the functions: an interrupt while
# it loads is then one line too (main)

SUBCOMMANDS = ("build", "show", "geometry", "paper", "design")
WHERE_VERBOSE = "before or after the subcommand"
log = logging.getLogger("ink-tables")


def package_version() -> str:
    """The installed package's version, else the source tree's."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("inkbsdf")
    except PackageNotFoundError:
        from solver import __version__

        return f"{__version__} (not installed)"


def make_parser() -> argparse.ArgumentParser:
    from .parsing import OneLineParser

    parser = OneLineParser(
        prog="ink-tables", description="Tables of printed-ink reflectance for the inkbsdf Mitsuba plugin.")
    add_verbose(parser, note=WHERE_VERBOSE)
    version = f"ink-tables {package_version()}"
    parser.add_argument("--version", action="version", version=version)
    sub = parser.add_subparsers(dest="command", required=True)
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"solver.apps.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"solver.apps.cli.{name}":
                continue          # subcommand not installed in this build
            raise
        module.add_parser(sub)
    for command in sub.choices.values():
        add_verbose(command, argparse.SUPPRESS, WHERE_VERBOSE)   # after the subcommand too, keeping one before it
        command.add_argument("--version", action="version", version=version)
    return parser


def main(argv: list[str] | None = None) -> int:
    """The command; returns the exit status (2: bad input, told in one line on stderr; the
    commands' one wrapper, parsing.run_guarded). Warnings are said as one `warning: …` line each.
    SIGINT and SIGTERM, from this function's first line on, end it with one line (exit 130 /
    143): temp files removed, workers stopped (solver.interrupts)."""
    with raising():
        try:
            with deferred():              # an import cut short by a signal fails oddly (numpy: ImportError)
                from .parsing import print_warning, run_guarded

                with warnings.catch_warnings():
                    warnings.showwarning = print_warning
                    args = make_parser().parse_args(argv)
        except KeyboardInterrupt as exc:               # it arrived while the commands' modules loaded
            print(f"ink-tables: {'terminated' if isinstance(exc, Terminated) else 'interrupted'}", file=sys.stderr)
            return exit_status(exc)
        prefix = f"ink-tables {args.command}"
        note = " (finished work units are kept; rerun to resume)" if getattr(args, "resumes", False) else ""
        hint = {"memory_hint": args.memory_hint} if getattr(args, "memory_hint", None) else {}
        return run_guarded(lambda: _run(args), prefix, f"{prefix}: {{interrupted}}{note}", **hint)


def _run(args) -> int:
    configure_logging(args.verbose)
    log.debug("ink-tables %s, Python %s; options %s", package_version(), sys.version.split()[0],
              {k: v for k, v in vars(args).items() if k not in ("func", "resumes", "memory_hint") and v is not None})
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
