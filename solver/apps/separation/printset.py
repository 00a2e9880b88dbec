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
from solver.table.request import DEFAULT_THICKNESS_NM, LAYER_SEPARATOR, table_request

MAX_INKS = 4
THICKNESS_SEPARATOR = "@"           # 'C8.7@1500': an ink and its layer thickness in nm
MIN_THICKNESS_NM, MAX_THICKNESS_NM = 10.0, 100000.0
PROCESS = "process"                 # --inks process: the process inks (solver.printing.process_inks)
#: the inks `python -m inkbsdf.print` prints with unless told (printing order; an ink list)
DEFAULT_INK_LIST = "process"


class InkListError(ValueError):
    """An ink list that cannot be printed; the message names the problem."""


def split_ink(label: str) -> tuple[str, float | None]:
    """'C8.7@1500' → ('C8.7', 1500.0); 'R30' → ('R30', None): an ink of a print and its layer
    thickness in nm (None: the table request's default)."""
    spec, sep, thickness = str(label).partition(THICKNESS_SEPARATOR)
    return spec, (float(thickness) if sep else None)


def dominant_pigment(label: str) -> str | None:
    """The pigment letter with the largest volume fraction of an ink ('M22.5+C1' → 'M'), None
    for clear varnish."""
    components = parse_ink(split_ink(label)[0]).components
    return max(components, key=lambda cf: cf[1])[0] if components else None


def process_paper_albedo() -> float:
    """The paper the process inks were designed on (their flat albedo)."""
    from solver.printing.process_inks import process_paper_albedo as albedo

    return albedo()


def default_paper(inks) -> float:
    """The paper albedo a print of `inks` gets unless told: the process inks' own paper for the
    process set, else `solver.paper.PAPER_ALBEDO`."""
    from solver.paper import PAPER_ALBEDO

    try:
        process = process_set()
    except ImportError:
        return PAPER_ALBEDO
    return process_paper_albedo() if tuple(inks) == process else PAPER_ALBEDO


def process_set() -> tuple[str, ...]:
    """The process inks (K, C, M, Y, printing order) as ink labels with their thicknesses."""
    from solver.printing.process_inks import process_inks

    return tuple(f"{ink.spec}{THICKNESS_SEPARATOR}{ink.thickness_nm:g}" for ink in process_inks())


def _process_hint(spec: str) -> str:
    """A hint for a bare process-ink letter ('C', 'M', …) where an ink spec was expected."""
    try:
        letters = [label[0] for label in process_set()]          # in printing order
    except ImportError:
        return ""
    return (f" (the process inks {', '.join(letters)} together are '{PROCESS}')"
            if spec.strip().upper() in letters else "")


def parse_ink_list(text: str) -> tuple[str, ...]:
    """'R30,Y30,B30' → ('R30', 'Y30', 'B30'): 1 to 4 molecular ink specs, canonical labels, each
    optionally with its layer thickness ('C8.7@1500', nm); `process` names the process inks.

    Raises InkListError before any table is built."""
    if str(text).strip().lower() == PROCESS:
        try:
            return process_set()
        except ImportError:
            raise InkListError("inks: the process inks are not in this version of the package; name the "
                               "inks, e.g. R30,Y30,B30") from None
    specs = tuple(s.strip() for s in str(text).split(","))
    if not specs or any(not s for s in specs):
        raise InkListError(f"inks: give 1 to {MAX_INKS} ink specs separated by commas, e.g. R30,Y30,B30 "
                           f"(or {PROCESS}); got {text!r}")
    if len(specs) > MAX_INKS:
        raise InkListError(f"inks: at most {MAX_INKS} inks (the ink BSDF's limit), got {len(specs)}")
    labels = []
    for item in specs:
        spec, sep, thickness = item.partition(THICKNESS_SEPARATOR)
        if LAYER_SEPARATOR in spec:
            raise InkListError(f"inks: '{spec}' is a stack; list single inks in printing order instead")
        try:
            label = parse_ink(spec).label
        except ValueError as exc:
            raise InkListError(f"inks: {exc}{_process_hint(spec)}") from None
        if sep:
            try:
                nm = float(thickness.strip().removesuffix("nm"))
            except ValueError:
                nm = float("nan")
            if not MIN_THICKNESS_NM <= nm <= MAX_THICKNESS_NM:
                raise InkListError(f"inks: '{item}': give the layer thickness in nm after '@', between "
                                   f"{MIN_THICKNESS_NM:g} and {MAX_THICKNESS_NM:g} (e.g. {spec}@1500)")
            label = f"{label}{THICKNESS_SEPARATOR}{nm:g}"
        labels.append(label)
    if len({split_ink(x)[0] for x in labels}) < len(labels):
        raise InkListError(f"inks: an ink is listed twice ({', '.join(labels)})")
    return tuple(labels)


def default_inks() -> tuple[str, ...]:
    """The default ink list, parsed."""
    return parse_ink_list(DEFAULT_INK_LIST)


def ink_requests(labels) -> dict:
    """{subset (0-based, ascending): TableRequest} of every printed primary but bare paper."""
    from solver.printing import all_subsets

    inks = [split_ink(x) for x in labels]
    out = {}
    for s in all_subsets(len(inks)):
        if not s:
            continue
        order = stack_order(s)
        thick = [inks[i][1] for i in order]
        kw = {} if all(t is None for t in thick) else {"thickness_nm": tuple(
            DEFAULT_THICKNESS_NM if t is None else t for t in thick) if len(order) > 1 else thick[0]}
        out[s] = table_request(LAYER_SEPARATOR.join(inks[i][0] for i in order), **kw)
    return out


def printed_inks(specs, cache=None) -> PrintedInks:
    """PrintedInks of the inks `specs` (printing order) with every overprint, tables from the
    cache (`solver.table.cache.TableCache`; default `TableCache.default()`), built when missing."""
    from solver.table.builder import BuildOptions, get_or_build
    from solver.table.cache import TableCache

    opts = BuildOptions(cache=cache or TableCache.default(), workers=1, progress=False)
    tables = {s: get_or_build(req, opts)[0] for s, req in ink_requests(tuple(specs)).items()}
    k = len(specs)
    return PrintedInks(tuple(tables[(i,)] for i in range(k)), {s: t for s, t in tables.items() if len(s) >= 2})
