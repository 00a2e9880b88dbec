"""Input records of the wave solver: one periodic cell of the layer and one incidence.

Conventions (DESIGN.md §1, §4): lengths in nm, angles in radians, time factor e^(−iωt),
relative permittivity ε = η² with Im ε ≥ 0 for absorbing media.  z increases downward into
the layer: light from above travels +z.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Cell:
    """One periodic cell of the layer, sampled on a voxel grid.

    eps: complex relative permittivity ε = η², shape (nx, ny, nz).  Voxel [i, j, k] is centred at
        x = (i+½)·Lx/nx, y = (j+½)·Ly/ny, z = z_top + (k+½)·(z_bottom − z_top)/nz; its value is the
        voxel average (sub-voxel averaged interfaces).
    period_nm: (Lx, Ly), the lateral periods in nm.
    z_range_nm: (z_top, z_bottom) in nm, z_bottom > z_top (z grows downward into the layer).
    eps_above, eps_below: permittivities of the two half-spaces (real, positive: the flux of the
        orders is only defined in lossless half-spaces).
    """

    eps: np.ndarray
    period_nm: tuple[float, float]
    z_range_nm: tuple[float, float]
    eps_above: complex = 1.0
    eps_below: complex = 1.0

    def __post_init__(self) -> None:
        eps = np.asarray(self.eps)
        if eps.ndim != 3 or min(eps.shape) < 1:
            raise ValueError(f"Cell.eps must be a non-empty 3-D array, got shape {eps.shape}")
        if not np.all(np.isfinite(eps)):
            raise ValueError("Cell.eps contains NaN or Inf")
        if np.any(np.imag(eps) < -1e-12):
            raise ValueError(f"Cell.eps has Im ε < 0 (gain) down to {np.imag(eps).min():.3g}; "
                             "only passive media")
        lx, ly = (float(p) for p in self.period_nm)
        if not (lx > 0 and ly > 0 and math.isfinite(lx) and math.isfinite(ly)):
            raise ValueError(f"period_nm must be positive and finite, got {self.period_nm}")
        z0, z1 = (float(z) for z in self.z_range_nm)
        if not (z1 > z0 and math.isfinite(z0) and math.isfinite(z1)):
            raise ValueError(f"z_range_nm must satisfy z_top < z_bottom, got {self.z_range_nm}")
        for name in ("eps_above", "eps_below"):
            v = complex(getattr(self, name))
            if abs(v.imag) > 0 or not v.real > 0 or not math.isfinite(v.real):
                raise ValueError(f"{name} must be real and positive, got {v}")

    @property
    def shape(self) -> tuple[int, int, int]:
        return tuple(np.shape(self.eps))  # type: ignore[return-value]

    @property
    def thickness_nm(self) -> float:
        return float(self.z_range_nm[1]) - float(self.z_range_nm[0])

    @property
    def voxel_nm(self) -> tuple[float, float, float]:
        """Voxel sizes (dx, dy, dz) in nm."""
        nx, ny, nz = self.shape
        return (float(self.period_nm[0]) / nx, float(self.period_nm[1]) / ny,
                self.thickness_nm / nz)

    def mirrored(self) -> "Cell":
        """The same cell turned upside down (z → z_top + z_bottom − z), half-spaces swapped."""
        return Cell(np.ascontiguousarray(np.asarray(self.eps)[:, :, ::-1]), self.period_nm,
                    self.z_range_nm, eps_above=self.eps_below, eps_below=self.eps_above)


@dataclass(frozen=True)
class Incidence:
    """A plane wave of unit amplitude incident on the cell.

    polar_rad: σ, angle to the layer normal in the medium of incidence, 0 ≤ σ < π/2.
    azimuth_rad: φ, direction (cos φ, sin φ) of the in-plane wavevector.
    from_below: False: from z < z_top travelling +z; True: from z > z_bottom travelling −z.
    """

    wavelength_nm: float
    polar_rad: float
    azimuth_rad: float = 0.0
    from_below: bool = False

    def __post_init__(self) -> None:
        if not (self.wavelength_nm > 0 and math.isfinite(self.wavelength_nm)):
            raise ValueError(f"wavelength_nm must be positive, got {self.wavelength_nm}")
        if not (0.0 <= self.polar_rad < math.pi / 2):
            raise ValueError(f"polar_rad must lie in [0, π/2), got {self.polar_rad}")
        if not math.isfinite(self.azimuth_rad):
            raise ValueError("azimuth_rad must be finite")


def bloch_vector(cell: Cell, incidence: Incidence) -> tuple[float, float]:
    """In-plane wavevector (kx0, ky0) in 1/nm of the incident wave (set by the incidence medium)."""
    eps_in = cell.eps_below if incidence.from_below else cell.eps_above
    kt = 2 * math.pi / incidence.wavelength_nm * math.sqrt(complex(eps_in).real) \
        * math.sin(incidence.polar_rad)
    return kt * math.cos(incidence.azimuth_rad), kt * math.sin(incidence.azimuth_rad)
