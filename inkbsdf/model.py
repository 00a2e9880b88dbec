"""One ink table's lookups in Dr.Jit, per lane (the quantities of eq. (4), docs/design.md §1).

`InkModel` interpolates, at located coordinates (`interp.Axis.locate`):

    at_incidence(λ, σ) → R_spec(σ), T̄(σ), R_diff(σ) (or None), ρ̄, τ̄
    exit_transmittance(λ, θ) → T̄(θ)                  (the σ-indexed column, one function of angle)
    layer(λ, σ, θ, Δφ) → R(σ, θ, Δφ)                  (tables with a diffuse lobe only)
    mirror(λ, σ) → (b, C, S)                          the mirror beam's Mueller elements besides
                                                      M00 = R_spec (polarized variants only)

σ = polar angle of ωi (toward the light), θ = polar angle of ωo (toward the viewer), both in
Mitsuba's local frame and pointing away from the surface; Δφ = |φi − φo| folded into [0, π]
(π = mirror, 0 = retro-reflection). Spectra are `mi.UnpolarizedSpectrum` (= `mi.Spectrum` in
unpolarized variants; in polarized ones `mi.Spectrum` is a Mueller matrix). How the inks of a
print and the paper combine these is `inkbsdf.mixing`. Every quantity comes from the table at
the lane's wavelengths (clamped to the table's range). Divisions elsewhere use `safe_div`: no lane ever yields NaN or Inf.
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
    n = dr.size_v(mi.UnpolarizedSpectrum)
    total = spectrum[0]
    for j in range(1, n):
        total = total + spectrum[j]
    return total * (1.0 / n)


def spectrum_of(values):
    """Assemble per-wavelength arrays into an (unpolarized) spectrum."""
    return mi.UnpolarizedSpectrum(*values)


def cos_dphi(wi, wo):
    """cos Δφ between the projections of ωi and ωo on the surface (1 where one is vertical)."""
    sin2 = (wi.x * wi.x + wi.y * wi.y) * (wo.x * wo.x + wo.y * wo.y)
    return dr.select(sin2 > 0, (wi.x * wo.x + wi.y * wo.y) * dr.rsqrt(dr.select(sin2 > 0, sin2, 1.0)), 1.0)


@dataclass(frozen=True)
class AtIncidence:
    """One table's Spectrum-valued quantities at the lane's wavelengths and incidence σ."""

    r_spec: object          # R_spec(σ)
    t_in: object            # T̄(σ)
    r_diff: object | None   # R_diff(σ), None for tables without a diffuse lobe
    rho: object             # ρ̄
    tau: object             # τ̄


class InkModel:
    """Dr.Jit lookup tables of one ink, or of several on one grid stacked in one buffer
    (`InkModel.stacked`: each method's `block` picks the table, per lane); built under (and
    used with) one Mitsuba variant.

    In polarized variants a table with s and p amplitudes (`lut.mirror_sp`) also gets the
    mirror beam's Mueller elements (`mirror`, when `has_mirror_sp`)."""

    def __init__(self, lut: InkLUT, stack: tuple = ()):
        luts = stack or (lut,)
        stacked = bool(stack)
        self.has_diffuse = any(l.has_diffuse for l in luts)
        self.lam_axis = Axis(lut.wavelengths_nm)
        self.sig_axis = Axis(lut.sigma_rad)

        def table(columns):
            values = np.stack([columns(l) for l in luts])
            return NodeTable(values if stacked else values[0], stacked=stacked)

        diff = self.has_diffuse
        self.sig_table = table(lambda l: np.stack([l.R_spec, l.Tbar] + ([l.R_diff] if diff else []), axis=-1))
        self.lam_table = table(lambda l: np.stack([l.rho_bar, l.tau_bar], axis=-1))        # [nλ, 2]
        if diff:
            grid = next(l for l in luts if l.has_diffuse)
            self.theta_axis = Axis(grid.theta_rad)
            self.dphi_axis = Axis(grid.dphi_rad)
            zeros = np.zeros_like(grid.R)
            self.R_table = table(lambda l: (l.R if l.has_diffuse else zeros)[..., None])   # [nλ, nσ, nθ, nφ, 1]
        self.has_mirror_sp = bool(mi.is_polarized) and all(l.mirror_sp is not None for l in luts)
        if self.has_mirror_sp:
            self.mirror_table = table(lambda l: l.mirror_sp)                             # [nλ, nσ, 3]

    @classmethod
    def stacked(cls, luts) -> "InkModel":
        """Several tables on one grid (λ, σ; θ, Δφ for those with a diffuse lobe) in one
        buffer each; `block` = the table's position in `luts`."""
        return cls(luts[0], tuple(luts))

    def at_incidence(self, lam, sig, block=0) -> AtIncidence:
        """Quantities at located wavelengths `lam` (one (i, t) per channel) and σ `sig`."""
        n = len(lam)
        cols = [self.sig_table.lerp([lam[j], sig], block=block) for j in range(n)]
        rho_tau = [self.lam_table.lerp([lam[j]], block=block) for j in range(n)]
        return AtIncidence(
            r_spec=spectrum_of([cols[j][0] for j in range(n)]),
            t_in=spectrum_of([cols[j][1] for j in range(n)]),
            r_diff=spectrum_of([cols[j][2] for j in range(n)]) if self.has_diffuse else None,
            rho=spectrum_of([rho_tau[j][0] for j in range(n)]),
            tau=spectrum_of([rho_tau[j][1] for j in range(n)]))

    def exit_transmittance(self, lam, theta, block=0):
        """T̄(θ) at located wavelengths and exit angle θ located on `sig_axis`."""
        return spectrum_of([self.sig_table.lerp([lam[j], theta], channels=(1,), block=block)[0]
                            for j in range(len(lam))])

    def layer(self, lam, sig, theta, dphi, block=0):
        """R(σ, θ, Δφ) (π·f of the layer's diffuse lobe); θ and Δφ located on `theta_axis`,
        `dphi_axis`. Only for tables with a diffuse lobe."""
        return spectrum_of([self.R_table.lerp([lam[j], sig, theta, dphi], block=block)[0]
                            for j in range(len(lam))])

    def mirror(self, lam, sig, block=0):
        """(b, C, S) of the mirror beam's Mueller matrix (`inkbsdf.lut.mirror_mueller`) at
        located wavelengths and σ; each element interpolated like R_spec, so a lerp of pure
        Mueller matrices (a physical, partly depolarising mix). Polarized variants only."""
        cols = [self.mirror_table.lerp([lam[j], sig], block=block) for j in range(len(lam))]
        return tuple(spectrum_of([cols[j][k] for j in range(len(lam))]) for k in range(3))
