"""Where everything goes in a Fig. 7 / Fig. 8 grid, in pixels (pure arithmetic, no drawing).

    title
    ┌────────────┬──────────── group header (spans its columns) ──────────┐
    │            │   sub-header   │   sub-header   │ …                     │
    │ row label  │ strip ▌square  │ strip ▌square  │ …   one cell per ink × grains
    │ …          │                                                       │
    caption

Pixel (x, y) has its origin at the top-left corner, x to the right, y down.  Label boxes are
the regions each label must stay within (the renderer wraps and sizes text to fit).
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass

Box = tuple[int, int, int, int]          # x0, y0, x1, y1 (x1, y1 exclusive)


@dataclass(frozen=True)
class CellGeometry:
    """Sizes (px) of one Fig. 6 picture inside a grid and of the spaces around it."""

    square: int = 96          # the BRDF square, side
    strip: int = 24           # the diffuse-light strip, width (its height is the square's)
    inner_gap: int = 4        # between strip and square
    pad: int = 10             # between neighbouring cells
    row_label: int = 132      # width of the row-label column
    group_header: int = 46    # height of the group header
    sub_header: int = 30      # height of the sub-header (0 when no column has a sub-label)
    title: int = 40
    caption: int = 34
    margin: int = 12

    @property
    def width(self) -> int:
        return self.strip + self.inner_gap + self.square


@dataclass(frozen=True)
class Label:
    text: str
    box: Box
    align: str                # 'center' or 'right'


#: the caption's smallest readable font (px) and line height (× font): the caption's box grows
#: to hold the text at this size (a narrow figure's caption wraps to more lines)
CAPTION_FONT_PX, LINE_SPACING = 9.0, 1.3


@dataclass(frozen=True)
class GridLayout:
    n_rows: int
    n_cols: int
    geometry: CellGeometry
    has_sub: bool
    caption_text: str = ""

    @property
    def caption_height(self) -> int:
        """The caption box's height (px): geometry.caption, or more for a long caption in a narrow
        figure (its lines at CAPTION_FONT_PX; characters ≈ 0.55 font wide, as draw._fit_text wraps)."""
        g = self.geometry
        width = self.cells_left + self.n_cols * self.pitch_x + g.margin - 2 * g.margin
        chars = max(4, int(width / (0.55 * CAPTION_FONT_PX)))
        lines = len(textwrap.wrap(self.caption_text, chars, break_long_words=False))
        return max(g.caption, int(math.ceil(lines * CAPTION_FONT_PX * LINE_SPACING)) + 4)

    # ---- sizes
    @property
    def pitch_x(self) -> int:
        return self.geometry.width + self.geometry.pad

    @property
    def pitch_y(self) -> int:
        return self.geometry.square + self.geometry.pad

    @property
    def header_height(self) -> int:
        g = self.geometry
        return g.group_header + (g.sub_header if self.has_sub else 0)

    @property
    def cells_top(self) -> int:
        return self.geometry.title + self.header_height

    @property
    def cells_left(self) -> int:
        return self.geometry.margin + self.geometry.row_label

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of the whole figure in pixels."""
        g = self.geometry
        return (self.cells_left + self.n_cols * self.pitch_x + g.margin,
                self.cells_top + self.n_rows * self.pitch_y + self.caption_height)

    # ---- boxes
    def cell_box(self, i: int, j: int) -> Box:
        """The cell (strip, gap and square) of row i, column j."""
        g = self.geometry
        x0 = self.cells_left + j * self.pitch_x + g.pad // 2
        y0 = self.cells_top + i * self.pitch_y + g.pad // 2
        return x0, y0, x0 + g.width, y0 + g.square

    def strip_box(self, i: int, j: int) -> Box:
        x0, y0, _, y1 = self.cell_box(i, j)
        return x0, y0, x0 + self.geometry.strip, y1

    def square_box(self, i: int, j: int) -> Box:
        _, y0, x1, y1 = self.cell_box(i, j)
        return x1 - self.geometry.square, y0, x1, y1

    def row_label_box(self, i: int) -> Box:
        g = self.geometry
        y0 = self.cells_top + i * self.pitch_y
        return g.margin, y0, self.cells_left - 6, y0 + self.pitch_y

    def columns_box(self, first: int, count: int, sub: bool) -> Box:
        """The header box over `count` columns from `first` (group row, or sub-header row)."""
        g = self.geometry
        x0 = self.cells_left + first * self.pitch_x
        y0 = g.title + (g.group_header if sub else 0)
        return x0 + 2, y0, x0 + count * self.pitch_x - 2, y0 + (g.sub_header if sub else g.group_header)

    def title_box(self) -> Box:
        return self.geometry.margin, 0, self.size[0] - self.geometry.margin, self.geometry.title

    def caption_box(self) -> Box:
        w, h = self.size
        return self.geometry.margin, h - self.caption_height, w - self.geometry.margin, h


def column_groups(groups: list[str]) -> list[tuple[str, int, int]]:
    """Runs of equal group labels: (label, first column, count)."""
    runs: list[tuple[str, int, int]] = []
    for j, name in enumerate(groups):
        if runs and runs[-1][0] == name and runs[-1][1] + runs[-1][2] == j:
            runs[-1] = (name, runs[-1][1], runs[-1][2] + 1)
        else:
            runs.append((name, j, 1))
    return runs


def grid_labels(layout: GridLayout, rows: list[str], groups: list[str], subs: list[str],
                title: str, caption: str) -> list[Label]:
    """Every label of the grid with the box it must stay within."""
    labels = [Label(title, layout.title_box(), "center")]
    labels += [Label(text, layout.row_label_box(i), "right") for i, text in enumerate(rows)]
    for name, first, count in column_groups(groups):
        labels.append(Label(name, layout.columns_box(first, count, sub=False), "center"))
    if layout.has_sub:
        labels += [Label(text, layout.columns_box(j, 1, sub=True), "center") for j, text in enumerate(subs) if text]
    labels.append(Label(caption, layout.caption_box(), "center"))
    return labels


def header_rules(layout: GridLayout, groups: list[str]) -> list[Box]:
    """Thin rules at the foot of each group header that spans several columns (as in the
    paper's table), inside the header's box."""
    rules = []
    for _, first, count in column_groups(groups):
        if count > 1:
            x0, _, x1, y1 = layout.columns_box(first, count, sub=False)
            rules.append((x0 + 6, y1 - 4, x1 - 6, y1 - 3))
    return rules
