"""`ink-tables show`: summary of a table and the paper's Fig. 6 picture.

Fig. 6 (paper §3.2; `solver.apps.figures.fig6`): a vertical strip of the ink on paper under uniform
diffuse light, view angle 0° (top) to 60° (bottom), beside a square of the diffuse BRDF colour,
light angle 0–60° along x and view angle 0–60° along y, drawn with axes, angle labels and a
caption.  sRGB under D65, scaled so that a white Lambertian of albedo 1 is (255, 255, 255).
The square shows π·f without the mirror lobe, averaged over the azimuth difference Δφ (or at
one Δφ with --dphi).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from solver.colour.cie import lab_hue_chroma
from solver.colour.measurement import DEFAULT, DEFAULT_GEOMETRY, GEOMETRIES, Measurement
from solver.colour.srgb import lab_to_srgb8
from solver.paper import PAPER_ALBEDO, check_paper_albedo
from solver.table import jackknife, read_table
from solver.table.evaluate import column_at
from ..figures.fig6 import plot_figure6
from .build import (add_cache_argument, add_request_arguments, cache_from_args, given_request_options,
                    request_from_args)
from .parsing import DefaultsFormatter, add_measurement_arguments, measurement_from_args, writable_output


#: the three ways to name the table, first (argparse's own line lists every option, the table last)
USAGE = """%(prog)s FILE.npz [--png PNG] [--plot PNG] [options]
       %(prog)s KEY [--png PNG] [--plot PNG] [options]
       %(prog)s --ink INK [build's request options] [--png PNG] [--plot PNG] [options]"""
#: what a cache key, or the start of one, looks like (request.TableRequest.key: hex digits)
CACHE_KEY = re.compile(r"[0-9a-f]{6,64}")


def _column_at_deg(table, name: str, degrees: float) -> np.ndarray:
    return column_at(table, name, np.radians(degrees))


def _pigment_eps(meta: dict) -> str:
    """How the table's pigments entered (tables from before the local field existed: bulk)."""
    return "local field" if meta.get("local_field") else "bulk"


def thickness_text(thickness_nm) -> str:
    """A table's thickness as read: '1000' for one layer, '800 + 800' for a stack (top first)."""
    values = thickness_nm if isinstance(thickness_nm, (list, tuple, np.ndarray)) else [thickness_nm]
    return " + ".join(f"{float(v):g}" if isinstance(v, (int, float, np.number)) else str(v) for v in values)


def colour_lines(table, paper: float, measurement: Measurement) -> list[str]:
    """The ink's colour on paper in every geometry under the measurement's illuminant and
    observer, the chosen geometry marked."""
    from dataclasses import replace

    from solver.colour.cie import ColourError
    from solver.colour.table_colour import table_colour

    try:
        measurement.check(table)
    except ColourError as exc:
        return [f"colour: not measured: {exc}"]
    lines = [f"colour on paper r={paper:g}, {measurement.illuminant} {measurement.observer}° "
             f"(* = --geometry {measurement.geometry.name}):"]
    for name, geometry in GEOMETRIES.items():
        m = replace(measurement, geometry=geometry)
        lab = m.lab(table, paper)
        hue, chroma = lab_hue_chroma(lab)
        mark = "*" if name == measurement.geometry.name else " "
        lines.append(f" {mark}{name:>8}: L*a*b* = ({lab[0]:5.1f}, {lab[1]:6.1f}, {lab[2]:6.1f}), hue {hue:3.0f}°, "
                     f"chroma {chroma:5.1f}, sRGB {tuple(int(v) for v in lab_to_srgb8(lab, m.illuminant, m.observer))}"
                     f"  — {geometry.description}")
    groups = table.meta.get("jackknife_groups") if table.jackknife else None
    count = jackknife.count(table) or None
    lines.append(f"  standard error of the * colour: {se_text(table_colour(table, paper, measurement), count, groups)}")
    return lines


def se_text(colour, realizations: int | None = None, groups=None) -> str:
    """'L* 0.16, a* 0.34, b* 0.32 (jackknife over 6 realizations, stratified 3 TE + 3 TM: 4 degrees
    of freedom)', or how it is known otherwise (solver/colour/table_colour.py `method`);
    realizations: the jackknife's replica count; groups: each realization's polarisation
    (TE 0, TM 1) where TE and TM were solved on separate cells (their strata cost one degree of
    freedom each)."""
    if colour.method == "unknown":
        return "unknown (one realization)"
    if colour.method == "exact":
        return "0 (exact film)"
    values = ", ".join(f"{k} {v:.2g}" for k, v in zip(("L*", "a*", "b*"), colour.se))
    dof = f"{colour.dof:g} degree{'s' if colour.dof != 1 else ''} of freedom"
    if colour.method == "jackknife":
        count = colour.dof + 1 if realizations is None else realizations
        strata = (f", stratified {list(groups).count(0)} TE + {list(groups).count(1)} TM cells"
                  if groups else "")
        return f"{values} (jackknife over {count:g} realizations{strata}: {dof})"
    return f"{values} (propagated bound from the nodes' standard errors, {colour.source})"


def _generator(gen) -> str:
    """'inkbsdf.solver 0.1.0' from the meta's {'name', 'version'} (anything else as it is)."""
    return f"{gen.get('name')} {gen.get('version')}" if isinstance(gen, dict) else str(gen)


def summary(table, paper: float = PAPER_ALBEDO, measurement: Measurement = DEFAULT) -> str:
    meta = table.meta
    wl = table.wavelengths
    lines = [
        f"ink {meta.get('ink')}  particles {meta.get('particles')}  tier {meta.get('tier')}  "
        f"thickness {thickness_text(meta.get('thickness_nm'))} nm  polarisation {meta.get('polarisation', 'te')}  "
        f"pigment ε {_pigment_eps(meta)}  schema v{meta.get('schema_version')}",
        f"wavelengths {wl[0]:g}–{wl[-1]:g} nm ({wl.size})  incidence angles {table.sigma.size}  "
        f"BRDF grid θ×Δφ {table.theta.size}×{table.dphi.size}  diffuse R: {'yes' if table.has_diffuse else 'none'}",
        f"generator {_generator(meta.get('generator'))}  seeds {meta.get('seeds')}",
    ]
    n_real = len(meta.get("seeds") or [])
    if table.errors:
        worst = {k: float(np.max(v)) for k, v in table.errors.items()}
        lines.append("largest standard errors: " + ", ".join(f"{k} {v:.2g}" for k, v in worst.items()))
    elif n_real == 1:
        lines.append("standard errors: unknown (one realization; build with --realizations ≥ 2)")
    err = table.errors.get("Tbar")
    head = f"  {'λ nm':>5}  {'R_spec(0°)':>10}  {'Rbar(0°)':>8}  {'Tbar(0°)':>8}  {'±Tbar':>6}  {'A(0°)':>6}  " \
           f"{'Rbar(60°)':>9}  {'Tbar(60°)':>9}"
    lines.append(head)
    r60, t60 = _column_at_deg(table, "Rbar", 60.0), _column_at_deg(table, "Tbar", 60.0)
    for li in np.unique(np.linspace(0, wl.size - 1, min(wl.size, 9)).round().astype(int)):
        pm = f"{err[li, 0]:6.3f}" if err is not None else f"{'n/a':>6}"
        lines.append(f"  {wl[li]:5.0f}  {table.R_spec[li, 0]:10.4f}  {table.Rbar[li, 0]:8.4f}  "
                     f"{table.Tbar[li, 0]:8.4f}  {pm}  {1 - table.Rbar[li, 0] - table.Tbar[li, 0]:6.4f}  "
                     f"{r60[li]:9.4f}  {t60[li]:9.4f}")
    lines.append("  (60° columns interpolated between the table's incidence nodes, as the renderer does)")
    lines += colour_lines(table, paper, measurement)
    return "\n".join(lines)


def plot_spectra(table, path: str) -> None:
    """Coherent and total reflectance/transmittance spectra at 0° and 45°, with error bars."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, angle in zip(axes, (0.0, 45.0)):
        i = int(np.argmin(np.abs(table.sigma - np.radians(angle))))
        for name in ("R_spec", "Rbar", "T_coh", "Tbar"):
            err = table.errors.get(name)
            ax.errorbar(table.wavelengths, table.column(name)[:, i],
                        yerr=None if err is None else err[:, i], label=name, capsize=2)
        ax.set_title(f"{table.meta.get('ink')} {table.meta.get('particles')}, σ = {np.degrees(table.sigma[i]):.0f}°")
        ax.set_xlabel("wavelength (nm)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("power fraction")
    axes[0].legend()
    dof = (table.meta.get("errors") or {}).get("se_dof")
    count = table.meta.get("realizations_used")
    fig.text(0.5, 0.01, "error bars: ±1 standard error across the table's random cells"
             + (f" ({count} realizations, {dof} degree{'s' if dof != 1 else ''} of freedom)" if count and dof else "")
             if table.errors else "no error bars: the table is exact or has one realization",
             ha="center", fontsize=8)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def add_parser(sub) -> None:
    p = sub.add_parser("show", help="summarise a table; draw the paper's Fig. 6",
                       formatter_class=DefaultsFormatter, usage=USAGE,
                       description="Summarise a table file, a cached table by its key, or the cached table "
                                   "that the request options describe (the same options as `build`, e.g. "
                                   "--ink R15 --particles sphere:100 --accuracy preview, a particle cell of a "
                                   "preview figure); nothing is computed.")
    p.add_argument("file", nargs="?", default=None, metavar="FILE|KEY",
                   help="table file (.npz), or a cache key or its start (a figure CSV's cache_key column); or "
                        "give --ink and the request options instead")
    p.add_argument("--png", help="write the Fig. 6 picture (strip + BRDF square, with axes and a caption) here")
    p.add_argument("--plot", help="write spectra with error bars here (PNG)")
    p.add_argument("--paper", type=float, default=PAPER_ALBEDO, help="paper albedo r")
    p.add_argument("--dphi", type=float, default=None,
                   help="azimuth difference (deg) for the BRDF square; default: average over Δφ")
    add_measurement_arguments(p, DEFAULT_GEOMETRY)
    add_request_arguments(p, ink_required=False)
    add_cache_argument(p)
    p.set_defaults(func=run)


def cached_table(args):
    """(table, path) of the cached table the request options describe; ValueError naming the
    build command when it is not there (nothing is computed)."""
    request = request_from_args(args)
    cache = cache_from_args(args)
    table = cache.load(request)
    if table is None:
        raise ValueError(f"--ink {args.ink}: no cached table for {request.describe()} in {cache.root} (key "
                         f"{request.key()}): build it with `ink-tables build` and the same options, -o FILE")
    return table, cache.table_path(request)


def cached_by_key(cache, key: str) -> Path:
    """The cached table file whose key is `key` or starts with it (unique); ValueError otherwise."""
    found = sorted((cache.root / "tables").glob(f"{key}*.npz"))
    if len(found) != 1:
        raise ValueError(f"{key}: no table file of that name, and {len(found) or 'no'} cached table"
                         f"{'s' if len(found) != 1 else ''} whose key starts so in {cache.root / 'tables'}"
                         + ("; give more of the key" if found else ""))
    return found[0]


def run(args) -> int:
    check_paper_albedo(args.paper, what="--paper (the paper albedo)")
    measurement = measurement_from_args(args, DEFAULT_GEOMETRY)
    if args.dphi is not None and not (np.isfinite(args.dphi) and 0.0 <= args.dphi <= 180.0):
        raise ValueError(f"--dphi {args.dphi}: the azimuth difference must lie in [0, 180] degrees")
    for option, path in (("--png", args.png), ("--plot", args.plot)):
        if path:
            writable_output(path, ".png", option, make_folder=True)
    given = given_request_options(args)
    if args.file is not None and (args.ink is not None or given):
        raise ValueError(f"{(['--ink'] if args.ink else given)[0]} describes a cached table (with --ink and the "
                         f"build's options): give it instead of the table file {args.file}, not with it")
    if args.file is None and args.ink is None:
        raise ValueError(f"{given[0]} needs --ink (the request of a cached table)" if given else
                         "name the table: a table FILE.npz, a cache KEY, or --ink INK with the build's "
                         "options (see --help)")
    if args.file is None:
        table, path = cached_table(args)
        print(f"cached table {path}")
    elif not Path(args.file).exists() and CACHE_KEY.fullmatch(args.file.removesuffix(".npz")):
        path = cached_by_key(cache_from_args(args), args.file.removesuffix(".npz"))
        print(f"cached table {path}")
        table = read_table(path)
    else:
        table = read_table(args.file)
    print(summary(table, args.paper, measurement))
    if args.png:
        plot_figure6(table, args.png, args.paper, dphi_deg=args.dphi)
        print(f"wrote {args.png}")
    if args.plot:
        plot_spectra(table, args.plot)
        print(f"wrote {args.plot}")
    return 0
