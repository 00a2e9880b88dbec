"""CIE colorimetry of reflectance spectra: tristimulus weights, CIELAB, colour differences.

Tristimulus values follow ASTM E308 as colour-science implements it (`sd_to_XYZ_ASTME308`:
its weighting of 1, 5, 10 and 20-nm data, with the bandpass and interval corrections). Since the
method is linear in the spectrum, the weights for a wavelength grid are computed once, as the
XYZ of the grid's unit spectra, and cached: XYZ = spectrum @ W. Grids of other steps (the
preview tables' 40 nm, irregular grids) are first interpolated linearly to 5 nm — the
interpolant the renderer uses between a table's wavelengths — and weighted there.

XYZ are scaled so that the perfect reflecting diffuser has Y = 1 under the illuminant, and CIELAB
is relative to that diffuser's XYZ computed with the same weights (a white spectrum is exactly
L* = 100, a* = b* = 0). Illuminants and observers are named as ISO 13655 and CIE 15 name them.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

#: illuminant names → colour-science's spectral data
ILLUMINANTS = {"D50": "D50", "D65": "D65"}
#: observer names (degrees of field) → colour-science's colour-matching functions
OBSERVERS = {"2": "CIE 1931 2 Degree Standard Observer", "10": "CIE 1964 10 Degree Standard Observer"}
#: E308 weights tabulated data of these intervals (nm); other grids are interpolated to 5 nm
E308_INTERVALS_NM = (1.0, 5.0, 10.0, 20.0)
#: a colour needs the spectrum over this range (nm); beyond it E308 extends the end values
#: (its practice for data that stop short of 360–780 nm)
REQUIRED_RANGE_NM = (400.0, 700.0)
_RESAMPLE_STEP_NM = 5.0


class ColourError(ValueError):
    """A colour that cannot be computed as asked (names the option or the data's range)."""


def check_illuminant(name: str) -> str:
    name = str(name).upper()
    if name not in ILLUMINANTS:
        raise ColourError(f"illuminant {name!r}: choose one of {', '.join(ILLUMINANTS)}")
    return name


def check_observer(name) -> str:
    text = str(name).strip().removesuffix("°").removesuffix("deg")
    if text not in OBSERVERS:
        raise ColourError(f"observer {name!r}: choose one of {', '.join(k + '°' for k in OBSERVERS)}")
    return text


def check_range(wavelengths_nm, what: str = "the spectrum") -> None:
    """ColourError unless the wavelengths cover REQUIRED_RANGE_NM."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    lo, hi = REQUIRED_RANGE_NM
    if wl.size < 2 or wl[0] > lo or wl[-1] < hi:
        span = f"{wl[0]:g}–{wl[-1]:g} nm" if wl.size else "no wavelengths"
        raise ColourError(f"{what}: wavelengths {span}; a colour needs at least {lo:g}–{hi:g} nm "
                          "(build the table with --wavelengths 380:780:STEP)")


def _uniform_step(wl: np.ndarray) -> float | None:
    steps = np.diff(wl)
    if np.allclose(steps, steps[0], rtol=0, atol=1e-9) and np.isclose(wl[0], round(wl[0]), atol=1e-9):
        return float(steps[0])
    return None


def _e308_weights(wl: np.ndarray, illuminant: str, observer: str) -> np.ndarray:
    import warnings

    import colour

    cmfs = colour.MSDS_CMFS[OBSERVERS[observer]]
    sd_illuminant = colour.SDS_ILLUMINANTS[ILLUMINANTS[illuminant]]
    out = np.empty((wl.size, 3))
    with warnings.catch_warnings():                  # colour-science says it aligns shapes: expected here
        warnings.simplefilter("ignore", colour.utilities.ColourRuntimeWarning)
        for i in range(wl.size):
            unit = np.zeros(wl.size)
            unit[i] = 1.0
            sd = colour.SpectralDistribution(dict(zip(wl, unit)))
            out[i] = colour.colorimetry.sd_to_XYZ_ASTME308(sd, cmfs, sd_illuminant) / 100.0
    return out


@lru_cache(maxsize=64)
def _weights(wl_key: tuple, illuminant: str, observer: str) -> np.ndarray:
    wl = np.asarray(wl_key)
    step = _uniform_step(wl)
    if step is not None and any(np.isclose(step, s) for s in E308_INTERVALS_NM):
        return _e308_weights(wl, illuminant, observer)
    fine = np.arange(np.ceil(wl[0] / _RESAMPLE_STEP_NM) * _RESAMPLE_STEP_NM, wl[-1] + 1e-9, _RESAMPLE_STEP_NM)
    resample = np.stack([np.interp(fine, wl, unit) for unit in np.eye(wl.size)], axis=-1)   # [n5, nλ]
    return resample.T @ _e308_weights(fine, illuminant, observer)


def tristimulus_weights(wavelengths_nm, illuminant: str, observer: str) -> np.ndarray:
    """[nλ, 3]: XYZ = spectrum @ W for reflectance spectra sampled on `wavelengths_nm` (strictly
    increasing, covering REQUIRED_RANGE_NM); the perfect white gives Y = 1."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    check_range(wl)
    return _weights(tuple(float(w) for w in wl), check_illuminant(illuminant), check_observer(observer))


def spectra_to_xyz(wavelengths_nm, reflectance, illuminant: str, observer: str, axis: int = -1) -> np.ndarray:
    """XYZ [..., 3] of reflectance spectra with their wavelength axis at `axis`."""
    w = tristimulus_weights(wavelengths_nm, illuminant, observer)
    return np.moveaxis(np.asarray(reflectance, dtype=float), axis, -1) @ w


@lru_cache(maxsize=16)
def white_xyz(illuminant: str, observer: str) -> np.ndarray:
    """XYZ of the perfect reflecting diffuser (Y = 1), computed with the same E308 weights."""
    grid = np.arange(360.0, 781.0, 5.0)
    return tristimulus_weights(grid, illuminant, observer).sum(axis=0)


def xyz_to_lab(xyz, white) -> np.ndarray:
    """CIELAB (L*, a*, b*) of XYZ [..., 3] relative to the white's XYZ."""
    t = np.asarray(xyz, dtype=float) / np.asarray(white, dtype=float)
    d = 6.0 / 29.0
    f = np.where(t > d ** 3, np.cbrt(t), t / (3 * d * d) + 4.0 / 29.0)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def spectra_to_lab(wavelengths_nm, reflectance, illuminant: str, observer: str, axis: int = -1) -> np.ndarray:
    """CIELAB [..., 3] of reflectance spectra relative to the perfect diffuser, weighted alike
    (on the same grid: a white spectrum is exactly L* = 100, a* = b* = 0)."""
    w = tristimulus_weights(wavelengths_nm, illuminant, observer)
    return xyz_to_lab(np.moveaxis(np.asarray(reflectance, dtype=float), axis, -1) @ w, w.sum(axis=0))


def lab_to_xyz(lab, white) -> np.ndarray:
    """Inverse of xyz_to_lab."""
    lab = np.asarray(lab, dtype=float)
    fy = (lab[..., 0] + 16.0) / 116.0
    f = np.stack([fy + lab[..., 1] / 500.0, fy, fy - lab[..., 2] / 200.0], axis=-1)
    d = 6.0 / 29.0
    t = np.where(f > d, f ** 3, 3 * d * d * (f - 4.0 / 29.0))
    return t * np.asarray(white, dtype=float)


def lab_hue_chroma(lab) -> tuple[np.ndarray, np.ndarray]:
    """CIELAB hue angle (degrees, 0–360) and chroma C*."""
    lab = np.asarray(lab)
    return np.degrees(np.arctan2(lab[..., 2], lab[..., 1])) % 360.0, np.hypot(lab[..., 1], lab[..., 2])


def saturation(lab) -> np.ndarray:
    """CIELAB saturation s = C*/L* (any leading shape)."""
    lab = np.asarray(lab, dtype=float)
    return np.hypot(lab[..., 1], lab[..., 2]) / lab[..., 0]


def delta_e76(lab1, lab2) -> np.ndarray:
    """CIE 1976 colour difference (Euclidean distance in CIELAB)."""
    return np.linalg.norm(np.asarray(lab1, dtype=float) - np.asarray(lab2, dtype=float), axis=-1)


def delta_e2000(lab1, lab2) -> np.ndarray:
    """CIE DE2000 colour difference (colour-science's implementation)."""
    from colour.difference import delta_E_CIE2000

    return np.asarray(delta_E_CIE2000(np.asarray(lab1, dtype=float), np.asarray(lab2, dtype=float)))


def bradford(source_white, target_white) -> np.ndarray:
    """3×3 von Kries matrix in the Bradford cone space taking XYZ seen under `source_white` to
    corresponding colours under `target_white` (ICC's chromatic adaptation)."""
    m = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]])
    gain = (m @ np.asarray(target_white, dtype=float)) / (m @ np.asarray(source_white, dtype=float))
    return np.linalg.inv(m) @ np.diag(gain) @ m
