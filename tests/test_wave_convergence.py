"""Observed order of accuracy under grid refinement in z (the lateral order is asserted in
test_wave_grating.py against RCWA).  Full tables: docs/wave_solver.md."""
from __future__ import annotations

import math

import pytest

from solver.wave.validation import slab_error

ETA = 1.4 + 0.2j


def _order(errors):
    return [math.log2(a / b) for a, b in zip(errors, errors[1:])]


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
