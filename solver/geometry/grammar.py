"""Pieces of the particle-spec grammar shared by `spec` and the shapes: the error of a bad spec,
and how numbers are read from and written into spec strings (labels are cache keys: one format)."""

from __future__ import annotations

import math


class ParticleSpecError(ValueError):
    """A malformed or unphysical particle description."""


def fmt(value: float) -> str:
    """A number as labels write it (6 significant digits, no trailing zeros)."""
    return f"{value:.6g}"


def parse_number(text: str, what: str, spec: str) -> float:
    """A finite number from a spec token, or one clear ParticleSpecError naming `what`."""
    try:
        value = float(text)
    except ValueError:
        raise ParticleSpecError(f"bad {what} {text!r} in particle spec {spec!r}: expected a number") from None
    if not math.isfinite(value):
        raise ParticleSpecError(f"bad {what} {text!r} in particle spec {spec!r}")
    return value
