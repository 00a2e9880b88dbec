"""Measuring the colour of an ink on paper from its table: a geometry, an illuminant, an observer
(docs/design.md §7). The one home of how a colour is measured: figures, findings, `show`, the
separation of images, `design` and the scenes all name a `Measurement`.

Geometries (the instrument's light and view, ISO 13655 / CIE 15), each giving the reflectance
factor of the print (the perfect diffuser = 1) from the ink-on-paper BRDF of docs/design.md §1,

    π f = R(σ, θ, Δφ) + g·T̄(σ)·T̄(θ) + π R_spec(σ)·δ(mirror),   g = r/(1 − r ρ̄):

    45:0      light in an annular band 45° ± 5° about the normal, view within 5° of the normal:
              the press's measurement (ISO 13655). The mirror reflection goes back into the band,
              away from the detector: the gloss is excluded. R and T̄ are averaged over the two
              cones (cos-weighted, all azimuths), exactly for the tables' linear interpolant.
    d:8:sci   diffuse light (an integrating sphere), view 8°, specular component included
    d:8:sce   … specular component excluded (the coherent mirror beam falls into the gloss trap)
    d:0       diffuse light, view 0°, the layer's mirror included (the glare of a uniform
              surround: the top of the paper's Fig. 6 strip, as this project drew it until now)
    paper     the paper's own strip colour: diffuse light, view 0°, eq. (4) with the layer's
              diffuse light only (its eq. 5 sums the orders m, n ≠ 0): no coherent mirror beam

With diffuse light the reflectance at view θ equals, by reciprocity, the table's directional
albedo at θ. Weighting: ASTM E308 (`cie`); CIELAB relative to the perfect diffuser under the
same illuminant (absolute colorimetry, as ISO 12647-2's aims are stated).

Defaults (`DEFAULT`): 45:0, D50, 2° — how printers measure and state their aims, so that a
number from here can be held against press data; the glare of a surround is a property of
the viewing booth, not of the ink.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..paper import check_paper_albedo
from ..table.eq4 import paper_gain
from ..table.integrals import azimuth_weights, band_weights, cosine_weights, hemispherical_mean
from ..table.interpolation import lerp_weights
from .cie import ColourError, check_illuminant, check_observer, check_range, spectra_to_lab, spectra_to_xyz

#: the table columns a reflectance factor reads (the keywords of `Measurement.reflectance`)
REFLECTANCE_COLUMNS = ("R_spec", "Tbar", "Rbar_below", "R")
DEFAULT_ILLUMINANT = "D50"
DEFAULT_OBSERVER = "2"
#: instrument cones of 45:0 (degrees): illumination band half-width, view cone half-angle
CONE_HALF_ANGLE_DEG = 5.0


@dataclass(frozen=True)
class Polar:
    """How an instrument's light or view is spread over polar angles: a band [lo, hi] (degrees)
    weighted by cos θ dω and averaged over all azimuths, or one direction (lo == hi)."""

    lo_deg: float
    hi_deg: float

    def weights(self, grid_rad) -> np.ndarray:
        """[nσ] weights of the grid's nodes: Σ w f(σ_i) is the mean of the linear interpolant."""
        grid = np.asarray(grid_rad, dtype=float)
        if self.hi_deg > self.lo_deg:
            if self.lo_deg == 0.0 and self.hi_deg == 90.0:
                return cosine_weights(grid)
            return band_weights(grid, np.radians(self.lo_deg), np.radians(self.hi_deg))
        i, t = lerp_weights(grid, np.radians(self.lo_deg))
        w = np.zeros(grid.size)
        w[i] += 1.0 - t
        w[i + 1] += t
        return w

    @property
    def label(self) -> str:
        if self.hi_deg == self.lo_deg:
            return f"{self.lo_deg:g}°"
        return "diffuse" if (self.lo_deg, self.hi_deg) == (0.0, 90.0) else f"{self.lo_deg:g}–{self.hi_deg:g}°"


HEMISPHERE = Polar(0.0, 90.0)


@dataclass(frozen=True)
class Geometry:
    """A measurement geometry: its light, its view, and whether the coherent mirror beam
    reaches the detector (only possible with diffuse light)."""

    name: str
    light: Polar
    view: Polar
    specular: bool
    description: str

    def __post_init__(self):
        if self.specular and self.light != HEMISPHERE:
            raise ValueError(f"{self.name}: the mirror beam reaches the view only under diffuse light")


_c = CONE_HALF_ANGLE_DEG
GEOMETRIES = {g.name: g for g in (
    Geometry("45:0", Polar(45.0 - _c, 45.0 + _c), Polar(0.0, _c), False,
             "light 45° annular, view 0° (ISO 13655; gloss excluded)"),
    Geometry("d:8:sci", HEMISPHERE, Polar(8.0, 8.0), True, "diffuse light, view 8°, specular included"),
    Geometry("d:8:sce", HEMISPHERE, Polar(8.0, 8.0), False, "diffuse light, view 8°, specular excluded"),
    Geometry("d:0", HEMISPHERE, Polar(0.0, 0.0), True, "diffuse light, view 0°, the layer's mirror included"),
    Geometry("paper", HEMISPHERE, Polar(0.0, 0.0), False,
             "the paper's strip: diffuse light, view 0°, the layer's diffuse light (no coherent mirror)"),
)}
DEFAULT_GEOMETRY = "45:0"


