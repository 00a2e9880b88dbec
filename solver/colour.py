"""Spectra → CIE XYZ → sRGB / CIELAB, for pictures and colour checks.

Tabulated CIE 1931 2° colour-matching functions and the D65 illuminant come from
colour-science (the authoritative tables, rather than hand-typed copies).  Reflectance
spectra are normalised so that a perfect white reflector gives Y = 1, i.e. sRGB (1, 1, 1):
the paper's convention that a Lambertian of albedo 1 shows as (255, 255, 255).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

_STEP_NM = 5.0
_RANGE_NM = (380.0, 780.0)


@lru_cache(maxsize=1)
def _weights() -> tuple[np.ndarray, np.ndarray]:
    """Wavelengths and the D65-weighted CMFs (normalised: Σ w_Y = 1)."""
    import colour

    wl = np.arange(_RANGE_NM[0], _RANGE_NM[1] + 0.5 * _STEP_NM, _STEP_NM)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    d65 = colour.SDS_ILLUMINANTS["D65"]
    xyz_bar = np.stack([np.interp(wl, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)], axis=1)
    s = np.interp(wl, d65.wavelengths, d65.values)
    w = xyz_bar * s[:, None]
    return wl, w / w[:, 1].sum()


_XYZ_TO_SRGB = np.array([[3.2404542, -1.5371385, -0.4985314],
                         [-0.9692660, 1.8760108, 0.0415560],
                         [0.0556434, -0.2040259, 1.0572252]])
_D65_WHITE = np.array([0.95047, 1.0, 1.08883])


def reflectance_to_xyz(wavelength_nm, reflectance, axis: int = -1) -> np.ndarray:
    """XYZ under D65 of reflectance spectra sampled at `wavelength_nm` along `axis` (clamped)."""
    wl, w = _weights()
    refl = np.moveaxis(np.asarray(reflectance, dtype=float), axis, -1)
    src = np.asarray(wavelength_nm, dtype=float)
    idx = np.clip(np.searchsorted(src, wl) - 1, 0, max(src.size - 2, 0))
    if src.size == 1:
        resampled = np.repeat(refl, wl.size, axis=-1)
    else:
        t = np.clip((wl - src[idx]) / (src[idx + 1] - src[idx]), 0.0, 1.0)
        resampled = refl[..., idx] * (1 - t) + refl[..., idx + 1] * t
    return resampled @ w


def xyz_to_linear_srgb(xyz) -> np.ndarray:
    return np.asarray(xyz) @ _XYZ_TO_SRGB.T


def encode_srgb(linear) -> np.ndarray:
    """sRGB transfer function on values clipped to [0, 1]."""
    x = np.clip(np.asarray(linear, dtype=float), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def reflectance_to_srgb8(wavelength_nm, reflectance, axis: int = -1) -> np.ndarray:
    """8-bit sRGB of reflectance spectra (white reflector → 255, 255, 255)."""
    rgb = encode_srgb(xyz_to_linear_srgb(reflectance_to_xyz(wavelength_nm, reflectance, axis)))
    return np.round(255.0 * rgb).astype(np.uint8)


def xyz_to_lab(xyz, white=_D65_WHITE) -> np.ndarray:
    """CIELAB (L*, a*, b*) relative to the D65 white (Y_white = 1)."""
    t = np.asarray(xyz, dtype=float) / white
    d = 6.0 / 29.0
    f = np.where(t > d**3, np.cbrt(t), t / (3 * d * d) + 4.0 / 29.0)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def linear_srgb_to_lab(rgb) -> np.ndarray:
    """CIELAB of linear sRGB values (e.g. pixels of a render)."""
    return xyz_to_lab(np.asarray(rgb, dtype=float) @ np.linalg.inv(_XYZ_TO_SRGB).T)


def lab_hue_chroma(lab) -> tuple[np.ndarray, np.ndarray]:
    """CIELAB hue angle (degrees, 0–360) and chroma."""
    lab = np.asarray(lab)
    return np.degrees(np.arctan2(lab[..., 2], lab[..., 1])) % 360.0, np.hypot(lab[..., 1], lab[..., 2])
