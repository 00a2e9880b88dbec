"""Optical constants of the binder and the pigments (docs/design.md §2).

Binder: transparent, index 1.558, no dispersion.  The paper's pigments R, Y, B: Re(η) = 1.4
(paper §3.1) and measured k(λ) stand-ins; the process pigments C, M, K (docs/printing.md): their
own measured n(λ) and k(λ) (carbon's n is about 2.3, a squaraine's dips below 1 across its band:
a fixed 1.4 would misplace their colours).  All from the package's derived spectra
(`solver/data/pigments_nk.csv`, see `derive_pigments.py` for the sources).  Green G is a
*molecular* mix of Blue and Yellow: one material whose permittivity is ε_G = (ε_Y + ε_B)/2.
The process set's yellow is the paper's Y.

Everything that sets a number lives in one `MaterialData` value (constants and spectra) with a
`fingerprint`: a table request carries the data it is computed from, and its cache key includes
the fingerprint, so editing the spectra or the constants can never serve an old table.
Wavelengths outside the data's range are refused by the request (`MaterialData.check_range`);
the plugin clamps at render time.
"""

from __future__ import annotations

import dataclasses
import hashlib
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from pathlib import Path

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
    "C": Pigment("C", "cyan", "SQIB squaraine film, n and k, mean of 3 axes (Funke et al. 2021)"),
    "M": Pigment("M", "magenta", "Rhodamine 6G film, n and k (Seckin et al. 2023)"),
    "K": Pigment("K", "black", "arc-evaporated amorphous carbon film, n and k (Arakawa et al. 1977)"),
}

# Display colours for pictures of the geometry (sRGB 0–1).
PIGMENT_DISPLAY_RGB = {"R": (0.85, 0.1, 0.45), "Y": (0.95, 0.85, 0.1),
                       "B": (0.1, 0.45, 0.85), "G": (0.15, 0.65, 0.3),
                       "C": (0.0, 0.62, 0.88), "M": (0.9, 0.0, 0.5), "K": (0.1, 0.1, 0.1)}


class UnknownPigmentError(ValueError):
    pass


def get_pigment(code: str) -> Pigment:
    try:
        return PIGMENTS[code]
    except KeyError:
        raise UnknownPigmentError(
            f"unknown pigment {code!r}: known pigments are "
            + ", ".join(f"{p.code} ({p.name})" for p in PIGMENTS.values())) from None


def base_parts(code: str) -> tuple[tuple[str, float], ...]:
    """The base pigments (with ε weights) a pigment code stands for: G → Y ½ + B ½; R → R 1."""
    return get_pigment(code).parts or ((code, 1.0),)


@dataclass(frozen=True)
class LocalField:
    """How a pigment grain polarises in the binder: pairs (w, L) of field weight and
    depolarisation factor along the grain's principal axes (Σ w = 1).  A sphere (or a dissolved
    molecule in its Lorentz cavity) has one pair (1, 1/3); a cylinder's come from its shape and
    orientation (`solver.geometry.depolarisation`).  dissolved: the pigment is dissolved as
    molecules, each base pigment's in its own cavity (a molecular G is Y and B molecules, so its
    ε' is the mix of theirs); a grain of a mixed pigment polarises as one body."""

    pairs: tuple[tuple[float, float], ...] = ((1.0, 1.0 / 3.0),)
    dissolved: bool = False

    def __post_init__(self):
        if not self.pairs or abs(sum(w for w, _ in self.pairs) - 1.0) > 1e-9 \
                or any(not (0.0 <= L <= 1.0) or w < 0 for w, L in self.pairs):
            raise ValueError(f"local-field pairs need weights summing to 1 and 0 ≤ L ≤ 1, got {self.pairs}")


#: a sphere's local field, and that of dissolved molecules (the Lorentz cavity)
SPHERE_FIELD = LocalField()
DISSOLVED_FIELD = LocalField(dissolved=True)


