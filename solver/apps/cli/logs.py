"""What the commands (`ink-tables`, `python -m inkbsdf.render`, `… print`) log on stderr, one
setup for all: by default only warnings, as `warning: …` lines like those of the warnings module
(the commands print their result lines themselves); -v/--verbose adds this package's INFO lines
(what a build computes and reuses, how long) and DEBUG lines (the request and its cache key, the
options in effect), never the libraries'."""

from __future__ import annotations

import argparse
import logging

#: the loggers whose level the commands set: this package's ("inkbsdf.*", the commands'
#: "ink-tables"), and "inkbsdf.tables", which a scene load outside a command sets to INFO
#: (inkbsdf.source.show_build_log)
PACKAGE_LOGGERS = ("inkbsdf", "inkbsdf.tables", "ink-tables")
VERBOSE_HELP = ("also log what is computed and reused, and debug details (the request and its cache key, "
                "the options in effect)")


def add_verbose(parser: argparse.ArgumentParser, default=False, note: str = "") -> None:
    """-v/--verbose on `parser` (`note` ends its help, e.g. where the option may stand)."""
    parser.add_argument("-v", "--verbose", action="store_true", default=default,
                        help=VERBOSE_HELP + (f"; {note}" if note else ""))


class LineFormatter(logging.Formatter):
    """`warning: message` (the level in lower case) for warnings and errors, as the commands say
    them; `inkbsdf: message` for a table build's first and last line (the logger `builds`);
    `INFO logger: message` for what -v adds."""

    def __init__(self, builds: str | None = None):
        super().__init__()
        self.builds = builds

    def format(self, record: logging.LogRecord) -> str:
        if record.name == self.builds and record.levelno == logging.INFO:
            return f"inkbsdf: {record.getMessage()}"
        if record.levelno >= logging.WARNING:
            return f"{record.levelname.lower()}: {record.getMessage()}"
        return f"{record.levelname} {record.name}: {record.getMessage()}"


def configure_logging(verbose: bool, builds: bool = False) -> None:
    """Warnings on stderr always; with `verbose` also this package's INFO and DEBUG lines; with
    `builds` (commands that build tables on the way: render, print) a table build's first and
    last line even without `verbose` ('inkbsdf: computing table: … (estimated 40 s …)', so a
    long scene load is not silent). The handler is installed once per process, unless the
    application (or pytest) configured logging already; the levels are set at every call."""
    # the table builder (NumPy, SciPy) is imported here, not with this module: the commands
    # import this module before their interrupt handling is in place (solver/apps/cli/__init__.py)
    from solver.table.builder import BUILDS_LOGGER

    handler = logging.StreamHandler()
    handler.setFormatter(LineFormatter(BUILDS_LOGGER))
    logging.basicConfig(level=logging.WARNING, handlers=[handler])
    for name in PACKAGE_LOGGERS:
        logging.getLogger(name).setLevel(logging.DEBUG if verbose else logging.NOTSET)
    logging.getLogger(BUILDS_LOGGER).setLevel(logging.INFO if builds or verbose else logging.NOTSET)
