"""Perceived hue of CIELAB colours: the hue angle of Oklab (Ottosson 2020), a space whose lines
of constant hue follow constant perceived hue, where CIELAB's bend — most in the blues: a
saturated sRGB blue kept at its CIELAB hue while its chroma is halved looks violet (IPT and
CAM16 agree: ≈ +10° of perceived hue). Gamut mapping keeps this hue (docs/printing.md,
"Gamut mapping").

CIELAB colours here are relative to the D50 white (the press's measurement, docs/design.md §7);
Oklab is defined on D65 XYZ, reached by the Bradford adaptation. `lab_hue` inverts `oklab_hue`
at a given L*, C*: a table of the hue offset on (L*, C*, hue) read trilinearly, then Newton
steps on the exact forward map, so the two are inverse to round-off.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .cie import bradford, lab_to_xyz, white_xyz
from .srgb import SRGB_WHITE

# Oklab (Ottosson 2020): XYZ (D65, Y = 1) → LMS → cube root → Lab
_M1 = np.array([[0.8189330101, 0.3618667424, -0.1288597137],
                [0.0329845436, 0.9293118715, 0.0361456387],
                [0.0482003018, 0.2643662691, 0.6338517070]])
_M2 = np.array([[0.2104542553, 0.7936177850, -0.0040720468],
                [1.9779984951, -2.4285922050, 0.4505937099],
                [0.0259040371, 0.7827717662, -0.8086757660]])
_TABLE_L = np.linspace(0.0, 100.0, 21)
_TABLE_C = np.linspace(0.0, 200.0, 81)
_TABLE_H = np.linspace(0.0, 360.0, 181)           # Oklab hue nodes (the last = the first)
NEWTON_STEPS = 3


@lru_cache(maxsize=1)
def _to_d65() -> tuple[np.ndarray, np.ndarray]:
    d50 = white_xyz("D50", "2")
    return d50, bradford(d50, SRGB_WHITE).T


def lab_from_lch(L, C, h_deg) -> np.ndarray:
    """CIELAB [..., 3] of L*, C* and the CIELAB hue h (degrees), broadcast together."""
    h = np.radians(h_deg)
    return np.stack(np.broadcast_arrays(L, C * np.cos(h), C * np.sin(h)), axis=-1)


def _oklab(lab) -> np.ndarray:
    white, adapt = _to_d65()
    xyz = lab_to_xyz(np.asarray(lab, dtype=np.float64), white) @ adapt / SRGB_WHITE[1]
    return np.cbrt(xyz @ _M1.T) @ _M2.T


def oklab_hue(lab) -> np.ndarray:
    """Oklab hue in degrees [0, 360) of CIELAB (D50) colours [..., 3], taken about the Oklab
    point of the CIELAB neutral of the same L* (the two spaces' neutrals differ by round-off of
    the published matrices; about it, hue is smooth down to zero chroma)."""
    lab = np.asarray(lab, dtype=np.float64)
    ok = _oklab(lab) - _oklab(lab * np.array([1.0, 0.0, 0.0]))
    return np.degrees(np.arctan2(ok[..., 2], ok[..., 1])) % 360.0


def _wrap(deg):
    return (np.asarray(deg) + 180.0) % 360.0 - 180.0


@lru_cache(maxsize=1)
def _offset_table() -> np.ndarray:
    """[L, C, H]: CIELAB hue − Oklab hue (wrapped) at the Oklab hue nodes, per (L*, C*) node."""
    fine = np.linspace(0.0, 360.0, 1441)[:-1]
    Lg, Cg, hg = np.meshgrid(_TABLE_L, np.maximum(_TABLE_C, 1e-3), fine, indexing="ij")
    ok = np.unwrap(np.radians(oklab_hue(lab_from_lch(Lg, Cg, hg))), axis=-1)
    ok = np.degrees(ok - 2 * np.pi * np.floor(ok[..., :1] / (2 * np.pi)))   # start in [0, 360)
    table = np.empty(Lg.shape[:2] + (_TABLE_H.size,))
    for i in range(Lg.shape[0]):
        for j in range(Lg.shape[1]):
            row = ok[i, j]
            ext_ok = np.concatenate([row - 360.0, row, row + 360.0])
            ext_lab = np.concatenate([fine - 360.0, fine, fine + 360.0])
            table[i, j] = _wrap(np.interp(_TABLE_H, ext_ok, ext_lab) - _TABLE_H)
    return table


def _table_guess(L, C, h_ok) -> np.ndarray:
    """CIELAB hue at (L*, C*, Oklab hue) from the offset table (trilinear; hue periodic)."""
    from scipy.ndimage import map_coordinates

    coords = [np.clip(np.asarray(L, float), 0.0, 100.0) / 100.0 * (_TABLE_L.size - 1),
              np.clip(np.asarray(C, float), 0.0, 200.0) / 200.0 * (_TABLE_C.size - 1),
              (np.asarray(h_ok, float) % 360.0) / 360.0 * (_TABLE_H.size - 1)]
    coords = np.broadcast_arrays(*coords)
    shape = coords[0].shape
    offset = map_coordinates(_offset_table(), [c.ravel() for c in coords], order=1, mode="nearest")
    return (np.asarray(h_ok, float) + offset.reshape(shape)) % 360.0


def lab_hue(L, C, h_ok, exact: bool = True) -> np.ndarray:
    """The CIELAB hue (degrees) of the colour of lightness L*, chroma C* and Oklab hue `h_ok`.
    exact=False: the table's value alone (≈ 0.1°; what a search along a ray needs)."""
    h = _table_guess(L, C, h_ok)
    if not exact:
        return h
    C_safe = np.maximum(np.asarray(C, float), 1e-6)
    for _ in range(NEWTON_STEPS):
        f = _wrap(oklab_hue(lab_from_lch(L, C_safe, h)) - h_ok)
        df = _wrap(oklab_hue(lab_from_lch(L, C_safe, h + 1e-3)) - oklab_hue(lab_from_lch(L, C_safe, h))) / 1e-3
        h = (h - f / np.where(np.abs(df) > 1e-6, df, 1.0)) % 360.0
    return h


__all__ = ["oklab_hue", "lab_hue", "lab_from_lch"]
