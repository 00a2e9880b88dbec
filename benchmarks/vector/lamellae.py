"""Lamellar gratings: the grains' local field depends on where the field points (issue 22 item 2;
docs/vector_referee.md, "The oblique TM error").

A y-invariant grating of pigment lamellae in binder is the limit of cylinders lying along y:
for TE light (E ∥ y, along the lamellae) the field inside a lamella is the outside one (no
depolarisation, L = 0): the scalar TE solve is Maxwell's s exactly; for TM light in the x–z
plane the field crosses the lamellae along x (L = 1: D_x continuous, E inside = ε_h/ε times
the outside) and runs along them in z (L = 0).  The scalar TM solve is compared with grcwa's
p on the same voxels for three pigment permittivities of the lamella voxels:

* bulk ε (no local field: the paper's model);
* the tables' isotropic average for an oriented body whose axes are not known to the field:
  one third across (L = 1), two thirds along (L = 0);
* the field's own direction in the layer: across with weight cos²θ_l, along with sin²θ_l
  (θ_l the refraction angle in the binder) — what a polarisation-aware local field would use.
"""
from __future__ import annotations

import math

import numpy as np

from solver.materials import BINDER_INDEX, LocalField, local_field_eps
from solver.wave import Cell, Incidence, solve
from solver.wave.vecops import one_blas_thread

from .rcwa_layer import rcwa_rt

PERIOD_NM, THICK_NM, GRID = 800.0, 1000.0, (32, 32, 16)
EPS_HOST = BINDER_INDEX ** 2
RIDGES = {"weak ridge": 1.4 + 0.05j, "strong grating": 1.4 + 0.6j}


def _grating(eps_ridge: complex, fill: float = 0.35) -> np.ndarray:
    nx, ny, nz = GRID
    x = (np.arange(nx) + 0.5) / nx
    frac = (x < fill).astype(float)
    eps1 = EPS_HOST + (eps_ridge - EPS_HOST) * frac
    return np.broadcast_to(eps1[:, None, None], GRID).copy()


def _scalar(eps_ridge: complex, pol: str, lam: float, sigma: float) -> tuple[float, float]:
    cell = Cell(_grating(eps_ridge), (PERIOD_NM, PERIOD_NM), (0.0, THICK_NM))
    res = solve(cell, Incidence(lam, sigma), polarisation=pol, tol=1e-6)
    return res.R, res.T


def study(lam: float = 500.0, angles_deg=(0.0, 30.0, 60.0)) -> list[dict]:
    """Rows per ridge and σ: Maxwell s/p (R, T) and the scalar TE / TM with each ε model."""
    rows = []
    with one_blas_thread():
        for name, eta in RIDGES.items():
            eps_p = eta ** 2
            for deg in angles_deg:
                sigma = math.radians(deg)
                cos2 = 1.0 - (math.sin(sigma) / BINDER_INDEX) ** 2      # cos²θ_l in the binder
                models = {
                    "bulk": eps_p,
                    "isotropic": local_field_eps(eps_p, EPS_HOST,
                                                 LocalField(((1 / 3, 1.0), (2 / 3, 0.0)))),
                    "field direction": local_field_eps(eps_p, EPS_HOST,
                                                       LocalField(((cos2, 1.0), (1 - cos2, 0.0)))),
                }
                vec = rcwa_rt(_grating(eps_p), (PERIOD_NM, PERIOD_NM), THICK_NM, lam, sigma)
                row = dict(ridge=name, deg=deg, s=(vec.R[0], vec.T[0]), p=(vec.R[1], vec.T[1]),
                           te=_scalar(eps_p, "te", lam, sigma))
                for model, eps in models.items():
                    row[f"tm {model}"] = _scalar(eps, "tm", lam, sigma)
                rows.append(row)
    return rows


def print_study(rows: list[dict]) -> None:
    print(f"lamellar grating: period {PERIOD_NM:g} nm, 35 % pigment lamellae along y, "
          f"{THICK_NM:g} nm, grid {GRID}, λ 500 nm; ΔR, ΔT = scalar − Maxwell")
    print(f"{'ridge':<15} {'σ':>4}  {'TE vs s: ΔR, ΔT':<20} " + "  ".join(
        f"{'TM ' + m + ' vs p: ΔR, ΔT':<30}" for m in ("bulk", "isotropic", "field direction")))
    for r in rows:
        te = f"{r['te'][0] - r['s'][0]:+.4f} {r['te'][1] - r['s'][1]:+.4f}"
        tms = "  ".join(f"{r['tm ' + m][0] - r['p'][0]:+.4f} {r['tm ' + m][1] - r['p'][1]:+.4f}"
                        + " " * 16 for m in ("bulk", "isotropic", "field direction"))
        print(f"{r['ridge']:<15} {r['deg']:>4g}  {te:<20} {tms}")
