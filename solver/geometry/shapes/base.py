"""The Shape protocol: everything a particle shape means to the geometry, the optics and the
figures, in one object (docs/geometry.md, "Shapes").

A grain is axisymmetric: radius r and half length h along its unit axis a (`bodies.Bodies`); a
shape says what r and h are for a grain of a given effective diameter (the sphere of equal
volume) and answers every question the stages ask about it — they never branch on its name:

* grammar: its word in spec strings, its own modifiers (`from_options`, `label_parts`), whether
  it has an axis (`oriented`: takes an orientation and a tilt) and its fragment of the grammar;
* one grain: `dimensions`, height in an orientation range, span (for the layer's checks);
* N grains: volumes, extents along x, y, z, z-chords (voxelisation), inside test (pictures),
  smallest half-width (voxel line spacing), moment of inertia;
* contacts: pair separations (gap ≤ the signed distance, `contacts`), horizontal separations,
  the support points a turn acts on (contact rows, walls, pushes);
* rough top: the binder surface over a protruding grain;
* placement: RSA and packing thresholds, packer limits, rigorous geometric bounds;
* cost model: placement, agglutination and memory coefficients (`cost`);
* optics: its local-field (depolarisation) model (`depolarisation`);
* figures: its column header and what its orientations are called.

Defaults below serve any convex axisymmetric body given its support function `width` and
`support_point`; a shape overrides what it knows better (the sphere: everything exact and fast).
The shapes are registered in `shapes/__init__.py`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..contacts import Separation
from ..grammar import ParticleSpecError
from ..neighbours import min_image
from ..orientation import ORIENTATION_LABELS
from ..separating_axis import ridge_search

if TYPE_CHECKING:
    from ...materials import LocalField
    from ..bodies import Bodies
    from ..spec import LayerSpec, ParticleSpec

#: Sample lines of the surface of a protruding grain against the binder points they lift are
#: compared in parts of this many points (memory).
_SURFACE_PART = 64


@dataclass(frozen=True)
class Shape:
    """Protocol and shared defaults of a particle shape (module doc).  Subclasses are frozen
    dataclasses whose fields are the shape's own parameters (written in its label)."""

    #: the word in spec strings, its plural (messages), and its grammar fragment (help texts)
    name: ClassVar[str]
    plural: ClassVar[str]
    grammar: ClassVar[str]
    #: what the fragment's own symbols mean (help texts; empty: nothing beyond the common ones)
    grammar_key: ClassVar[str] = ""
    #: the shape's own modifiers (key=value tokens of the spec string)
    option_keys: ClassVar[tuple[str, ...]] = ()
    #: has a symmetry axis: takes an orientation (isotropic by default) and a tilt
    oriented: ClassVar[bool] = False
    #: pair separations warm-start from each pair's previous axis (a search, not a formula)
    uses_axis_hint: ClassVar[bool] = False
    #: RSA alone up to this total fraction; beyond it RSA places grains shrunk to fill
    #: pack_start_fraction and the packer grows them (`placement`, `limits`)
    rsa_fraction: ClassVar[float]
    pack_start_fraction: ClassVar[float] = 0.15
    #: largest total fraction the packer is trusted to reach, per orientation (None: no axis),
    #: measured with `python -m benchmarks.bench_geometry --limits` (docs/geometry.md)
    packer_limits: ClassVar[dict]
    #: placement cost per orientation: points (φ, fixed s, µs per grain) (`cost`); Brownian
    #: steps of agglutination (fixed s, µs per grain); the generator's bytes per grain
    place_cost: ClassVar[dict]
    agglutination_cost: ClassVar[tuple[float, float]]
    gen_bytes_per_grain: ClassVar[float]

    def __str__(self) -> str:
        return self.name

    # ------------------------------------------------------------------ grammar
    @classmethod
    def from_options(cls, options: dict[str, str], spec: str) -> "Shape":
        """The shape with its own modifiers (key → value text, keys from option_keys)."""
        if options:
            raise ParticleSpecError(f"{cls.name} takes no {', '.join(options)} in {spec!r}")
        return cls()

    def label_parts(self) -> tuple[str, ...]:
        """The shape's own modifiers as the canonical label writes them (after the diameter)."""
        return ()

    # ------------------------------------------------------------------ one grain
    def dimensions(self, diameter_nm):
        """(radius, half length) in nm of grains of this effective diameter (floats or arrays)."""
        raise NotImplementedError

    def max_height_nm(self, diameter_nm: float, polar_range: tuple[float, float] | None) -> float:
        """Largest height (nm) of a grain of this diameter with its axis in polar_range (radians
        from the vertical; None: a shape without an axis)."""
        raise NotImplementedError

    def span_nm(self, diameter_nm: float) -> float:
        """Diameter (nm) of the sphere about the centre enclosing a grain of this diameter."""
        r, h = self.dimensions(diameter_nm)
        return 2.0 * float(self.bounding_radius_nm(np.asarray(r), np.asarray(h)))

    # ------------------------------------------------------------------ N grains
    def volumes_nm3(self, radii_nm: np.ndarray, half_lengths_nm: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def width(self, c, radius, half_length):
        """Half-width along a unit n of a grain with c = a·n (its support function; arrays broadcast)."""
        raise NotImplementedError

    def support_point(self, axes, half_lengths, radii, n):
        """The point (P, 3), from the centre, where a grain touches its support plane along n (P, 3)."""
        raise NotImplementedError

    def half_extent_nm(self, bodies: Bodies, direction: int) -> np.ndarray:
        """Half of each grain's extent along coordinate axis 0, 1 or 2: its width along it."""
        return self.width(bodies.axes[:, direction], bodies.radii_nm, bodies.half_lengths_nm)

    def bounding_radius_nm(self, radii_nm, half_lengths_nm):
        raise NotImplementedError

    def smallest_half_width_nm(self, radii_nm, half_lengths_nm):
        raise NotImplementedError

    def inertia_nm5(self, bodies: Bodies) -> np.ndarray:
        """Transverse moment of inertia per unit density (nm⁵) of each grain."""
        raise NotImplementedError

    def z_chords(self, bodies: Bodies, dx: np.ndarray, dy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Exact crossings (z_lo, z_hi) of vertical lines at lateral offsets dx, dy (N, M) from the
        centres with each grain, relative to its centre; z_lo >= z_hi marks a line that misses."""
        raise NotImplementedError

    def contains(self, bodies: Bodies, dx, dy, dz) -> np.ndarray:
        """Whether points at offsets (dx, dy, dz) (N, M) from each centre lie inside."""
        raise NotImplementedError

    # ------------------------------------------------------------------ contacts
    def separation(self, bodies_i: Bodies, centres_i, bodies_j: Bodies, centres_j, i, j, period_nm, hint,
                   margin_nm: float, search_iterations: int, full_search: bool) -> Separation:
        """`contacts.separation` for this shape: pairs (i of bodies_i, j of bodies_j)."""
        d = min_image(centres_j[j] - centres_i[i], period_nm)
        normal, gap = self.pair_axes(d, bodies_i.axes[i], bodies_j.axes[j], bodies_i.radii_nm[i],
                                     bodies_j.radii_nm[j], bodies_i.half_lengths_nm[i],
                                     bodies_j.half_lengths_nm[j], hint, margin_nm, search_iterations, full_search)
        return Separation(normal, gap)

    def pair_axes(self, d, ai, aj, ri, rj, hi, hj, hint, margin_nm, search_iterations, full_search):
        """(normal (P, 3) from i to j, gap (P,)): the best separating axes found for pairs at
        separations d (P, 3), stopping where a pair is certified apart by margin_nm."""
        raise NotImplementedError

    def horizontal_separation(self, bodies: Bodies, centres, i, j, period_nm) -> Separation:
        """Best horizontal separating axis (n_z = 0) of each pair: a search on the horizontal circle."""
        d = min_image(centres[j] - centres[i], period_nm)
        ez = np.tile([0.0, 0.0, 1.0], (len(i), 1))
        n, g = ridge_search(self.width, d, bodies.axes[i], bodies.axes[j], bodies.radii_nm[i],
                            bodies.radii_nm[j], bodies.half_lengths_nm[i], bodies.half_lengths_nm[j], axis=ez)
        sign = np.where(np.einsum("pc,pc->p", n, d) < 0, -1.0, 1.0)
        return Separation(n * sign[:, None], g)

    def support_candidates(self, axes, half_lengths, radii, n):
        """Points a turn may make the support point along n: (points (P, K, 3) from the centre,
        mask (P, K), width (P,)); slot 0 is the support point (a smooth body has no other)."""
        c = np.einsum("pc,pc->p", axes, n)
        return (self.support_point(axes, half_lengths, radii, n)[:, None, :], np.ones((len(c), 1), dtype=bool),
                self.width(c, radii, half_lengths))

    def wall_point(self, axes, half_lengths, radii, toward_wall):
        """The grain's point deepest into a wall whose outward normal (into the wall) is toward_wall (P, 3)."""
        return self.support_point(axes, half_lengths, radii, toward_wall)

    def contact_point(self, d, ai, aj, hi, hj, ri, rj, normal):
        """Contact point of pairs (from c_i) for pushes: midway between the support points of
        i along +n and of j along −n."""
        return 0.5 * (self.support_point(ai, hi, ri, normal) + d - self.support_point(aj, hj, rj, normal))

    # ------------------------------------------------------------------ rough top
    def surface_points(self, radius_nm: float, half_length_nm: float, axis: np.ndarray) -> np.ndarray:
        """Points (Q, 3) on a grain's surface relative to its centre, a few nm apart (rough top)."""
        raise NotImplementedError

    def meniscus_nm(self, radius_nm, half_length_nm, axis, z_centre_nm, dx, dy, angle_rad):
        """Height of the binder lifted by one protruding grain at lateral offsets (dx, dy) from
        its centre: min over its surface points q above z = 0 of q_z + tan α·|(dx, dy) − q_xy|
        (`surface`); None when no point of it is above z = 0."""
        q = self.surface_points(radius_nm, half_length_nm, axis)
        q = q[q[:, 2] + z_centre_nm < 0]                 # only points above the flat top matter
        if q.size == 0:
            return None
        tan_a = np.tan(angle_rad)
        f = np.full(dx.size, np.inf)
        for part in np.array_split(np.arange(len(q)), max(1, len(q) // _SURFACE_PART)):
            qp = q[part]
            dist = np.hypot(dx[:, None] - qp[None, :, 0], dy[:, None] - qp[None, :, 1])
            f = np.minimum(f, np.min(z_centre_nm + qp[None, :, 2] + tan_a * dist, axis=1))
        return f

    # ------------------------------------------------------------------ placement limits
    def packer_limit(self, layer: LayerSpec) -> float:
        """Largest total fraction the packer is trusted to reach for this layer (`limits`)."""
        return self.packer_limits[layer.particles.orientation]

    def geometric_limit(self, layer: LayerSpec) -> float:
        """A rigorous geometric bound of the fraction (times the packer's share of it) where one
        applies, else 1."""
        return 1.0

    def aligned_column_bound(self, layer: LayerSpec) -> float | None:
        """The fraction grains fill when hexagonally packed one per column, where they are too
        long to stack two in the layer (an upper bound), else None."""
        return None

    # ------------------------------------------------------------------ optics
    def local_field(self, spec: ParticleSpec) -> LocalField:
        """How a small grain of this spec polarises in the binder (`depolarisation`)."""
        raise NotImplementedError

    # ------------------------------------------------------------------ figures
    def column_group(self, diameter_nm: float) -> str:
        """A figure's column header for grains of this diameter ('Balls 300 nm')."""
        raise NotImplementedError

    def orientation_label(self, orientation: str) -> str:
        """How a figure's column sub-header names an orientation of this shape."""
        return ORIENTATION_LABELS[orientation]