def local_field_eps(eps_particle, eps_host, field: LocalField = SPHERE_FIELD):
    """ε' = ε_h + Σ_j w_j ε_h(ε_p − ε_h)/(ε_h + L_j(ε_p − ε_h)): the permittivity whose scalar
    contrast equals the dipole response of a small grain ε_p in a host ε_h (the field inside it
    along axis j is ε_h/(ε_h + L_j(ε_p − ε_h)) times the outside one).  For a sphere (L = 1/3)
    ε' = ε_h + 3ε_h(ε_p − ε_h)/(ε_p + 2ε_h).  Exact for grains small against the wavelength in
    the pigment (docs/polarisation.md: the model and what it does to the colour against
    Maxwell's equations)."""
    contrast = eps_particle - eps_host
    return eps_host + sum(w * eps_host * contrast / (eps_host + L * contrast) for w, L in field.pairs)


@dataclass(frozen=True, eq=False)
class MaterialData:
    """Binder and pigment constants and n(λ), k(λ) spectra; `fingerprint` identifies the numbers.

    k: every base pigment's k; n: the pigments with a measured real index (the process
    pigments); the others have Re(η) = pigment_real_index (the paper's 1.4).

    local_field: None (pigments enter with their bulk ε: the paper's volume mix) or how the
    pigment polarises in the binder (`LocalField`): pigments then enter with `local_field_eps`.
    A request gives each layer its own (`TableRequest.layer_materials`)."""

    binder_index: float
    pigment_real_index: float
    wavelengths_nm: np.ndarray = field(repr=False)          # [n] strictly increasing
    k: dict = field(repr=False)                             # base code → k [n]
    source: str = "package data"
    local_field: LocalField | None = None
    n: dict = field(default_factory=dict, repr=False)       # base code → measured n [n]

    def with_local_field(self, field: LocalField = SPHERE_FIELD) -> "MaterialData":
        return dataclasses.replace(self, local_field=field)

    @property
    def fingerprint(self) -> str:
        h = hashlib.sha256()
        h.update(repr((float(self.binder_index), float(self.pigment_real_index),
                       sorted((c, p.parts) for c, p in PIGMENTS.items()))).encode())
        if self.local_field is not None:
            h.update(repr(("local field", self.local_field.pairs, self.local_field.dissolved)).encode())
        h.update(np.ascontiguousarray(self.wavelengths_nm, dtype=np.float64).tobytes())
        for code in sorted(self.k):
            h.update(code.encode() + np.ascontiguousarray(self.k[code], dtype=np.float64).tobytes())
        for code in sorted(self.n):
            h.update(b"n" + code.encode() + np.ascontiguousarray(self.n[code], dtype=np.float64).tobytes())
        return h.hexdigest()[:16]

    def __eq__(self, other) -> bool:
        return isinstance(other, MaterialData) and other.fingerprint == self.fingerprint

    def __hash__(self) -> int:
        return hash(self.fingerprint)

    @property
    def range_nm(self) -> tuple[float, float]:
        return float(self.wavelengths_nm[0]), float(self.wavelengths_nm[-1])

    def check_range(self, wavelengths_nm, what: str = "wavelengths") -> None:
        """Raise ValueError when a wavelength lies outside the spectra (no silent clamping)."""
        wl = np.asarray(wavelengths_nm, dtype=float)
        lo, hi = self.range_nm
        if wl.size and (wl.min() < lo - 1e-9 or wl.max() > hi + 1e-9):
            raise ValueError(f"{what} {wl.min():g}–{wl.max():g} nm lie outside the pigment data "
                             f"({lo:g}–{hi:g} nm); choose wavelengths inside it")

    def binder_eps(self, wavelength_nm) -> np.ndarray:
        """Relative permittivity of the binder (no dispersion)."""
        return np.full(np.shape(wavelength_nm), self.binder_index**2, dtype=complex)

    def pigment_k(self, code: str, wavelength_nm) -> np.ndarray:
        """k(λ) of a base pigment (R, Y, B, C, M, K); clamped outside the data (the request
        refuses that)."""
        if code not in self.k:
            raise ValueError(f"pigment {code!r} has no tabulated k (it is a mix); use pigment_eps")
        return np.interp(np.asarray(wavelength_nm, dtype=float), self.wavelengths_nm, self.k[code])

    def pigment_n(self, code: str, wavelength_nm) -> np.ndarray:
        """Re(η)(λ) of a base pigment: its measured n, or the paper's constant where it has none."""
        wl = np.asarray(wavelength_nm, dtype=float)
        if code in self.n:
            return np.interp(wl, self.wavelengths_nm, self.n[code])
        if code not in self.k:
            raise ValueError(f"pigment {code!r} has no tabulated index (it is a mix); use pigment_eps")
        return np.full(wl.shape, self.pigment_real_index)

    def pigment_eps(self, code: str, wavelength_nm) -> np.ndarray:
        """Relative permittivity ε = η² of a pigment (mixes ε-weighted) at λ in nm; with
        local_field, the local-field permittivity of its grains in the binder."""
        if self.local_field is None:
            return self._bulk_eps(code, wavelength_nm)
        host = self.binder_eps(wavelength_nm)
        if self.local_field.dissolved:               # each base pigment's molecules in their cavity
            return sum(w * local_field_eps(self._bulk_eps(c, wavelength_nm), host, self.local_field)
                       for c, w in base_parts(code))
        # a grain (of a mixed pigment too: a G grain is the Y–B mix, then its local field)
        return local_field_eps(self._bulk_eps(code, wavelength_nm), host, self.local_field)

    def _bulk_eps(self, code: str, wavelength_nm) -> np.ndarray:
        pig = get_pigment(code)
        if pig.parts:
            return sum(w * self._bulk_eps(c, wavelength_nm) for c, w in pig.parts)
        return (self.pigment_n(code, wavelength_nm) + 1j * self.pigment_k(code, wavelength_nm)) ** 2


