"""Optical constants of the binder and the pigments (DESIGN.md §1–§2).

Binder: transparent, index 1.558, no dispersion.  Pigments R, Y, B: Re(η) = 1.4 and k(λ) from
the package's derived spectra (`solver/data/pigments_k.csv`, see `derive_pigments.py` for the
sources).  Green G is a *molecular* mix of Blue and Yellow: one material whose permittivity is
ε_G = (ε_Y + ε_B)/2.  Wavelengths outside 360–830 nm clamp to the end values.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np

BINDER_INDEX = 1.558
PIGMENT_REAL_INDEX = 1.4
AIR_EPS = 1.0 + 0.0j


@dataclass(frozen=True)
class Pigment:
    code: str                           # one letter, as in the paper's ink names
    name: str
    source: str                         # where k(λ) comes from
    parts: tuple[tuple[str, float], ...] = ()   # molecular mix of other pigments (ε-weighted)


PIGMENTS: dict[str, Pigment] = {
    "R": Pigment("R", "red", "Rhodamine 6G film (Seckin et al. 2023), refractiveindex.info"),
    "Y": Pigment("Y", "yellow", "F8BT film, k_iso=(2k_o+k_e)/3 (Kamptner et al. 2024)"),
    "B": Pigment("B", "blue", "ZZ50 / c-PCPDTBT film, k_iso=(2k_o+k_e)/3 (Kamptner et al. 2024)"),
    "G": Pigment("G", "green", "molecular mix: eps_G = (eps_Y + eps_B)/2", (("Y", 0.5), ("B", 0.5))),
}

# Display colours for pictures of the geometry (sRGB 0–1).
PIGMENT_DISPLAY_RGB = {"R": (0.85, 0.1, 0.45), "Y": (0.95, 0.85, 0.1),
                       "B": (0.1, 0.45, 0.85), "G": (0.15, 0.65, 0.3)}


class UnknownPigmentError(ValueError):
    pass


def get_pigment(code: str) -> Pigment:
    try:
        return PIGMENTS[code]
    except KeyError:
        raise UnknownPigmentError(
            f"unknown pigment {code!r}: known pigments are "
            + ", ".join(f"{p.code} ({p.name})" for p in PIGMENTS.values())) from None


@lru_cache(maxsize=1)
def _k_table() -> tuple[np.ndarray, dict[str, np.ndarray]]:
    text = resources.files("solver.data").joinpath("pigments_k.csv").read_text()
    data = np.loadtxt(text.splitlines(), delimiter=",", comments="#", skiprows=3)
    wl = data[:, 0]
    return wl, {"R": data[:, 1], "Y": data[:, 2], "B": data[:, 3]}


def binder_eps(wavelength_nm) -> np.ndarray:
    """Relative permittivity of the binder (no dispersion)."""
    return np.full(np.shape(wavelength_nm), BINDER_INDEX**2, dtype=complex)


def pigment_k(code: str, wavelength_nm) -> np.ndarray:
    """Extinction coefficient k(λ) of a base pigment (R, Y, B), clamped outside 360–830 nm."""
    wl, table = _k_table()
    if code not in table:
        raise ValueError(f"pigment {code!r} has no tabulated k (it is a mix); use pigment_eps")
    return np.interp(np.asarray(wavelength_nm, dtype=float), wl, table[code])


def pigment_eps(code: str, wavelength_nm) -> np.ndarray:
    """Relative permittivity ε = η² of a pigment at the given wavelengths (nm)."""
    pig = get_pigment(code)
    if pig.parts:
        return sum(w * pigment_eps(c, wavelength_nm) for c, w in pig.parts)
    return (PIGMENT_REAL_INDEX + 1j * pigment_k(code, wavelength_nm)) ** 2