@dataclass(frozen=True)
class Measurement:
    """A colour measurement: geometry, illuminant, observer."""

    geometry: Geometry
    illuminant: str = DEFAULT_ILLUMINANT
    observer: str = DEFAULT_OBSERVER

    @property
    def label(self) -> str:
        """'45:0/D50/2°': how CSVs and reports name it; parse_measurement reads it back."""
        return f"{self.geometry.name}/{self.illuminant}/{self.observer}°"

    # ---------------------------------------------------------------- spectra
    def check_grids(self, wavelengths_nm, sigma_rad, what: str = "the table") -> None:
        """ColourError when grids (of a table, or of a request before it is built) lack the
        wavelengths or angles this measurement needs, naming their range."""
        check_range(wavelengths_nm, what)
        sigma_deg = np.degrees([sigma_rad[0], sigma_rad[-1]])
        for part, polar in (("light", self.geometry.light), ("view", self.geometry.view)):
            if polar.lo_deg < sigma_deg[0] - 1e-9 or polar.hi_deg > sigma_deg[1] + 1e-9:
                raise ColourError(f"geometry {self.geometry.name} needs {part} angles {polar.label}; {what} "
                                  f"holds {sigma_deg[0]:g}–{sigma_deg[1]:g}°")

    def check(self, table) -> None:
        """ColourError when the table lacks the wavelengths or angles this measurement needs."""
        self.check_grids(table.wavelengths, table.sigma, f"the table ({table.meta.get('ink', 'ink')})")

    def r_weights(self, table) -> np.ndarray:
        """[nσ, nθ, nφ]: the diffuse lobe's share of the reflectance factor is Σ w·R[λ] (linear)."""
        return _r_weights(self.geometry, tuple(table.sigma), tuple(table.theta), tuple(table.dphi))

    def reflectance(self, table, paper, *, R_spec=None, Tbar=None, Rbar_below=None, R=None) -> np.ndarray:
        """[nλ] reflectance factor of the ink on paper of albedo `paper` (a number or a spectrum on
        the table's wavelengths). The keyword columns replace the table's (error propagation)."""
        g = self.geometry
        R_spec = table.R_spec if R_spec is None else R_spec
        Tbar = table.Tbar if Tbar is None else Tbar
        Rbar_below = table.Rbar_below if Rbar_below is None else Rbar_below
        R = table.R if R is None else R
        r = check_paper_albedo(paper, table.wavelengths)
        gain = paper_gain(r, hemispherical_mean(table.sigma, Rbar_below))
        out = gain * (Tbar @ g.light.weights(table.sigma)) * (Tbar @ g.view.weights(table.sigma))
        if table.has_diffuse or R is not table.R:
            out = out + np.einsum("lstp,stp->l", R, self.r_weights(table))
        if g.specular:
            out = out + R_spec @ g.view.weights(table.sigma)
        return out

    # ------------------------------------------------------------------ colour
    def xyz(self, wavelengths_nm, spectra, axis: int = -1) -> np.ndarray:
        return spectra_to_xyz(wavelengths_nm, spectra, self.illuminant, self.observer, axis)

    def lab_of_spectra(self, wavelengths_nm, spectra, axis: int = -1) -> np.ndarray:
        """CIELAB of reflectance spectra relative to the perfect diffuser under this illuminant."""
        return spectra_to_lab(wavelengths_nm, spectra, self.illuminant, self.observer, axis)

    def lab(self, table, paper) -> np.ndarray:
        """CIELAB (L*, a*, b*) of the ink on paper."""
        self.check(table)
        return self.lab_of_spectra(table.wavelengths, self.reflectance(table, paper))


@lru_cache(maxsize=64)
def _r_weights(geometry: Geometry, sigma: tuple, theta: tuple, dphi: tuple) -> np.ndarray:
    w_phi = azimuth_weights(np.asarray(dphi))
    return np.einsum("s,t,p->stp", geometry.light.weights(sigma), geometry.view.weights(theta), w_phi / w_phi.sum())


def parse_geometry(name: str) -> Geometry:
    key = str(name).strip().lower()
    if key not in GEOMETRIES:
        raise ColourError(f"geometry {name!r}: choose one of {', '.join(GEOMETRIES)}")
    return GEOMETRIES[key]


def parse_measurement(geometry: str = DEFAULT_GEOMETRY, illuminant: str = DEFAULT_ILLUMINANT,
                      observer: str = DEFAULT_OBSERVER) -> Measurement:
    """A Measurement from its three names (each checked: one line listing the valid ones)."""
    return Measurement(parse_geometry(geometry), check_illuminant(illuminant), check_observer(observer))


def from_label(label: str) -> Measurement:
    """The Measurement a label ('45:0/D50/2°') names."""
    parts = str(label).split("/")
    if len(parts) != 3:
        raise ColourError(f"measurement {label!r}: expected GEOMETRY/ILLUMINANT/OBSERVER, e.g. 45:0/D50/2°")
    return parse_measurement(*parts)


DEFAULT = parse_measurement()
