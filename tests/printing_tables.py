"""Tables for the printing tests: thin films of the demo inks and stacks of them.

`incoherent_stack` is the test's own model of an overprint: two flat layers with a thin air gap
between them, light bouncing between them incoherently at the same polar angle (flat faces keep
the angle). It is a valid, physical table (lossless layers give a lossless stack) whose
reflectance from below differs from that from above, so stacking order is visible.
"""

from __future__ import annotations

import numpy as np

from solver.inks import parse_ink
from solver.table import InkTable, validate
from solver.table.thinfilm_tier import build_thinfilm_table

WAVELENGTHS_NM = np.arange(380.0, 781.0, 10.0)
SIGMA_RAD = np.linspace(0.0, np.pi / 2, 46)


def film(ink: str, thickness_nm: float = 1000.0, wavelengths=WAVELENGTHS_NM, sigma=SIGMA_RAD) -> InkTable:
    """Exact thin-film table of a molecular ink (solver.table.thinfilm_tier)."""
    return build_thinfilm_table(parse_ink(ink), thickness_nm, wavelengths, sigma)


def incoherent_stack(top: InkTable, bottom: InkTable) -> InkTable:
    """`top` over `bottom` (specular-only tables on one grid), incoherent bounces in a gap:

    R = R_a + T_a²·R_b/(1 − R'_a·R_b),  T = T_a·T_b/(1 − R'_a·R_b),
    R' = R'_b + T_b²·R'_a/(1 − R'_a·R_b)     (R' = reflectance from below)."""
    assert not top.has_diffuse and not bottom.has_diffuse
    assert np.array_equal(top.wavelengths, bottom.wavelengths) and np.array_equal(top.sigma, bottom.sigma)
    ra, rpa, ta = top.Rbar, top.Rbar_below, top.Tbar
    rb, rpb, tb = bottom.Rbar, bottom.Rbar_below, bottom.Tbar
    den = 1.0 - rpa * rb                        # 0 only at grazing incidence, where T_a = T_b = 0
    loop = np.divide(1.0, den, out=np.zeros_like(den), where=den > 0)
    R = ra + ta * ta * rb * loop
    T = ta * tb * loop
    R_below = rpb + tb * tb * rpa * loop
    meta = dict(top.meta, ink=f"{top.meta.get('ink')}/{bottom.meta.get('ink')}", tier="synthetic",
                tier_reason="test: incoherent stack with an air gap")
    return validate(InkTable(wavelengths=top.wavelengths, sigma=top.sigma, theta=top.theta, dphi=top.dphi,
                             R=np.zeros_like(top.R), R_spec=R, T_coh=T, Rbar=R.copy(), Tbar=T.copy(),
                             Rbar_below=R_below, meta=meta))


def stack_of(tables_top_first) -> InkTable:
    """The incoherent stack of several specular tables, listed from the top."""
    tables = list(tables_top_first)
    out = tables[-1]
    for upper in reversed(tables[:-1]):
        out = incoherent_stack(upper, out)
    return out


def stack_table(tables_top_first) -> InkTable:
    """The test's overprint: the incoherent stack of specular tables; where a member has a
    diffuse lobe, a synthetic absorbing diffuse table (conftest) whose strength grows with the
    number of layers (valid, reciprocal; stands in for what the solver would compute)."""
    from conftest import diffuse_layer_table

    tables = list(tables_top_first)
    if any(t.has_diffuse for t in tables):
        return diffuse_layer_table(lossless=False, strength=0.1 * len(tables) + 0.05 * tables[0].Rbar.mean())
    return stack_of(tables)


class StackProvider:
    """A stack provider for the `ink` BSDF (inkbsdf.inks): reads the members' tables, returns
    the InkLUT of `stack_table`, and records the calls (member ink numbers, top first)."""

    def __init__(self):
        self.calls = []

    def __call__(self, members):
        from inkbsdf.lut import lut_from_table
        from solver.table import read_table

        self.calls.append(tuple(m.index for m in members))
        table = stack_table([read_table(m.lut.source) for m in members])
        return lut_from_table(table, source="stack:" + "/".join(m.label for m in members))


def write_print_tables(folder) -> dict:
    """{name: path}: thin films of R30, Y30, B30, clear films of 700, 1000 and 1500 nm, and a
    synthetic absorbing table with a diffuse lobe (other λ and σ grids than the films)."""
    from conftest import diffuse_layer_table
    from solver.table import write_table

    out = {ink: write_table(folder / f"{ink}.npz", film(ink)) for ink in ("R30", "Y30", "B30")}
    for h in (700, 1000, 1500):
        out[f"clear{h}"] = write_table(folder / f"clear{h}.npz", film("clear", float(h)))
    out["diffuse"] = write_table(folder / "diffuse.npz", diffuse_layer_table(lossless=False))
    return out


def load(mi, inks, coverages, model="clapper-yule", paper=0.9, **extra):
    """An `ink` BSDF with numbered inks (table paths) and coverages (numbers or texture dicts)."""
    d = {"type": "ink", "paper": paper, "coverage_model": model, **extra}
    for n, (path, c) in enumerate(zip(inks, coverages), start=1):
        d[f"filename{n}"] = str(path)
        d[f"coverage{n}"] = c
    return mi.load_dict(d)


def reference(paths):
    """solver.printing.PrintedInks of the same tables, every overprint from `stack_table`."""
    from solver.printing import PrintedInks, stack_order
    from solver.table import read_table

    inks = tuple(read_table(p) for p in paths)
    return PrintedInks.from_provider(inks, lambda s: stack_table([inks[i] for i in stack_order(s)]))
