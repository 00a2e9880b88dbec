"""`ink-tables build`: make a table file for one ink (molecular or particles)."""

from __future__ import annotations

import argparse
import logging
import shutil
import time
from pathlib import Path

import numpy as np

from ..table.builder import BuildOptions, get_or_build
from ..table.executor import default_workers
from ..table.cache import TableCache
from ..table.request import TableRequest

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
    p.add_argument("--particles", default="molecular",
                   help="molecular | sphere:D[:agglutinated|:rough] | cylinder:D:isotropic|inplane|vertical (D in nm)")
    p.add_argument("--thickness", type=float, default=1000.0, help="layer thickness, nm")
    p.add_argument("--wavelengths", default=None,
                   help="START:STOP:STEP in nm (default 380:780:10 molecular, 380:780:20 particles)")
    p.add_argument("--angles", type=int, default=None,
                   help="incidence angles 0–90° (default 46 molecular; particles 0,15,30,45,60,70,80,90)")
    g = p.add_argument_group("particle inks (wave-optics tiers)")
    g.add_argument("--realizations", type=int, default=4, help="random cells per wavelength")
    g.add_argument("--azimuths", type=int, default=2, help="incidence azimuths per realization")
    g.add_argument("--tolerance", type=float, default=0.01,
                   help="allowed error in Rbar/Tbar/R_spec when choosing the cheapest tier")
    g.add_argument("--tier", default="auto", choices=("auto", "effective-medium", "born", "full"))
    g.add_argument("--cell", type=float, default=2000.0, help="lateral period of the cell, nm")
    g.add_argument("--grid", type=int, nargs=3, default=(64, 64, 32), metavar=("NX", "NY", "NZ"))
    g.add_argument("--solver-tol", type=float, default=1e-4, help="wave solver relative residual")
    g.add_argument("--seed", type=int, default=1)
    r = p.add_argument_group("running")
    r.add_argument("--workers", type=int, default=default_workers(),
                   help="local worker processes (default: one per core; 1 = in this process)")
    r.add_argument("--scheduler", default=None, help="Dask scheduler address (runs the units there)")
    r.add_argument("--cache", default=None, help="cache directory (default $INKBSDF_CACHE or ~/.cache/inkbsdf)")
    r.add_argument("--no-progress", action="store_true")
    p.add_argument("-o", "--output", required=True, help="table file (.npz)")
    p.set_defaults(func=run)


def request_from_args(args) -> TableRequest:
    molecular = args.particles.strip().lower() in ("molecular", "infinitesimal", "none")
    wl = parse_range(args.wavelengths or ("380:780:10" if molecular else "380:780:20"))
    if wl[0] <= 0:
        raise ValueError(f"wavelengths must be positive, got {args.wavelengths}")
    kwargs = dict(ink=args.ink, particles=args.particles, thickness_nm=args.thickness,
                  wavelengths_nm=tuple(wl), realizations=args.realizations, azimuths=args.azimuths,
                  tolerance=args.tolerance, tier=args.tier, cell_nm=args.cell, grid=tuple(args.grid),
                  solver_tol=args.solver_tol, seed=args.seed)
    if args.angles is not None:
        kwargs["sigma_rad"] = tuple(sigma_grid(args.angles))
    return TableRequest(**kwargs)


def run(args) -> int:
    request = request_from_args(args)
    cache = TableCache(Path(args.cache)) if args.cache else TableCache.default()
    opts = BuildOptions(workers=args.workers, scheduler=args.scheduler, progress=not args.no_progress,
                        cache=cache)
    t0 = time.perf_counter()
    table, cached_path, built = get_or_build(request, opts)
    out = Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    if out.resolve() != Path(cached_path).resolve():
        shutil.copyfile(cached_path, out)
    meta = table.meta
    print(f"{out}: ink {request.ink}, particles {request.particles}, {meta['tier']} tier, "
          f"{table.wavelengths.size} wavelengths, {table.sigma.size} angles "
          f"({'built' if built else 'from cache'} in {time.perf_counter() - t0:.1f} s)")
    if built and meta.get("timings_s"):
        print("  stage seconds: " + ", ".join(f"{k} {v:.1f}" for k, v in meta["timings_s"].items()))
    if meta.get("tier_probe"):
        print("  tier probe (max deviation from full solve): " + ", ".join(
            f"{k} {v:.4f}" for k, v in meta["tier_probe"]["deviation"].items()))
    errors = {k: v for k, v in meta.get("errors", {}).items() if k.endswith("_max")}
    if errors:
        print("  error estimates: " + ", ".join(f"{k} {v:.2g}" for k, v in errors.items()))
    return 0
