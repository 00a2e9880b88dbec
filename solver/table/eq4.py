"""The pieces of the paper's eq. (4) (docs/design.md §1) that a table gives, in one home:

    ρ̄ = 2∫ Rbar_below(s) cos s sin s ds      the layer's reflectance seen from the paper
    τ̄ = 2∫ Tbar(s) cos s sin s ds            its transmittance, cosine mean
    R_diff(σ) = ∫ R(σ, θ, Δφ) cos θ dω / π    the diffuse lobe's directional albedo
    g = r / (1 − r·ρ̄)                        the paper term's interreflection gain

so that f = [R + g·T̄(σ)·T̄(θ)]/π + R_spec·δ. Every angular integral is exact for the tables'
linear interpolant (`integrals`), so a lossless layer on white paper reflects exactly 1. The
reference evaluator, the colour measurement, the print model and the plugin's precomputation
all take these from here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .integrals import diffuse_albedo, hemispherical_mean


def paper_gain(paper, rho_bar) -> np.ndarray:
    """g = r/(1 − r ρ̄): light reaching the paper, bouncing between paper and layer (r a checked
    albedo, ρ̄ < 1)."""
    return paper / (1.0 - paper * rho_bar)


@dataclass(frozen=True)
class LayerTerms:
    rho_bar: np.ndarray          # [nλ]
    tau_bar: np.ndarray          # [nλ]
    diffuse_albedo: np.ndarray   # [nλ, nσ]: R_diff per incidence (zeros without a diffuse lobe)

    def gain(self, paper) -> np.ndarray:
        return paper_gain(paper, self.rho_bar)


def layer_terms(table) -> LayerTerms:
    """ρ̄, τ̄ and R_diff of a table."""
    rdiff = (diffuse_albedo(table.theta, table.dphi, table.R) if table.has_diffuse
             else np.zeros_like(np.asarray(table.R_spec, dtype=np.float64)))
    return LayerTerms(hemispherical_mean(table.sigma, table.Rbar_below), hemispherical_mean(table.sigma, table.Tbar),
                      np.asarray(rdiff, dtype=np.float64))
