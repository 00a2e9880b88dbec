"""Colours of the separation: sRGB pixels and printed reflectances in CIELAB under the press's
measurement (`solver.colour.measurement`: 45:0, D50, 2° by default — ISO 13655, the way
ISO 12647-2 aims are stated, docs/design.md §7).

Pixels are sRGB (IEC 61966-2-1, white D65): decoded, converted to XYZ, carried to the
measurement's white with the Bradford adaptation (ICC practice: the sRGB white is the
measurement white, a grey pixel is a neutral print) and to CIELAB (`solver.colour.srgb`). A
printed colour is the model's reflectance factor under the measurement's illuminant (ASTM E308
weights, `solver.colour.cie`, linear in the spectrum) in CIELAB relative to

- `relative` (default): the bare paper's XYZ — media-relative colorimetry, the paper is the
  image's white (an image white of 255 prints as bare paper);
- `absolute`: the perfect diffuser (Y = 1) — white paper of albedo 0.9 is then L* 96 and
  an image white of L* 100 cannot be printed.

Colour differences: ΔE76 (Euclidean in CIELAB; what the separation minimises) and ΔE2000 (CIE
DE2000 from colour-science; reported).
"""

from __future__ import annotations

import numpy as np

from solver.colour import srgb
from solver.colour.cie import delta_e76, delta_e2000, spectra_to_xyz, xyz_to_lab  # noqa: F401 (re-exported)
from solver.colour.measurement import DEFAULT as DEFAULT_MEASUREMENT
from solver.colour.measurement import Measurement

INTENTS = ("relative", "absolute")
DEFAULT_INTENT = "relative"


def check_intent(intent: str) -> str:
    """The rendering intent if known; ValueError naming the choices otherwise."""
    if intent not in INTENTS:
        raise ValueError(f"intent must be one of {', '.join(INTENTS)}; got {intent!r}")
    return intent


def srgb_to_lab(encoded, measurement: Measurement = DEFAULT_MEASUREMENT) -> np.ndarray:
    """CIELAB of encoded sRGB values in [0, 1] [..., 3] (the sRGB white at L* = 100 of the
    measurement's white)."""
    return srgb.linear_to_lab(srgb.decode(np.asarray(encoded, dtype=float)), measurement.illuminant,
                              measurement.observer)


def srgb8_to_lab(pixels, measurement: Measurement = DEFAULT_MEASUREMENT) -> np.ndarray:
    """CIELAB of 8-bit sRGB colours [..., 3] (the sRGB white at L* = 100)."""
    return srgb_to_lab(np.asarray(pixels, dtype=float) / 255.0, measurement)


def lab_to_linear_srgb(lab, measurement: Measurement = DEFAULT_MEASUREMENT) -> np.ndarray:
    """Linear sRGB (unclipped) of CIELAB colours relative to the measurement white: the inverse of
    `srgb_to_lab` before the transfer curve (a colour is in the sRGB gamut when all three lie
    in [0, 1])."""
    from solver.colour.cie import bradford, lab_to_xyz, white_xyz

    source = white_xyz(measurement.illuminant, measurement.observer)
    xyz = lab_to_xyz(lab, source) @ bradford(source, srgb.SRGB_WHITE).T
    return xyz @ srgb.XYZ_TO_LINEAR.T


def xyz_matrix(wavelengths_nm, measurement: Measurement = DEFAULT_MEASUREMENT) -> np.ndarray:
    """[nλ, 3]: XYZ (perfect diffuser Y = 1) = reflectance @ matrix, for spectra on
    `wavelengths_nm` (the tristimulus weighting is linear in the spectrum)."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    return spectra_to_xyz(wl, np.eye(wl.size), measurement.illuminant, measurement.observer)


def lab_from_xyz(xyz, white_xyz) -> np.ndarray:
    """CIELAB of XYZ [..., 3] relative to `white_xyz` (3 values)."""
    return xyz_to_lab(xyz, np.asarray(white_xyz, dtype=np.float64))


def lab_to_srgb8(lab, measurement: Measurement = DEFAULT_MEASUREMENT) -> np.ndarray:
    """8-bit sRGB of CIELAB colours taken relative to the measurement white (a soft proof: a
    print's Lab relative to its paper shows the paper as display white), clipped to the sRGB gamut."""
    return srgb.lab_to_srgb8(lab, measurement.illuminant, measurement.observer)
