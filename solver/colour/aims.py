"""Colour aims: the one home of the standard's numbers a print is held against (docs/printing.md).

ISO 12647-2 (offset lithography), paper type 1 — PC1, coated — as the 2004 edition with its
Amendment 1 (2007) states it and FOGRA39 characterises it: CIELAB, D50, 2° observer, 45:0
geometry (ISO 13655), black backing, measurement condition M0 (the 2004 standard measures
without a UV-cut filter; the model has no fluorescence, so M0 = M1 here). Solids of the four
process inks, the paper white, and the two-colour overprints in the printing order K, C, M, Y:
red = M + Y, green = C + Y, blue = C + M. Process-control tolerance for solids: ΔE*ab ≤ 5
(the standard's deviation tolerance).

Names: `iso12647-2:PC1:<colour>` (`iso12647-2:PC1:cyan`); `iso12647-2` (or `iso12647-2:PC1`)
names the whole set. A free aim is given as CIELAB numbers, "L,a,b".
"""

from __future__ import annotations

from dataclasses import dataclass

STANDARD = "iso12647-2"
PRINTING_CONDITION = "PC1"
#: how the standard's numbers are measured (solver.colour.measurement names)
AIM_GEOMETRY, AIM_ILLUMINANT, AIM_OBSERVER = "45:0", "D50", "2"
#: ISO 12647-2's process-control (deviation) tolerance for solids, ΔE*ab
SOLID_TOLERANCE_DE76 = 5.0
#: the process colours in printing order (ISO 12647-2 sequence K, C, M, Y: yellow on top)
PROCESS_ORDER = ("black", "cyan", "magenta", "yellow")


class AimError(ValueError):
    """An aim that is neither a known name nor CIELAB numbers; the message lists the names."""


@dataclass(frozen=True)
class Aim:
    """A colour to print: its CIELAB (D50, 2°, 45:0 unless stated) and what prints it.

    colour: the standard's name (paper, cyan, …, red); inks: the process colours printed, in
    printing order (() for the paper white, one for a solid, two for an overprint)."""

    name: str
    colour: str
    lab: tuple[float, float, float]
    inks: tuple[str, ...]

    @property
    def kind(self) -> str:
        """paper, solid, overprint, or custom (CIELAB numbers)."""
        if self.colour == "custom":
            return "custom"
        return {0: "paper", 1: "solid"}.get(len(self.inks), "overprint")


def _aim(colour: str, lab, inks=()) -> Aim:
    return Aim(f"{STANDARD}:{PRINTING_CONDITION}:{colour}", colour, tuple(float(v) for v in lab), tuple(inks))


#: ISO 12647-2:2004/Amd 1:2007, paper type 1 (PC1), black backing (FOGRA39): CIELAB D50 2°
ISO12647_2_PC1: dict[str, Aim] = {a.name: a for a in (
    _aim("paper", (95.0, 0.0, -2.0)),
    _aim("cyan", (55.0, -37.0, -50.0), ("cyan",)),
    _aim("magenta", (48.0, 74.0, -3.0), ("magenta",)),
    _aim("yellow", (89.0, -5.0, 93.0), ("yellow",)),
    _aim("black", (16.0, 0.0, 0.0), ("black",)),
    _aim("red", (47.0, 68.0, 48.0), ("magenta", "yellow")),
    _aim("green", (50.0, -65.0, 27.0), ("cyan", "yellow")),
    _aim("blue", (24.0, 22.0, -46.0), ("cyan", "magenta")),
)}
#: every named aim, by name
AIMS: dict[str, Aim] = dict(ISO12647_2_PC1)
#: names that stand for a whole set
SETS: dict[str, tuple[Aim, ...]] = {STANDARD: tuple(ISO12647_2_PC1.values()),
                                    f"{STANDARD}:{PRINTING_CONDITION}": tuple(ISO12647_2_PC1.values())}


def known_aims_text() -> str:
    return ", ".join(list(SETS) + list(AIMS))


def parse_aim(text: str) -> tuple[Aim, ...]:
    """The aims a `--aim` value names: a set, one named aim, or "L,a,b" (a free aim named by its
    numbers). AimError (one line, listing the known names) otherwise."""
    value = str(text).strip()
    key = value.lower().replace("pc1", "PC1")
    if key in SETS:
        return SETS[key]
    if key in AIMS:
        return (AIMS[key],)
    parts = value.split(",")
    if len(parts) == 3:
        try:
            lab = tuple(float(p) for p in parts)
        except ValueError:
            lab = None
        if lab is not None:
            if not all(v == v and abs(v) != float("inf") for v in lab) or not 0.0 <= lab[0] <= 100.0:
                raise AimError(f"--aim {value!r}: CIELAB needs finite numbers with 0 ≤ L* ≤ 100")
            return (Aim(value, "custom", lab, ()),)
    raise AimError(f"--aim {value!r} is not a known aim or L,a,b numbers; known aims: {known_aims_text()}")
