"""One record per cell — what the CSV holds and the findings report reads.

CSV columns (docs/figures.md): figure, ink, column, grains, particles, tilt_deg, accuracy, tier,
status, L, a, b, L_se, a_se, b_se, se_source, cache_key, computed, seconds, reason.
The colour is CIELAB (D65) of the ink on paper r = 0.9 under diffuse light seen at 0°
(`cell_colour`); *_se its propagated standard error (empty: unknown).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .cell_colour import CellColour, cell_colour
from .cells import CellResult

FIELDS = ("figure", "ink", "column", "grains", "particles", "tilt_deg", "accuracy", "tier", "status",
          "L", "a", "b", "L_se", "a_se", "b_se", "se_source", "cache_key", "computed", "seconds", "reason")


@dataclass(frozen=True)
class CellRecord:
    figure: str
    ink: str                  # ink spec (row)
    column: str               # the column's particle spec, as the figure names it
    grains: str               # the paper's column label
    particles: str            # the table's particle label (e.g. with the tilt used)
    tilt_deg: float | None
    accuracy: str
    tier: str
    status: str               # 'ok' or 'failed'
    lab: np.ndarray           # (L*, a*, b*); NaN for a failed cell
    se: np.ndarray            # their standard errors; NaN where unknown
    se_source: str
    cache_key: str
    computed: bool            # built by this run (False: from the cache)
    seconds: float
    reason: str = ""

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def record_of(figure: str, result: CellResult, accuracy: str, colour: CellColour | None = None) -> CellRecord:
    """The CSV record of a cell; `colour` is its cell_colour (computed here when not given)."""
    plan = result.plan
    key = plan.request.key() if plan.request is not None else ""
    common = dict(figure=figure, ink=plan.row.spec, column=plan.column.particles, grains=plan.column.label,
                  particles=plan.particles, tilt_deg=plan.tilt_deg, accuracy=accuracy,
                  computed=result.built, seconds=result.seconds)
    if not result.ok:
        nan = np.full(3, np.nan)
        return CellRecord(**common, tier="", status="failed", lab=nan, se=nan, se_source="", cache_key=key,
                          reason=result.error or "")
    colour = colour or cell_colour(result.table)
    return CellRecord(**common, tier=str(result.table.meta.get("tier", "")), status="ok", lab=colour.lab,
                      se=colour.se, se_source=colour.source, cache_key=str(result.table.meta.get("cache_key", key)))


def plural(count: int, noun: str) -> str:
    """'1 cell', '4 cells'."""
    return f"{count} {noun}{'' if count == 1 else 's'}"


def run_counts(records: list[CellRecord]) -> str:
    """What this run did with its cells (the console and the report): '4 cells: 3 drawn (1
    computed by this run, 2 from the cache), 1 failed'."""
    drawn = [r for r in records if r.ok]
    computed = sum(r.computed for r in drawn)
    return (f"{plural(len(records), 'cell')}: {len(drawn)} drawn ({computed} computed by this run, "
            f"{len(drawn) - computed} from the cache), {len(records) - len(drawn)} failed")


def _num(x, digits: int = 4) -> str:
    return "" if x is None or not math.isfinite(float(x)) else f"{float(x):.{digits}f}"


def write_csv(records: list[CellRecord], path) -> Path:
    path = Path(path)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(FIELDS)
        for r in records:
            w.writerow([r.figure, r.ink, r.column, r.grains, r.particles, _num(r.tilt_deg, 1), r.accuracy, r.tier,
                        r.status, *(_num(v, 3) for v in r.lab), *(_num(v, 3) for v in r.se), r.se_source,
                        r.cache_key, "yes" if r.computed else "no", f"{r.seconds:.1f}", r.reason])
    return path


def read_csv(path) -> list[CellRecord]:
    def f(text: str) -> float:
        return float(text) if text != "" else math.nan

    out = []
    with open(path, newline="", encoding="utf-8") as fh:
        for row in csv.DictReader(fh):
            out.append(CellRecord(
                figure=row["figure"], ink=row["ink"], column=row["column"], grains=row["grains"],
                particles=row["particles"], tilt_deg=None if row["tilt_deg"] == "" else float(row["tilt_deg"]),
                accuracy=row["accuracy"], tier=row["tier"], status=row["status"],
                lab=np.array([f(row[k]) for k in ("L", "a", "b")]),
                se=np.array([f(row[k]) for k in ("L_se", "a_se", "b_se")]), se_source=row["se_source"],
                cache_key=row["cache_key"], computed=row["computed"] == "yes", seconds=float(row["seconds"]),
                reason=row["reason"]))
    return out
