"""The paper's findings (§3.3, docs/design.md §6) tested as the paper states them, on every pair
of cells of a figure that a finding speaks of (docs/findings.md).

Each finding is a set of checks `value > 0` (value: a difference of saturations s = C*/L* or of
colour differences, FINDINGS says which), one per pair of cells it applies to:

1. saturation grows with concentration — the same column, the next load of equal proportions;
2. saturation grows as grains shrink — real size steps of one shape: molecular → 30 → 100 → 200
   → 300 → 450-nm balls; molecular → 100 → 200 → 300-nm cylinders of one orientation (never a
   step to an agglutinated or rough-top column);
3. the size effect (ΔE to molecular) is strongest at low concentration — plain grains only;
4. agglutinated grains look like bigger ones: their saturation lies between that of their own
   size and of the next larger size — in Fig. 8's rows (15 % and 30 %), where the paper shows it;
5. a Y+B grain mix approaches G grains of equal composition as the grains shrink;
6. a rough top changes little: less than the step to the next grain size;
7. the role of size is practically the same for balls and cylinders: replacing balls by
   isotropic cylinders of the same effective size changes the colour less than a size step of
   the balls does;
8. at 15 % finite grains clearly differ from the molecular mix in transmittance (Fig. 9): the
   transmitted colour at normal incidence of 300-nm grains differs from the molecular layer's by
   more than one just-noticeable difference (ΔE2000 = 1).

Verdicts (Student's t): each check's standard error comes from its cells' colour standard
errors by sampling (each cell's Lab drawn from a normal with its standard error; cells are
independent: their tables come from different random cells), cell by cell, and its degrees of
freedom are Welch–Satterthwaite's from the cells' own (realizations − 1; an exact film has
infinitely many). With t the two-sided 95 % quantile:

    agrees       value >  t·SE
    contradicts  value < −t·SE
    undecided    otherwise (within the noise, or a cell's standard error unknown)
    not testable a cell of the check failed (not a verdict)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from solver.colour.cie import delta_e76, delta_e2000, saturation
from solver.geometry.spec import parse_particles
from solver.inks import parse_ink
from .paper_grid import FIG8_ROWS, FIG9_COLUMNS
from .records import CellRecord, run_counts

CONFIDENCE = 0.95
SAMPLES = 4000
JND_DE2000 = 1.0                 # finding 8: a just-noticeable colour difference
_PROPORTION_STEP = 0.05          # ink families: pigment proportions rounded to this (Y42+B8 ~ Y25+B5)
_FIG8_INKS = frozenset(r.spec for r in FIG8_ROWS)


@dataclass(frozen=True)
class Check:
    finding: int
    where: str
    value: float
    se: float
    dof: float
    verdict: str

    @property
    def t_critical(self) -> float:
        return t_critical(self.dof)


def t_critical(dof: float) -> float:
    """Two-sided Student's t quantile at CONFIDENCE for `dof` degrees of freedom (normal: inf)."""
    from scipy.stats import norm, t

    q = 0.5 + CONFIDENCE / 2
    return float(norm.ppf(q)) if math.isinf(dof) else float(t.ppf(q, dof))


def _ink_key(spec: str) -> str:
    return parse_ink(spec).label


def _col_key(spec: str) -> str:
    p = parse_particles(spec)
    return "molecular" if p is None else p.label


def _family(spec: str) -> tuple:
    ink = parse_ink(spec)
    total = ink.total_fraction
    return tuple(sorted((c, round(f / total / _PROPORTION_STEP) * _PROPORTION_STEP) for c, f in ink.components))


def _plain(spec) -> bool:
    """Grains of one size and shape, dispersed, under a flat top: a member of a size series."""
    return spec is not None and spec.agglutination_kT == 0 and spec.rough_top == 0 and spec.size_spread == 0


