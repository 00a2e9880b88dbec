"""One record per cell — what the CSV holds and the findings report reads.

CSV columns (docs/figures.md): figure, model, ink, column, grains, particles, tilt_deg, accuracy,
tier, status, measurement, L, a, b, L_se, a_se, b_se, se_source, se_method, se_dof, cache_key,
computed, seconds, reason. The colour is CIELAB of the ink on paper r = 0.9 as `measurement` names it
(geometry/illuminant/observer, `solver.colour.measurement`); *_se its standard error (empty:
unknown), computed as se_method says ('jackknife' over the realizations, or 'propagated' from the
nodes' standard errors; `solver.colour.table_colour`; empty in CSVs written before it was
recorded) with se_dof degrees of freedom (realizations − 1; 'inf' for an exact film or a model
bound); T_L, T_a, T_b (and *_se) the colour the layer transmits at normal incidence (Tbar at
σ = 0, the paper's Fig. 9 quantity) under the same illuminant and observer.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.colour.table_colour import TableColour, table_colour, transmitted_colour
from solver.paper import PAPER_ALBEDO
from .cells import CellResult, FigureSettings

FIELDS = ("figure", "model", "ink", "column", "grains", "particles", "tilt_deg", "accuracy", "tier", "status",
          "measurement", "L", "a", "b", "L_se", "a_se", "b_se", "se_source", "se_method", "se_dof", "T_L", "T_a", "T_b",
          "T_L_se", "T_a_se", "T_b_se", "cache_key", "computed", "seconds", "reason")
OPTIONAL_FIELDS = ("se_method",)     # absent from the CSVs of earlier versions: read as ""


@dataclass(frozen=True)
class CellRecord:
    figure: str
    model: str                # 'default' or 'paper' (figures.models)
    ink: str                  # ink spec (row)
    column: str               # the column's particle spec, as the figure names it
    grains: str               # the paper's column label
    particles: str            # the table's particle label (e.g. with the tilt used)
    tilt_deg: float | None
    accuracy: str
    tier: str
    status: str               # 'ok' or 'failed'
    measurement: str          # how the colour is measured, e.g. '45:0/D50/2°'
    lab: np.ndarray           # (L*, a*, b*); NaN for a failed cell
    se: np.ndarray            # their standard errors; NaN where unknown
    se_source: str
    se_dof: float             # degrees of freedom of se (inf: exact; 0: unknown)
    lab_t: np.ndarray         # transmitted colour (Tbar at 0°, Fig. 9's quantity) in CIELAB; NaN if failed
    se_t: np.ndarray          # its standard errors
    cache_key: str
    computed: bool            # built by this run (False: from the cache)
    seconds: float
    reason: str = ""
    se_method: str = ""       # how se was computed ('jackknife', 'propagated', …; "" when not recorded)

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def record_of(figure: str, result: CellResult, settings: FigureSettings,
              colour: TableColour | None = None) -> CellRecord:
    """The CSV record of a cell; `colour` is its table_colour (computed here when not given)."""
    plan = result.plan
    key = plan.request.key() if plan.request is not None else ""
    measurement = settings.colour_measurement
    common = dict(figure=figure, model=settings.model.name, ink=plan.row.spec, column=plan.column.particles,
                  grains=plan.column.label, particles=plan.particles, tilt_deg=plan.tilt_deg,
                  accuracy=settings.label, measurement=measurement.label, computed=result.built,
                  seconds=result.seconds)
    if not result.ok:
        nan = np.full(3, np.nan)
        return CellRecord(**common, tier="", status="failed", lab=nan, se=nan, se_source="", se_method="", se_dof=0.0,
                          lab_t=nan, se_t=nan, cache_key=key, reason=result.error or "")
    colour = colour or table_colour(result.table, PAPER_ALBEDO, measurement)
    through = transmitted_colour(result.table, measurement)
    return CellRecord(**common, tier=str(result.table.meta.get("tier", "")), status="ok", lab=colour.lab,
                      se=colour.se, se_source=colour.source, se_method=colour.method, se_dof=colour.dof, lab_t=through.lab, se_t=through.se,
                      cache_key=str(result.table.meta.get("cache_key", key)))


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
            w.writerow([r.figure, r.model, r.ink, r.column, r.grains, r.particles, _num(r.tilt_deg, 1), r.accuracy,
                        r.tier, r.status, r.measurement, *(_num(v, 3) for v in r.lab), *(_num(v, 3) for v in r.se),
                        r.se_source, r.se_method, _dof(r.se_dof), *(_num(v, 3) for v in r.lab_t), *(_num(v, 3) for v in r.se_t),
                        r.cache_key, "yes" if r.computed else "no",
                        f"{r.seconds:.1f}", r.reason])
    return path


def _dof(value: float) -> str:
    return "inf" if math.isinf(value) else f"{value:g}"


def read_csv(path) -> list[CellRecord]:
    def f(text: str) -> float:
        return float(text) if text != "" else math.nan

    out = []
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        missing = [k for k in FIELDS if k not in (reader.fieldnames or ()) and k not in OPTIONAL_FIELDS]
        if missing:
            raise ValueError(f"{path}: not a figure CSV of this version (no column {', '.join(missing)}); "
                             "draw the figure again with `ink-tables paper`")
        for row in reader:
            out.append(CellRecord(
                figure=row["figure"], model=row["model"], ink=row["ink"], column=row["column"], grains=row["grains"],
                particles=row["particles"], tilt_deg=None if row["tilt_deg"] == "" else float(row["tilt_deg"]),
                accuracy=row["accuracy"], tier=row["tier"], status=row["status"],
                measurement=row["measurement"],
                lab=np.array([f(row[k]) for k in ("L", "a", "b")]),
                se=np.array([f(row[k]) for k in ("L_se", "a_se", "b_se")]), se_source=row["se_source"],
                se_method=row.get("se_method") or "",
                se_dof=float(row["se_dof"] or 0.0),
                lab_t=np.array([f(row[k]) for k in ("T_L", "T_a", "T_b")]),
                se_t=np.array([f(row[k]) for k in ("T_L_se", "T_a_se", "T_b_se")]),
                cache_key=row["cache_key"], computed=row["computed"] == "yes", seconds=float(row["seconds"]),
                reason=row["reason"]))
    return out
