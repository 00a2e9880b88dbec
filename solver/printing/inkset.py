"""The tables of a print: one per ink, plus one per overprint (a stack of inks).

    printed = PrintedInks(inks=(R30, Y30, B30), stacks={(0, 2): B30_over_R30, ...})

`inks[i]` is printed after `inks[i−1]` (on top of it where both are present). `stacks` maps a
subset of ≥ 2 ink indices (ascending, 0-based) to the table of that stack of layers, read from
the top: (0, 2) ↦ the stack "ink 2 over ink 0" (`demichel.stack_order`). A subset without a
stack table is taken as impossible: coverages that give it a non-zero area are refused.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

from ..table.schema import InkTable
from .demichel import Subset, all_subsets, check_subset


@dataclass(frozen=True)
class PrintedInks:
    """Ink tables in printing order and the tables of their overprints (see module docstring)."""

    inks: tuple[InkTable, ...]
    stacks: Mapping[Subset, InkTable] = field(default_factory=dict)

    def __post_init__(self):
        inks = tuple(self.inks)
        if not inks:
            raise ValueError("PrintedInks needs at least one ink table")
        stacks = {}
        for key, table in dict(self.stacks).items():
            s = check_subset(key, len(inks))
            if len(s) < 2:
                raise ValueError(f"stack key {key!r}: a stack has at least two inks (single inks "
                                 "come from `inks`)")
            stacks[s] = table
        object.__setattr__(self, "inks", inks)
        object.__setattr__(self, "stacks", stacks)

    @property
    def n_inks(self) -> int:
        return len(self.inks)

    def primaries(self) -> tuple[Subset, ...]:
        """The printed primaries with a table: bare paper (), each ink, each given stack."""
        return tuple(s for s in all_subsets(self.n_inks) if len(s) < 2 or s in self.stacks)

    def table(self, subset: Subset) -> InkTable | None:
        """The table of a printed primary (None for bare paper)."""
        s = check_subset(subset, self.n_inks)
        if not s:
            return None
        if len(s) == 1:
            return self.inks[s[0]]
        if s not in self.stacks:
            raise ValueError(f"no stack table for the overprint of inks {s} (0-based)")
        return self.stacks[s]

    @classmethod
    def from_provider(cls, inks: Iterable[InkTable], stack_table: Callable[[Subset], InkTable],
                      subsets: Iterable[Subset] | None = None) -> "PrintedInks":
        """Ask `stack_table(subset)` for every overprint in `subsets` (default: all of them)."""
        inks = tuple(inks)
        wanted = all_subsets(len(inks)) if subsets is None else tuple(subsets)
        return cls(inks, {tuple(s): stack_table(tuple(s)) for s in wanted if len(s) >= 2})