class _Grid:
    """The records indexed by (ink, column), with the figure's row and column order."""

    def __init__(self, records: list[CellRecord]):
        self.cells = {(_ink_key(r.ink), _col_key(r.column)): r for r in records}
        self.inks = list(dict.fromkeys(_ink_key(r.ink) for r in records))
        self.columns = list(dict.fromkeys(_col_key(r.column) for r in records))

    def has(self, ink, col) -> bool:
        return (ink, col) in self.cells

    def families(self):
        """Inks of equal pigment proportions, by increasing concentration."""
        groups: dict = {}
        for ink in self.inks:
            groups.setdefault(_family(ink), []).append(ink)
        return [sorted(v, key=lambda s: parse_ink(s).total_fraction) for v in groups.values() if len(v) > 1]

    def size_series(self, with_molecular: bool = True):
        """Real size steps: plain columns of one shape (and orientation) by size, molecular (size
        0 of every shape) first when present."""
        groups: dict = {}
        for col in self.columns:
            p = parse_particles(col) if col != "molecular" else None
            if _plain(p):
                groups.setdefault((p.shape, p.orientation), []).append(col)
        mol = ["molecular"] if with_molecular and "molecular" in self.columns else []
        series = (mol + sorted(v, key=lambda c: parse_particles(c).diameter_nm) for v in groups.values())
        return [s for s in series if len(s) > 1]

    def plain_columns(self):
        return [c for c in self.columns if c != "molecular" and _plain(parse_particles(c))]

    def next_larger(self, plain: str) -> str | None:
        """The next larger size of a plain column's series (None: the largest)."""
        series = next((s for s in self.size_series(False) if plain in s), None)
        if series is None or series.index(plain) == len(series) - 1:
            return None
        return series[series.index(plain) + 1]

    def variant_pairs(self, attribute: str):
        """(plain column, modified column) pairs differing only in `attribute` (e.g. rough_top)."""
        pairs = []
        for col in self.columns:
            p = parse_particles(col) if col != "molecular" else None
            if p is not None and getattr(p, attribute) > 0:
                plain = replace(p, **{attribute: 0.0}).label
                if plain in self.columns:
                    pairs.append((plain, col))
        return pairs


def _s(cell):
    return lambda labs: saturation(labs[cell])


def _de(a, b):
    return lambda labs: delta_e76(labs[a], labs[b])


def _short(col: str) -> str:
    return col.replace("molecular", "mol")


def _checks(grid: _Grid):
    """(finding, where, cells, value function, colour) for every pair each finding applies to;
    colour 'lab' (reflected) or 'lab_t' (transmitted, finding 8)."""
    out = []
    add = lambda n, where, cells, fn, colour="lab": out.append((n, where, cells, fn, colour))
    # 1. saturation grows with concentration
    for col in grid.columns:
        for fam in grid.families():
            for lo, hi in zip(fam, fam[1:]):
                a, b = (lo, col), (hi, col)
                add(1, f"{_short(col)}: {lo} → {hi}", (a, b), lambda L, a=a, b=b: _s(b)(L) - _s(a)(L))
    # 2. saturation grows as grains shrink: real size steps of one shape
    for ink in grid.inks:
        for series in grid.size_series():
            for small, big in zip(series, series[1:]):
                a, b = (ink, small), (ink, big)
                add(2, f"{ink}: {_short(small)} → {_short(big)}", (a, b), lambda L, a=a, b=b: _s(a)(L) - _s(b)(L))
    # 3. the size effect (ΔE to molecular) is stronger at the lower concentration (plain grains)
    if "molecular" in grid.columns:
        for col in grid.plain_columns():
            for fam in grid.families():
                for lo, hi in zip(fam, fam[1:]):
                    cells = ((lo, col), (lo, "molecular"), (hi, col), (hi, "molecular"))
                    add(3, f"{_short(col)}: {lo} vs {hi}", cells,
                        lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[2], c[3])(L))
    # 4. agglutinated grains lie between their own size and the next larger (Fig. 8's rows)
    for plain, aggl in grid.variant_pairs("agglutination_kT"):
        bigger = grid.next_larger(plain)
        if bigger is None:
            continue
        for ink in grid.inks:
            if ink not in _FIG8_INKS:
                continue
            cells = ((ink, plain), (ink, aggl), (ink, bigger))
            add(4, f"{ink}: {_short(plain)} ≥ agglutinated ≥ {_short(bigger)}", cells,
                lambda L, c=cells: np.minimum(_s(c[0])(L) - _s(c[1])(L), _s(c[1])(L) - _s(c[2])(L)))
    # 5. Y+B grains approach G grains of the same size (and composition) as the size shrinks
    for ink in grid.inks:
        comp = dict(parse_ink(ink).components)
        if set(comp) != {"Y", "B"} or abs(comp["Y"] - comp["B"]) > 1e-9:
            continue
        green = _ink_key(f"G{100 * (comp['Y'] + comp['B']):.6g}")
        if green not in grid.inks:
            continue
        for series in grid.size_series(with_molecular=False):
            for small, big in zip(series, series[1:]):
                cells = ((ink, big), (green, big), (ink, small), (green, small))
                add(5, f"{ink} vs {green}: {_short(small)} vs {_short(big)}", cells,
                    lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[2], c[3])(L))
    # 6. a rough top changes little: less than the step to the next grain size
    for flat, rough in grid.variant_pairs("rough_top"):
        series = next((s for s in grid.size_series(with_molecular=False) if flat in s), None)
        if series is None:
            continue
        k = series.index(flat)
        other = series[k - 1] if k > 0 else series[k + 1]
        for ink in grid.inks:
            cells = ((ink, flat), (ink, other), (ink, rough))
            add(6, f"{ink}: {_short(flat)} rough vs {_short(other)}", cells,
                lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[2], c[0])(L))
    # 7. balls and isotropic cylinders of one size differ less than a size step of the balls
    for col in grid.plain_columns():
        p = parse_particles(col)
        if p.shape.name != "sphere":
            continue
        cylinder = next((c for c in grid.plain_columns() if parse_particles(c).shape.name == "cylinder"
                         and parse_particles(c).orientation == "isotropic"
                         and parse_particles(c).diameter_nm == p.diameter_nm), None)
        bigger = grid.next_larger(col)
        if cylinder is None or bigger is None:
            continue
        for ink in grid.inks:
            cells = ((ink, col), (ink, bigger), (ink, cylinder))
            add(7, f"{ink}: {_short(col)} → {_short(cylinder)} vs → {_short(bigger)}", cells,
                lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[0], c[2])(L))
    # 8. at 15 %, finite grains differ from the molecular mix in transmittance (Fig. 9): the grains
    # Fig. 9 shows (300 nm), not every size — small grains tend to the molecular mix (finding 5)
    fig9_grains = {c.particles for c in FIG9_COLUMNS} - {"molecular"}
    if "molecular" in grid.columns:
        for ink in grid.inks:
            if abs(parse_ink(ink).total_fraction - 0.15) > 1e-9:
                continue
            for col in (c for c in grid.plain_columns() if c in fig9_grains):
                cells = ((ink, col), (ink, "molecular"))
                add(8, f"{ink}: {_short(col)} vs mol, transmitted", cells,
                    lambda L, c=cells: delta_e2000(L[c[0]], L[c[1]]) - JND_DE2000, "lab_t")
    return out


