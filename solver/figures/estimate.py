"""How long a cell's table will take (seconds), for the figure's up-front estimate and its ETA.

The table preflight's model (`solver.table.preflight.estimate`) is the one home of the cost
model; until its geometry cost (`solver.geometry.geometry_cost`) lands, particle inks fall back
to the preflight's own wave-solve term alone (geometry left out: it is a few % of a build).
"""

from __future__ import annotations

import math

from ..table import preflight
from ..table.request import TableRequest
from ..table.wave_tier import needs_below


def _solves_only(request: TableRequest, workers: int) -> float:
    g, w = request.grids, request.wave
    voxels = math.prod(w.grid)
    solves = (w.realizations * len(g.wavelengths_nm) * int(g.solved_mask.sum()) * w.azimuths
              * (2 if needs_below(request) else 1))
    per_solve = (preflight.APPLICATIONS_PER_SOLVE * preflight.SECONDS_PER_VOXEL_LOG
                 * voxels * math.log2(max(voxels, 2)))
    return solves * per_solve / max(1, workers)


def estimate_seconds(request: TableRequest, workers: int) -> float:
    """Expected wall time (s) of building the request's table with `workers` local workers."""
    try:
        return float(preflight.estimate(request, workers).seconds)
    except ImportError:                      # preflight's geometry cost model is not on main yet
        return _solves_only(request, workers)
