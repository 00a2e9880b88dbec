"""The inks of an `ink` BSDF: one (`filename` | `ink`) or several, numbered in printing order
(`filename1` | `ink1`, …, up to `filename4` | `ink4`), and the tables of their overprints.

Each numbered ink takes the single-ink parameters with its number (`particles2`, `thickness2`,
…); an unnumbered one (`particles`, `cache`, …) applies to every ink that does not number it.
Each ink's table comes from `inkbsdf.source.load_table`, as for a single ink.

Where inks overlap, the printed primary is a stack of layers; its table comes from the *stack
provider*, a callable

    stack_lut(members: tuple[InkSource, ...]) -> InkLUT      # members top first, ≥ 2

set with `set_stack_provider` (or, when none is set, `inkbsdf.source.stack_lut` if that module
defines one). It is called once per overprint that can occur on a surface, at scene load.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import mitsuba as mi

from solver.table import TableError

from . import source
from .errors import InkParameterError
from .lut import InkLUT

MAX_INKS = 4
TABLE_PARAMS = ("filename", "ink")                       # what names an ink's table
OWN_PARAMS = ("paper", "coverage", "coverage_model")     # the BSDF's own, never an ink's
#: the parameters that take an ink's number (`coverage2`, `thickness2`, …)
PER_INK_PARAMS = ("coverage",) + TABLE_PARAMS + tuple(source.REQUEST_PARAMS) + ("cache", "workers", "force")
_NUMBERED = re.compile(r"^([A-Za-z_]+?)([0-9]+)$")
_PLAIN = (mi.Properties.Type.String, mi.Properties.Type.Float, mi.Properties.Type.Integer,
          mi.Properties.Type.Bool)


@dataclass(frozen=True)
class InkSource:
    """One ink of a BSDF as the stack provider sees it."""

    index: int                      # printing position, 1-based: ink 2 is printed over ink 1
    params: Mapping[str, object]    # its parameters under the single-ink names: `filename`
                                    # (resolved path) or `ink` (+ `particles`, `thickness`, …)
    lut: InkLUT                     # its table

    @property
    def label(self) -> str:
        """The ink spec (e.g. 'Y30') or the table file's stem."""
        return str(self.params["ink"]) if "ink" in self.params else Path(self.lut.source).stem


StackProvider = Callable[[tuple], InkLUT]
_provider: StackProvider | None = None


def set_stack_provider(provider: StackProvider | None) -> StackProvider | None:
    """Install the stack provider used by BSDFs loaded from now on; return the previous one."""
    global _provider
    previous, _provider = _provider, provider
    return previous


@contextmanager
def stack_provider(provider: StackProvider | None):
    """`with stack_provider(fn): mi.load_dict(...)`: a provider for the loads inside."""
    previous = set_stack_provider(provider)
    try:
        yield provider
    finally:
        set_stack_provider(previous)


def stack_lut(members: tuple) -> InkLUT:
    """The table of the stack `members` (InkSource, top first) from the provider."""
    provider = _provider if _provider is not None else getattr(source, "stack_lut", None)
    names = " over ".join(f"ink {m.index} ({m.label})" for m in members)
    if provider is None:
        raise TableError(f"ink BSDF: {names} can overlap (coverages both > 0 somewhere), which needs "
                         "a table of that stack; no stack provider is set "
                         "(inkbsdf.inks.set_stack_provider)")
    lut = provider(tuple(members))
    if not isinstance(lut, InkLUT):
        raise TableError(f"ink BSDF: the stack provider returned {type(lut).__name__} for {names}, "
                         "not an InkLUT")
    return lut


