"""An ink table reduced, once at load, to the colour channels of an RGB or mono Mitsuba variant
(docs/plugin.md, "RGB and mono variants").

Every wavelength-dependent array q(λ) of an `InkLUT` (R_spec, T̄, R_diff, ρ̄, τ̄, R, the mirror's
Mueller elements) becomes q_c = Σ_λ q(λ)·w_c(λ), the colour of what q returns of a light that
is D65:

    rgb:   w_c = the CIE 1931 2° tristimulus weights under D65 (ASTM E308, `solver.colour.cie`),
           taken to linear sRGB (Bradford from the E308 white to sRGB's), each channel scaled
           so that q ≡ 1 gives exactly 1: a white reflector is (1, 1, 1)
    mono:  w = the luminance weights ȳ under D65 (Y of the perfect white = 1)

The coverage model then combines the channels as it combines wavelengths, which is exact for
each quantity taken alone but not for products: light that reaches the paper crosses the layer
twice, T̄(σ)·T̄(θ), and the channel mean of a product is not the product of the channel means
(a saturated ink rendered with channel-mean T̄ came out up to 6 ΔE2000 off beyond its gamut
limit, and 20 L* in mono). T̄ and τ̄ are therefore reduced for the round trip:

    T̄_c(σ) = Σ_λ w_c T̄(λ, σ)·T̄(λ, 0) / sqrt(Σ_λ w_c T̄(λ, 0)²)      (τ̄ alike)

so that T̄_c(0)² is exactly the channel of T̄(λ, 0)², and T̄_c(σ)·T̄_c(θ) that of T̄(λ, σ)·T̄(λ, θ)
wherever T̄(λ, σ) is proportional to T̄(λ, 0); a channel with Σ w_c T̄(λ, 0)² ≤ 0 keeps the plain
weighted sum. The error against spectral rendering, in ΔE2000, is printed by
`python -m benchmarks variants`, bounded by tests/test_bsdf_rgb.py and quoted in docs/plugin.md. Fractions (R_spec, T̄, R_diff, ρ̄, τ̄)
are clamped to [0, 1] and R to ≥ 0 (an sRGB channel of a colour outside the sRGB gamut can be
negative); the Mueller elements b, C, S are not clamped.

The wavelength axis of the reduced table is the channel index (0, 1, 2; mono: 0, 1 with equal
rows, an axis needs two nodes), and `channel_coordinates` gives each lane's channel there.
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import mitsuba as mi
import numpy as np

from .lut import InkLUT

ILLUMINANT, OBSERVER = "D65", "2"


def colour_space() -> str:
    """'spectral', 'rgb' or 'mono': the active variant's colour representation."""
    if mi.is_spectral:
        return "spectral"
    return "rgb" if mi.is_rgb else "mono"


@lru_cache(maxsize=8)
def _weights(wavelengths: tuple, space: str) -> np.ndarray:
    from solver.colour.cie import bradford, tristimulus_weights, white_xyz
    from solver.colour.srgb import SRGB_WHITE, XYZ_TO_LINEAR

    w_xyz = tristimulus_weights(np.asarray(wavelengths), ILLUMINANT, OBSERVER)    # [nλ, 3]
    if space == "mono":
        w = w_xyz[:, 1:2]
    else:
        w = w_xyz @ (XYZ_TO_LINEAR @ bradford(white_xyz(ILLUMINANT, OBSERVER), SRGB_WHITE)).T
    return w / w.sum(axis=0)                                                       # white → 1


def channel_weights(wavelengths_nm, space: str) -> np.ndarray:
    """[nλ, n_channels]: a channel's value of a spectrum q sampled on `wavelengths_nm` is
    q @ weights (see the module docstring)."""
    return _weights(tuple(float(x) for x in np.asarray(wavelengths_nm, dtype=np.float64)), space)


_REDUCED: dict[tuple, tuple] = {}      # (id(lut), space) → (lut, reduced): once per table
_MAX_REDUCED = 64


def reduce_lut(lut: InkLUT, space: str) -> InkLUT:
    """The table in `space` ('rgb' or 'mono'); 'spectral' returns it unchanged. Cached per
    table and space."""
    if space == "spectral":
        return lut
    hit = _REDUCED.get((id(lut), space))
    if hit is None or hit[0] is not lut:
        while len(_REDUCED) >= _MAX_REDUCED:
            _REDUCED.pop(next(iter(_REDUCED)))
        hit = _REDUCED[id(lut), space] = (lut, _reduce(lut, space))
    return hit[1]


def _reduce(lut: InkLUT, space: str) -> InkLUT:
    w = channel_weights(lut.wavelengths_nm, space)

    def reduce(q, lo=0.0, hi=1.0):
        if q is None:
            return None
        out = np.tensordot(w, q, axes=([0], [0]))           # [n_channels, ...]
        if out.shape[0] == 1:                               # mono: two equal rows
            out = np.concatenate([out, out], axis=0)
        return out if lo is None else np.clip(out, lo, hi)

    normal = lut.Tbar[:, int(np.argmin(np.abs(lut.sigma_rad)))]        # T̄(λ, 0) [nλ]
    norm = np.tensordot(w, normal**2, axes=([0], [0]))                  # [n_channels]
    scale = np.sqrt(np.where(norm > 0, norm, 1.0))

    def round_trip(q):
        """Σ w q·T̄(λ, 0)/sqrt(Σ w T̄(λ, 0)²) per channel (see the module docstring)."""
        q_nd = np.moveaxis(q, 0, -1)                                   # [..., nλ]
        weighted = np.moveaxis(np.tensordot(q_nd * normal, w, axes=([-1], [0])), -1, 0) / \
            scale.reshape((-1,) + (1,) * (q.ndim - 1))
        plain = np.tensordot(w, q, axes=([0], [0]))
        out = np.where((norm > 0).reshape((-1,) + (1,) * (q.ndim - 1)), weighted, plain)
        if out.shape[0] == 1:
            out = np.concatenate([out, out], axis=0)
        return np.clip(out, 0.0, 1.0)

    n = 2 if space == "mono" else 3
    return replace(lut, source=f"{lut.source} ({space})", wavelengths_nm=np.arange(n, dtype=np.float64),
                   R_spec=reduce(lut.R_spec), Tbar=round_trip(lut.Tbar), R_diff=reduce(lut.R_diff),
                   rho_bar=reduce(lut.rho_bar), tau_bar=round_trip(lut.tau_bar), R=reduce(lut.R, 0.0, None),
                   mirror_sp=reduce(lut.mirror_sp, None))


def channel_coordinates(si):
    """Per channel of the lane's Spectrum, its coordinate on a table's wavelength axis: the
    wavelengths in spectral variants, the channel index in RGB and mono ones."""
    if mi.is_spectral:
        return si.wavelengths
    return tuple(mi.Float(float(j)) for j in range(3 if mi.is_rgb else 1))
