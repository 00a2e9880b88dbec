"""Colours of the separation: 8-bit sRGB pixels and printed reflectances in CIELAB.

Pixels are sRGB (IEC 61966-2-1) under D65: decoded, converted to XYZ and to CIELAB relative to
the sRGB white (`solver.colour.srgb`). A printed colour is the model's reflectance under D65
(ASTM E308 weights, `solver.colour.cie`, a linear map of the spectrum) in CIELAB relative to

- `relative` (default): the bare paper's XYZ — media-relative colorimetry, the paper is the
  image's white (an image white of 255 prints as bare paper);
- `absolute`: the perfect white reflector (Y = 1) — white paper of albedo 0.9 is then L* 96 and
  an image white of L* 100 cannot be printed.

Colour differences: ΔE76 (Euclidean in CIELAB; what the separation minimises) and ΔE2000 (CIE
DE2000 from colour-science; reported).
"""

from __future__ import annotations

import numpy as np

from solver.colour import srgb
from solver.colour.cie import delta_e76, delta_e2000, spectra_to_xyz, xyz_to_lab  # noqa: F401 (re-exported)

INTENTS = ("relative", "absolute")
DEFAULT_INTENT = "relative"
#: the separation's colorimetry (the sRGB image's own illuminant)
ILLUMINANT, OBSERVER = "D65", "2"


def check_intent(intent: str) -> str:
    """The rendering intent if known; ValueError naming the choices otherwise."""
    if intent not in INTENTS:
        raise ValueError(f"intent must be one of {', '.join(INTENTS)}; got {intent!r}")
    return intent


def srgb8_to_lab(pixels) -> np.ndarray:
    """CIELAB (D65, the sRGB white at L* = 100) of 8-bit sRGB colours [..., 3]."""
    return srgb.srgb8_to_lab(pixels, ILLUMINANT, OBSERVER)


def xyz_matrix(wavelengths_nm) -> np.ndarray:
    """[nλ, 3]: XYZ (white reflector Y = 1) = reflectance @ matrix, for spectra on
    `wavelengths_nm` (the tristimulus weighting is linear in the spectrum)."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    return spectra_to_xyz(wl, np.eye(wl.size), ILLUMINANT, OBSERVER)


def lab_from_xyz(xyz, white_xyz) -> np.ndarray:
    """CIELAB of XYZ [..., 3] relative to `white_xyz` (3 values)."""
    return xyz_to_lab(xyz, np.asarray(white_xyz, dtype=np.float64))


def lab_to_srgb8(lab) -> np.ndarray:
    """8-bit sRGB of CIELAB colours taken relative to the measurement white (a soft proof: a
    print's Lab relative to its paper shows the paper as display white), clipped to the sRGB gamut."""
    return srgb.lab_to_srgb8(lab, ILLUMINANT, OBSERVER)
