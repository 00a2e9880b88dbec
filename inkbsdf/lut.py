"""Lane-independent precomputation for the `ink` BSDF (NumPy only, no Mitsuba).

Everything the plugin needs that does not depend on a ray is computed here once, at scene load,
from a validated `solver.table.InkTable`:

    rho_bar(λ) = 2∫ Rbar_below(s) cos s sin s ds    paper-side reflectance of the layer, cosine mean
    tau_bar(λ) = 2∫ Tbar(s) cos s sin s ds          transmittance of the layer, cosine mean
    R_diff(λ, σ) = ∫ R cos θ dω / π                 directional albedo of the diffuse R lobe
                                                    (≈ Rbar − R_spec, exactly the evaluated lobe)
    mirror_sp(λ, σ) = (b, C, S)                     the mirror beam's Mueller elements besides
                                                    M00 = R_spec, from r_s, r_p (polarized variants)

The integrals go through `solver.table.integrals`, exact for the piecewise-linear interpolant in
σ that the plugin evaluates, so that a lossless layer on white paper reflects exactly 1.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.table import InkTable, read_table
from solver.table.eq4 import layer_terms


@dataclass(frozen=True)
class InkLUT:
    """Arrays the BSDF interpolates; angles in radians, wavelengths in nm.

    `sigma_rad` is the grid of the σ-indexed columns; the plugin uses the same grid for the exit
    angle θ in Tbar(θ) (Tbar is one function of the polar angle). `R` is None for layers with
    no diffuse scattering (molecular inks): the plugin then skips every R lookup.
    """

    source: str
    wavelengths_nm: np.ndarray      # [nλ]
    sigma_rad: np.ndarray           # [nσ]
    R_spec: np.ndarray              # [nλ, nσ]
    Tbar: np.ndarray                # [nλ, nσ]
    R_diff: np.ndarray              # [nλ, nσ]
    rho_bar: np.ndarray             # [nλ]
    tau_bar: np.ndarray             # [nλ]
    theta_rad: np.ndarray           # [nθ] grid of R
    dphi_rad: np.ndarray            # [nφ] grid of R, 0 (retro) .. π (mirror)
    R: np.ndarray | None            # [nλ, nσ, nθ, nφ] or None
    polarisation: str = "te"        # the table's meta polarisation ("unpolarised" or "te")
    mirror_sp: np.ndarray | None = None   # [nλ, nσ, 3] (b, C, S), see mirror_mueller; None
                                          # when the table has no r_s, r_p

    @property
    def has_diffuse(self) -> bool:
        return self.R is not None


def mirror_mueller(r_s, r_p, r_spec) -> np.ndarray:
    """Mueller elements of the mirror beam, [..., 3] = (b, C, S), from its s and p amplitudes
    in Mitsuba's convention (docs/polarisation.md), so that with a = R_spec

        M = [[a, b, 0, 0], [b, a, 0, 0], [0, 0, C, −S], [0, 0, S, C]]

    in the frame whose Stokes basis vector is the s direction (normal to the plane of
    incidence), as `mi.mueller.specular_reflection` writes it: b = (|r_s|² − |r_p|²)/2,
    C + iS = r_p·conj(r_s) (= |r_s||r_p| e^{iδ}, δ = arg r_p − arg r_s).  The three are scaled
    by R_spec/((|r_s|² + |r_p|²)/2) (1 within the schema's 1e-6) so that M00 is exactly the
    unpolarised column the spectral variants use and M stays a pure (non-depolarising) matrix."""
    r_s = np.asarray(r_s, dtype=np.complex128)
    r_p = np.asarray(r_p, dtype=np.complex128)
    rs2, rp2 = np.abs(r_s) ** 2, np.abs(r_p) ** 2
    mean = 0.5 * (rs2 + rp2)
    scale = np.divide(np.asarray(r_spec, dtype=np.float64), mean, out=np.zeros_like(mean), where=mean > 0)
    cross = r_p * np.conj(r_s)
    return np.stack([0.5 * (rs2 - rp2) * scale, cross.real * scale, cross.imag * scale], axis=-1)


def lut_from_table(table: InkTable, source: str = "table") -> InkLUT:
    """Derive the plugin's arrays from a validated table (pure function)."""
    sigma = np.asarray(table.sigma, dtype=np.float64)
    terms = layer_terms(table)
    return InkLUT(
        source=source,
        wavelengths_nm=np.asarray(table.wavelengths, dtype=np.float64),
        sigma_rad=sigma,
        R_spec=np.asarray(table.R_spec, dtype=np.float64),
        Tbar=np.asarray(table.Tbar, dtype=np.float64),
        R_diff=terms.diffuse_albedo,
        rho_bar=np.asarray(terms.rho_bar, dtype=np.float64),
        tau_bar=np.asarray(terms.tau_bar, dtype=np.float64),
        theta_rad=np.asarray(table.theta, dtype=np.float64),
        dphi_rad=np.asarray(table.dphi, dtype=np.float64),
        R=np.asarray(table.R, dtype=np.float64) if table.has_diffuse else None,
        polarisation=table.polarisation,
        mirror_sp=(mirror_mueller(table.r_s, table.r_p, table.R_spec)
                   if table.r_s is not None and table.r_p is not None else None),
    )


_LUTS: dict[tuple, InkLUT] = {}       # (path, modification time, size) → InkLUT
_MAX_LUTS = 32


def load_lut(path, table: InkTable | None = None) -> InkLUT:
    """Read, validate and precompute a table file; raises solver.table.TableError. `table`: the
    file's table when the caller holds it already (a build just made it), so it is not read again.

    Cached on (path, modification time, size): a scene that uses one ink on several shapes
    reads it once, and a rewritten file is read again.
    """
    p = Path(path)
    try:
        st = os.stat(p)
    except OSError:
        return lut_from_table(read_table(p), source=str(p))   # read_table raises "not found"
    key = (str(p.resolve()), st.st_mtime_ns, st.st_size)
    lut = _LUTS.get(key)
    if lut is None:
        while len(_LUTS) >= _MAX_LUTS:
            _LUTS.pop(next(iter(_LUTS)))
        lut = _LUTS[key] = lut_from_table(table if table is not None else read_table(p), source=key[0])
    return lut

