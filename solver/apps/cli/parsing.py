"""Command-line plumbing shared by `ink-tables`, `python -m inkbsdf.render` and `… print`:
one-line usage errors, help that states each default once, and output paths checked before any
work."""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from solver.interrupts import Terminated, exit_status, received
from solver.geometry.spec import PARTICLE_GRAMMAR, PARTICLE_GRAMMAR_KEY  # noqa: F401  (the commands' help)
from solver.table.request import MAX_ANGLES, RequestError


def print_warning(message, category=None, filename=None, lineno=None, file=None, line=None) -> None:
    """`warnings.showwarning` of the commands: one `warning: …` line on stderr, no source line."""
    print(f"warning: {message}", file=sys.stderr)


def os_error_text(exc: OSError) -> str:
    """An OSError as one line: what went wrong, and the file."""
    return f"{exc.strerror or exc}: {exc.filename}" if exc.filename else str(exc.strerror or exc)


def interrupted_word(exc: KeyboardInterrupt) -> str:
    """How an interrupt is told: "interrupted" (Ctrl-C) or "terminated" (SIGTERM)."""
    return "terminated" if isinstance(exc, Terminated) else "interrupted"


#: what run_guarded tells a command that ran out of memory to do (a command may name its own)
MEMORY_HINT = "use coarser settings (--grid, --wavelengths, --angles) or fewer --workers"


def run_guarded(work, program: str, interrupted: str | None = None, memory_hint: str = MEMORY_HINT) -> int:
    """The commands' one wrapper (`ink-tables`, `python -m inkbsdf.print`, `… render`): run
    `work()` (→ exit status) with each warning said as one `warning: …` line, bad input (a
    ValueError: requests, specs, tables, images, usage) and file problems (OSError) as one
    `PROGRAM: error: …` line and exit 2 (argparse's form: `program` is the usage line's, e.g.
    "ink-tables build" or "python -m inkbsdf.render"), a table refused for want of a converged solve
    (solver.wave.WaveSolverError, solver/table/retry.py) as one such line and exit 1, an interrupt
    (Ctrl-C, or SIGTERM as solver.interrupts.Terminated) as the line `interrupted` — its
    `{interrupted}` filled with "interrupted" or "terminated" — and exit 128 + the signal (None:
    the caller handles interrupts), a worker process lost (killed from outside) as one line and
    exit 1, a closed output pipe quietly (`… | head`), memory exhausted
    as one line (with `memory_hint`) and exit 1. Anything else is a bug and keeps its traceback."""
    lead = f"{program}: error:"
    with warnings.catch_warnings():
        warnings.showwarning = print_warning
        try:
            return int(work() or 0)
        except BaseException as exc:
            interrupt = exc if isinstance(exc, KeyboardInterrupt) else None
            if interrupt is None and not isinstance(exc, SystemExit):
                interrupt = received()                # an interrupt that C code turned into another error
            if interrupt is None or interrupted is None:
                return _failure(exc, lead, memory_hint)
            print(interrupted.replace("{interrupted}", interrupted_word(interrupt)), file=sys.stderr)
            return exit_status(interrupt)


def _failure(exc: BaseException, lead: str, memory_hint: str) -> int:
    """run_guarded's exit status for a failure that is not a bug (told in one line), else the
    exception again."""
    if isinstance(exc, BrokenPipeError):
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    if isinstance(exc, MemoryError):                  # e.g. a build forced past the preflight's estimate
        first = str(exc).splitlines()[0] if str(exc) else "out of memory"
        print(f"{lead} ran out of memory ({first}); {memory_hint}", file=sys.stderr)
        return 1
    if isinstance(exc, RuntimeError):                 # a table refused: no converged solve (why); a worker lost
        from solver.table.workers import WorkerLost
        from solver.wave import WaveSolverError        # (here: the commands start without NumPy)
        if isinstance(exc, (WaveSolverError, WorkerLost)):
            print(f"{lead} {exc}", file=sys.stderr)
            return 1
        raise exc
    if isinstance(exc, (ValueError, OSError)):        # bad input; read-only folder, full disk, missing file
        print(f"{lead} {exc if isinstance(exc, ValueError) else os_error_text(exc)}", file=sys.stderr)
        return 2
    raise exc


