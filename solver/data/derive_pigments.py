"""Derive the package's pigment extinction spectra from the raw refractiveindex.info files.

Run once by a maintainer (not at install or run time):

    python -m solver.data.derive_pigments /path/to/shared/data/pigments > solver/data/pigments_k.csv

Sources (refractiveindex.info database, commit ff11b589, CC0 1.0):
  Red    = Rhodamine 6G film, Seckin et al., ACS Appl. Mater. Interfaces 15, 43124 (2023).
  Yellow = F8BT film, Kamptner, Scharber, Schiek, ChemPhysChem e202400233 (2024).
  Blue   = ZZ50 (c-PCPDTBT) film, same reference.
Uniaxial films are made isotropic with k_iso = (2 k_o + k_e) / 3 (docs/design.md §2), then all
spectra are linearly resampled to a 5 nm grid over 360–830 nm (Mitsuba's spectral range).
Only k is kept: the model uses Re(eta) = 1.4 for every pigment (paper §3.1).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

GRID_NM = np.arange(360.0, 830.0 + 0.5, 5.0)

SOURCES = {
    "red": [("red_rhodamine6G_Seckin.csv", 1.0)],
    "yellow": [("yellow_F8BT_Kamptner-o.csv", 2.0 / 3.0), ("yellow_F8BT_Kamptner-e.csv", 1.0 / 3.0)],
    "blue": [("blue_ZZ50_cPCPDTBT_Kamptner-o.csv", 2.0 / 3.0),
             ("blue_ZZ50_cPCPDTBT_Kamptner-e.csv", 1.0 / 3.0)],
}


def _read_k(path: Path) -> tuple[np.ndarray, np.ndarray]:
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=2)
    return data[:, 0], data[:, 2]


def derive(raw_dir: Path) -> dict[str, np.ndarray]:
    """k_iso(λ) on GRID_NM for each pigment."""
    out = {}
    for name, parts in SOURCES.items():
        k = np.zeros_like(GRID_NM)
        for filename, weight in parts:
            wl, kk = _read_k(raw_dir / filename)
            k += weight * np.interp(GRID_NM, wl, kk)
        out[name] = np.clip(k, 0.0, None)
    return out


def main(argv: list[str]) -> int:
    spectra = derive(Path(argv[1]))
    print("# Pigment extinction k_iso(lambda) for inkbsdf, derived by solver/data/derive_pigments.py")
    print("# from refractiveindex.info (CC0): Red=Rhodamine 6G (Seckin 2023), Yellow=F8BT, "
          "Blue=ZZ50/c-PCPDTBT (Kamptner 2024); k_iso=(2k_o+k_e)/3; linear resampling to 5 nm")
    print("wavelength_nm,k_red,k_yellow,k_blue")
    for i, wl in enumerate(GRID_NM):
        print(f"{wl:.1f},{spectra['red'][i]:.6f},{spectra['yellow'][i]:.6f},{spectra['blue'][i]:.6f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
