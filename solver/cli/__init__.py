"""`ink-tables`: build, inspect and picture ink tables and layer geometry.

Each subcommand lives in its own module exposing `add_parser(subparsers)`; the parser sets
`func(args) -> int`.  Angles are in degrees and concentrations in percent at this level only.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import signal
import sys
import threading

from .parsing import OneLineParser

SUBCOMMANDS = ("build", "show", "geometry", "paper")


def make_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
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


def _terminated(signum, _frame):
    """SIGTERM: unwind like an interrupt, so temp files are removed and workers stopped."""
    raise SystemExit(128 + signum)


def _os_error(exc: OSError) -> str:
    return f"{exc.strerror or exc}: {exc.filename}" if exc.filename else str(exc.strerror or exc)


def main(argv: list[str] | None = None) -> int:
    args = make_parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("inkbsdf.tables").setLevel(logging.INFO)   # what a build computes, and reuses
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminated)
    prefix = f"ink-tables {args.command}"
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"{prefix}: interrupted (finished work units are kept; rerun to resume)", file=sys.stderr)
        return 130
    except BrokenPipeError:                     # e.g. `ink-tables show t.npz | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except MemoryError as exc:                  # e.g. a build forced past the preflight's estimate
        first = str(exc).splitlines()[0] if str(exc) else "out of memory"
        print(f"{prefix}: error: ran out of memory ({first}); use coarser settings (--grid, --wavelengths, "
              "--angles) or fewer --workers", file=sys.stderr)
        return 1
    except ValueError as exc:                   # bad input: requests, specs, tables, the cache
        print(f"{prefix}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:                      # read-only folder, full disk, missing file
        print(f"{prefix}: error: {_os_error(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
