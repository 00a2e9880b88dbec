"""Where an `ink` BSDF gets its table: the one place that reads scene parameters into an InkLUT.

Either a table file (`filename`, resolved like every Mitsuba asset: relative to the scene file,
then Mitsuba's search path) or the ink itself (`ink`, `particles`, `thickness`, …), whose table
comes from the content-addressed cache of `solver.table.builder`.
"""

from __future__ import annotations

import os
from pathlib import Path

import mitsuba as mi

from solver.table import TableError

from .lut import InkLUT, load_lut


def resolve_path(filename: str) -> Path:
    """Resolve a file name with Mitsuba's file resolver (scene directory first)."""
    resolved = mi.file_resolver().resolve(str(filename))
    return Path(str(resolved))


#: Scene parameters of an in-scene ink (instead of `filename`) → TableRequest fields.
REQUEST_PARAMS = {"ink": ("ink", str), "particles": ("particles", str),
                  "thickness": ("thickness_nm", float), "realizations": ("realizations", int),
                  "tolerance": ("tolerance", float), "seed": ("seed", int), "tier": ("tier", str)}


def table_request(props):
    """The TableRequest described by an `ink=...` BSDF (see REQUEST_PARAMS)."""
    from solver.table.request import TableRequest

    kwargs = {field: kind(props.get(name)) for name, (field, kind) in REQUEST_PARAMS.items() if name in props}
    return TableRequest(**kwargs)


def build_workers(props) -> int:
    """Worker processes for a table built during a scene load: the `workers` parameter, else
    $INKBSDF_WORKERS, else 1 (in the loading process).

    Not one per core as for `ink-tables build`: workers are spawned, and spawning re-runs the
    calling script's top level; a script that loads a scene without an
    `if __name__ == "__main__":` guard would load it again in every worker.
    `python -m inkbsdf.render` is guarded and sets $INKBSDF_WORKERS to its `--workers`.
    """
    if "workers" in props:
        return max(1, int(props.get("workers")))
    try:
        return max(1, int(os.environ.get("INKBSDF_WORKERS", "1")))
    except ValueError:
        raise TableError(f"$INKBSDF_WORKERS={os.environ['INKBSDF_WORKERS']!r} is not an integer") from None


def show_build_log() -> None:
    """Make the table builder's INFO lines (what a scene load computes) visible on stderr,
    unless the application configured logging itself."""
    import logging

    log = logging.getLogger("inkbsdf.tables")
    if not log.handlers and not logging.getLogger().handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("inkbsdf: %(message)s"))
        log.addHandler(handler)
        log.setLevel(logging.INFO)


def load_table(props) -> InkLUT:
    """The table named by the BSDF's properties; raises TableError naming file and problem.

    Either `filename` (a table file) or `ink` (+ optional particles, thickness, …): the table is
    then taken from the content-addressed cache, computed first if missing (logged, with
    progress; $INKBSDF_CACHE or the `cache` parameter names the cache directory).
    """
    if "filename" in props and "ink" in props:
        raise TableError("ink BSDF: give either 'filename' or 'ink', not both")
    if "ink" in props:
        from solver.table.builder import BuildOptions, get_or_build
        from solver.table.cache import TableCache

        try:
            request = table_request(props)
        except ValueError as exc:
            raise TableError(f"ink BSDF: {exc}") from None
        cache = TableCache(Path(str(props.get("cache")))) if "cache" in props else TableCache.default()
        show_build_log()
        _, path, _ = get_or_build(request, BuildOptions(cache=cache, workers=build_workers(props)))
        return load_lut(path)
    if "filename" not in props:
        raise TableError("ink BSDF: needs 'filename' (an ink table .npz, built with `ink-tables build`) "
                         "or 'ink' (e.g. 'Y7.5+B7.5', with optional 'particles', 'thickness')")
    filename = str(props.get("filename"))
    path = resolve_path(filename)
    if not path.is_file():
        raise TableError(f"{filename}: table file not found (looked relative to the scene file and "
                         "on Mitsuba's search path; build it with `ink-tables build` or `make tables`)")
    return load_lut(path)
