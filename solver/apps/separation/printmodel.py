"""Printed colour of coverage mixes in CIELAB: the NumPy reference model plus colorimetry.

    model = PrintColourModel.build(printed, paper=0.9, coverage_model="clapper-yule")
    model.lab(coverages)          # [..., k] → CIELAB [..., 3]

The reflectance is `solver.printing.ReflectancePredictor`: diffuse (uniform) light, seen from
`view_rad` (default 0°, the normal), the mirror reflection of the light included
(`specular=True`, like a d/8 "specular included" measurement), with the chosen coverage model
and the overprint stacks of `printed`. Its XYZ under D65 and CIELAB follow `colour_space`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.paper import PAPER_ALBEDO
from solver.printing import DEFAULT_COVERAGE_MODEL, PrintedInks, ReflectancePredictor
from .colour_space import DEFAULT_INTENT, check_intent, lab_from_xyz, xyz_matrix

DEFAULT_VIEW_RAD = 0.0


@dataclass(frozen=True)
class PrintColourModel:
    """Coverages → XYZ (D65) → CIELAB of one print (inks, paper, coverage model, intent)."""

    predictor: ReflectancePredictor
    to_xyz: np.ndarray            # [nλ, 3]
    white_xyz: np.ndarray         # reference white of CIELAB (paper or perfect reflector)
    intent: str

    @classmethod
    def build(cls, printed: PrintedInks, paper=PAPER_ALBEDO, coverage_model: str = DEFAULT_COVERAGE_MODEL,
              intent: str = DEFAULT_INTENT, view_rad: float = DEFAULT_VIEW_RAD,
              specular: bool = True) -> "PrintColourModel":
        check_intent(intent)
        predictor = ReflectancePredictor.build(printed, paper, view_rad, coverage_model, specular=specular)
        to_xyz = xyz_matrix(predictor.wavelengths_nm)
        if intent == "relative":
            white = predictor(np.zeros(printed.n_inks)) @ to_xyz
        else:
            white = np.ones(predictor.wavelengths_nm.size) @ to_xyz
        return cls(predictor, to_xyz, white, intent)

    @property
    def n_inks(self) -> int:
        return self.predictor.printed.n_inks

    @property
    def coverage_model(self) -> str:
        return self.predictor.coverage_model

    def reflectance(self, coverages) -> np.ndarray:
        """Reflectance spectra [..., nλ] of coverages [..., k] (clamped to [0, 1])."""
        return self.predictor(coverages)

    def xyz(self, coverages) -> np.ndarray:
        """XYZ under D65 [..., 3] (perfect white reflector Y = 1)."""
        return self.predictor(coverages) @ self.to_xyz

    def lab(self, coverages) -> np.ndarray:
        """CIELAB [..., 3] relative to the model's white (paper: `relative`, else Y = 1)."""
        return lab_from_xyz(self.xyz(coverages), self.white_xyz)

    def full_ink_lightness(self) -> np.ndarray:
        """L* of each ink alone at full coverage, [k]."""
        return self.lab(np.eye(self.n_inks))[:, 0]
