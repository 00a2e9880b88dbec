"""Colour: CIE colorimetry of spectra (`cie`), sRGB (`srgb`), and how a print's colour is
measured from its table — geometry, illuminant, observer (`measurement`).

    from solver.colour import measurement
    m = measurement.parse_measurement("45:0", "D50", "2")      # = measurement.DEFAULT
    lab = m.lab(table, paper=0.9)                              # CIELAB of the ink on paper
"""

from . import measurement, srgb
from .cie import (ColourError, delta_e76, delta_e2000, lab_hue_chroma, lab_to_xyz, saturation,
                  spectra_to_lab, spectra_to_xyz, tristimulus_weights, white_xyz, xyz_to_lab)
from .measurement import DEFAULT as DEFAULT_MEASUREMENT
from .measurement import GEOMETRIES, Measurement, parse_measurement

__all__ = ["ColourError", "DEFAULT_MEASUREMENT", "GEOMETRIES", "Measurement", "delta_e76", "delta_e2000",
           "lab_hue_chroma", "lab_to_xyz", "measurement", "parse_measurement", "saturation", "spectra_to_lab", "spectra_to_xyz",
           "srgb", "tristimulus_weights", "white_xyz", "xyz_to_lab"]
