"""An ink recipe (pigment loads, layer thickness, particles) and the free parameters a design
varies, with their bounds: the one home of the design's defaults (docs/printing.md).

Loads are volume fractions inside (percent at the CLI), thicknesses in nm.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..inks import Ink, InkSpecError, parse_ink
from ..table.request import DEFAULT_THICKNESS_NM, ThinLayerWarning, thin_layers_warning

#: a pigment load's range (volume fraction): the paper's heaviest inks carry 50 %
LOAD_RANGE = (0.0, 0.5)
#: a printed layer's thickness range (nm): offset ink films are about 1 µm (0.5–2 µm)
THICKNESS_RANGE_NM = (500.0, 2000.0)
#: the paper albedo's range when the paper white is designed
PAPER_RANGE = (0.5, 1.0)
#: the pigments each process colour is made of. Black is toned: carbon alone is brown
#: (its k falls from 0.91 at 380 nm to 0.70 at 780 nm, and α = 4πk/λ falls faster), and ink
#: makers tone carbon black with blue; here with the process cyan and magenta pigments.
#: Magenta is shaded with a little cyan pigment: Rhodamine 6G alone, with its local field in
#: the binder, is a red-shaded magenta (b* ≈ +15 at the aim's a*; docs/printing.md).
PROCESS_PIGMENTS = {"cyan": ("C",), "magenta": ("M", "C"), "yellow": ("Y",), "black": ("K", "C", "M")}


class DesignError(ValueError):
    """Free parameters that cannot be designed; the message names the option."""


@dataclass(frozen=True)
class Recipe:
    """One ink: pigment loads ((code, fraction), …), layer thickness (nm), particles spec."""

    loads: tuple[tuple[str, float], ...]
    thickness_nm: float
    particles: str = "molecular"

    @property
    def ink(self) -> Ink:
        return Ink(tuple((c, float(f)) for c, f in self.loads if f > 0.0))

    @property
    def label(self) -> str:
        """'C11.6@812nm' (loads rounded to 0.01 %, thickness to 1 nm)."""
        ink = Ink(tuple((c, round(f, 4)) for c, f in self.loads if round(f, 4) > 0.0))
        text = f"{ink.label}@{self.thickness_nm:.0f}nm"
        return text if self.particles == "molecular" else f"{text} {self.particles}"

    def to_json(self) -> dict:
        return {"ink": Ink(tuple((c, round(f, 6)) for c, f in self.loads if f > 0.0)).label,
                "loads_percent": {c: round(100.0 * f, 4) for c, f in self.loads},
                "thickness_nm": round(float(self.thickness_nm), 2), "particles": self.particles}


@dataclass(frozen=True)
class InkTemplate:
    """The free parameters of an ink design: one load per pigment, and the layer thickness
    (each free within its range, or fixed when the range is one value: `--load-range 5`,
    `--thickness-range 1000`)."""

    pigments: tuple[str, ...]
    load_range: tuple[float, float] = LOAD_RANGE
    thickness_range_nm: tuple[float, float] = THICKNESS_RANGE_NM
    particles: str = "molecular"

    def __post_init__(self):
        lo, hi = self.load_range
        if not (0.0 <= lo <= hi <= 1.0):
            raise DesignError(f"--load-range {100 * lo:g},{100 * hi:g}: need 0 ≤ MIN ≤ MAX ≤ 100 (percent), "
                              "or one value to fix the loads")
        tlo, thi = self.thickness_range_nm
        if not (0.0 < tlo <= thi):
            raise DesignError(f"--thickness-range {tlo:g},{thi:g}: need 0 < MIN ≤ MAX (nm), "
                              "or one value to fix the thickness")
        if lo * len(self.pigments) > 1.0:
            raise DesignError(f"--load-range: the pigments' least loads ({len(self.pigments)} × {100 * lo:g} %) "
                              "already exceed 100 %: lower MIN")
        thin = thin_layers_warning(sorted({tlo, thi}), "--thickness-range")
        if thin:       # valid, but most likely µm typed as nm: said here once, not for each film (colour.py)
            warnings.warn(thin, ThinLayerWarning, stacklevel=3)

    @classmethod
    def of(cls, pigments: str, **kw) -> "InkTemplate":
        """From a pigment list 'K+C+M' (letters of the ink grammar, solver.inks)."""
        text = str(pigments).strip()
        try:
            ink = parse_ink("+".join(f"{code.strip()}1" for code in text.split("+")))
        except InkSpecError as exc:
            raise DesignError(f"--pigments {text!r}: {exc}") from None
        return cls(tuple(code for code, _ in ink.components), **kw)

    @property
    def names(self) -> tuple[str, ...]:
        """The free parameters' names, in the order of `bounds`."""
        return ((tuple(f"load {c}" for c in self.pigments) if self.loads_free else ())
                + (("thickness_nm",) if self.thickness_free else ()))

    @property
    def loads_free(self) -> bool:
        return self.load_range[1] > self.load_range[0]

    @property
    def thickness_free(self) -> bool:
        return self.thickness_range_nm[1] > self.thickness_range_nm[0]

    @property
    def fixed(self) -> list[str]:
        """The parameters the user fixed, each with the option that fixed it ('thickness fixed at
        1000 nm by --thickness-range'): limits of a design as real as a bound."""
        out = [] if self.loads_free else [
            f"load {c} fixed at {100 * self.load_range[0]:g} % by --load-range" for c in self.pigments]
        if not self.thickness_free:
            out.append(f"thickness fixed at {self.thickness_range_nm[0]:g} nm by --thickness-range")
        return out

    def bounds(self) -> np.ndarray:
        """[n, 2] lower and upper bounds of the free parameters (fractions, nm); n may be 0."""
        rows = [self.load_range] * len(self.pigments) if self.loads_free else []
        if self.thickness_free:
            rows.append(self.thickness_range_nm)
        return np.array(rows, dtype=float).reshape(-1, 2)

    def recipe(self, x) -> Recipe:
        x = list(np.asarray(x, dtype=float))
        fractions = x[:len(self.pigments)] if self.loads_free else [self.load_range[0]] * len(self.pigments)
        thickness = x[-1] if self.thickness_free else self.thickness_range_nm[0]
        return Recipe(tuple((c, float(f)) for c, f in zip(self.pigments, fractions)), float(thickness),
                      self.particles)

    def params(self, recipe: Recipe) -> np.ndarray:
        """The free parameters of `recipe` (the inverse of `recipe`)."""
        loads = dict(recipe.loads)
        x = [loads[c] for c in self.pigments] if self.loads_free else []
        if self.thickness_free:
            x.append(recipe.thickness_nm)
        return np.array(x, dtype=float)

    def start(self) -> np.ndarray:
        """A feasible middle point: loads at a tenth of their range, thickness 1 µm if allowed."""
        b = self.bounds()
        x = b[:, 0] + 0.1 * (b[:, 1] - b[:, 0])
        if self.thickness_free:
            x[-1] = float(np.clip(DEFAULT_THICKNESS_NM, *self.thickness_range_nm))
        return x

    def feasible(self, x) -> bool:
        """The total load stays within 100 %."""
        return sum(f for _, f in self.recipe(x).loads) <= 1.0
