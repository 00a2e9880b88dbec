"""The ink-on-paper BRDF of DESIGN.md §1, evaluated per lane in Dr.Jit.

    f(ωi, ωo) = c·[ (R(σ, θ, Δφ) + r·T̄(σ)·T̄(θ)/(1 − r·ρ̄)) / π + R_spec(σ)·δ(mirror) ] + (1 − c)·r/π

σ = polar angle of ωi (toward the light), θ = polar angle of ωo (toward the viewer), both in
Mitsuba's local frame and pointing away from the surface; Δφ = |φi − φo| folded into [0, π]
(π = mirror, 0 = retro-reflection). c = coverage, r = paper albedo, per lane; every other
quantity comes from the table at the lane's wavelengths (clamped to the table's range).

`InkModel.incident` computes everything that depends on ωi only (one σ lookup); `diffuse`
adds what depends on ωo. Divisions are guarded so that no lane ever yields NaN or Inf.
"""

from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .interp import Axis, NodeTable
from .lut import InkLUT


def safe_div(num, den):
    """num/den where den > 0, else 0 (no NaN/Inf in either branch, AD-safe)."""
    ok = den > 0
    return dr.select(ok, num / dr.select(ok, den, 1.0), 0.0)


def lane_mean(spectrum):
    """Mean over the lane's wavelengths (explicit: dr.mean's axis differs between variants)."""
    n = dr.size_v(mi.Spectrum)
    total = spectrum[0]
    for j in range(1, n):
        total = total + spectrum[j]
    return total * (1.0 / n)


def spectrum_of(values):
    """Assemble per-wavelength arrays into a Spectrum."""
    return mi.Spectrum(*values)


def cos_dphi(wi, wo):
    """cos Δφ between the projections of ωi and ωo on the surface (1 where one is vertical)."""
    sin2 = (wi.x * wi.x + wi.y * wi.y) * (wo.x * wo.x + wo.y * wo.y)
    return dr.select(sin2 > 0, (wi.x * wo.x + wi.y * wo.y) * dr.rsqrt(dr.select(sin2 > 0, sin2, 1.0)), 1.0)


@dataclass(frozen=True)
class Incident:
    """Per-lane quantities fixed by ωi, the wavelengths, coverage c and paper albedo r."""

    lam: tuple          # located wavelength per Spectrum channel: ((i, t), ...)
    sig: tuple          # located σ: (i, t)
    front: object       # Bool: ωi above the surface
    coupling: object    # Spectrum: c·r·T̄(σ)/(π(1 − r·ρ̄)), multiplies T̄(θ)
    paper: object       # Spectrum: (1 − c)·r/π
    specular: object    # Spectrum: c·R_spec(σ), weight of the delta lobe
    albedo_diffuse: object  # Spectrum: ∫ (smooth part of f) cos θo dωo
    coverage: object    # Float c


class InkModel:
    """Dr.Jit lookup tables of one ink; built under (and used with) one Mitsuba variant."""

    def __init__(self, lut: InkLUT):
        self.has_diffuse = lut.has_diffuse
        self.lam_axis = Axis(lut.wavelengths_nm)
        self.sig_axis = Axis(lut.sigma_rad)
        cols = [lut.R_spec, lut.Tbar] + ([lut.R_diff] if self.has_diffuse else [])
        self.sig_table = NodeTable(np.stack(cols, axis=-1))               # [nλ, nσ, 2|3]
        self.lam_table = NodeTable(np.stack([lut.rho_bar, lut.tau_bar], axis=-1))   # [nλ, 2]
        if self.has_diffuse:
            self.theta_axis = Axis(lut.theta_rad)
            self.dphi_axis = Axis(lut.dphi_rad)
            self.R_table = NodeTable(lut.R[..., None])                    # [nλ, nσ, nθ, nφ, 1]

    def incident(self, wi, wavelengths, coverage, paper) -> Incident:
        """Everything that depends on ωi only; `paper` is a Spectrum, `coverage` a Float."""
        c, r = coverage, paper
        cos_i = mi.Frame3f.cos_theta(wi)
        sig = self.sig_axis.locate(dr.safe_acos(cos_i))
        n = dr.size_v(mi.Spectrum)
        lam = tuple(self.lam_axis.locate(wavelengths[j]) for j in range(n))
        cols = [self.sig_table.lerp([lam[j], sig]) for j in range(n)]
        rho_tau = [self.lam_table.lerp([lam[j]]) for j in range(n)]
        r_spec = spectrum_of([cols[j][0] for j in range(n)])
        t_in = spectrum_of([cols[j][1] for j in range(n)])
        rho = spectrum_of([rho_tau[j][0] for j in range(n)])
        tau = spectrum_of([rho_tau[j][1] for j in range(n)])
        # r·T̄(σ)/(1 − r·ρ̄): the paper's multiple bounces under the layer (ρ̄ < 1 unless lossless
        # and totally reflecting, which no table has; guarded anyway).
        through = safe_div(r * t_in, 1.0 - r * rho)
        albedo_diffuse = c * (through * tau) + (1.0 - c) * r
        if self.has_diffuse:
            albedo_diffuse += c * spectrum_of([cols[j][2] for j in range(n)])
        return Incident(lam=lam, sig=sig, front=cos_i > 0,
                        coupling=c * through * dr.inv_pi, paper=(1.0 - c) * r * dr.inv_pi,
                        specular=c * r_spec, albedo_diffuse=albedo_diffuse, coverage=c)

    def spec_probability(self, inc: Incident):
        """Probability of sampling the delta lobe: mean_λ(c·R_spec) / mean_λ(total albedo)."""
        spec = lane_mean(inc.specular)
        return safe_div(spec, spec + lane_mean(inc.albedo_diffuse))

    def diffuse(self, inc: Incident, wi, wo):
        """Smooth part of f(ωi, ωo)·cos θo (Spectrum); zero unless both directions are above."""
        cos_o = mi.Frame3f.cos_theta(wo)
        theta_o = dr.safe_acos(cos_o)
        theta = self.sig_axis.locate(theta_o)
        n = dr.size_v(mi.Spectrum)
        t_out = spectrum_of([self.sig_table.lerp([inc.lam[j], theta], channels=(1,))[0]
                             for j in range(n)])
        f = inc.coupling * t_out + inc.paper
        if self.has_diffuse:
            loc_t = self.theta_axis.locate(theta_o)
            loc_p = self.dphi_axis.locate(dr.safe_acos(cos_dphi(wi, wo)))
            layer = spectrum_of([self.R_table.lerp([inc.lam[j], inc.sig, loc_t, loc_p])[0]
                                 for j in range(n)])
            f += inc.coverage * dr.inv_pi * layer
        valid = inc.front & (cos_o > 0)
        return dr.select(valid, f * cos_o, 0.0)
