"""`ink-tables build`: make a table file for one ink."""

from __future__ import annotations

import argparse
import logging
import time

import numpy as np

from ..inks import parse_ink
from ..table import write_table
from ..table.thinfilm_tier import build_thinfilm_table

log = logging.getLogger("ink-tables")


def parse_range(text: str) -> np.ndarray:
    """'380:780:10' → 380, 390, …, 780 (inclusive); a single number gives one value."""
    parts = text.split(":")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"bad range {text!r}: expected START:STOP:STEP, e.g. 380:780:10") from None
    if len(values) == 1:
        return np.array(values)
    if len(values) != 3 or values[2] <= 0 or values[1] < values[0]:
        raise ValueError(f"bad range {text!r}: expected START:STOP:STEP with STEP > 0 and STOP ≥ START")
    start, stop, step = values
    n = int(np.floor((stop - start) / step + 1e-9)) + 1
    return start + step * np.arange(n)


def sigma_grid(count: int) -> np.ndarray:
    """`count` incidence angles uniformly from 0 to 90° inclusive (radians)."""
    if count < 2:
        raise ValueError(f"--angles must be ≥ 2 (0° and 90° are both needed), got {count}")
    return np.linspace(0.0, np.pi / 2, count)


def add_parser(sub) -> None:
    p = sub.add_parser("build", help="compute a table for one ink",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--ink", required=True, help="ink spec, e.g. R15, Y7.5+B7.5, G30, clear")
    p.add_argument("--thickness", type=float, default=1000.0, help="layer thickness, nm")
    p.add_argument("--wavelengths", default="380:780:10", help="START:STOP:STEP in nm")
    p.add_argument("--angles", type=int, default=46, help="number of incidence angles 0–90°")
    p.add_argument("-o", "--output", required=True, help="table file (.npz)")
    p.set_defaults(func=run)


def run(args) -> int:
    ink = parse_ink(args.ink)
    wl = parse_range(args.wavelengths)
    if wl[0] <= 0:
        raise ValueError(f"wavelengths must be positive, got {args.wavelengths}")
    t0 = time.perf_counter()
    table = build_thinfilm_table(ink, args.thickness, wl, sigma_grid(args.angles))
    path = write_table(args.output, table)
    log.info("wrote %s (%s, %d wavelengths × %d angles) in %.2f s", path, table.meta["tier"],
             wl.size, table.sigma.size, time.perf_counter() - t0)
    print(f"{path}: ink {ink.label}, {table.meta['tier']} tier, {wl.size} wavelengths, "
          f"{table.sigma.size} angles")
    return 0
