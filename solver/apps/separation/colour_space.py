"""Colours of the separation: 8-bit sRGB pixels and printed reflectances in CIELAB.

Pixels are sRGB (IEC 61966-2-1) under D65: decoded, converted to XYZ and to CIELAB relative to
the sRGB white (`solver.colour`). A printed colour is the model's reflectance under D65
(`solver.colour.reflectance_to_xyz`, a linear map of the spectrum) in CIELAB relative to

- `relative` (default): the bare paper's XYZ — media-relative colorimetry, the paper is the
  image's white (an image white of 255 prints as bare paper);
- `absolute`: the perfect white reflector (Y = 1) — white paper of albedo 0.9 is then L* 96 and
  an image white of L* 100 cannot be printed.

Colour differences: ΔE76 (Euclidean in CIELAB; what the separation minimises) and ΔE2000 (CIE
DE2000 from colour-science; reported).
"""

from __future__ import annotations

import numpy as np

from solver.colour import linear_srgb_to_lab, reflectance_to_xyz, xyz_to_lab

INTENTS = ("relative", "absolute")
DEFAULT_INTENT = "relative"


def check_intent(intent: str) -> str:
    """The rendering intent if known; ValueError naming the choices otherwise."""
    if intent not in INTENTS:
        raise ValueError(f"intent must be one of {', '.join(INTENTS)}; got {intent!r}")
    return intent


def decode_srgb(encoded) -> np.ndarray:
    """Inverse sRGB transfer function: encoded values in [0, 1] → linear (IEC 61966-2-1)."""
    x = np.asarray(encoded, dtype=np.float64)
    return np.where(x <= 0.04045, x / 12.92, np.power((x + 0.055) / 1.055, 2.4))


def srgb8_to_lab(pixels) -> np.ndarray:
    """CIELAB (D65, the sRGB white at L* = 100) of 8-bit sRGB colours [..., 3]."""
    return linear_srgb_to_lab(decode_srgb(np.asarray(pixels, dtype=np.float64) / 255.0))


def xyz_matrix(wavelengths_nm) -> np.ndarray:
    """[nλ, 3]: XYZ under D65 (white reflector Y = 1) = reflectance @ matrix, for spectra on
    `wavelengths_nm` (reflectance_to_xyz is linear in the spectrum)."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    return reflectance_to_xyz(wl, np.eye(wl.size))


def lab_from_xyz(xyz, white_xyz) -> np.ndarray:
    """CIELAB of XYZ [..., 3] relative to `white_xyz` (3 values)."""
    return xyz_to_lab(xyz, white=np.asarray(white_xyz, dtype=np.float64))


def delta_e76(lab1, lab2) -> np.ndarray:
    """CIE 1976 colour difference (Euclidean distance in CIELAB)."""
    return np.linalg.norm(np.asarray(lab1, dtype=np.float64) - np.asarray(lab2, dtype=np.float64), axis=-1)


def delta_e2000(lab1, lab2) -> np.ndarray:
    """CIE DE2000 colour difference (colour-science's implementation)."""
    from colour.difference import delta_E_CIE2000

    return np.asarray(delta_E_CIE2000(np.asarray(lab1, dtype=np.float64), np.asarray(lab2, dtype=np.float64)))


def lab_to_srgb8(lab) -> np.ndarray:
    """8-bit sRGB of CIELAB colours taken relative to the sRGB white (a soft proof: a print's
    Lab relative to its paper shows the paper as display white), clipped to the sRGB gamut."""
    from colour import Lab_to_XYZ

    from solver.colour import encode_srgb, xyz_to_linear_srgb

    d65_xy = np.array([0.3127, 0.3290])
    xyz = Lab_to_XYZ(np.asarray(lab, dtype=np.float64), d65_xy)
    return np.round(255.0 * encode_srgb(xyz_to_linear_srgb(xyz))).astype(np.uint8)
