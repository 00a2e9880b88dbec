"""Orientations of an axisymmetric grain's symmetry axis a (unit, a_z ≥ 0: a and −a are one axis).

A spec's orientation mode (docs/design.md §3) says where the axes are drawn and how the packer
may turn them:

* 'isotropic': the whole sphere of directions; turns freely (about any axis ⟂ a);
* 'inplane': a in the layer plane (a_z = 0), or within tilt of it; turns about z only (keeping
  the elevation);
* 'vertical': a along the layer normal, or within tilt of it; does not turn.

The words name the *symmetry axis*, whatever the shape: a vertical rod stands up, a vertical
flake (an oblate spheroid) lies flat.  Shapes without an axis (spheres) take no orientation.
"""

from __future__ import annotations

import math

import numpy as np

ORIENTATIONS = ("isotropic", "inplane", "vertical")
#: Orientations that take an orientation spread (`tilt=`).
TILTED_ORIENTATIONS = ("inplane", "vertical")
#: Which rotations the packer may use, per orientation mode (None: a shape without an axis).
ROTATION = {"isotropic": "free", "inplane": "z", "vertical": "none", None: "none"}
#: How a figure's column header says it (axes, not the grain's long side: see the module doc).
ORIENTATION_LABELS = {"isotropic": "isotropic", "inplane": "horiz aligned", "vertical": "vertically aligned"}


def polar_range_rad(orientation: str, tilt_rad: float = 0.0) -> tuple[float, float]:
    """Range of the angle between the axis and the vertical that an orientation mode allows."""
    return {"vertical": (0.0, tilt_rad), "inplane": (0.5 * math.pi - tilt_rad, 0.5 * math.pi),
            "isotropic": (0.0, 0.5 * math.pi)}[orientation]


def sample_orientations(mode: str, n: int, rng: np.random.Generator, tilt_rad: float = 0.0) -> np.ndarray:
    """Unit axes (n, 3), a_z ≥ 0, uniform on the part of the sphere the mode allows (Archimedes:
    uniform on the sphere ⇔ a_z uniform), azimuth uniform:

    * 'isotropic': the whole sphere, a_z uniform in [0, 1];
    * 'vertical': the cap within tilt_rad of the vertical, a_z uniform in [cos tilt, 1]
      (tilt 0: all (0, 0, 1));
    * 'inplane': the band within tilt_rad of the layer plane, a_z uniform in [0, sin tilt]
      (tilt 0: a_z = 0)."""
    if mode not in ORIENTATIONS:
        raise ValueError(f"unknown orientation {mode!r}")
    if mode == "vertical" and tilt_rad == 0:
        return np.tile([0.0, 0.0, 1.0], (n, 1))
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    if mode == "isotropic":
        cos_t = rng.uniform(0.0, 1.0, n)
    elif mode == "vertical":
        cos_t = rng.uniform(np.cos(tilt_rad), 1.0, n)
    elif tilt_rad > 0:
        cos_t = rng.uniform(0.0, np.sin(tilt_rad), n)
    else:
        cos_t = np.zeros(n)
    sin_t = np.sqrt(1.0 - cos_t**2)
    return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=1)