def _colour(record: CellRecord, colour: str):
    return (record.lab, record.se) if colour == "lab" else (record.lab_t, record.se_t)


def _verdict(value: float, se: float, dof: float) -> str:
    if not (np.isfinite(se) and dof > 0):
        return "undecided"
    bound = t_critical(dof) * se
    return "agrees" if value > bound else "contradicts" if value < -bound else "undecided"


def evaluate(records: list[CellRecord], seed: int = 0) -> list[Check]:
    """Every check of every finding on the records' grid."""
    grid = _Grid(records)
    rng = np.random.default_rng(seed)
    checks = []
    for finding, where, cells, fn, colour in _checks(grid):
        if not all(grid.has(*c) for c in cells):
            continue
        recs = {c: grid.cells[c] for c in cells}
        if not all(r.ok for r in recs.values()):
            checks.append(Check(finding, where, math.nan, math.nan, 0.0, "not testable"))
            continue
        nominal = {c: _colour(r, colour)[0] for c, r in recs.items()}
        value = float(fn(nominal))
        ses = {c: _colour(r, colour)[1] for c, r in recs.items()}
        if not all(np.all(np.isfinite(se)) for se in ses.values()):
            checks.append(Check(finding, where, value, math.nan, 0.0, "undecided"))
            continue
        parts, dof_terms = [], []
        for c in dict.fromkeys(cells):              # one cell's noise at a time: its share of the variance
            if not np.any(ses[c]):
                continue
            draws = dict(nominal)
            draws[c] = nominal[c] + rng.standard_normal((SAMPLES, 3)) * ses[c]
            var = float(np.var(fn(draws), ddof=1))
            parts.append(var)
            dof_terms.append(var * var / recs[c].se_dof if recs[c].se_dof > 0 else math.inf)
        total = sum(parts)
        se = math.sqrt(total)
        dof = math.inf if not parts or sum(dof_terms) == 0 else total * total / sum(dof_terms)
        if total > 0 and math.isinf(sum(dof_terms)):
            dof = 0.0                                # a cell with unknown degrees of freedom
        checks.append(Check(finding, where, value, se, dof, _verdict(value, se, dof)))
    return checks


