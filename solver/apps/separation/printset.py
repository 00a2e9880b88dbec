"""The tables of a print named by ink specs: each ink and every overprint, through the cache.

    printed = printed_inks(("R30", "Y30", "B30"))       # PrintedInks, printing order

Each ink's table is `table_request(spec)` and the overprint of inks S is the stack
`table_request("top/…/bottom")` (`solver.printing.stack_order`): the same requests an `ink`
BSDF with in-scene inks `ink1 … inkN` makes (`inkbsdf.source`), so a scene load after a
separation finds every table in the cache. Molecular inks only: overprints are exact multilayer
films of molecular layers (the BSDF refuses particle overprints too).
"""

from __future__ import annotations

from solver.inks import parse_ink
from solver.printing import PrintedInks, stack_order
from solver.table.request import LAYER_SEPARATOR, table_request

MAX_INKS = 4
#: the inks `python -m inkbsdf.print` prints with unless told (printing order)
DEFAULT_INKS = ("R30", "Y30", "B30")


class InkListError(ValueError):
    """An ink list that cannot be printed; the message names the problem."""


def parse_ink_list(text: str) -> tuple[str, ...]:
    """'R30,Y30,B30' → ('R30', 'Y30', 'B30'): 1 to 4 molecular ink specs, canonical labels.

    Raises InkListError before any table is built."""
    specs = tuple(s.strip() for s in str(text).split(","))
    if not specs or any(not s for s in specs):
        raise InkListError(f"inks: give 1 to {MAX_INKS} ink specs separated by commas, e.g. R30,Y30,B30; "
                           f"got {text!r}")
    if len(specs) > MAX_INKS:
        raise InkListError(f"inks: at most {MAX_INKS} inks (the ink BSDF's limit), got {len(specs)}")
    labels = []
    for spec in specs:
        if LAYER_SEPARATOR in spec:
            raise InkListError(f"inks: '{spec}' is a stack; list single inks in printing order instead")
        try:
            labels.append(parse_ink(spec).label)
        except ValueError as exc:
            raise InkListError(f"inks: {exc}") from None
    if len(set(labels)) < len(labels):
        raise InkListError(f"inks: an ink is listed twice ({', '.join(labels)})")
    return tuple(labels)


def ink_requests(specs) -> dict:
    """{subset (0-based, ascending): TableRequest} of every printed primary but bare paper."""
    from solver.printing import all_subsets

    return {s: table_request(LAYER_SEPARATOR.join(specs[i] for i in stack_order(s)))
            for s in all_subsets(len(specs)) if s}


def printed_inks(specs, cache=None) -> PrintedInks:
    """PrintedInks of the inks `specs` (printing order) with every overprint, tables from the
    cache (`solver.table.cache.TableCache`; default `TableCache.default()`), built when missing."""
    from solver.table.builder import BuildOptions, get_or_build
    from solver.table.cache import TableCache

    opts = BuildOptions(cache=cache or TableCache.default(), workers=1, progress=False)
    tables = {s: get_or_build(req, opts)[0] for s, req in ink_requests(tuple(specs)).items()}
    k = len(specs)
    return PrintedInks(tuple(tables[(i,)] for i in range(k)), {s: t for s, t in tables.items() if len(s) >= 2})
