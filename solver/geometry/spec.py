"""What a layer's geometry is made of: particle shape, size, orientation, clustering, rough top.

`parse_particles` reads the CLI / table strings (docs/design.md §2–§3):

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
    spheroid:200:aspect=0.25:vertical   oblate spheroids (flakes, axis ratio 0.25) of effective
                                 diameter 200 nm, lying flat (their axes vertical)

The first word names the shape (`shapes.SHAPES`; PARTICLE_GRAMMAR lists each one's fragment);
the shape reads its own modifiers.  Lengths are in nm.  `ParticleSpec.label` is the canonical
string (every default written out), stable for use as a cache key: parse_particles(spec.label) == spec.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

from solver.inks import Ink

from .grammar import ParticleSpecError, fmt, parse_number
from .orientation import ORIENTATIONS, TILTED_ORIENTATIONS, polar_range_rad
from .shapes import SHAPES, Shape, oriented_plurals, shape_class

MOLECULAR_WORDS = ("molecular", "infinitesimal", "none")

#: Well depth of the inter-particle attraction (in units of kT) meant by the bare keyword
#: `agglutinated`: 100-nm spheres at 15 % then gather into strands and clumps with voids,
#: obvious in sections (docs/geometry.md has the cluster statistic against the strength).
AGGLUTINATED_DEFAULT_KT = 6.0
#: Largest fraction of a particle's height that may stand above the flat binder top, meant by
#: the bare keyword `rough` (each particle draws its own limit uniformly in [0, this]).
ROUGH_DEFAULT = 0.5
#: Log-normal diameters are truncated at this many σ from the median.
SPREAD_TRUNCATION_SIGMA = 3.0
#: The modifiers every shape takes, after its own fragment.
COMMON_GRAMMAR = "[:agglutinated[=kT]][:rough[=f]][:spread=σ]"
#: The particle specs `--particles` takes (build, paper's columns, geometry): each shape's
#: fragment, then the common modifiers.
PARTICLE_GRAMMAR = "(" + " | ".join(shape.grammar for shape in SHAPES.values()) + ")" + COMMON_GRAMMAR
#: What the grammar's symbols mean (help texts).
PARTICLE_GRAMMAR_KEY = "; ".join(
    ["D: diameter in nm (of the sphere of equal volume: the effective diameter)",
     "orientation of the symmetry axis, isotropic by default", "tilt: orientation spread of aligned axes, degrees"]
    + [shape.grammar_key for shape in SHAPES.values() if shape.grammar_key]
    + ["σ of ln D", "kT well depth", "f protruding fraction"])


class GeometryError(ValueError):
    """A layer that cannot be built (sizes, cell, concentration)."""


class UnreachableConcentrationError(GeometryError):
    """The requested pigment concentration is beyond what the packer reaches."""

    def __init__(self, message: str, limit: float):
        super().__init__(message)
        self.limit = limit


@dataclass(frozen=True)
class ParticleSpec:
    """One kind of pigment grain (all populations of an ink share it).

    shape: a `Shape` (its name is accepted and means the shape with its defaults).
    diameter_nm: sphere diameter, or the effective diameter (sphere of equal volume) of other
    shapes; the median diameter when size_spread > 0.
    orientation: of the symmetry axis of shapes that have one ('isotropic', 'inplane',
    'vertical'; isotropic by default); None for spheres.
    agglutination_kT: attraction well depth in kT (0 = none).
    rough_top: 0 = flat binder top; p in (0, 1) = a particle may stand out of the binder's top
    surface by up to this fraction of its height.
    size_spread: σ of ln(diameter) (0 = all equal).
    tilt_rad: orientation spread of aligned axes (radians, 0 ≤ tilt < π/2): vertical axes
    are uniform on the cap within tilt of the vertical, in-plane axes uniform on the band within
    tilt of the layer plane (`orientation.sample_orientations`); 0 = exactly aligned.
    """

    shape: Shape
    diameter_nm: float
    orientation: str | None = None
    agglutination_kT: float = 0.0
    rough_top: float = 0.0
    size_spread: float = 0.0
    tilt_rad: float = 0.0

    def __post_init__(self):
        if isinstance(self.shape, str):
            object.__setattr__(self, "shape", shape_class(self.shape)())
        if not isinstance(self.shape, Shape):
            raise ParticleSpecError(f"unknown particle shape {self.shape!r}: expected one of {', '.join(SHAPES)}")
        if not (isinstance(self.diameter_nm, numbers.Real) and math.isfinite(self.diameter_nm)):
            raise ParticleSpecError(f"particle diameter must be a number of nm, got {self.diameter_nm!r}")
        if self.diameter_nm <= 0:
            raise ParticleSpecError(f"particle diameter must be positive, got {fmt(self.diameter_nm)} nm")
        if self.shape.oriented:
            if self.orientation is None:
                object.__setattr__(self, "orientation", "isotropic")
            if self.orientation not in ORIENTATIONS:
                raise ParticleSpecError(f"unknown {self.shape.name} orientation {self.orientation!r}: expected one of "
                                        + ", ".join(ORIENTATIONS))
        elif self.orientation is not None:
            raise ParticleSpecError(f"orientation {self.orientation!r} applies to {oriented_plurals()} only, "
                                    f"not {self.shape.plural}")
        if not (0.0 <= self.agglutination_kT < math.inf):
            raise ParticleSpecError(f"agglutination strength must be >= 0 kT, got {self.agglutination_kT!r}")
        if not (0.0 <= self.rough_top < 1.0):
            raise ParticleSpecError(f"rough top must be a protruding fraction in [0, 1), got {self.rough_top!r}")
        if not (0.0 <= self.size_spread <= 1.0):
            raise ParticleSpecError(f"size spread (log-normal sigma) must be in [0, 1], got {self.size_spread!r}")
        if not (isinstance(self.tilt_rad, numbers.Real) and 0.0 <= self.tilt_rad < 0.5 * math.pi):
            shown = fmt(math.degrees(self.tilt_rad)) if isinstance(self.tilt_rad, numbers.Real) else repr(self.tilt_rad)
            raise ParticleSpecError(f"orientation spread tilt must be in [0, 90) degrees, got {shown}")
        if self.tilt_rad > 0 and self.orientation not in TILTED_ORIENTATIONS:
            example = self.shape.name if self.shape.oriented else next(n for n, s in SHAPES.items() if s.oriented)
            raise ParticleSpecError(
                f"tilt (orientation spread) applies to inplane or vertical {oriented_plurals()} only, not to "
                f"{self.shape.plural if not self.shape.oriented else self.orientation + ' ones'}: drop 'tilt=' or "
                f"use '{example}:D:vertical:tilt=DEG' / '{example}:D:inplane:tilt=DEG'")

    @property
    def label(self) -> str:
        """Canonical spec string, every parameter written out (cache key)."""
        parts = [self.shape.name, fmt(self.diameter_nm), *self.shape.label_parts()]
        if self.orientation is not None:
            parts.append(self.orientation)
        if self.agglutination_kT > 0:
            parts.append(f"agglutinated={fmt(self.agglutination_kT)}")
        if self.rough_top > 0:
            parts.append(f"rough={fmt(self.rough_top)}")
        if self.size_spread > 0:
            parts.append(f"spread={fmt(self.size_spread)}")
        if self.tilt_rad > 0:
            parts.append(f"tilt={fmt(self.tilt_deg)}")
        return ":".join(parts)

    @property
    def tilt_deg(self) -> float:
        """Orientation spread in degrees (the spec string's unit)."""
        return math.degrees(self.tilt_rad)

    @property
    def max_diameter_nm(self) -> float:
        """Largest (effective) diameter drawn, after truncation of the log-normal spread."""
        return self.diameter_nm * math.exp(SPREAD_TRUNCATION_SIGMA * self.size_spread)

    def max_height_nm(self, diameter_nm: float) -> float:
        """Largest height (nm) a particle of this (effective) diameter can take in its orientation mode."""
        polar = polar_range_rad(self.orientation, self.tilt_rad) if self.shape.oriented else None
        return self.shape.max_height_nm(diameter_nm, polar)

    def span_nm(self, diameter_nm: float) -> float:
        """Diameter of the sphere enclosing a particle of this (effective) diameter."""
        return self.shape.span_nm(diameter_nm)


def parse_particles(text: str) -> ParticleSpec | None:
    """Parse a particle spec string; None for a molecular (homogeneous) layer."""
    if not isinstance(text, str) or not text.strip():
        raise ParticleSpecError("empty particle spec: expected e.g. 'molecular', 'sphere:100', "
                                "'sphere:100:agglutinated', 'cylinder:200:inplane'")
    spec = text.strip()
    if spec.lower() in MOLECULAR_WORDS:
        return None
    tokens = [t.strip() for t in spec.split(":")]
    shape = shape_class(tokens[0], spec)
    if len(tokens) < 2 or not tokens[1]:
        raise ParticleSpecError(f"particle spec {spec!r} lacks a diameter in nm, e.g. '{shape.name}:100'")
    diameter = parse_number(tokens[1].removesuffix("nm"), "diameter", spec)
    if diameter < 0:
        raise ParticleSpecError(f"negative particle size {fmt(diameter)} nm in {spec!r}")
    kwargs: dict = {}
    own: dict[str, str] = {}
    for token in tokens[2:]:
        key, _, value = token.partition("=")
        key = key.strip().lower()
        if key in ORIENTATIONS and not value:
            if "orientation" in kwargs:
                raise ParticleSpecError(f"two orientations in particle spec {spec!r}")
            kwargs["orientation"] = key
        elif key in ("agglutinated", "agglutination"):
            kwargs["agglutination_kT"] = (parse_number(value, "agglutination strength", spec) if value
                                          else AGGLUTINATED_DEFAULT_KT)
        elif key == "rough":
            kwargs["rough_top"] = parse_number(value, "rough-top fraction", spec) if value else ROUGH_DEFAULT
        elif key == "spread":
            kwargs["size_spread"] = parse_number(value, "size spread", spec) if value else 0.0
        elif key == "tilt":
            if not value:
                raise ParticleSpecError(f"'tilt' in {spec!r} needs a value in degrees, e.g. 'tilt=15'")
            kwargs["tilt_rad"] = math.radians(parse_number(value.removesuffix("deg"), "tilt", spec))
        elif key in ("orientation", "orient") and value:
            kwargs["orientation"] = value.strip().lower()
        elif key in shape.option_keys:
            own[key] = value
        else:
            extra = "".join(f", '{k}=…'" for k in shape.option_keys)
            raise ParticleSpecError(
                f"unknown particle modifier {token!r} in {spec!r}: expected an orientation ("
                + ", ".join(ORIENTATIONS) + f"), 'agglutinated[=kT]', 'rough[=fraction]', 'spread=sigma', "
                f"'tilt=degrees'{extra}")
    return ParticleSpec(shape.from_options(own, spec), diameter, **kwargs)


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
        height = spec.max_height_nm(dmax)
        if height > self.thickness_nm:
            what = "particle" if spec.size_spread == 0 else f"largest particle ({fmt(dmax)} nm at 3σ)"
            raise GeometryError(
                f"{what} {spec.label} is {fmt(height)} nm high in its orientation, larger than the "
                f"layer ({fmt(self.thickness_nm)} nm)")
        span = spec.span_nm(dmax)
        if span >= 0.5 * min(cell):
            raise GeometryError(
                f"particle {spec.label} spans {fmt(span)} nm, too large for a {fmt(cell[0])}x{fmt(cell[1])} nm "
                "cell (needs less than half the cell side)")

    @property
    def label(self) -> str:
        return (f"{self.ink.label}|{self.particles.label}|H={fmt(self.thickness_nm)}"
                f"|L={fmt(self.cell_nm[0])}x{fmt(self.cell_nm[1])}")
