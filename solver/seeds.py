"""A random seed given by the user — `--seed` of `ink-tables build`/`geometry` and of
`python -m inkbsdf.render`, `--table-seed`, a table request's seed: the one check and its one
message (solver.geometry.populations keeps its own guard of a generator seed ≥ 0: editing that
module would change every cached table's key, solver/table/fingerprint.py).

A seed is an unsigned 32-bit integer, [0, 2^32): the range Mitsuba's sampler takes (`mi.render`'s
seed is a UInt32; outside it nanobind refuses the call with a raw type error). The tables' and
the geometry's seeds (NumPy SeedSequence, which takes any integer ≥ 0) share the range, so a seed
valid for one command is valid for all.
"""

from __future__ import annotations

import numbers

#: seeds lie in [0, SEED_LIMIT)
SEED_LIMIT = 2**32


def checked_seed(value, option: str = "seed", error: type[ValueError] = ValueError) -> int:
    """`value` as an int, or `error` naming `option` and the range: '--seed: give an integer in
    [0, 2^32), got -1'."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 0 <= value < SEED_LIMIT:
        raise error(f"{option}: give an integer in [0, 2^32), got {value!r}")
    return int(value)
