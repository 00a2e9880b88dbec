"""Short errors through Mitsuba: bad input to the `ink` BSDF in one line naming the parameter and
the fix, and Mitsuba's loader errors read back as that line (docs/design.md §5).

What Mitsuba 3.9 does with an exception raised while a Python plugin is constructed (probed):
it catches it and raises `RuntimeError("[parser.cpp:…] At <where>: failed to instantiate bsdf
plugin of type "ink": <what>")`, where <what> is nanobind's rendering of the Python exception:
"Traceback (most recent call last):", then one line per frame of the *whole* Python stack (every
caller up to the script's top level, tens of lines under pytest or Jupyter), then
"Type: message". Only the message survives; the exception object and its type are lost.

`plugin_factory` wraps the BSDF class for `mi.register_bsdf`: an input error (bad parameter
value or type, unusable table file or cache) is raised as a short exception (InkParameterError,
or the TableError / CacheError / VariantError that was raised) whose traceback is a single frame
with no callers, so <what> is three lines whatever the caller's stack, the cause on the last
one, worded for a scene (parameter 'thickness', not the `ink-tables` option --thickness). A bug
(any other exception) keeps its whole traceback. `loader_problem` turns Mitsuba's message back
into one line for the command line.
"""

from __future__ import annotations

import re
import types

from solver.table import TableError

from .variant import VariantError


class InkParameterError(ValueError):
    """A parameter of an `ink` BSDF has a wrong value or type; the message names it and the fix."""


# ------------------------------------------------------------------ raising through Mitsuba
def ink_bsdf_input():
    """Never run: the unstarted frame of this generator has no caller, so a traceback made of it
    is one line long (nanobind prints a traceback's deepest frame and all that frame's callers)."""
    yield


def detached(exc: BaseException) -> BaseException:
    """`exc` with a one-frame, caller-free traceback (see the module docstring)."""
    frame = ink_bsdf_input().gi_frame
    return exc.with_traceback(types.TracebackType(None, frame, 0, frame.f_lineno))


def plugin_factory(cls):
    """The constructor to register with Mitsuba: `cls(props)`, with input errors made short."""
    def ink_bsdf(props):
        try:
            return cls(props)
        except Exception as exc:           # noqa: BLE001 - sorted below: input error or bug
            short = input_error(exc, props)
            if short is None:
                raise                      # a bug: keep the whole traceback
        raise detached(short) from None
    return ink_bsdf


# ------------------------------------------------------------------- input errors, explained
_WRONG_TYPE = re.compile(r'The property "(\w+)" has the wrong type \(expected ([\w/]+), got (\w+)\)')
#: XML element of each Mitsuba property type, simplest first (the example given in a fix).
_XML = {"float": '<float name="{0}" value="…"/>', "integer": '<integer name="{0}" value="…"/>',
        "string": '<string name="{0}" value="…"/>', "boolean": '<boolean name="{0}" value="true"/>',
        "color": '<rgb name="{0}" value="…"/>', "spectrum": '<spectrum name="{0}" value="…"/>',
        "texture": '<texture type="bitmap" name="{0}">…</texture>'}


def input_error(exc: Exception, props) -> Exception | None:
    """The short exception telling the user what to fix, or None when `exc` is a bug."""
    if isinstance(exc, ValueError):            # TableError, CacheError, InkParameterError, …
        message = scene_wording(str(exc))
        return exc if message == str(exc) else InkParameterError(message)
    if isinstance(exc, VariantError):
        return exc
    if isinstance(exc, OSError):
        return TableError(f"ink BSDF: cannot use {exc.filename or 'a file'}: {exc.strerror or exc}")
    match = _WRONG_TYPE.search(str(exc))       # Mitsuba's props.get_texture & co.
    if match:
        name, expected, got = match.groups()
        kinds = sorted(expected.split("/"), key=lambda k: list(_XML).index(k) if k in _XML else len(_XML))
        example = f": write e.g. {_XML[kinds[0]].format(name)}" if kinds[0] in _XML else ""
        listed = kinds[0] if len(kinds) == 1 else f"{', '.join(kinds[:-1])} or {kinds[-1]}"
        return InkParameterError(f"ink BSDF: parameter '{name}' is a {got}, not a {listed}{example}")
    return None


