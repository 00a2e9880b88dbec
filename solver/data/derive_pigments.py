"""Derive the package's pigment spectra from the raw refractiveindex.info files.

Run once by a maintainer (not at install or run time):

    python -m solver.data.derive_pigments RAW_DIR DATABASE_DIR > solver/data/pigments_nk.csv

RAW_DIR holds the paper's stand-in spectra as CSV (wavelength_nm,n,k; converted from the
database's YAML, values unchanged); DATABASE_DIR is a checkout of the refractiveindex.info
database (https://github.com/polyanskiy/refractiveindex.info-database, commit ff11b589, CC0 1.0),
whose YAML files the process pigments are read from.

The paper's pigments (k only: the model gives them Re(eta) = 1.4, paper §3.1):
  Red    = Rhodamine 6G film, Seckin et al., ACS Appl. Mater. Interfaces 15, 43124 (2023),
           doi:10.1021/acsami.3c07532.
  Yellow = F8BT film, Kamptner, Scharber, Schiek, ChemPhysChem e202400233 (2024),
           doi:10.1002/cphc.202400233.
  Blue   = ZZ50 (c-PCPDTBT) film, same reference.

The process pigments (n and k, both measured; docs/printing.md "Process inks"):
  Cyan    = SQIB squaraine film, Funke, Duwe, Balzer, Thiesen, Hingerl, Schiek, J. Phys. Chem.
            Lett. 12, 3053 (2021), doi:10.1021/acs.jpclett.1c00317
            (`organic/C32H44N2O6 - SQIB/nk/Funke-{alpha,beta,gamma}.yml`). Biaxial: the
            isotropic mean of the three axes, n_iso = (n_α + n_β + n_γ)/3, likewise k. The data
            start at 450 nm: below it n and k are held at their 450-nm values (the film's
            absorption minimum, k ≈ 0.07; what that choice can move is measured by
            `python -m benchmarks design`).
  Magenta = Rhodamine 6G film, Seckin et al. 2023 (as Red), with its measured n
            (`organic/C28H31ClN2O3 - Rhodamine 6G/nk/Seckin.yml`).
  Black   = arc-evaporated amorphous carbon film, Arakawa, Williams, Inagaki, J. Appl. Phys. 48,
            3176 (1977), doi:10.1063/1.324057 (`main/C/nk/Arakawa.yml`): n 2.06–2.43, k 0.70–0.91
            over 380–780 nm.
Uniaxial films are made isotropic with k_iso = (2 k_o + k_e) / 3 (docs/design.md §2), biaxial
ones with the mean of the three axes; then all spectra are linearly resampled to a 5 nm grid
over 360–830 nm (Mitsuba's spectral range), held constant beyond a file's range.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

GRID_NM = np.arange(360.0, 830.0 + 0.5, 5.0)

#: the paper's pigments: CSV files in RAW_DIR, (file, weight); only k is kept
K_SOURCES = {
    "red": [("red_rhodamine6G_Seckin.csv", 1.0)],
    "yellow": [("yellow_F8BT_Kamptner-o.csv", 2.0 / 3.0), ("yellow_F8BT_Kamptner-e.csv", 1.0 / 3.0)],
    "blue": [("blue_ZZ50_cPCPDTBT_Kamptner-o.csv", 2.0 / 3.0),
             ("blue_ZZ50_cPCPDTBT_Kamptner-e.csv", 1.0 / 3.0)],
}
_SQIB = "database/data/organic/C32H44N2O6 - SQIB/nk/Funke-{}.yml"
#: the process pigments: YAML files in the database checkout, (path, weight); n and k kept
NK_SOURCES = {
    "cyan": [(_SQIB.format(axis), 1.0 / 3.0) for axis in ("alpha", "beta", "gamma")],
    "magenta": [("database/data/organic/C28H31ClN2O3 - Rhodamine 6G/nk/Seckin.yml", 1.0)],
    "black": [("database/data/main/C/nk/Arakawa.yml", 1.0)],
}


def _read_csv(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=2)
    return data[:, 0], data[:, 1], data[:, 2]


_TABULATED = re.compile(r"type:\s*tabulated nk\s*\n\s*data:\s*\|\s*\n(.*?)(?:\n\s*-\s*type:|\n\S|\Z)", re.S)


def read_database_nk(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(λ nm, n, k) of a refractiveindex.info YAML file's `tabulated nk` block, λ rising."""
    match = _TABULATED.search(Path(path).read_text(encoding="utf-8"))
    if match is None:
        raise ValueError(f"{path}: no 'tabulated nk' data block")
    rows = np.array([line.split() for line in match.group(1).strip().splitlines()], dtype=float)
    rows = rows[np.argsort(rows[:, 0])]
    return 1000.0 * rows[:, 0], rows[:, 1], rows[:, 2]          # µm → nm


def _mix(parts, read) -> tuple[np.ndarray, np.ndarray]:
    n = np.zeros_like(GRID_NM)
    k = np.zeros_like(GRID_NM)
    for source, weight in parts:
        wl, nn, kk = read(source)
        n += weight * np.interp(GRID_NM, wl, nn)          # held at the end values outside the data
        k += weight * np.interp(GRID_NM, wl, kk)
    return n, np.clip(k, 0.0, None)


def derive(raw_dir: Path, database_dir: Path) -> dict[str, dict[str, np.ndarray]]:
    """{"k": {name: k(GRID_NM)}, "n": {name: n(GRID_NM)}}: k of every pigment, n of the
    process pigments."""
    out: dict[str, dict[str, np.ndarray]] = {"k": {}, "n": {}}
    for name, parts in K_SOURCES.items():
        out["k"][name] = _mix(parts, lambda f: _read_csv(Path(raw_dir) / f))[1]
    for name, parts in NK_SOURCES.items():
        out["n"][name], out["k"][name] = _mix(parts, lambda f: read_database_nk(Path(database_dir) / f))
    return out


def columns(spectra: dict[str, dict[str, np.ndarray]]) -> list[tuple[str, np.ndarray]]:
    """The file's columns in order: k of the paper's pigments, then n, k of each process pigment."""
    cols = [(f"k_{name}", spectra["k"][name]) for name in K_SOURCES]
    for name in NK_SOURCES:
        cols += [(f"n_{name}", spectra["n"][name]), (f"k_{name}", spectra["k"][name])]
    return cols


def main(argv: list[str]) -> int:
    if len(argv) != 3:
        print("usage: python -m solver.data.derive_pigments RAW_DIR DATABASE_DIR", file=sys.stderr)
        return 2
    cols = columns(derive(Path(argv[1]), Path(argv[2])))
    print("# Pigment optical constants for inkbsdf, derived by solver/data/derive_pigments.py from the "
          "refractiveindex.info database (CC0, commit ff11b589); sources and DOIs in its docstring")
    print("# Red=Rhodamine 6G (Seckin 2023), Yellow=F8BT, Blue=ZZ50/c-PCPDTBT (Kamptner 2024): k only, "
          "k_iso=(2k_o+k_e)/3; Cyan=SQIB (Funke 2021, mean of 3 axes, held at 450 nm below it), "
          "Magenta=Rhodamine 6G (Seckin 2023), Black=amorphous carbon (Arakawa 1977): n and k")
    print(",".join(["wavelength_nm"] + [name for name, _ in cols]))
    for i, wl in enumerate(GRID_NM):
        print(",".join([f"{wl:.1f}"] + [f"{values[i]:.6f}" for _, values in cols]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
