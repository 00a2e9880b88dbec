"""What a layer's geometry is made of: particle shape, size, orientation, clustering, rough top.

`parse_particles` reads the CLI / table strings (DESIGN.md §2–§3):

    molecular                    -> None (homogeneous layer, no geometry)
    sphere:300                   spheres of diameter 300 nm
    sphere:100:agglutinated      attraction of the default strength (AGGLUTINATED_DEFAULT_KT)
    sphere:100:agglutinated=2.5  attraction well depth 2.5 kT
    sphere:300:rough             particles may stand out of the binder top (ROUGH_DEFAULT)
    sphere:300:spread=0.2        log-normal diameters, σ = 0.2 (median = the given diameter)
    cylinder:200:inplane         cylinders of *effective* diameter 200 nm (sphere of equal volume),
                                 length 6 radii; orientation isotropic | inplane | vertical
    cylinder:300:vertical:tilt=15   axes spread uniformly over the cone of half-angle 15° about
                                 the vertical (inplane: elevation within ±15° of the layer plane)

Lengths are in nm.  `ParticleSpec.label` is the canonical string (every default written out),
stable for use as a cache key: parse_particles(spec.label) == spec.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

from solver.inks import Ink

SHAPES = ("sphere", "cylinder")
ORIENTATIONS = ("isotropic", "inplane", "vertical")
MOLECULAR_WORDS = ("molecular", "infinitesimal", "none")

#: Well depth of the inter-particle attraction (in units of kT) meant by the bare keyword
#: `agglutinated`: 100-nm spheres at 15 % then gather into strands and clumps with voids,
#: obvious in sections (docs/geometry.md has the cluster statistic against the strength).
AGGLUTINATED_DEFAULT_KT = 6.0
#: Largest fraction of a particle's height that may stand above the flat binder top, meant by
#: the bare keyword `rough` (each particle draws its own limit uniformly in [0, this]).
ROUGH_DEFAULT = 0.5
#: Cylinder length in radii (the paper's cylinders).
CYLINDER_LENGTH_RADII = 6.0
#: Log-normal diameters are truncated at this many σ from the median.
SPREAD_TRUNCATION_SIGMA = 3.0
#: Orientations that take an orientation spread (`tilt=`).
TILTED_ORIENTATIONS = ("inplane", "vertical")


class ParticleSpecError(ValueError):
    """A malformed or unphysical particle description."""


class GeometryError(ValueError):
    """A layer that cannot be built (sizes, cell, concentration)."""


class UnreachableConcentrationError(GeometryError):
    """The requested pigment concentration is beyond what the packer reaches."""

    def __init__(self, message: str, limit: float):
        super().__init__(message)
        self.limit = limit


def _fmt(value: float) -> str:
    return f"{value:.6g}"


@dataclass(frozen=True)
class ParticleSpec:
    """One kind of pigment grain (all populations of an ink share it).

    diameter_nm: sphere diameter, or a cylinder's effective diameter (sphere of equal volume);
    the median diameter when size_spread > 0.
    orientation: cylinders only ('isotropic', 'inplane', 'vertical'); None for spheres.
    agglutination_kT: attraction well depth in kT (0 = none).
    rough_top: 0 = flat binder top; p in (0, 1) = a particle may stand out of the binder's top
    surface by up to this fraction of its height.
    size_spread: σ of ln(diameter) (0 = all equal).
    tilt_rad: orientation spread of aligned cylinders (radians, 0 ≤ tilt < π/2): vertical axes
    are uniform on the cap within tilt of the vertical, in-plane axes uniform on the band within
    tilt of the layer plane (`shapes.sample_orientations`); 0 = exactly aligned.
    """

    shape: str
    diameter_nm: float
    orientation: str | None = None
    agglutination_kT: float = 0.0
    rough_top: float = 0.0
    size_spread: float = 0.0
    tilt_rad: float = 0.0

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ParticleSpecError(f"unknown particle shape {self.shape!r}: expected one of {', '.join(SHAPES)}")
        if not (isinstance(self.diameter_nm, numbers.Real) and math.isfinite(self.diameter_nm)):
            raise ParticleSpecError(f"particle diameter must be a number of nm, got {self.diameter_nm!r}")
        if self.diameter_nm <= 0:
            raise ParticleSpecError(f"particle diameter must be positive, got {_fmt(self.diameter_nm)} nm")
        if self.shape == "cylinder":
            if self.orientation is None:
                object.__setattr__(self, "orientation", "isotropic")
            if self.orientation not in ORIENTATIONS:
                raise ParticleSpecError(f"unknown cylinder orientation {self.orientation!r}: expected one of "
                                        + ", ".join(ORIENTATIONS))
        elif self.orientation is not None:
            raise ParticleSpecError(f"orientation {self.orientation!r} applies to cylinders only, not spheres")
        if not (0.0 <= self.agglutination_kT < math.inf):
            raise ParticleSpecError(f"agglutination strength must be >= 0 kT, got {self.agglutination_kT!r}")
        if not (0.0 <= self.rough_top < 1.0):
            raise ParticleSpecError(f"rough top must be a protruding fraction in [0, 1), got {self.rough_top!r}")
        if not (0.0 <= self.size_spread <= 1.0):
            raise ParticleSpecError(f"size spread (log-normal sigma) must be in [0, 1], got {self.size_spread!r}")
        if not (isinstance(self.tilt_rad, numbers.Real) and 0.0 <= self.tilt_rad < 0.5 * math.pi):
            shown = _fmt(math.degrees(self.tilt_rad)) if isinstance(self.tilt_rad, numbers.Real) else repr(self.tilt_rad)
            raise ParticleSpecError(f"orientation spread tilt must be in [0, 90) degrees, got {shown}")
        if self.tilt_rad > 0 and self.orientation not in TILTED_ORIENTATIONS:
            raise ParticleSpecError(
                f"tilt (orientation spread) applies to inplane or vertical cylinders only, not to "
                f"{'spheres' if self.shape == 'sphere' else self.orientation + ' ones'}: drop 'tilt=' or use "
                "'cylinder:D:vertical:tilt=DEG' / 'cylinder:D:inplane:tilt=DEG'")

    @property
    def label(self) -> str:
        """Canonical spec string, every parameter written out (cache key)."""
        parts = [self.shape, _fmt(self.diameter_nm)]
        if self.orientation is not None:
            parts.append(self.orientation)
        if self.agglutination_kT > 0:
            parts.append(f"agglutinated={_fmt(self.agglutination_kT)}")
        if self.rough_top > 0:
            parts.append(f"rough={_fmt(self.rough_top)}")
        if self.size_spread > 0:
            parts.append(f"spread={_fmt(self.size_spread)}")
        if self.tilt_rad > 0:
            parts.append(f"tilt={_fmt(self.tilt_deg)}")
        return ":".join(parts)

    @property
    def tilt_deg(self) -> float:
        """Orientation spread in degrees (the spec string's unit)."""
        return math.degrees(self.tilt_rad)

    @property
    def max_diameter_nm(self) -> float:
        """Largest (effective) diameter drawn, after truncation of the log-normal spread."""
        return self.diameter_nm * math.exp(SPREAD_TRUNCATION_SIGMA * self.size_spread)


def cylinder_radius_length(effective_diameter_nm):
    """Radius and length (nm) of a cylinder of length 6 radii with the volume of a sphere of
    the given diameter: π r²·6r = π D³/6  ⇒  r = D / 36^(1/3)."""
    radius = effective_diameter_nm / (6.0 * CYLINDER_LENGTH_RADII) ** (1.0 / 3.0)
    return radius, CYLINDER_LENGTH_RADII * radius


def polar_range_rad(spec: ParticleSpec) -> tuple[float, float]:
    """Range of the angle between a cylinder's axis and the vertical allowed by its orientation."""
    return {"vertical": (0.0, spec.tilt_rad), "inplane": (0.5 * math.pi - spec.tilt_rad, 0.5 * math.pi),
            "isotropic": (0.0, 0.5 * math.pi)}[spec.orientation]


def cylinder_height_nm(radius_nm: float, length_nm: float, polar_rad: float) -> float:
    """Vertical extent (nm) of a cylinder whose axis makes the angle polar_rad with the vertical."""
    return length_nm * abs(math.cos(polar_rad)) + 2.0 * radius_nm * abs(math.sin(polar_rad))


def max_z_extent_nm(spec: ParticleSpec, diameter_nm: float) -> float:
    """Largest height (nm) a particle of this (effective) diameter can take in its orientation mode."""
    if spec.shape == "sphere":
        return diameter_nm
    r, length = cylinder_radius_length(diameter_nm)
    lo, hi = polar_range_rad(spec)
    peak = math.atan2(2.0 * r, length)                 # the extent L cos θ + 2r sin θ peaks here
    if lo <= peak <= hi:
        return math.hypot(length, 2.0 * r)
    return max(cylinder_height_nm(r, length, lo), cylinder_height_nm(r, length, hi))


def bounding_diameter_nm(spec: ParticleSpec, diameter_nm: float) -> float:
    """Diameter of the sphere enclosing a particle of this (effective) diameter."""
    if spec.shape == "sphere":
        return diameter_nm
    r, length = cylinder_radius_length(diameter_nm)
    return math.hypot(length, 2 * r)


def _number(text: str, what: str, spec: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ParticleSpecError(f"bad {what} {text!r} in particle spec {spec!r}: expected a number") from None
    if not math.isfinite(value):
        raise ParticleSpecError(f"bad {what} {text!r} in particle spec {spec!r}")
    return value


def parse_particles(text: str) -> ParticleSpec | None:
    """Parse a particle spec string; None for a molecular (homogeneous) layer."""
    if not isinstance(text, str) or not text.strip():
        raise ParticleSpecError("empty particle spec: expected e.g. 'molecular', 'sphere:100', "
                                "'sphere:100:agglutinated', 'cylinder:200:inplane'")
    spec = text.strip()
    if spec.lower() in MOLECULAR_WORDS:
        return None
    tokens = [t.strip() for t in spec.split(":")]
    shape = tokens[0].lower()
    if shape not in SHAPES:
        raise ParticleSpecError(f"unknown particle shape {tokens[0]!r} in {spec!r}: expected "
                                + ", ".join(SHAPES + ("molecular",)))
    if len(tokens) < 2 or not tokens[1]:
        raise ParticleSpecError(f"particle spec {spec!r} lacks a diameter in nm, e.g. '{shape}:100'")
    diameter = _number(tokens[1].removesuffix("nm"), "diameter", spec)
    if diameter < 0:
        raise ParticleSpecError(f"negative particle size {_fmt(diameter)} nm in {spec!r}")
    kwargs: dict = {}
    for token in tokens[2:]:
        key, _, value = token.partition("=")
        key = key.strip().lower()
        if key in ORIENTATIONS and not value:
            if "orientation" in kwargs:
                raise ParticleSpecError(f"two orientations in particle spec {spec!r}")
            kwargs["orientation"] = key
        elif key in ("agglutinated", "agglutination"):
            kwargs["agglutination_kT"] = (_number(value, "agglutination strength", spec) if value
                                          else AGGLUTINATED_DEFAULT_KT)
        elif key == "rough":
            kwargs["rough_top"] = _number(value, "rough-top fraction", spec) if value else ROUGH_DEFAULT
        elif key == "spread":
            kwargs["size_spread"] = _number(value, "size spread", spec) if value else 0.0
        elif key == "tilt":
            if not value:
                raise ParticleSpecError(f"'tilt' in {spec!r} needs a value in degrees, e.g. 'tilt=15'")
            kwargs["tilt_rad"] = math.radians(_number(value.removesuffix("deg"), "tilt", spec))
        elif key in ("orientation", "orient") and value:
            kwargs["orientation"] = value.strip().lower()
        else:
            raise ParticleSpecError(
                f"unknown particle modifier {token!r} in {spec!r}: expected an orientation ("
                + ", ".join(ORIENTATIONS) + "), 'agglutinated[=kT]', 'rough[=fraction]', 'spread=sigma' "
                "or 'tilt=degrees'")
    return ParticleSpec(shape, diameter, **kwargs)


@dataclass(frozen=True)
class LayerSpec:
    """One ink layer: binder slab 0 ≤ z ≤ thickness_nm (z down, light from z < 0), periodic in
    x and y with period cell_nm, holding the ink's pigments as particles of one kind."""

    ink: Ink
    particles: ParticleSpec
    thickness_nm: float = 1000.0
    cell_nm: tuple[float, float] = field(default=(2000.0, 2000.0))

    def __post_init__(self):
        if not isinstance(self.particles, ParticleSpec):
            raise GeometryError("a layer with geometry needs particles (a molecular ink has no geometry: "
                                "use the homogeneous-layer path instead)")
        cell = tuple(float(c) for c in (self.cell_nm if hasattr(self.cell_nm, "__len__") else (self.cell_nm,) * 2))
        if len(cell) != 2 or min(cell) <= 0 or not all(map(math.isfinite, cell)):
            raise GeometryError(f"cell must be two positive lengths in nm, got {self.cell_nm!r}")
        object.__setattr__(self, "cell_nm", cell)
        if not (self.thickness_nm > 0 and math.isfinite(self.thickness_nm)):
            raise GeometryError(f"layer thickness must be positive, got {self.thickness_nm!r} nm")
        spec = self.particles
        dmax = spec.max_diameter_nm
        height = max_z_extent_nm(spec, dmax)
        if height > self.thickness_nm:
            what = "particle" if spec.size_spread == 0 else f"largest particle ({_fmt(dmax)} nm at 3σ)"
            raise GeometryError(
                f"{what} {spec.label} is {_fmt(height)} nm high in its orientation, larger than the "
                f"layer ({_fmt(self.thickness_nm)} nm)")
        span = bounding_diameter_nm(spec, dmax)
        if span >= 0.5 * min(cell):
            raise GeometryError(
                f"particle {spec.label} spans {_fmt(span)} nm, too large for a {_fmt(cell[0])}x{_fmt(cell[1])} nm "
                "cell (needs less than half the cell side)")

    @property
    def label(self) -> str:
        return (f"{self.ink.label}|{self.particles.label}|H={_fmt(self.thickness_nm)}"
                f"|L={_fmt(self.cell_nm[0])}x{_fmt(self.cell_nm[1])}")
