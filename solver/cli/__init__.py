"""`ink-tables`: build, inspect and picture ink tables and layer geometry.

Each subcommand lives in its own module exposing `add_parser(subparsers)`; the parser sets
`func(args) -> int`.  Angles are in degrees and concentrations in percent at this level only.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys

SUBCOMMANDS = ("build", "show", "geometry")


def make_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ink-tables", description="Tables of printed-ink reflectance for the inkbsdf Mitsuba plugin.")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = parser.add_subparsers(dest="command", required=True)
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"solver.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"solver.cli.{name}":
                continue          # subcommand not installed in this build
            raise
        module.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = make_parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("inkbsdf.tables").setLevel(logging.INFO)   # what a build computes, and reuses
    try:
        return int(args.func(args) or 0)
    except (ValueError, FileNotFoundError) as exc:
        print(f"ink-tables {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
