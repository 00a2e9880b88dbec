"""The paper's findings (§3.3, docs/design.md §6) tested on every row/column pair of a figure.

Each finding is a set of checks `value > 0` (value: a difference of saturations or of ΔE, see
FINDINGS), one per pair of cells it applies to.  A check's standard error comes from the cells'
colour standard errors by sampling (each cell's L*, a*, b* drawn independently from a normal
with its standard error; cells are independent: their tables come from different random cells),
so cells shared by both sides of a check are handled exactly.  Verdicts:

    agrees          value >  RESOLVED_SE · SE
    contradicts     value < −RESOLVED_SE · SE
    not resolved    otherwise (the difference is within the noise: not a contradiction)
    SE unknown      a cell's standard error is unknown (sign given, not judged)
    not testable    a cell of the check failed
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.geometry.spec import parse_particles
from solver.inks import parse_ink
from .cell_colour import delta_e, saturation
from .records import CellRecord, run_counts

RESOLVED_SE = 2.0
SAMPLES = 4000
_PROPORTION_STEP = 0.05       # ink families: pigment proportions rounded to this (Y42+B8 ~ Y25+B5)


@dataclass(frozen=True)
class Check:
    finding: int
    where: str
    value: float
    se: float
    verdict: str


def _ink_key(spec: str) -> str:
    return parse_ink(spec).label


def _col_key(spec: str) -> str:
    p = parse_particles(spec)
    return "molecular" if p is None else p.label


def _family(spec: str) -> tuple:
    ink = parse_ink(spec)
    total = ink.total_fraction
    return tuple(sorted((c, round(f / total / _PROPORTION_STEP) * _PROPORTION_STEP) for c, f in ink.components))


def _series_key(spec: str):
    """Columns that differ only in size share a key (None: molecular, size 0 of every series)."""
    p = parse_particles(spec)
    return None if p is None else (p.shape, p.orientation, p.agglutination_kT, p.rough_top, p.size_spread)


def _size(spec: str) -> float:
    p = parse_particles(spec)
    return 0.0 if p is None else p.diameter_nm


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
        """Columns differing only in size, smallest first (molecular first when present)."""
        groups: dict = {}
        for col in self.columns:
            key = _series_key(col)
            if key is not None:
                groups.setdefault(key, []).append(col)
        mol = ["molecular"] if with_molecular and "molecular" in self.columns else []
        series = (mol + sorted(v, key=_size) for v in groups.values())
        return [s for s in series if len(s) > 1]      # molecular + one grain size is a step too

    def variant_pairs(self, attribute: str):
        """(plain column, modified column) pairs differing only in `attribute` (e.g. rough_top)."""
        from dataclasses import replace

        pairs = []
        for col in self.columns:
            p = parse_particles(col)
            if p is not None and getattr(p, attribute) > 0:
                plain = replace(p, **{attribute: 0.0}).label
                if plain in self.columns:
                    pairs.append((plain, col))
        return pairs


def _s(cell):
    return lambda labs: saturation(labs[cell])


def _de(a, b):
    return lambda labs: delta_e(labs[a], labs[b])


def _checks(grid: _Grid):
    """(finding number, where, cells, value function) for every pair each finding applies to."""
    out = []
    short = lambda col: col.replace("molecular", "mol")
    # 1. saturation grows with concentration
    for col in grid.columns:
        for fam in grid.families():
            for lo, hi in zip(fam, fam[1:]):
                a, b = (lo, col), (hi, col)
                out.append((1, f"{short(col)}: {lo} → {hi}", (a, b), lambda L, a=a, b=b: _s(b)(L) - _s(a)(L)))
    # 2. saturation grows as grains shrink
    for ink in grid.inks:
        for series in grid.size_series():
            for small, big in zip(series, series[1:]):
                a, b = (ink, small), (ink, big)
                out.append((2, f"{ink}: {short(small)} vs {short(big)}", (a, b),
                            lambda L, a=a, b=b: _s(a)(L) - _s(b)(L)))
    # 3. the size effect (ΔE to molecular) is stronger at the lower concentration
    if "molecular" in grid.columns:
        for col in grid.columns:
            if col == "molecular":
                continue
            for fam in grid.families():
                for lo, hi in zip(fam, fam[1:]):
                    cells = ((lo, col), (lo, "molecular"), (hi, col), (hi, "molecular"))
                    out.append((3, f"{short(col)}: {lo} vs {hi}", cells,
                                lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[2], c[3])(L)))
    # 4. agglutinated grains are less saturated than dispersed ones (look bigger)
    for plain, aggl in grid.variant_pairs("agglutination_kT"):
        for ink in grid.inks:
            a, b = (ink, plain), (ink, aggl)
            out.append((4, f"{ink}: {short(plain)} vs agglutinated", (a, b), lambda L, a=a, b=b: _s(a)(L) - _s(b)(L)))
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
                out.append((5, f"{ink} vs {green}: {short(small)} vs {short(big)}", cells,
                            lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[2], c[3])(L)))
    # 6. a rough top changes little: less than the step to the next grain size
    for flat, rough in grid.variant_pairs("rough_top"):
        series = next((s for s in grid.size_series(with_molecular=False) if flat in s), None)
        if series is None:
            continue
        k = series.index(flat)
        other = series[k - 1] if k > 0 else series[k + 1]
        for ink in grid.inks:
            cells = ((ink, flat), (ink, other), (ink, rough))
            out.append((6, f"{ink}: {short(flat)} rough vs {short(other)}", cells,
                        lambda L, c=cells: _de(c[0], c[1])(L) - _de(c[2], c[0])(L)))
    return out


def evaluate(records: list[CellRecord], seed: int = 0) -> list[Check]:
    """Every check of every finding on the records' grid."""
    grid = _Grid(records)
    rng = np.random.default_rng(seed)
    checks = []
    for finding, where, cells, fn in _checks(grid):
        if not all(grid.has(*c) for c in cells):
            continue
        recs = [grid.cells[c] for c in cells]
        if not all(r.ok for r in recs):
            checks.append(Check(finding, where, float("nan"), float("nan"), "not testable"))
            continue
        nominal = {c: grid.cells[c].lab for c in cells}
        value = float(fn(nominal))
        if not all(np.all(np.isfinite(r.se)) for r in recs):
            checks.append(Check(finding, where, value, float("nan"), "SE unknown"))
            continue
        draws = {c: grid.cells[c].lab + rng.standard_normal((SAMPLES, 3)) * grid.cells[c].se for c in set(cells)}
        se = float(np.std(fn(draws), ddof=1))
        verdict = ("agrees" if value > RESOLVED_SE * se else
                   "contradicts" if value < -RESOLVED_SE * se else "not resolved")
        checks.append(Check(finding, where, value, se, verdict))
    return checks