def numbered_inks(props) -> list[int]:
    """Ink numbers named by `filenameN`/`inkN` (sorted); [] for the single-ink form. Checks the
    numbering (1..k, no gaps, k ≤ 4) and that the two forms are not mixed."""
    numbers = set()
    for key in props.keys():
        m = _NUMBERED.match(key)
        if m and m.group(1) in TABLE_PARAMS:
            numbers.add(int(m.group(2)))
    found = sorted(numbers)
    if found and any(name in props for name in TABLE_PARAMS + ("coverage",)):
        raise InkParameterError("ink BSDF: give one ink ('filename' or 'ink', with 'coverage') or several "
                         "('filename1'/'ink1', … with 'coverage1', …), not both forms")
    if found != list(range(1, len(found) + 1)) or len(found) > MAX_INKS:
        raise InkParameterError(f"ink BSDF: inks must be numbered 1 to k ≤ {MAX_INKS} without gaps "
                         f"('filename1'/'ink1', …); found {', '.join(map(str, found))}")
    for n in found:
        if f"filename{n}" in props and f"ink{n}" in props:
            raise InkParameterError(f"ink BSDF: ink {n}: give either 'filename{n}' or 'ink{n}', not both")
    check_ink_numbers(props.keys(), found)
    return found


def check_ink_numbers(keys, numbers) -> None:
    """InkParameterError for a numbered ink parameter (`coverage2`, `thickness3`, …) whose ink
    is not given (`numbers`: the inks' numbers, [] for the single-ink form)."""
    for key in keys:
        m = _NUMBERED.match(key)
        if not m or m.group(1) not in PER_INK_PARAMS or int(m.group(2)) in numbers:
            continue
        n = int(m.group(2))
        if numbers:
            given = f"inks given: {', '.join(map(str, numbers))}"
        else:
            given = (f"this BSDF has one ink, 'filename'/'ink': to print several, number every ink from 1 "
                     f"('filename1'/'ink1' with 'coverage1', …); for the one ink, write '{m.group(1)}'")
        raise InkParameterError(f"ink BSDF: '{key}' names no ink: it needs ink {n}, given as 'ink{n}' or "
                                f"'filename{n}' ({given})")


def _ink_properties(props, number: int):
    """Properties of ink `number` under single-ink names: its numbered parameters and the
    shared unnumbered ones; {new name: original name}."""
    own = mi.Properties("ink")
    origin = {}
    for key in props.keys():
        m = _NUMBERED.match(key)
        if m:
            if int(m.group(2)) != number or m.group(1) in OWN_PARAMS:
                continue
            name = m.group(1)
        elif key in OWN_PARAMS or key in TABLE_PARAMS:
            continue
        else:
            name = key
        if props.type(key) not in _PLAIN or (not m and name in origin):
            continue
        queried = props.was_queried(key)
        own[name] = props[key]
        props.mark_queried(key, queried)       # reading marks it; only a use should
        origin[name] = key
    return own, origin


def load_inks(props) -> tuple[InkSource, ...]:
    """The BSDF's inks in printing order, tables loaded (raises TableError naming the problem).

    Parameters nobody used stay unqueried, so Mitsuba still reports them as unreferenced."""
    numbers = numbered_inks(props)
    if not numbers:
        before = {k for k in props.keys() if props.was_queried(k)}
        lut = source.load_table(props)
        used = {k: props[k] for k in props.keys()
                if k not in before and k not in OWN_PARAMS and props.was_queried(k)}
        return (InkSource(1, _with_path(used, lut), lut),)
    inks = []
    for n in numbers:
        own, origin = _ink_properties(props, n)
        try:
            lut = source.load_table(own)
        except ValueError as exc:                  # TableError, CacheError, a request's error
            message = f"ink BSDF, ink {n}: {re.sub(r'^(ink BSDF:? )+', '', str(exc))}"
            for name, key in origin.items():       # the parameters as the scene names them
                message = message.replace(f"'{name}'", f"'{key}'").replace(f'name="{name}"', f'name="{key}"')
            raise (TableError if isinstance(exc, TableError) else InkParameterError)(message) from None
        used = {}
        for name, key in origin.items():
            if own.was_queried(name):
                props.mark_queried(key)
                used[name] = own[name]
        inks.append(InkSource(n, _with_path(used, lut), lut))
    return tuple(inks)


def _with_path(params: dict, lut: InkLUT) -> dict:
    """`filename` as the resolved path of the table that was read."""
    return {**params, "filename": lut.source} if "filename" in params else params
