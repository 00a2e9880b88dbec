"""Per-primary optical quantities of a print, on common wavelengths, primary axis first.

Every printed primary (bare paper, an ink, a stack of inks) enters the coverage models through
the same few quantities of eq. (4) (docs/design.md §1), taken from its table with the
interpolation the BSDF uses (linear in λ, clamped; linear in the polar angles; multilinear R):

    R_spec(σ), T̄(σ), R_diff(σ) = ∫ R cos θ dω / π,  ρ̄ = 2∫ Rbar_below cos s sin s ds,
    τ̄ = 2∫ T̄ cos s sin s ds,  R(σ, θ, Δφ)

Bare paper is the primary () with R_spec = R_diff = R = 0, T̄ = τ̄ = 1, ρ̄ = 0. Angular work is
done by `solver.table.evaluate` and `solver.table.integrals`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..table.evaluate import brdf_R_at, column_at
from ..table.eq4 import LayerTerms, layer_terms
from ..table.interpolation import lerp_weights
from ..table.schema import InkTable
from .demichel import Subset
from .inkset import PrintedInks

_LAMBDA_COLUMNS = ("R", "R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")


def resample_wavelengths(table: InkTable, wavelengths_nm) -> InkTable:
    """The table at other wavelengths (1-D, nm), linear in λ and clamped, like the BSDF's lanes."""
    wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=np.float64))
    if wl.ndim != 1:
        raise ValueError("wavelengths_nm must be a 1-D array of wavelengths in nm")
    i, t = lerp_weights(table.wavelengths, wl)

    def lerp(a):
        a = np.asarray(a)
        a = a.astype(np.complex128 if np.iscomplexobj(a) else np.float64)   # r_s, r_p are complex
        tt = t.reshape((-1,) + (1,) * (a.ndim - 1))
        return a[i] * (1.0 - tt) + a[i + 1] * tt

    names = _LAMBDA_COLUMNS + tuple(table.sp_arrays)        # s/p split of unpolarised tables
    return dataclasses.replace(table, wavelengths=wl, errors={}, jackknife=None,
                               **{name: lerp(getattr(table, name)) for name in names})


@dataclass(frozen=True)
class PrimaryOptics:
    """Tables of the printed primaries resampled to `wavelengths_nm`, with ρ̄ and τ̄."""

    subsets: tuple[Subset, ...]
    wavelengths_nm: np.ndarray          # [nλ]
    tables: tuple[InkTable | None, ...] # per primary; None = bare paper
    terms: tuple[LayerTerms | None, ...]  # eq. (4)'s pieces per primary; None = bare paper
    rho: np.ndarray                     # [nP, nλ]
    tau: np.ndarray                     # [nP, nλ]

    def at_polar(self, polar_rad) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(R_spec, R_diff, T̄) at polar angles: each [nP, nλ, *shape(polar_rad)]."""
        polar = np.asarray(polar_rad, dtype=np.float64)
        shape = (self.wavelengths_nm.size,) + polar.shape
        spec, rdiff, tbar = [], [], []
        for table, terms in zip(self.tables, self.terms):
            if table is None:
                spec.append(np.zeros(shape))
                rdiff.append(np.zeros(shape))
                tbar.append(np.ones(shape))
                continue
            spec.append(column_at(table, "R_spec", polar))
            tbar.append(column_at(table, "Tbar", polar))
            rdiff.append(_column(table.sigma, terms.diffuse_albedo, polar))
        return np.stack(spec), np.stack(rdiff), np.stack(tbar)

    def layer_brdf(self, sigma_rad, theta_rad, dphi_rad) -> np.ndarray:
        """R(σ, θ, Δφ) of each primary's layer (π·f of its diffuse lobe): [nP, nλ, *shape]."""
        s, th, ph = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64)
                                          for a in (sigma_rad, theta_rad, dphi_rad)))
        out = np.zeros((len(self.tables), self.wavelengths_nm.size) + s.shape)
        for n, table in enumerate(self.tables):
            if table is not None and table.has_diffuse:
                out[n] = brdf_R_at(table, s, th, ph)
        return out


def _column(sigma, values, polar):
    """A [λ, σ] array interpolated at polar angles (as evaluate.column_at does for columns)."""
    i, t = lerp_weights(sigma, polar)
    return values[:, i] * (1.0 - t) + values[:, i + 1] * t


def primary_optics(printed: PrintedInks, subsets, wavelengths_nm=None) -> PrimaryOptics:
    """Optics of the given primaries (bare paper, inks, stacks) at `wavelengths_nm`
    (default: the first ink's wavelength grid)."""
    wl = (np.asarray(printed.inks[0].wavelengths, dtype=np.float64) if wavelengths_nm is None
          else np.atleast_1d(np.asarray(wavelengths_nm, dtype=np.float64)))
    subsets = tuple(tuple(s) for s in subsets)
    tables = tuple(None if not s else resample_wavelengths(printed.table(s), wl) for s in subsets)
    terms = tuple(None if t is None else layer_terms(t) for t in tables)
    rho = np.stack([np.zeros(wl.size) if t is None else t.rho_bar for t in terms])
    tau = np.stack([np.ones(wl.size) if t is None else t.tau_bar for t in terms])
    return PrimaryOptics(subsets=subsets, wavelengths_nm=wl, tables=tables, terms=terms, rho=rho, tau=tau)
