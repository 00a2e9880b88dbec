"""The demo scene's inks and a way to build their tables without `make tables` (tests, bench).

Same settings as `ink-tables build` defaults: exact thin-film tier, 1000 nm layer,
380–780 nm every 10 nm, 46 incidence angles; files named `<ink>.npz` like `make tables`.
"""

from __future__ import annotations

from pathlib import Path

DEMO_INKS = ("clear", "R30", "Y30", "B30", "G30", "Y25+B5")
THICKNESS_NM = 1000.0


def build_tables(folder, inks=DEMO_INKS, wavelengths="380:780:10", angles=46, overwrite=True) -> dict:
    """{ink: path} of thin-film tables written into `folder`."""
    from solver.cli.build import parse_range, sigma_grid
    from solver.inks import parse_ink
    from solver.table import write_table
    from solver.table.thinfilm_tier import build_thinfilm_table

    folder = Path(folder)
    paths = {}
    for ink in inks:
        path = folder / f"{ink}.npz"
        if overwrite or not path.is_file():
            table = build_thinfilm_table(parse_ink(ink), THICKNESS_NM, parse_range(wavelengths),
                                         sigma_grid(angles))
            write_table(path, table)
        paths[ink] = path
    return paths
