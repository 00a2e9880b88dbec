"""The binder's top surface over a rough top (paper Fig. 5).

Where no particle stands out, the binder top is flat at z = 0.  A particle whose top is above
z = 0 lifts the binder: the binder wets it up to its top and falls away around it with the
meniscus slope tan α (α = MENISCUS_ANGLE_RAD), so the surface height is the lower envelope

    z_s(x, y) = min(0, min over protruding particles p, points q of p: q_z + tan α·|(x, y) − q_xy|)

(z grows downward, so smaller z is higher).  Each shape gives its part (`Shape.meniscus_nm`): for
a sphere of radius R at depth z_c the spherical cap z_c − √(R² − ρ²) for ρ ≤ R sin α and the
tangent cone z_c − R/cos α + ρ tan α beyond; for other shapes the minimum over a dense sample of
their surface (a few nm).  Everything below z_s (to z = H) is binder or particle, everything
above is air.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .bodies import Bodies
from .neighbours import wrap_xy

MENISCUS_ANGLE_RAD = np.deg2rad(45.0)


def binder_surface_nm(bodies: Bodies, centres: np.ndarray, period_nm, x_nm, y_nm) -> np.ndarray:
    """Height z_s (nm, ≤ 0) of the binder top at points (x, y) (arrays of one shape)."""
    x = np.asarray(x_nm, dtype=float)
    y = np.asarray(y_nm, dtype=float)
    z = np.zeros(x.shape)
    hz = bodies.half_extent_nm(2)
    top = centres[:, 2] - hz
    prot = np.flatnonzero(top < 0)
    if prot.size == 0 or z.size == 0:
        return z
    tan_a = np.tan(MENISCUS_ANGLE_RAD)
    pts = wrap_xy(np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1), period_nm)[:, :2]
    tree = cKDTree(pts, boxsize=period_nm)
    lateral = np.maximum(bodies.half_extent_nm(0), bodies.half_extent_nm(1))
    reach = lateral + (-top) / tan_a
    cxy = wrap_xy(centres[prot], period_nm)[:, :2]
    flat = z.ravel()
    for p, c, near in zip(prot, cxy, tree.query_ball_point(cxy, r=reach[prot])):
        if not near:
            continue
        near = np.asarray(near)
        dx = pts[near, 0] - c[0]
        dy = pts[near, 1] - c[1]
        dx -= period_nm[0] * np.round(dx / period_nm[0])
        dy -= period_nm[1] * np.round(dy / period_nm[1])
        f = bodies.shape.meniscus_nm(bodies.radii_nm[p], bodies.half_lengths_nm[p], bodies.axes[p], centres[p, 2],
                                     dx, dy, MENISCUS_ANGLE_RAD)
        if f is not None:
            np.minimum.at(flat, near, f)
    return np.minimum(flat.reshape(x.shape), 0.0)
