"""The comparison cases and their geometry (shared by the vector and the scalar side).

A case is a layer of equal spheres of one pigment in binder (docs/design.md §1–§3), air above
and below, in a periodic cell.  Both solvers see exactly the same spheres: the project's
generator (`solver.geometry.generate`) places them, seeded per realization.

Face buffer.  The generator lets spheres touch the binder faces (centre at z = r).  The vector
model expands the field scattered by the sphere lattice in plane waves at the faces, which
converges only if no sphere touches a face (and slowly if one nearly does).  So the spheres are
generated in a layer thinner by 2·FACE_BUFFER_NM and moved down by FACE_BUFFER_NM: the binder
layer keeps its thickness (1000 nm), every sphere keeps ≥ FACE_BUFFER_NM of binder to each face.
The scalar side voxelises this same shifted realization.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass

import numpy as np

from solver.geometry import LayerSpec, generate, parse_particles
from solver.inks import parse_ink
from solver.materials import BINDER_INDEX, pigment_eps

from .oracles import mie_coefficients

FACE_BUFFER_NM = 5.0
#: Multipole truncation: drop degrees whose single-sphere Mie coefficients are all below this.
MIE_TAIL = 1e-3
MIN_LMAX = 2


@dataclass(frozen=True)
class Case:
    """One comparison case.  Lengths in nm, angles in degrees (as printed), fraction in 0..1."""

    diameter_nm: float
    fraction: float
    cell_nm: float
    wavelengths_nm: tuple[float, ...]
    polar_deg: tuple[float, ...] = (0.0, 30.0, 60.0)
    realizations: int = 1
    pigment: str = "Y"
    thickness_nm: float = 1000.0
    seed: int = 1
    pw_cutoff_per_nm: float = 0.05

    @property
    def label(self) -> str:
        return (f"{self.pigment}{100 * self.fraction:g}% sphere:{self.diameter_nm:g} "
                f"cell {self.cell_nm:g} nm")

    @property
    def geometry_key(self) -> str:
        """Hash of what fixes one realization's spheres (not the wavelengths or angles)."""
        fields = dict(d=float(self.diameter_nm), f=float(self.fraction), cell=float(self.cell_nm), pig=self.pigment,
                      h=float(self.thickness_nm), seed=int(self.seed), buffer=FACE_BUFFER_NM)
        return hashlib.sha256(json.dumps(fields, sort_keys=True).encode()).hexdigest()[:16]

    def with_(self, **changes) -> "Case":
        return dataclasses.replace(self, **changes)


def realization(case: Case, index: int):
    """Realization `index` of the case, spheres ≥ FACE_BUFFER_NM inside both binder faces.

    Returns a `solver.geometry.Realization` whose z range is (0, thickness)."""
    ink = parse_ink(f"{case.pigment}{100 * case.fraction:g}")
    inner = case.thickness_nm - 2 * FACE_BUFFER_NM
    layer = LayerSpec(ink, parse_particles(f"sphere:{case.diameter_nm:g}"), thickness_nm=inner,
                      cell_nm=(case.cell_nm, case.cell_nm))
    seed = int(np.random.SeedSequence([case.seed, index]).generate_state(1)[0])
    real = generate(layer, seed)
    centres = real.centres_nm + np.array([0.0, 0.0, FACE_BUFFER_NM])
    full = dataclasses.replace(layer, thickness_nm=case.thickness_nm)
    return dataclasses.replace(real, layer=full, centres_nm=centres, z_range_nm=(0.0, case.thickness_nm))


def sphere_eps(case: Case, wavelength_nm: float) -> complex:
    return complex(pigment_eps(case.pigment, wavelength_nm))


def host_eps() -> float:
    return BINDER_INDEX ** 2


def lmax_for(radius_nm: float, wavelength_nm: float, eps_sphere: complex, tail: float = MIE_TAIL) -> int:
    """Smallest degree L ≥ MIN_LMAX such that every Mie coefficient |a_n|, |b_n| with n > L is
    below `tail` (single sphere in binder; the measured effect on R, T is ~half of it)."""
    x = 2 * math.pi * BINDER_INDEX / wavelength_nm * radius_nm
    a, b = mie_coefficients(x, np.sqrt(eps_sphere) / BINDER_INDEX, 30)
    big = np.flatnonzero(np.maximum(abs(a), abs(b)) >= tail)
    return max(MIN_LMAX, int(big[-1]) + 1 if big.size else 1)
