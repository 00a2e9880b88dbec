"""The paper's figures reproduced: Fig. 7 and Fig. 8 (grids of Fig. 6 pictures), Fig. 9
(transmission spectra), their CSV of cell colours and the findings report (docs/figures.md).

    from solver.apps.figures import FigureSettings, make_figure, parse_rows, parse_columns
    make_figure("fig8", parse_rows(None, "fig8"), parse_columns(None, "fig8"),
                FigureSettings("preview"), BuildOptions(), "fig8.png", report_path="fig8.md")

Modules, one stage each: paper_grid (rows, columns, labels), cells (requests, estimate, build),
models (the paper's and this project's), fig6 (the Fig. 6 picture), layout (pixels of a
grid), draw (PNG output), records (CSV), findings (the report), make (the whole figure).
"""

from .cells import FigureSettings
from .make import make_figure
from .paper_grid import FIGURES, parse_columns, parse_rows

__all__ = ["FIGURES", "FigureSettings", "make_figure", "parse_columns", "parse_rows"]
