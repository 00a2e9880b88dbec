"""Command-line plumbing shared by `ink-tables`, `python -m inkbsdf.render` and `… print`:
one-line usage errors, help that states each default once, and output paths checked before any
work."""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path


class OneLineParser(argparse.ArgumentParser):
    """argparse's usage errors as one line naming the problem (not the usage block); exit 2, or
    `usage_error` raised when a subclass sets it (a caller that prints its own errors)."""

    usage_error: type[Exception] | None = None

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


def writable_output(path, suffix: str, option: str) -> Path:
    """`path` as a Path if a file ending in `suffix` can be written there, else ValueError naming
    the option and the fix — checked by creating (and removing) a file in the first existing
    folder on its way, so a read-only or pseudo file system is refused before any work; missing
    folders are created when the file is written."""
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
        raise ValueError(f"{option} '{path}': cannot write in {folder} ({exc.strerror}): "
                         "choose a writable folder") from None
    return path
