"""Ink descriptions as the paper writes them: `R15`, `Y7.5+B7.5`, `G30`, `clear`; the process
pigments C, M, K in the same grammar (`C8.7`, `K14.6+C6.4+M5.1`; solver.materials).

Percent by volume at the CLI and in spec strings; fractions inside the code.  A *molecular*
ink (pigment dissolved in the binder, the paper's "infinitesimal particles") is one homogeneous
material whose permittivity is the volume-weighted mean (linear ε mixing, the same rule the
voxeliser uses for sub-voxel fractions):

    ε_mix(λ) = (1 − Σ f_i)·ε_binder + Σ f_i·ε_i(λ)
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from .materials import MaterialData, base_parts, default_materials, get_pigment


class InkSpecError(ValueError):
    """A malformed or unphysical ink description."""


@dataclass(frozen=True)
class Ink:
    """Pigment volume fractions, e.g. ((\"Y\", 0.075), (\"B\", 0.075)); empty for clear varnish."""

    components: tuple[tuple[str, float], ...]

    @property
    def total_fraction(self) -> float:
        return float(sum(f for _, f in self.components))

    @property
    def label(self) -> str:
        """Canonical spec string (`clear` for binder only)."""
        if not self.components:
            return "clear"
        return "+".join(f"{code}{_fmt_percent(f)}" for code, f in self.components)

    def base_composition(self) -> tuple[tuple[str, float], ...]:
        """Volume fractions of the base pigments, mixes such as G expanded (G30 → Y15 + B15),
        rounded to 1e-12 and sorted: two inks with equal base composition are one material."""
        total: dict[str, float] = {}
        for code, fraction in self.components:
            for base, weight in base_parts(code):
                total[base] = total.get(base, 0.0) + fraction * weight
        return tuple(sorted((c, round(f, 12)) for c, f in total.items()))


def _fmt_percent(fraction: float) -> str:
    return f"{100.0 * fraction:.6g}"


_TERM = re.compile(r"^([A-Za-z]+)\s*(-?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*%?$")


def parse_ink(spec: "str | Ink") -> Ink:
    """Parse an ink spec string (an Ink passes through); raise InkSpecError naming the problem."""
    if isinstance(spec, Ink):
        return spec
    if not isinstance(spec, str) or not spec.strip():
        raise InkSpecError("empty ink spec: expected e.g. 'R15', 'Y7.5+B7.5', 'G30' or 'clear'")
    text = spec.strip()
    if text.lower() in ("clear", "varnish", "binder"):
        return Ink(())
    components: dict[str, float] = {}
    for term in text.split("+"):
        match = _TERM.match(term.strip())
        if not match:
            raise InkSpecError(
                f"bad ink term {term.strip()!r} in {spec!r}: expected a pigment letter and a "
                "volume percent, e.g. 'Y7.5'")
        code, percent = match.group(1).upper(), float(match.group(2))
        try:
            get_pigment(code)
        except ValueError as exc:
            raise InkSpecError(f"in ink {spec!r}: {exc}") from None
        if percent < 0:
            raise InkSpecError(f"negative concentration {percent}% of {code} in ink {spec!r}")
        if code in components:
            raise InkSpecError(f"pigment {code} appears twice in ink {spec!r}")
        components[code] = percent / 100.0
    total = sum(components.values())
    if total > 1.0 + 1e-12:
        raise InkSpecError(f"total pigment concentration {100 * total:.6g}% exceeds 100% in ink {spec!r}")
    return Ink(tuple((c, f) for c, f in components.items() if f > 0.0))


def molecular_eps(ink: Ink, wavelength_nm, materials: MaterialData | None = None) -> np.ndarray:
    """Permittivity of the ink as one homogeneous material (linear volume-weighted ε)."""
    data = materials or default_materials()
    wl = np.asarray(wavelength_nm, dtype=float)
    eps = (1.0 - ink.total_fraction) * data.binder_eps(wl)
    for code, fraction in ink.components:
        eps = eps + fraction * data.pigment_eps(code, wl)
    return eps