FINDINGS = {
    1: ("Colour saturates with concentration",
        "s = C*/L* at the higher concentration minus s at the lower, same column and pigment proportions"),
    2: ("Colour saturates as grains shrink",
        "s of the smaller grains minus s of the next larger ones, same ink; series of columns that differ "
        "only in size (molecular = size 0)"),
    3: ("The size effect is strongest at low concentration",
        "ΔE(column ↔ molecular) at the lower concentration minus at the next higher one"),
    4: ("Agglutination looks like bigger grains",
        "s of dispersed grains minus s of agglutinated grains of the same size"),
    5: ("A Y+B grain mix approaches molecular green (G grains) as grains shrink",
        "ΔE(Y+B ↔ G of equal composition) for the larger grains minus for the next smaller ones"),
    6: ("A rough top changes little",
        "ΔE(flat ↔ next grain size) minus ΔE(rough ↔ flat), same ink"),
}
VERDICTS = ("agrees", "not resolved", "contradicts", "SE unknown", "not testable")


def report(records: list[CellRecord], title: str, checks: list[Check] | None = None) -> str:
    """The findings report (Markdown)."""
    checks = evaluate(records) if checks is None else checks
    sources = sorted({r.se_source for r in records if r.ok})
    lines = [f"# {title}: the paper's findings (§3.3) tested on the grid", "",
             f"{run_counts(records)}; accuracy "
             f"{', '.join(sorted({r.accuracy for r in records}))}; colour: CIELAB (D65) of the ink on paper "
             "r = 0.9 under diffuse light, 0° view; saturation s = C*/L*; ΔE = CIE76.",
             f"A check agrees when its value exceeds {RESOLVED_SE:g} standard errors, contradicts below "
             f"−{RESOLVED_SE:g} SE, and is not resolved in between (standard errors from: {', '.join(sources)}; "
             "docs/figures.md).", "",
             "| finding | checks | " + " | ".join(VERDICTS) + " |", "|---|---|" + "---|" * len(VERDICTS)]
    for n, (name, _) in FINDINGS.items():
        mine = [c for c in checks if c.finding == n]
        counts = [sum(c.verdict == v for c in mine) for v in VERDICTS]
        lines.append(f"| {n}. {name} | {len(mine)} | " + " | ".join(map(str, counts)) + " |")
    for n, (name, definition) in FINDINGS.items():
        mine = [c for c in checks if c.finding == n]
        lines += ["", f"## {n}. {name}", "", f"Value: {definition}.", ""]
        if not mine:
            lines.append("No pair of cells of this figure to test it on.")
            continue
        exceptions = [c for c in mine if c.verdict != "agrees"]
        agree = len(mine) - len(exceptions)
        lines.append(f"{agree} of {len(mine)} checks agree." + (" Exceptions:" if exceptions else ""))
        for c in sorted(exceptions, key=lambda c: (VERDICTS.index(c.verdict), c.where)):
            num = "" if not np.isfinite(c.value) else f" {c.value:+.3f}" + (
                f" ± {c.se:.3f}" if np.isfinite(c.se) else "")
            lines.append(f"- {c.verdict}: {c.where}{num}")
    failed = [r for r in records if not r.ok]
    if failed:
        lines += ["", "## Failed cells", ""] + [f"- {r.ink} × {r.grains} ({r.particles}): {r.reason}" for r in failed]
    return "\n".join(lines) + "\n"
