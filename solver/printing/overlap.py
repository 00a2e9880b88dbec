"""Which printed primaries can occur on a surface, decided once from the coverages' data.

Each ink's coverage is described by its *support*, where it can be > 0:

    a number        a uniform coverage (clamped to [0, 1]): 0 never, ≥ 1 everywhere
    TexelMask       a texture: True on the texels where it can be > 0 (after filtering), in a
                    `frame` naming the texel grid and uv mapping; masks of one frame intersect
    None            unknown (any other texture): anywhere

A primary S (a set of ink indices, `demichel`) can occur when every ink of S can be present at
one point and no ink outside S covers everything. Only those primaries are evaluated, so a
surface whose inks never overlap needs no stack tables.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass

import numpy as np

from .demichel import Subset, all_subsets


@dataclass(frozen=True)
class TexelMask:
    """Texels where a textured coverage can be > 0, on the texel grid named by `frame`."""

    mask: np.ndarray            # bool, any shape
    frame: Hashable             # equal frames ⇔ the same texels at the same surface points


Support = float | TexelMask | None


def _can_be_present(support: Support) -> bool:
    if support is None:
        return True
    if isinstance(support, TexelMask):
        return bool(np.any(support.mask))
    return float(support) > 0.0


def _can_meet(supports: Sequence[Support]) -> bool:
    """True when all these inks can be > 0 at one point."""
    if not all(_can_be_present(s) for s in supports):
        return False
    frames: dict = {}
    for s in supports:
        if isinstance(s, TexelMask):
            frames.setdefault(s.frame, []).append(np.asarray(s.mask, dtype=bool))
    return all(bool(np.any(np.logical_and.reduce(masks))) for masks in frames.values())


def possible_primaries(supports: Sequence[Support]) -> tuple[Subset, ...]:
    """The primaries (ascending index tuples, bare paper () first) that can have area > 0."""
    full = {i for i, s in enumerate(supports)
            if s is not None and not isinstance(s, TexelMask) and float(s) >= 1.0}
    return tuple(s for s in all_subsets(len(supports))
                 if full.issubset(s) and _can_meet([supports[i] for i in s]))
