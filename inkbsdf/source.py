"""Where an `ink` BSDF gets its table: the one place that reads scene parameters into an InkLUT.

Either a table file (`filename`, resolved like every Mitsuba asset: relative to the scene file,
then Mitsuba's search path) or the ink itself (`ink`, `particles`, `thickness`, …), whose table
comes from the content-addressed cache of `solver.table.builder`.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import mitsuba as mi

from solver.table import TableError
from solver.table.options import OPTIONS, SCENE_PARAMS

from .errors import InkParameterError
from .lut import InkLUT, load_lut


def resolve_path(filename: str) -> Path:
    """Resolve a file name with Mitsuba's file resolver (scene directory first)."""
    resolved = mi.file_resolver().resolve(str(filename))
    return Path(str(resolved))


#: Scene parameters of an in-scene ink (instead of `filename`) → `table_request` arguments
#: (derived from the one list of request options, solver/table/options.py).
REQUEST_PARAMS = SCENE_PARAMS
_INTEGER_PARAMS = tuple(o.scene for o in OPTIONS if o.scene and o.scene_type is int) + ("workers",)
#: the parameters written as <string …/>, each with the example its type error shows
STRING_PARAMS = {"ink": "R15", "particles": "sphere:300", "polarisation": "unpolarised", "accuracy": "default",
                 "tier": "auto", "filename": "ink.npz", "cache": "tables", "coverage_model": "clapper-yule"}
assert {o.scene for o in OPTIONS if o.scene and o.scene_type is str} <= set(STRING_PARAMS)

#: worker processes for tables that scene loads build (set by `set_build_workers`)
_build_workers: int | None = None


def scene_param(props, name: str, default=None):
    """A scene parameter's value (`default` when absent), its type checked: integers (Mitsuba
    gives XML ints as int, floats as float) and strings (STRING_PARAMS), in one line naming
    the parameter and the XML that gives it."""
    if name not in props:
        return default
    value = props.get(name)
    if name in _INTEGER_PARAMS and not (isinstance(value, int) and not isinstance(value, bool)):
        raise TableError(f"ink BSDF: parameter '{name}' must be an integer, got {value!r}")
    if name in STRING_PARAMS and not isinstance(value, str):
        raise InkParameterError(f"ink BSDF: parameter '{name}' must be a <string> (e.g. "
                                f'<string name="{name}" value="{STRING_PARAMS[name]}"/>), got {value!r}')
    return value


def table_request(props):
    """The TableRequest described by an `ink=...` BSDF (see REQUEST_PARAMS)."""
    from solver.table.request import table_request as make_request

    from .errors import scene_wording

    kwargs = {arg: scene_param(props, name) for name, arg in REQUEST_PARAMS.items() if name in props}
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        request = make_request(kwargs.pop("ink"), kwargs.pop("particles", "molecular"), **kwargs)
    for warning in said:               # the request's warnings name the parameters, not --options
        warnings.warn(scene_wording(str(warning.message)), warning.category, stacklevel=2)
    return request


def set_build_workers(workers: int | None) -> None:
    """Worker processes for tables that scene loads in this process build (None: back to
    $INKBSDF_WORKERS, else 1).  `python -m inkbsdf.render` sets it from --workers."""
    global _build_workers
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be an integer ≥ 1, got {workers!r}")
    _build_workers = workers


def build_workers(props) -> int:
    """Worker processes for a table built during a scene load: the `workers` parameter, else
    `set_build_workers(...)`, else $INKBSDF_WORKERS, else 1 (in the loading process).

    Not one per core as for `ink-tables build`: workers are spawned, and spawning re-runs the
    calling script's top level; a script that loads a scene without an
    `if __name__ == "__main__":` guard would load it again in every worker — detected by the
    executor, and such a script builds in one process with a warning.
    """
    if "workers" in props:
        workers = scene_param(props, "workers")
        if workers < 1:
            raise TableError(f"ink BSDF: parameter 'workers' must be ≥ 1, got {workers}")
    elif _build_workers is not None:
        workers = _build_workers
    else:
        text = os.environ.get("INKBSDF_WORKERS", "1")
        try:
            workers = int(text)
        except ValueError:
            raise TableError(f"$INKBSDF_WORKERS={text!r} is not an integer: set it to a number of "
                             "worker processes, e.g. 2") from None
        workers = max(1, workers)
    return workers


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
        except (TableError, InkParameterError):
            raise
        except ValueError as exc:       # RequestError, InkSpecError, ParticleSpecError
            raise TableError(f"ink BSDF: {exc}") from None
        from solver.table.preflight import PreflightError

        cache = TableCache(Path(scene_param(props, "cache"))) if "cache" in props else TableCache.default()
        force = props.get("force") if "force" in props else False
        if not isinstance(force, bool):
            raise TableError(f"ink BSDF: parameter 'force' must be a boolean, got {force!r}")
        show_build_log()
        try:
            table, path, _ = get_or_build(request, BuildOptions(cache=cache, workers=build_workers(props), force=force))
        except PreflightError as exc:
            raise TableError(f"ink BSDF: {exc}") from None
        return load_lut(path, table)
    if "filename" not in props:
        raise TableError("ink BSDF: needs 'filename' (an ink table .npz, built with `ink-tables build`) "
                         "or 'ink' (e.g. 'Y7.5+B7.5', with optional 'particles', 'thickness')")
    filename = scene_param(props, "filename")
    path = resolve_path(filename)
    if not path.is_file():
        raise TableError(f"{filename}: table file not found (looked relative to the scene file and "
                         "on Mitsuba's search path; build it with `ink-tables build` or `make tables`)")
    return load_lut(path)


class _Params(dict):
    """A plain mapping read like mitsuba.Properties (`name in p`, `p.get(name)`)."""

    def get(self, name, default=None):
        return self[name] if name in self else default


def _member_request(member):
    """The request of one ink of an overprint: from its scene parameters, or read back from the
    meta of its table file (every setting: TableRequest.of_table)."""
    from solver.table import read_table
    from solver.table.request import TableRequest

    params = _Params(member.params)
    if "ink" in params:
        return table_request(params)
    return TableRequest.of_table(read_table(params["filename"]))


def stack_lut(members) -> InkLUT:
    """The table of an overprint (members top first) through the cache: an exact multilayer
    film when every layer is molecular, else the wave solver over the stacked layers
    (inkbsdf.inks calls this for every overprint a scene can show)."""
    from solver.table.builder import BuildOptions, get_or_build
    from solver.table.cache import TableCache
    from solver.table.request import table_request as make_request

    try:
        requests = [_member_request(m) for m in members]
        layers = tuple(layer for req in requests for layer in req.layers)
        # molecular layers: an exact multilayer film; particle layers: the wave solver over the
        # stacked geometry, at the accuracy of the first particle ink
        accuracy = next((req.accuracy for req in requests if not req.molecular), "default")
        stack = make_request(layers, polarisation=requests[0].polarisation, materials=requests[0].materials,
                             accuracy=accuracy, local_field=requests[0].local_field)
    except TableError:
        raise
    except ValueError as exc:
        raise TableError(f"ink BSDF: overprint {'/'.join(m.label for m in members)}: {exc}") from None
    cache_dir = next((m.params["cache"] for m in members if "cache" in m.params), None)
    cache = TableCache(Path(str(cache_dir))) if cache_dir else TableCache.default()
    workers = build_workers(_Params(next((m.params for m in members if "workers" in m.params), {})))
    table, path, _ = get_or_build(stack, BuildOptions(cache=cache, workers=workers, progress=False))
    return load_lut(path, table)
