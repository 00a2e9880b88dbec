"""Fast prediction of printed colour: coverage mixes → reflectance spectra under diffuse light.

    predict = ReflectancePredictor.build(printed, paper=0.9, view_rad=np.radians(8))
    spectra = predict(coverages)            # coverages [..., k] in [0, 1] → [..., nλ]

Everything that does not depend on the coverages (each primary's R_spec, R_diff, T̄ at the view
angle, ρ̄, τ̄) is computed once in `build`; a call is then a few matrix products over the
primaries' Demichel weights (`model.albedo_terms`; `python -m benchmarks.bench_printing
--colour-only` prints the time per mix).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .inkset import PrintedInks
from ..paper import PAPER_ALBEDO
from .model import DEFAULT_COVERAGE_MODEL, albedo_terms, check_coverage_model, paper_albedo, primary_weights
from .optics import PrimaryOptics, primary_optics


@dataclass(frozen=True)
class ReflectancePredictor:
    """Reflectance of coverage mixes seen from `view_rad` under uniform diffuse light."""

    printed: PrintedInks
    optics: PrimaryOptics
    paper: np.ndarray            # r on the wavelengths, [nλ]
    view_rad: float
    coverage_model: str
    specular: bool               # include the mirror reflection of the diffuse light

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self.optics.wavelengths_nm

    @classmethod
    def build(cls, printed: PrintedInks, paper=PAPER_ALBEDO, view_rad: float = 0.0,
              coverage_model: str = DEFAULT_COVERAGE_MODEL, wavelengths_nm=None,
              specular: bool = True) -> "ReflectancePredictor":
        """Precompute for one print, paper albedo (number or spectrum on the wavelengths), view
        polar angle (rad), model and wavelengths (default: the first ink's grid)."""
        check_coverage_model(coverage_model)
        if not 0.0 <= float(view_rad) <= np.pi / 2:
            raise ValueError(f"view_rad must lie in [0, π/2], got {view_rad}")
        optics = primary_optics(printed, printed.primaries(), wavelengths_nm)
        return cls(printed, optics, paper_albedo(paper, optics.wavelengths_nm), float(view_rad),
                   coverage_model, bool(specular))

    def __call__(self, coverages) -> np.ndarray:
        """Reflectance spectra [..., nλ] of coverages [..., k] (clamped to [0, 1])."""
        _, weights = primary_weights(self.printed, coverages, self.optics.subsets)
        return albedo_terms(self.optics, self.coverage_model, weights, self.paper,
                            self.view_rad, self.specular)


def reflectance(printed: PrintedInks, coverages, paper=PAPER_ALBEDO, view_rad: float = 0.0,
                coverage_model: str = DEFAULT_COVERAGE_MODEL, wavelengths_nm=None,
                specular: bool = True) -> np.ndarray:
    """One-off form of `ReflectancePredictor.build(...)(coverages)`: [..., k] → [..., nλ]."""
    return ReflectancePredictor.build(printed, paper, view_rad, coverage_model, wavelengths_nm,
                                      specular)(coverages)