class _StoreOnce(argparse._StoreAction):
    """argparse's `store`, refusing an option given twice in one command line (`--ink R15 --ink
    Y15` kept the last silently): a usage error naming both values."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = parser.__dict__.setdefault("_given_once", {})
        if self.dest in seen:
            first_option, first = seen[self.dest]
            raise argparse.ArgumentError(self, f"given twice ({first_option} {_shown(first)}, then "
                                               f"{option_string} {_shown(values)}): give it once")
        seen[self.dest] = (option_string, values)
        super().__call__(parser, namespace, values, option_string)


def _shown(values) -> str:
    return " ".join(map(str, values)) if isinstance(values, list) else str(values)


class OneLineParser(argparse.ArgumentParser):
    """argparse's usage errors as one line naming the problem (not the usage block); exit 2, or
    `usage_error` raised when a subclass sets it (a caller that prints its own errors).  A
    single-value option (argparse's `store`) given twice is such an error, for every command
    and subcommand (their parsers are of this class)."""

    usage_error: type[Exception] | None = None

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)

    def parse_known_args(self, args=None, namespace=None):
        self._given_once = {}                     # options given in this command line
        return super().parse_known_args(args, namespace)

    def parse_args(self, args=None, namespace=None):
        """argparse's, but arguments left over after a subcommand are that subcommand's error
        (`ink-tables show: error: unrecognized arguments: b.npz`), as its other errors are."""
        args, extras = self.parse_known_args(args, namespace)
        if extras:
            self._subcommand_parser(args).error(f"unrecognized arguments: {' '.join(extras)}")
        return args

    def _subcommand_parser(self, args) -> argparse.ArgumentParser:
        """The parser of the subcommand `args` chose (this parser where there is none)."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                chosen = action.choices.get(getattr(args, action.dest, None))
                if chosen is not None:
                    return chosen
        return self

    def error(self, message):
        text = f"{message} (see --help)"
        if self.usage_error is not None:
            raise self.usage_error(text)
        self.exit(2, f"{self.prog}: error: {text}\n")


class DefaultsFormatter(argparse.HelpFormatter):
    """Adds "(default: X)" to an option's help unless the help states its default itself or
    there is none to state (None, False, suppressed)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if ("default" in text or default is None or default is False or default is argparse.SUPPRESS
                or not action.option_strings):
            return text
        return text + " (default: %(default)s)"


def writable_output(path, suffix: str, option: str, make_folder: bool = False) -> Path:
    """`path` as a Path if a file ending in `suffix` can be written there, else ValueError naming
    the option and the fix — checked by creating (and removing) a file in the first existing
    folder on its way, so a read-only or pseudo file system is refused before any work.  Missing
    folders are created now with `make_folder` (for writers that do not make them), else when
    the file is written."""
    return writable_outputs([(path, suffix, option)], make_folders=make_folder)[0]


def writable_outputs(outputs, make_folders: bool = False) -> list[Path]:
    """`writable_output` for several (path, suffix, option): every path is checked before any
    folder is made, so a refused one leaves no folder behind for the others."""
    paths = [_checked_output(*output) for output in outputs]
    for path, (_, _, option) in zip(paths, outputs) if make_folders else ():
        try:
            path.absolute().parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise _cannot_write(option, path, path.absolute().parent, exc) from None
    return paths


def _cannot_write(option: str, path: Path, folder: Path, exc: OSError) -> ValueError:
    return ValueError(f"{option} '{path}': cannot write in {folder} ({exc.strerror}): choose a writable folder")


def _checked_output(path, suffix: str, option: str) -> Path:
    """`path` as a Path, or ValueError (writable_output's check, without making folders)."""
    path = Path(path)
    if path.suffix.lower() != suffix:
        raise ValueError(f"{option} '{path}' must end in {suffix}")
    if path.is_dir():
        raise ValueError(f"{option} '{path}' is a folder: give a file name ending in {suffix}")
    folder = path.absolute().parent
    while not folder.exists():
        folder = folder.parent
    try:
        if not folder.is_dir():
            raise NotADirectoryError(20, "not a folder")
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".inkbsdf-write-test-")
        os.close(fd)
        os.unlink(probe)
        if path.exists() and not os.access(path, os.W_OK):
            raise PermissionError(13, f"{path.name} is read-only")
    except OSError as exc:
        raise _cannot_write(option, path, folder, exc) from None
    return path


def wavelength_range(text: str) -> tuple[float, ...]:
    """'380:780:10' → 380, 390, …, 780 nm (inclusive); a single number gives one value."""
    parts = str(text).split(":")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise RequestError(f"--wavelengths {text!r}: expected START:STOP:STEP in nm, e.g. 380:780:10") from None
    if not all(math.isfinite(v) for v in values):
        raise RequestError(f"--wavelengths {text!r}: values must be finite numbers of nm")
    if len(values) == 1:
        return (values[0],)
    if len(values) != 3 or values[2] <= 0 or values[1] < values[0]:
        raise RequestError(f"--wavelengths {text!r}: expected START:STOP:STEP with STEP > 0 and STOP ≥ START")
    start, stop, step = values
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    if n > 100_000:
        raise RequestError(f"--wavelengths {text!r} asks for {n:,} wavelengths; use a step of ≥ 1 nm")
    return tuple(float(v) for v in start + step * np.arange(n))


def uniform_angles(count: int) -> tuple[float, ...]:
    """`count` incidence angles uniformly from 0 to 90° inclusive (radians)."""
    if not isinstance(count, (int, np.integer)) or not 2 <= count <= MAX_ANGLES:
        raise RequestError(f"--angles is a count of incidence angles from 0° to 90° inclusive, 2 … {MAX_ANGLES}; "
                           f"got {count!r}")
    return tuple(float(s) for s in np.linspace(0.0, np.pi / 2, int(count)))


def add_measurement_arguments(parser, geometry_default: str | None = None) -> None:
    """--geometry, --illuminant, --observer: how a colour is measured (solver.colour.measurement);
    `geometry_default` None means the command's own default (e.g. the figure model's)."""
    from solver.colour.cie import ILLUMINANTS, OBSERVERS
    from solver.colour.measurement import DEFAULT_ILLUMINANT, DEFAULT_OBSERVER, GEOMETRIES

    g = parser.add_argument_group("colour measurement (docs/design.md §7)")
    g.add_argument("--geometry", default=geometry_default, metavar="GEOMETRY",
                   help=f"{' | '.join(GEOMETRIES)}: 45:0 = light 45°, view 0°, gloss excluded (ISO 13655); "
                        "d:8:sci / d:8:sce = sphere, view 8°, specular included / excluded; d:0 = diffuse light, "
                        "view 0°, the layer's mirror included; paper = the paper's strip (no coherent mirror)"
                        + ("" if geometry_default else " (default: the model's, 45:0 for the default model)"))
    g.add_argument("--illuminant", default=DEFAULT_ILLUMINANT, metavar="NAME", help=" | ".join(ILLUMINANTS))
    g.add_argument("--observer", default=DEFAULT_OBSERVER, metavar="DEG", help=" | ".join(OBSERVERS) + " (degrees)")


def measurement_from_args(args, geometry_default: str):
    """The Measurement the options name (each name checked: one line listing the valid ones)."""
    from solver.colour.cie import check_illuminant, check_observer
    from solver.colour.measurement import Measurement, parse_geometry

    parts = []
    for option, check, value in (("--geometry", parse_geometry, args.geometry or geometry_default),
                                 ("--illuminant", check_illuminant, args.illuminant),
                                 ("--observer", check_observer, args.observer)):
        try:
            parts.append(check(value))
        except ValueError as exc:                     # the option named before the choices
            raise ValueError(f"{option}: {exc}") from None
    return Measurement(*parts)
