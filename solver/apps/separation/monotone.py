"""One ink: a monotone (spot-colour) print of the image's lightness (docs/printing.md, "One ink:
a monotone").

With one ink the printable colours are a curve, the ink's tint ramp from bare paper (coverage 0)
to the solid (1), not a volume: there is no gamut boundary per hue to compress toward, and a
colour off the curve cannot be matched. A press prints such a job as a monotone: the image's
tone in the ink. Each colour's L* (CIELAB, relative to the measurement white) is black-point
compensated onto the ramp's L* range — L' = L_solid + L*·(L_paper − L_solid)/100, the
perceptual mapping's compensation (`gamut.compensate_lightness`) with the solid as its black —
and printed as the coverage whose printed L* is L'. The colour to print (the mapped
colour) is the ink's own colour at that coverage, so the separation is exact.

    ramp = MonotoneRamp.build(model)        # a PrintColourModel of one ink; MonotoneError unless
                                            # its L* falls steadily with coverage
    sep = ramp.separate(source_lab)         # solve.Separation: targets = printed colours

The ramp is tabulated at `RAMP_NODES` coverages and inverted linearly in L*: the printed L* of
the interpolated coverage is the chord error of a smooth ramp away from L' (20,000 random
colours: at most 1.2·10⁻⁶ L* with B30, 5·10⁻⁸ with Y30).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .gamut import compensate_lightness
from .solve import Separation

RAMP_NODES = 4097               # coverages 0, 1/4096, …, 1 at which the ink's L* is tabulated


class MonotoneError(ValueError):
    """One ink whose printed L* does not fall steadily with coverage: its tones cannot carry
    the image's lightness (the message names the ink and where the ramp turns)."""


def ink_name(model, index: int = 0) -> str:
    """The spec of the model's ink `index` as its table records it ('B30'), else 'the ink'."""
    return str(model.predictor.printed.inks[index].meta.get("ink", "the ink"))


@dataclass(frozen=True)
class MonotoneRamp:
    """The tint ramp of one ink under a print model, and its inverse in L*."""

    model: object                 # PrintColourModel of one ink
    coverage_nodes: np.ndarray    # [RAMP_NODES] in [0, 1]
    lightness: np.ndarray         # [RAMP_NODES] L* printed at them, strictly decreasing
    ink: str                      # the ink's name, for the report

    black_label = "one ink, no black generation"

    @classmethod
    def build(cls, model) -> "MonotoneRamp":
        if model.n_inks != 1:
            raise ValueError(f"a monotone is printed with one ink, the model has {model.n_inks}")
        c = np.linspace(0.0, 1.0, RAMP_NODES)
        L = model.lab(c[:, None])[:, 0]
        ink = ink_name(model)
        rises = np.flatnonzero(np.diff(L) >= 0.0)
        if rises.size:
            i = int(rises[0])
            raise MonotoneError(
                f"one ink ({ink}): its printed L* does not fall steadily with coverage (L* {L[i]:.2f} at "
                f"{100 * c[i]:.1f} %, {L[i + 1]:.2f} at {100 * c[i + 1]:.1f} %; paper {L[0]:.1f}, solid "
                f"{L[-1]:.1f}), so its tones cannot carry the image's lightness: print with an ink that darkens "
                "the paper, or with a second ink")
        return cls(model, c, L, ink)

    @property
    def paper_l(self) -> float:
        """L* of the bare paper (coverage 0): the image's white."""
        return float(self.lightness[0])

    @property
    def solid_l(self) -> float:
        """L* of the solid (coverage 1): the image's black."""
        return float(self.lightness[-1])

    @property
    def lightness_range(self) -> tuple[float, float]:
        """(black, white) L* of the black-point compensation."""
        return self.solid_l, self.paper_l

    def lightness_map(self, L) -> np.ndarray:
        """Black-point compensation: L* 0…100 → solid_l…paper_l (linear)."""
        return compensate_lightness(L, self.solid_l, self.paper_l)

    def coverage(self, L) -> np.ndarray:
        """The coverage [N] whose printed L* is L [N] (clamped to the ramp's range)."""
        return np.interp(-np.asarray(L, dtype=np.float64).reshape(-1), -self.lightness, self.coverage_nodes)

    def separate(self, source_lab, gamut_de: float = 0.5, chunk: int | None = None) -> Separation:
        """The monotone of source colours CIELAB [N, 3]: coverages [N, 1] printing their
        compensated L*, the mapped colours the printed ones (`gamut_de`: the Separation's
        out-of-gamut threshold, never exceeded; `chunk` unused: one interpolation per colour)."""
        source = np.asarray(source_lab, dtype=np.float64).reshape(-1, 3)
        c = self.coverage(self.lightness_map(source[:, 0]))[:, None]
        printed = self.model.lab(c)
        return Separation(c, printed.copy(), printed, np.zeros(c.shape[0], dtype=np.int64), gamut_de)

    def mapped(self, source_lab, chunk: int | None = None) -> np.ndarray:
        """The colours to print (CIELAB [N, 3]) of source colours: the ink's at their coverage."""
        return self.separate(source_lab).printed_lab

    def report_line(self, mean_de2000: float, max_de2000: float) -> str:
        """What was printed instead of a gamut mapping (the ΔE2000 image → print: unused, the
        report's first line has the mean)."""
        return (f"one ink: a monotone of the image's lightness in {self.ink} (each pixel's L*, compensated onto "
                f"the ink's L* {self.solid_l:.1f} solid – {self.paper_l:.1f} paper, printed as the coverage that "
                "prints it); the image's hues are not reproduced")