FINDINGS = {
    1: ("Colour saturates with concentration",
        "s = C*/L* at the higher concentration minus s at the lower, same column and pigment proportions"),
    2: ("Colour saturates as grains shrink",
        "s of the smaller grains minus s of the next larger ones, same ink; real size steps of one shape "
        "(molecular = size 0), never to an agglutinated or rough-top column"),
    3: ("The size effect is strongest at low concentration",
        "ΔE76(column ↔ molecular) at the lower concentration minus at the next higher one; plain grains"),
    4: ("Agglutination looks like bigger grains",
        "the smaller of s(dispersed) − s(agglutinated) and s(agglutinated) − s(next larger size): positive when "
        "the agglutinated grains lie between their own size and the next larger; Fig. 8's rows (15 %, 30 %)"),
    5: ("A Y+B grain mix approaches G grains of equal composition as grains shrink",
        "ΔE76(Y+B ↔ G) for the larger grains minus for the next smaller ones"),
    6: ("A rough top changes little",
        "ΔE76(flat ↔ next grain size) minus ΔE76(rough ↔ flat), same ink"),
    7: ("The role of size is practically the same for balls and cylinders",
        "ΔE76(balls ↔ next larger balls) minus ΔE76(balls ↔ isotropic cylinders of the same effective size)"),
    8: ("At 15 % finite grains clearly differ from the molecular mix in transmittance (Fig. 9)",
        f"ΔE2000 of the transmitted colour at normal incidence (grains ↔ molecular) minus {JND_DE2000:g} "
        "(one just-noticeable difference)"),
}
VERDICTS = ("agrees", "undecided", "contradicts", "not testable")


def _number(c: Check) -> str:
    if not np.isfinite(c.value):
        return ""
    if not np.isfinite(c.se):
        return f" {c.value:+.3f} (SE unknown)"
    dof = "∞" if math.isinf(c.dof) else f"{c.dof:.1f}"
    return f" {c.value:+.3f} ± {c.se:.3f} (ν = {dof}, t = {c.t_critical:.2f})" if c.se > 0 else f" {c.value:+.3f} (exact)"


def summary_table(checks: list[Check]) -> list[str]:
    lines = ["| finding | checks | " + " | ".join(VERDICTS) + " |", "|---|---|" + "---|" * len(VERDICTS)]
    for n, (name, _) in FINDINGS.items():
        mine = [c for c in checks if c.finding == n]
        counts = [sum(c.verdict == v for c in mine) for v in VERDICTS]
        lines.append(f"| {n}. {name} | {len(mine)} | " + " | ".join(map(str, counts)) + " |")
    return lines


def report(records: list[CellRecord], title: str, checks: list[Check] | None = None) -> str:
    """The findings report (Markdown) of one figure run."""
    checks = evaluate(records) if checks is None else checks
    ok = [r for r in records if r.ok]
    sources = sorted({r.se_source for r in ok})
    lines = [f"# {title}: the paper's findings (§3.3) tested on the grid", "",
             f"{run_counts(records)}; model {', '.join(sorted({r.model for r in records}))}; accuracy "
             f"{', '.join(sorted({r.accuracy for r in records}))}; colour measured "
             f"{', '.join(sorted({r.measurement for r in records}))} on paper r = 0.9; saturation s = C*/L*.",
             f"A check agrees when its value exceeds t·SE, contradicts below −t·SE, and is undecided in between "
             f"(Student's t, two-sided {100 * CONFIDENCE:g} %, degrees of freedom from the cells' realizations; "
             f"standard errors from: {', '.join(sources)}; docs/findings.md).", ""] + summary_table(checks)
    for n, (name, definition) in FINDINGS.items():
        mine = [c for c in checks if c.finding == n]
        lines += ["", f"## {n}. {name}", "", f"Value: {definition}.", ""]
        if not mine:
            lines.append("No pair of cells of this figure to test it on.")
            continue
        exceptions = [c for c in mine if c.verdict != "agrees"]
        lines.append(f"{len(mine) - len(exceptions)} of {len(mine)} checks agree."
                     + (" The others:" if exceptions else ""))
        for c in sorted(exceptions, key=lambda c: (VERDICTS.index(c.verdict), c.where)):
            lines.append(f"- {c.verdict}: {c.where}{_number(c)}")
    failed = [r for r in records if not r.ok]
    if failed:
        lines += ["", "## Failed cells", ""] + [f"- {r.ink} × {r.grains} ({r.particles}): {r.reason}" for r in failed]
    return "\n".join(lines) + "\n"
