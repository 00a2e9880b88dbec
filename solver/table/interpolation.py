"""The tables' one interpolant: piecewise linear in every grid coordinate (λ, σ, θ, Δφ).

The reduction spreads diffraction orders onto grid nodes with these hat weights, the reference
evaluator and the plugin interpolate with them, and `integrals` integrates them exactly.
"""

from __future__ import annotations

import numpy as np


def lerp_weights(grid, x) -> tuple[np.ndarray, np.ndarray]:
    """(i, t): lower node index and the upper node's hat value at x (the lower one's is 1 − t),
    x clamped to the grid's ends; x ≈ (1 − t)·grid[i] + t·grid[i + 1]."""
    grid = np.asarray(grid, dtype=float)
    x = np.clip(np.asarray(x, dtype=float), grid[0], grid[-1])
    i = np.clip(np.searchsorted(grid, x, side="right") - 1, 0, grid.size - 2)
    return i, (x - grid[i]) / (grid[i + 1] - grid[i])
