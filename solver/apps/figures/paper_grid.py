"""The paper's figures as rows (inks) and columns (grains), labelled as the paper labels them.

docs/design.md §2 lists them: Fig. 7 is 21 inks × 17 grain columns, Fig. 8 the first 14 inks ×
4 columns (agglutination), Fig. 9 the G, B, Y and R layers at 15, 30 and 50 %, molecular
against 300-nm spheres.  `parse_rows` / `parse_columns` read the CLI's `--rows` / `--columns`;
a column named by a spec of the paper's figure keeps the paper's label.
"""

from __future__ import annotations

from dataclasses import dataclass

from solver.geometry.spec import MOLECULAR_WORDS, parse_particles
from solver.inks import Ink, parse_ink


class FigureSpecError(ValueError):
    """A --rows / --columns value that names no ink or grain column."""


@dataclass(frozen=True)
class Row:
    """One ink of a figure: its spec (as table_request takes it) and the paper's label."""

    ink: Ink

    @property
    def spec(self) -> str:
        return self.ink.label

    @property
    def label(self) -> str:
        """The paper's row label: 'Y12.5% + B2.5%'."""
        return " + ".join(f"{code}{100 * f:.6g}%" for code, f in self.ink.components) or "clear"


@dataclass(frozen=True)
class Column:
    """One grain column: the particle spec ('molecular' for the homogeneous layer), the paper's
    header (group over its sub-label; an empty sub-label: a one-level header).

    across: grains with vertical axes 'across the layer' — with the smallest orientation spread
    that reaches the row's concentration (docs/design.md §3: the paper's cylinders).
    """

    particles: str
    group: str
    sub: str = ""
    across: bool = False

    @property
    def molecular(self) -> bool:
        return self.particles.strip().lower() in MOLECULAR_WORDS

    @property
    def label(self) -> str:
        """One-line label (CSV, messages)."""
        return f"{self.group} {self.sub}".strip()


def _ink(spec: str) -> Row:
    return Row(parse_ink(spec))


_BLOCK = ("R{0}", "Y{0}", "Y{1}+B{2}", "Y{3}+B{3}", "G{0}", "Y{2}+B{1}", "B{0}")
#: Fig. 7's rows (docs/design.md §2; the paper's row 6 'Y25% + B12.5%' is read Y2.5+B12.5)
FIG7_ROWS = tuple(_ink(t.format(*v)) for v in (("15", "12.5", "2.5", "7.5"), ("30", "25", "5", "15"),
                                               ("50", "42", "8", "25")) for t in _BLOCK)
#: Fig. 8's rows: the 15 % and 30 % blocks (the paper's 'Y30%+B30%' is Y15+B15)
FIG8_ROWS = FIG7_ROWS[:14]
#: Fig. 9's layers: G, B, Y, R (panels 9.1–9.4) at 15, 30, 50 %
FIG9_ROWS = tuple(_ink(f"{p}{c}") for p in "GBYR" for c in (15, 30, 50))

FIG7_COLUMNS = (
    Column("molecular", "infinitesimal particles"),
    Column("sphere:30", "Balls 30 nm"),
    Column("sphere:100", "Balls 100 nm", "normal"),
    Column("sphere:100:agglutinated", "Balls 100 nm", "agglutinated"),
    Column("sphere:200", "Balls 200 nm"),
    Column("sphere:300", "Balls 300 nm", "normal"),
    Column("sphere:300:rough", "Balls 300 nm", "rough surface"),
    Column("sphere:450", "Balls 450 nm"),
) + tuple(
    Column(f"cylinder:{d}:{orient}", f"cylinders D_eff = {d} nm", sub, across=orient == "vertical")
    for d in (100, 200, 300)
    for orient, sub in (("isotropic", "isotropic"), ("inplane", "horiz aligned"), ("vertical", "vertically aligned")))
FIG8_COLUMNS = (Column("sphere:100", "100 nm"), Column("sphere:200", "200 nm"),
                Column("sphere:100:agglutinated", "100 nm Aggl."), Column("sphere:300", "300 nm"))
FIG9_COLUMNS = (Column("molecular", "molecular"), Column("sphere:300", "300-nm spheres"))

FIGURES = {"fig7": (FIG7_ROWS, FIG7_COLUMNS), "fig8": (FIG8_ROWS, FIG8_COLUMNS),
           "fig9": (FIG9_ROWS, FIG9_COLUMNS)}
TITLES = {"fig7": "Fig. 7. Results of simulation", "fig8": "Fig. 8. Results of simulation. Effect of agglutination",
          "fig9": "Fig. 9. Transmission spectra of the layer at normal incidence"}


def _canonical(particles: str) -> str:
    spec = parse_particles(particles)
    return "molecular" if spec is None else spec.label


def derived_column(particles: str) -> Column:
    """A column for a spec outside the paper's figures, labelled in the paper's style."""
    spec = parse_particles(particles)
    if spec is None:
        return Column("molecular", "infinitesimal particles")
    mods = [w for w, on in (("agglutinated", spec.agglutination_kT > 0), ("rough surface", spec.rough_top > 0),
                            (f"spread {spec.size_spread:g}", spec.size_spread > 0)) if on]
    group = spec.shape.column_group(spec.diameter_nm)
    if not spec.shape.oriented:
        return Column(particles, group, " ".join(mods))
    return Column(particles, group, " ".join([spec.shape.orientation_label(spec.orientation)] + mods),
                  across=spec.orientation == "vertical" and ":tilt" not in particles.lower())


def parse_rows(text: str | None, figure: str) -> tuple[Row, ...]:
    """`--rows R15,Y7.5+B7.5` (None: the figure's rows)."""
    if text is None:
        return FIGURES[figure][0]
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise FigureSpecError(f"--rows {text!r}: expected ink specs separated by commas, e.g. R15,Y7.5+B7.5")
    try:
        rows = tuple(_ink(t) for t in items)
    except ValueError as exc:
        raise FigureSpecError(f"--rows: {exc}") from None
    return _unique(rows, "--rows", lambda r: r.spec)


def parse_columns(text: str | None, figure: str) -> tuple[Column, ...]:
    """`--columns molecular,sphere:100,cylinder:200:inplane` (None: the figure's columns)."""
    paper = FIGURES[figure][1]
    if text is None:
        return paper
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise FigureSpecError(f"--columns {text!r}: expected particle specs separated by commas, "
                              "e.g. molecular,sphere:100,cylinder:200:inplane")
    known = {}
    for column in FIG7_COLUMNS + paper:          # the figure's own labels win
        known[_canonical(column.particles)] = column
    columns = []
    for item in items:
        try:
            key = _canonical(item)
            columns.append(known.get(key) or derived_column(item))
        except ValueError as exc:
            raise FigureSpecError(f"--columns: {exc}") from None
    return _unique(tuple(columns), "--columns", lambda c: _canonical(c.particles))


def _unique(items: tuple, option: str, key) -> tuple:
    seen = set()
    for item in items:
        if key(item) in seen:
            raise FigureSpecError(f"{option}: {key(item)} is given twice")
        seen.add(key(item))
    return items
