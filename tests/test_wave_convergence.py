"""Observed order of accuracy under grid refinement in z (the lateral order is asserted in
test_wave_grating.py against RCWA).  Full tables: docs/wave_solver.md."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from solver.wave import Cell, Incidence, solve

sys.path.insert(0, str(Path(__file__).parent))
from test_wave_oracles import airy_te, layer_fraction  # noqa: E402

LAM, SIGMA, ETA = 500.0, 0.4, 1.4 + 0.2j


def _order(errors):
    return [math.log2(a / b) for a, b in zip(errors, errors[1:])]


def slab_error(eta, n, *, half_voxels, z_order=1):
    """|Δr| + |Δt| against Airy for a 1000-nm slab on n cells per 1000 nm (λ = 500, σ = 0.4).

    half_voxels: the slab sits on the grid [−h/2, 1000 + h/2], both face voxels half filled
    (own, volume-mean background); else it fills the grid and is carried by the contrast to a
    forced air background (ε_b = 1 + 0.01i)."""
    r, t, _, _ = airy_te(1.0, eta, 1.0, 1000.0, LAM, SIGMA)
    kz = 2 * math.pi / LAM * math.cos(SIGMA)
    if half_voxels:
        h = 1000.0 / n
        lo = -h / 2 + np.arange(n + 1) * h
        eps = 1 + (eta ** 2 - 1) * layer_fraction(lo, lo + h, 0.0, 1000.0)
        cell = Cell(np.broadcast_to(eps, (1, 1, n + 1)).copy(), (300.0, 300.0),
                    (-h / 2, 1000.0 + h / 2))
        res = solve(cell, Incidence(LAM, SIGMA), tol=1e-10, z_order=z_order)
        phase = np.exp(2j * kz * h / 2)          # the grid's faces lie h/2 outside the slab
    else:
        cell = Cell(np.full((1, 1, n), eta ** 2), (300.0, 300.0), (0.0, 1000.0))
        res = solve(cell, Incidence(LAM, SIGMA), tol=1e-11, eps_background=1.0 + 0.01j,
                    z_order=z_order)
        phase = 1.0
    return (abs(res.reflected.amp(0, 0) - r * phase)
            + abs(res.transmitted.amp(0, 0) - t * phase))


def test_sub_voxel_interface_is_second_order():
    """Half-filled, averaged face voxels at every resolution.  Measured orders 1.90, 1.97, 1.99
    (n = 16 … 128)."""
    errors = [slab_error(ETA, n, half_voxels=True) for n in (32, 64, 128)]
    assert min(_order(errors)) >= 1.8, errors


@pytest.mark.parametrize("z_order,bound", [(1, 3.5), (0, 1.8)])
def test_grid_aligned_contrast_slab_order(z_order, bound):
    """A binder slab carried by the contrast to a forced background (ε_b = air + 0.01i):
    linear Legendre functions per z-cell give O(h⁴) (measured ≈ 4.0), cell averages O(h²)."""
    errors = [slab_error(1.558, nz, half_voxels=False, z_order=z_order) for nz in (16, 32, 64)]
    assert min(_order(errors)) >= bound, errors
