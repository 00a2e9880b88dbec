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
import warnings

from .parsing import OneLineParser, print_warning

SUBCOMMANDS = ("build", "show", "geometry", "paper")
VERBOSE_HELP = ("also log debug details (the request and its cache key, the options in effect); "
                "before or after the subcommand")
log = logging.getLogger("ink-tables")


def package_version() -> str:
    """The installed package's version, else the source tree's."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("inkbsdf")
    except PackageNotFoundError:
        from solver import __version__

        return f"{__version__} (not installed)"


def add_verbose(parser: argparse.ArgumentParser, default=False) -> None:
    parser.add_argument("-v", "--verbose", action="store_true", default=default, help=VERBOSE_HELP)


def make_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="ink-tables", description="Tables of printed-ink reflectance for the inkbsdf Mitsuba plugin.")
    add_verbose(parser)
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
        add_verbose(command, default=argparse.SUPPRESS)   # after the subcommand too, keeping one before it
        command.add_argument("--version", action="version", version=version)
    return parser


def configure_logging(verbose: bool) -> None:
    """What a build computes and reuses is logged always (INFO of inkbsdf.tables); -v adds the
    DEBUG lines of this package (not of the libraries it uses)."""
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("inkbsdf").setLevel(logging.DEBUG if verbose else logging.NOTSET)
    logging.getLogger("inkbsdf.tables").setLevel(logging.DEBUG if verbose else logging.INFO)
    log.setLevel(logging.DEBUG if verbose else logging.NOTSET)


def _terminated(signum, _frame):
    """SIGTERM: unwind like an interrupt, so temp files are removed and workers stopped."""
    raise SystemExit(128 + signum)


def _os_error(exc: OSError) -> str:
    return f"{exc.strerror or exc}: {exc.filename}" if exc.filename else str(exc.strerror or exc)


def main(argv: list[str] | None = None) -> int:
    """The command; returns the exit status (2: bad input, told in one line on stderr).
    Warnings are said as one `warning: …` line each on stderr."""
    with warnings.catch_warnings():
        warnings.showwarning = print_warning
        return _main(argv)


def _main(argv: list[str] | None) -> int:
    args = make_parser().parse_args(argv)
    configure_logging(args.verbose)
    log.debug("ink-tables %s, Python %s; options %s", package_version(), sys.version.split()[0],
              {k: v for k, v in vars(args).items() if k != "func" and v is not None})
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
    except RuntimeError as exc:                 # a table refused: no converged solve (the reason)
        from solver.wave import WaveSolverError      # (imported here: the CLI starts without NumPy)
        if not isinstance(exc, WaveSolverError):
            raise
        print(f"{prefix}: error: {exc}", file=sys.stderr)
        return 1
    except ValueError as exc:                   # bad input: requests, specs, tables, the cache
        print(f"{prefix}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:                      # read-only folder, full disk, missing file
        print(f"{prefix}: error: {_os_error(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
