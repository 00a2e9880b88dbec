"""Reference (numpy) evaluation of the ink-on-paper BRDF from a table (docs/design.md §1).

    f(σ, θ, Δφ) = ( R(σ, θ, Δφ) + r·T̄(σ)·T̄(θ) / (1 − r·ρ̄) ) / π  +  R_spec(σ)·δ(mirror)
    ρ̄ = 2∫ Rbar_below(s) cos s sin s ds

Same interpolation as the plugin (linear in λ, σ, θ, Δφ), for pictures, summaries and tests.
Results have the wavelength axis first.  `paper` is the paper albedo r: a number or a
spectrum sampled on the table's wavelengths.
"""

from __future__ import annotations

import numpy as np

from ..paper import check_paper_albedo
from .eq4 import layer_terms, paper_gain
from .integrals import hemispherical_mean
from .interpolation import lerp_weights
from .schema import InkTable


def column_at(table: InkTable, name: str, polar_rad) -> np.ndarray:
    """A [λ, σ] column interpolated at polar angles: shape (nλ,) + shape(polar_rad)."""
    col = table.column(name)
    i, t = lerp_weights(table.sigma, polar_rad)
    return col[:, i] * (1 - t) + col[:, i + 1] * t


def brdf_R_at(table: InkTable, sigma_rad, theta_rad, dphi_rad) -> np.ndarray:
    """Multilinear R(σ, θ, Δφ) per wavelength; inputs broadcast together."""
    s, th, ph = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (sigma_rad, theta_rad, dphi_rad)))
    i, ti = lerp_weights(table.sigma, s)
    j, tj = lerp_weights(table.theta, th)
    k, tk = lerp_weights(table.dphi, np.abs(ph))
    out = 0.0
    for di, wi in ((0, 1 - ti), (1, ti)):
        for dj, wj in ((0, 1 - tj), (1, tj)):
            for dk, wk in ((0, 1 - tk), (1, tk)):
                out = out + table.R[:, i + di, j + dj, k + dk] * (wi * wj * wk)
    return out


def multiple_reflection_gain(table: InkTable, paper) -> np.ndarray:
    """r / (1 − r·ρ̄) per wavelength: the paper term's interreflection factor."""
    return paper_gain(check_paper_albedo(paper, table.wavelengths), hemispherical_mean(table.sigma, table.Rbar_below))


def diffuse_brdf(table: InkTable, paper, sigma_rad, theta_rad, dphi_rad) -> np.ndarray:
    """π·f without the delta lobe, per wavelength: R + r T̄(σ) T̄(θ)/(1 − r ρ̄)."""
    sigma_rad, theta_rad, dphi_rad = np.broadcast_arrays(sigma_rad, theta_rad, dphi_rad)
    gain = multiple_reflection_gain(table, paper)
    extra = (slice(None),) + (None,) * sigma_rad.ndim
    out = gain[extra] * column_at(table, "Tbar", sigma_rad) * column_at(table, "Tbar", theta_rad)
    if table.has_diffuse:
        out = out + brdf_R_at(table, sigma_rad, theta_rad, dphi_rad)
    return out


def directional_albedo(table: InkTable, paper, polar_rad) -> np.ndarray:
    """Total reflectance (specular + diffuse) for light from `polar_rad`; by reciprocity also
    the brightness seen from `polar_rad` under uniform diffuse light of unit radiance."""
    terms = layer_terms(table)
    gain = terms.gain(check_paper_albedo(paper, table.wavelengths))
    i, t = lerp_weights(table.sigma, polar_rad)
    layer = terms.diffuse_albedo[:, i] * (1 - t) + terms.diffuse_albedo[:, i + 1] * t
    extra = (slice(None),) + (None,) * np.ndim(polar_rad)
    return (column_at(table, "R_spec", polar_rad) + layer
            + (gain * terms.tau_bar)[extra] * column_at(table, "Tbar", polar_rad))