def scene_wording(message: str) -> str:
    """A table-request message as said to a scene: the `ink-tables` options it names (shared
    checks, solver/table/request.py) become the BSDF's parameters (`--thickness` → parameter
    'thickness'); a doubled "ink BSDF:" prefix is said once."""
    from solver.table.request import OPTION

    from .source import REQUEST_PARAMS

    parameter = {OPTION[arg]: name for name, arg in REQUEST_PARAMS.items() if arg in OPTION}
    parameter.update({"--cache": "cache", "--workers": "workers", "--force": "force"})
    message = re.sub(r"(?<![\w-])(--[a-z][\w-]*)",
                     lambda m: f"parameter '{parameter[m.group(1)]}'" if m.group(1) in parameter else m.group(1),
                     message)
    return re.sub(r"^(ink BSDF:? )+(?=ink BSDF)", "", message)


# --------------------------------------------------------- Mitsuba's messages, read back
_TAG = re.compile(r"\[[\w.]+:\d+\]\s*")                    # "[parser.cpp:1718] "
_FRAME = re.compile(r"^\s+File \".*\", line \d+, in ")
_LOCATION = re.compile(r"(?:At|While loading) (.+?(?: \(line \d+, col \d+\))?|dictionary node \"[^\"]*\"): ")
_EXCEPTION_NAME = re.compile(r"^(?:[\w.]+\.)?(\w+(?:Error|Exception|Interrupt)): ")
_UNREFERENCED = re.compile(r'Found \d+ unreferenced propert(?:y|ies) in (\w+) plugin of type "(\w+)":')
_UNREFERENCED_ITEM = re.compile(r'- (\w+) "(\w+)": (.*)')


def deepest_cause(exc: BaseException) -> BaseException:
    """The innermost of an exception's explicit causes (Dr.Jit's "(see above)" chains)."""
    while exc.__cause__ is not None:
        exc = exc.__cause__
    return exc


def loader_problem(exc: BaseException) -> str:
    """One line saying what went wrong in a Mitsuba loader/render error: where (file, line) and
    the cause, without the embedded Python traceback or Mitsuba's source tags."""
    text = str(deepest_cause(exc))
    lines = [ln for ln in text.splitlines() if ln.strip()]
    if not lines:
        return repr(exc)
    location = _LOCATION.search(_TAG.sub("", lines[0]))
    where = location.group(1) if location else None
    frames = [i for i, ln in enumerate(lines) if _FRAME.match(ln)]
    if "Traceback (most recent call last):" in text:     # a Python exception: its message follows
        body = lines[frames[-1] + 1:] if frames else lines[-1:]    # the last frame line
        cause = " ".join(ln.strip() for ln in body)
    else:
        first = _TAG.sub("", lines[0])
        cause = first[location.end():] if location else first
        unreferenced = _UNREFERENCED.search(cause)
        if unreferenced:
            cause = _unreferenced(unreferenced.groups(), lines[1:])
        else:
            cause = " ".join([cause.strip()] + [ln.strip() for ln in lines[1:]])
    cause = _EXCEPTION_NAME.sub("", _TAG.sub("", cause)).strip()
    return f"{where}: {cause}" if where and where not in cause else cause


def _unreferenced(kind_and_name: tuple, items: list) -> str:
    kind, name = kind_and_name
    found = [m.groups() for m in map(_UNREFERENCED_ITEM.search, items) if m]
    listed = ", ".join(f"'{prop}' ({ptype} {value})" for ptype, prop, value in found) or "?"
    docs = " (docs/plugin.md lists the ink BSDF's parameters)" if name == "ink" else ""
    plugin = f'the {kind} plugin "{name}"' if kind != "unknown" else f'the plugin "{name}"'
    return f"{plugin} takes no parameter {listed}: remove it or correct its name{docs}"
