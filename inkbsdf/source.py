"""Where an `ink` BSDF gets its table: the one place that reads scene parameters into an InkLUT.

Today a table file (`filename`, resolved like every Mitsuba asset: relative to the scene file,
then Mitsuba's search path). A later `ink=`/`particles=` parameter (content-addressed cache)
plugs in here as one more branch of `load_table`.
"""

from __future__ import annotations

from pathlib import Path

import mitsuba as mi

from solver.table import TableError

from .lut import InkLUT, load_lut


def resolve_path(filename: str) -> Path:
    """Resolve a file name with Mitsuba's file resolver (scene directory first)."""
    resolved = mi.file_resolver().resolve(str(filename))
    return Path(str(resolved))


def load_table(props) -> InkLUT:
    """The table named by the BSDF's properties; raises TableError naming file and problem."""
    if "filename" not in props:
        raise TableError("ink BSDF: the 'filename' parameter (an ink table .npz, built with "
                         "`ink-tables build`) is required")
    filename = str(props.get("filename"))
    path = resolve_path(filename)
    if not path.is_file():
        raise TableError(f"{filename}: table file not found (looked relative to the scene file and "
                         "on Mitsuba's search path; build it with `ink-tables build` or `make tables`)")
    return load_lut(path)
