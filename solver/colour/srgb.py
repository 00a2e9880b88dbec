"""sRGB (IEC 61966-2-1): the transfer curve, the primaries, and pictures of spectra — the one
home of the sRGB transfer in the project (pictures, image decoding, renders written as PNG).

sRGB's white is D65. A colour measured under another illuminant (D50, the press's) is carried
to and from sRGB with the Bradford adaptation between the two whites (ICC practice), so that
paper white shows as display white and an sRGB grey is a neutral print.
"""

from __future__ import annotations

import numpy as np

from .cie import bradford, lab_to_xyz, spectra_to_xyz, white_xyz, xyz_to_lab

XYZ_TO_LINEAR = np.array([[3.2404542, -1.5371385, -0.4985314],
                          [-0.9692660, 1.8760108, 0.0415560],
                          [0.0556434, -0.2040259, 1.0572252]])
LINEAR_TO_XYZ = np.linalg.inv(XYZ_TO_LINEAR)
#: the white of the sRGB primaries (their XYZ at R = G = B = 1)
SRGB_WHITE = LINEAR_TO_XYZ.sum(axis=1)
#: pictures of spectra are computed under sRGB's own illuminant and the 2° observer
PICTURE_ILLUMINANT, PICTURE_OBSERVER = "D65", "2"


def encode(linear) -> np.ndarray:
    """sRGB transfer curve on values clipped to [0, 1] (NaN → 0): linear → encoded."""
    x = np.clip(np.nan_to_num(np.asarray(linear, dtype=float), nan=0.0), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def decode(encoded) -> np.ndarray:
    """Inverse transfer curve: encoded values in [0, 1] → linear."""
    x = np.asarray(encoded, dtype=float)
    return np.where(x <= 0.04045, x / 12.92, np.power((x + 0.055) / 1.055, 2.4))


def to_8bit(encoded) -> np.ndarray:
    return np.round(255.0 * np.asarray(encoded, dtype=float)).astype(np.uint8)


def spectra_to_srgb8(wavelengths_nm, reflectance, axis: int = -1) -> np.ndarray:
    """8-bit sRGB pictures of reflectance spectra (D65, 2°): a white reflector is 255, 255, 255."""
    xyz = spectra_to_xyz(wavelengths_nm, reflectance, PICTURE_ILLUMINANT, PICTURE_OBSERVER, axis)
    xyz = xyz / white_xyz(PICTURE_ILLUMINANT, PICTURE_OBSERVER)[1]
    adapt = bradford(white_xyz(PICTURE_ILLUMINANT, PICTURE_OBSERVER), SRGB_WHITE)
    return to_8bit(encode(xyz @ (XYZ_TO_LINEAR @ adapt).T))


def linear_to_lab(rgb, illuminant: str = "D65", observer: str = "2") -> np.ndarray:
    """CIELAB of linear sRGB values, relative to the measurement white of (illuminant,
    observer): sRGB white maps to that white (Bradford)."""
    target = white_xyz(illuminant, observer)
    xyz = np.asarray(rgb, dtype=float) @ (bradford(SRGB_WHITE, target) @ LINEAR_TO_XYZ).T
    return xyz_to_lab(xyz, target)


def srgb8_to_lab(pixels, illuminant: str = "D65", observer: str = "2") -> np.ndarray:
    """CIELAB of 8-bit sRGB colours [..., 3] (sRGB white = L* 100 of the measurement white)."""
    return linear_to_lab(decode(np.asarray(pixels, dtype=float) / 255.0), illuminant, observer)


def lab_to_srgb8(lab, illuminant: str = "D65", observer: str = "2") -> np.ndarray:
    """8-bit sRGB of CIELAB colours relative to the measurement white of (illuminant, observer),
    clipped to the sRGB gamut (a soft proof: a print's colour relative to its paper shows the
    paper as display white)."""
    source = white_xyz(illuminant, observer)
    xyz = lab_to_xyz(lab, source) @ bradford(source, SRGB_WHITE).T
    return to_8bit(encode(xyz @ XYZ_TO_LINEAR.T))