#: the spectra file's columns: "k_<name>" (every base pigment), "n_<name>" (measured n)
_BASE_CODES = {p.name: p.code for p in PIGMENTS.values() if not p.parts}


def _columns(header: str, source: str) -> dict[tuple[str, str], int]:
    """{(quantity, code): column} from the file's header line "wavelength_nm,k_red,…,n_cyan,…"."""
    names = [h.strip() for h in header.split(",")]
    out = {}
    for i, name in enumerate(names[1:], start=1):
        quantity, _, pigment = name.partition("_")
        if quantity not in ("n", "k") or pigment not in _BASE_CODES:
            raise ValueError(f"{source}: unknown column {name!r}; expected k_<pigment> or n_<pigment> "
                             f"with pigment one of {', '.join(_BASE_CODES)}")
        out[(quantity, _BASE_CODES[pigment])] = i
    missing = [n for n, c in _BASE_CODES.items() if ("k", c) not in out]
    if names[0] != "wavelength_nm" or missing:
        raise ValueError(f"{source}: need a wavelength_nm column and k_<pigment> for "
                         f"{', '.join(missing) or 'every pigment'}")
    return out


def load_material_data(path: str | Path | None = None) -> MaterialData:
    """Read a spectra file (default: the package's `solver/data/pigments_nk.csv`)."""
    if path is None:
        text = resources.files("solver.data").joinpath("pigments_nk.csv").read_text()
        source = "package data"
    else:
        text = Path(path).read_text()
        source = str(path)
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    cols = _columns(lines[0], source)
    data = np.loadtxt(lines[1:], delimiter=",", ndmin=2)
    wl = data[:, 0]
    if wl.size < 2 or np.any(np.diff(wl) <= 0) or not np.all(np.isfinite(data)):
        raise ValueError(f"{source}: pigment spectra must be finite with increasing wavelengths")
    return MaterialData(BINDER_INDEX, PIGMENT_REAL_INDEX, wl,
                        {c: data[:, i] for (q, c), i in cols.items() if q == "k"}, source,
                        n={c: data[:, i] for (q, c), i in cols.items() if q == "n"})


@lru_cache(maxsize=1)
def default_materials() -> MaterialData:
    """The package's material data (read once)."""
    return load_material_data()


def binder_eps(wavelength_nm) -> np.ndarray:
    """Binder permittivity from the package data."""
    return default_materials().binder_eps(wavelength_nm)


def pigment_k(code: str, wavelength_nm) -> np.ndarray:
    """k(λ) of a base pigment from the package data."""
    return default_materials().pigment_k(code, wavelength_nm)


def pigment_eps(code: str, wavelength_nm) -> np.ndarray:
    """Pigment permittivity from the package data."""
    return default_materials().pigment_eps(code, wavelength_nm)
