"""What a table is computed from: the request, and its content address.

The cache key hashes everything that changes the numbers and nothing else: for a molecular ink
only the ink, thickness and the λ/σ grids; for a particle ink also the particles, the cell, the
grid, the realizations, the azimuth samples, the tolerances, the seed and the code versions.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from ..inks import parse_ink

#: Bump when the numbers a table pipeline produces change for the same request.
PIPELINE_VERSION = {"thin-film": 1, "wave": 1}

DEFAULT_WAVELENGTHS_NM = tuple(float(w) for w in np.arange(380.0, 781.0, 20.0))        # 21
#: Solved incidence angles for particle inks; 90° is added analytically (grazing limit).
DEFAULT_PARTICLE_SIGMA_DEG = (0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0)
DEFAULT_FILM_SIGMA_COUNT = 46


def _canonical_particles(text: str) -> str:
    from ..geometry.spec import parse_particles

    spec = parse_particles(text)
    return "molecular" if spec is None else spec.label


def _base_composition(ink_label: str) -> list:
    """Volume fractions of the base pigments (mixes such as G expanded), rounded, sorted."""
    from ..materials import get_pigment

    total: dict[str, float] = {}
    for code, fraction in parse_ink(ink_label).components:
        parts = get_pigment(code).parts or ((code, 1.0),)
        for base, weight in parts:
            total[base] = total.get(base, 0.0) + fraction * weight
    return sorted([c, round(f, 12)] for c, f in total.items())


@dataclass(frozen=True)
class TableRequest:
    """Everything that determines a table's numbers (lengths nm, angles rad)."""

    ink: str
    particles: str = "molecular"
    thickness_nm: float = 1000.0
    wavelengths_nm: tuple[float, ...] = DEFAULT_WAVELENGTHS_NM
    sigma_rad: tuple[float, ...] = ()          # () = the default grid for the kind of ink
    # particle inks only:
    cell_nm: float = 2000.0
    grid: tuple[int, int, int] = (64, 64, 32)
    realizations: int = 4
    azimuths: int = 2                          # incidence azimuths per realization
    dphi_count: int = 13                       # Δφ nodes of R over [0, π]
    solver_tol: float = 1e-4
    tolerance: float = 0.01                    # tier choice: allowed error in Rbar, Tbar, R_spec
    seed: int = 1
    tier: str = "auto"                         # auto | thin-film | effective-medium | born | full
    extra: dict = field(default_factory=dict, compare=False, hash=False)

    def __post_init__(self):
        object.__setattr__(self, "ink", parse_ink(self.ink).label)
        object.__setattr__(self, "particles", _canonical_particles(self.particles))
        object.__setattr__(self, "wavelengths_nm", tuple(float(w) for w in self.wavelengths_nm))
        if not self.sigma_rad:
            if self.molecular:
                sigma = np.linspace(0.0, np.pi / 2, DEFAULT_FILM_SIGMA_COUNT)
            else:
                sigma = np.radians(DEFAULT_PARTICLE_SIGMA_DEG + (90.0,))
            object.__setattr__(self, "sigma_rad", tuple(float(s) for s in sigma))
        object.__setattr__(self, "sigma_rad", tuple(float(s) for s in self.sigma_rad))
        object.__setattr__(self, "grid", tuple(int(n) for n in self.grid))
        if not self.thickness_nm > 0:
            raise ValueError(f"layer thickness must be > 0 nm, got {self.thickness_nm}")
        if len(self.wavelengths_nm) < 2 or np.any(np.diff(self.wavelengths_nm) <= 0):
            raise ValueError("wavelengths must be ≥ 2 strictly increasing values (nm)")
        s = np.asarray(self.sigma_rad)
        if s.size < 2 or abs(s[0]) > 1e-12 or abs(s[-1] - np.pi / 2) > 1e-12 or np.any(np.diff(s) <= 0):
            raise ValueError("incidence angles must increase strictly from 0° to 90°")
        if self.realizations < 1 or self.azimuths < 1:
            raise ValueError("realizations and azimuths must be ≥ 1")
        if self.tier not in ("auto", "thin-film", "effective-medium", "born", "full"):
            raise ValueError(f"unknown tier {self.tier!r}")

    @property
    def molecular(self) -> bool:
        return self.particles == "molecular"

    def numeric_fields(self) -> dict:
        """The fields that change the numbers (the cache key's content)."""
        d = asdict(self)
        d.pop("extra")
        if self.molecular:
            d = {k: d[k] for k in ("particles", "thickness_nm", "wavelengths_nm", "sigma_rad")}
            d["composition"] = _base_composition(self.ink)   # G30 ≡ Y15+B15 when molecular
            d["pipeline"] = PIPELINE_VERSION["thin-film"]
        else:
            d["pipeline"] = PIPELINE_VERSION
        return d

    def key(self) -> str:
        text = json.dumps(self.numeric_fields(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:24]

    def describe(self) -> str:
        what = f"{self.ink} {self.particles} H={self.thickness_nm:g} nm"
        if self.molecular:
            return what
        return (f"{what}, {len(self.wavelengths_nm)} λ × {len(self.sigma_rad)} σ, "
                f"{self.realizations} realizations × {self.azimuths} azimuths, grid "
                f"{'×'.join(map(str, self.grid))} over {self.cell_nm:g} nm")

    def with_(self, **changes) -> "TableRequest":
        return replace(self, **changes)
