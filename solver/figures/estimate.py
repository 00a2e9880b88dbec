"""How long a cell's table will take (seconds), for the figure's up-front estimate and its ETA.

The table preflight's model (`solver.table.preflight.estimate`: geometry cost + wave solves) is
the one home of the cost model; this only asks it.
"""

from __future__ import annotations

from ..table import preflight
from ..table.request import TableRequest


def estimate_seconds(request: TableRequest, workers: int) -> float:
    """Expected wall time (s) of building the request's table with `workers` local workers."""
    return float(preflight.estimate(request, workers).seconds)
