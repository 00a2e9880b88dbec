"""Printed colour of coverage mixes in CIELAB: the NumPy reference model plus colorimetry.

    model = PrintColourModel.build(printed, paper=0.9, coverage_model="clapper-yule")
    model.lab(coverages)          # [..., k] → CIELAB [..., 3]

The reflectance factor is `solver.printing.MeasuredPredictor` under a `Measurement` (default
45:0, D50, 2°: the press's measurement, which excludes the gloss), with the chosen coverage
model and the overprint stacks of `printed`. Its XYZ and CIELAB follow `colour_space`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.colour.measurement import Measurement
from solver.paper import PAPER_ALBEDO
from solver.printing import DEFAULT_COVERAGE_MODEL, MeasuredPredictor, PrintedInks
from .colour_space import DEFAULT_INTENT, DEFAULT_MEASUREMENT, check_intent, lab_from_xyz, xyz_matrix


@dataclass(frozen=True)
class PrintColourModel:
    """Coverages → XYZ → CIELAB of one print (inks, paper, coverage model, intent, measurement)."""

    predictor: MeasuredPredictor
    to_xyz: np.ndarray            # [nλ, 3]
    white_xyz: np.ndarray         # reference white of CIELAB (paper or perfect diffuser)
    intent: str
    measurement: Measurement

    @classmethod
    def build(cls, printed: PrintedInks, paper=PAPER_ALBEDO, coverage_model: str = DEFAULT_COVERAGE_MODEL,
              intent: str = DEFAULT_INTENT, measurement: Measurement = DEFAULT_MEASUREMENT) -> "PrintColourModel":
        check_intent(intent)
        predictor = MeasuredPredictor.build(printed, paper, measurement.geometry, coverage_model)
        to_xyz = xyz_matrix(predictor.wavelengths_nm, measurement)
        if intent == "relative":
            white = predictor(np.zeros(printed.n_inks)) @ to_xyz
        else:
            white = np.ones(predictor.wavelengths_nm.size) @ to_xyz
        return cls(predictor, to_xyz, white, intent, measurement)

    @property
    def n_inks(self) -> int:
        return self.predictor.printed.n_inks

    @property
    def coverage_model(self) -> str:
        return self.predictor.coverage_model

    @property
    def absolute_white_xyz(self) -> np.ndarray:
        """XYZ of the perfect diffuser (the white of absolute colorimetry, e.g. for profilers)."""
        return np.ones(self.predictor.wavelengths_nm.size) @ self.to_xyz

    def reflectance(self, coverages) -> np.ndarray:
        """Reflectance factors [..., nλ] of coverages [..., k] (clamped to [0, 1])."""
        return self.predictor(coverages)

    def xyz(self, coverages) -> np.ndarray:
        """XYZ [..., 3] (perfect diffuser Y = 1)."""
        return self.predictor(coverages) @ self.to_xyz

    def lab(self, coverages) -> np.ndarray:
        """CIELAB [..., 3] relative to the model's white (paper: `relative`, else Y = 1)."""
        return lab_from_xyz(self.xyz(coverages), self.white_xyz)

    def absolute_lab(self, coverages) -> np.ndarray:
        """CIELAB [..., 3] relative to the perfect diffuser whatever the intent."""
        return lab_from_xyz(self.xyz(coverages), self.absolute_white_xyz)

    def full_ink_lightness(self) -> np.ndarray:
        """L* of each ink alone at full coverage, [k]."""
        return self.lab(np.eye(self.n_inks))[:, 0]
