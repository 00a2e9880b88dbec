"""Printed colour of a halftone as an instrument measures it: a `solver.colour.Measurement`
(geometry, illuminant, observer; 45:0 D50 2° by default, the press's measurement, ISO 13655).

    predict = MeasuredPredictor.build(printed, paper=0.9, geometry=DEFAULT_MEASUREMENT.geometry)
    spectra = predict(coverages)            # coverages [..., k] in [0, 1] → reflectance factor [..., nλ]

The coverage models of `model` (docs/plugin.md, "Printing") with each primary's eq. (4) terms
averaged over the instrument's light L and view V (the weights `Measurement` uses for one table,
so a solid of one ink gives exactly `Measurement.reflectance` of its table):

    Clapper–Yule   A = Σ_S a_S [R̄_S + R_spec,S(V)] + r·[Σ_S a_S T̄_S(L)]·[Σ_S a_S T̄_S(V)] / (1 − r·Σ_S a_S ρ̄_S)
    Murray–Davies  A = Σ_S a_S (R̄_S + R_spec,S(V) + r·T̄_S(L)·T̄_S(V) / (1 − r·ρ̄_S))

where R̄_S is the diffuse lobe R(σ, θ, Δφ) averaged over light L, view V and all azimuths, and
the mirror term R_spec(V) enters only for geometries that see it (d:8:sci, d:0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..paper import PAPER_ALBEDO
from .inkset import PrintedInks
from .model import DEFAULT_COVERAGE_MODEL, check_coverage_model, paper_albedo, primary_weights, smooth_mix
from .optics import primary_optics


@dataclass(frozen=True)
class MeasuredPredictor:
    """Reflectance factor of coverage mixes under one measurement geometry (module docstring)."""

    printed: PrintedInks
    subsets: tuple
    wavelengths_nm: np.ndarray     # [nλ]
    paper: np.ndarray              # r, [nλ]
    coverage_model: str
    layer: np.ndarray              # [nP, nλ]: R̄_S (+ R_spec,S(V) where the geometry sees the mirror)
    t_light: np.ndarray            # [nP, nλ]: T̄_S averaged over the light
    t_view: np.ndarray             # [nP, nλ]: T̄_S averaged over the view
    rho: np.ndarray                # [nP, nλ]: ρ̄_S

    @classmethod
    def build(cls, printed: PrintedInks, paper=PAPER_ALBEDO, geometry=None,
              coverage_model: str = DEFAULT_COVERAGE_MODEL, wavelengths_nm=None) -> "MeasuredPredictor":
        """Precompute every primary's terms for `geometry` (a `solver.colour.measurement.Geometry`;
        default: 45:0)."""
        from ..colour.measurement import DEFAULT, Measurement

        check_coverage_model(coverage_model)
        measurement = Measurement(geometry or DEFAULT.geometry)
        g = measurement.geometry
        optics = primary_optics(printed, printed.primaries(), wavelengths_nm)
        nl = optics.wavelengths_nm.size
        layer, t_light, t_view = [], [], []
        for table in optics.tables:
            if table is None:                               # bare paper
                layer.append(np.zeros(nl))
                t_light.append(np.ones(nl))
                t_view.append(np.ones(nl))
                continue
            measurement.check(table)
            r = np.einsum("lstp,stp->l", table.R, measurement.r_weights(table)) if table.has_diffuse else np.zeros(nl)
            if g.specular:
                r = r + table.R_spec @ g.view.weights(table.sigma)
            layer.append(r)
            t_light.append(table.Tbar @ g.light.weights(table.sigma))
            t_view.append(table.Tbar @ g.view.weights(table.sigma))
        return cls(printed, optics.subsets, optics.wavelengths_nm, paper_albedo(paper, optics.wavelengths_nm),
                   coverage_model, np.stack(layer), np.stack(t_light), np.stack(t_view), optics.rho)

    def __call__(self, coverages) -> np.ndarray:
        """Reflectance factors [..., nλ] of coverages [..., k] (clamped to [0, 1])."""
        _, weights = primary_weights(self.printed, coverages, self.subsets)
        return smooth_mix(self.coverage_model, weights, self.paper, self.layer, self.t_light, self.t_view, self.rho)
