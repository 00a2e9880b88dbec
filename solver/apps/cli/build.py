"""`ink-tables build`: make a table file for one ink (molecular, particles, or a stack)."""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

from solver.table.atomic import atomic_copy
from solver.table import preflight
from solver.table.builder import BuildOptions, get_or_build
from solver.table.cache import TableCache
from solver.table.executor import default_workers
from solver.table.options import OPTIONS
from solver.table.request import (ACCURACY, DEFAULT_POLARISATION, DEFAULT_THICKNESS_NM, DPHI_COUNT, POLARISATIONS,
                                  TIERS, TableRequest, WaveSettings, table_request)
from .parsing import PARTICLE_GRAMMAR, PARTICLE_GRAMMAR_KEY, DefaultsFormatter, uniform_angles, wavelength_range, writable_output

log = logging.getLogger("ink-tables")


def _per_preset(field: str) -> str:
    """'default 6, preview 2, fine 6': a wave setting in every accuracy preset (--help)."""
    return ", ".join(f"{name} {getattr(preset, field):g}" for name, (preset, _) in ACCURACY.items())


def given_request_options(args) -> list[str]:
    """The request options (`add_request_arguments`) other than --ink that `args` gives a value
    other than their default, as options (e.g. ['--particles'])."""
    probe = argparse.ArgumentParser(add_help=False)
    add_request_arguments(probe, ink_required=False)
    defaults = vars(probe.parse_args([]))           # the one home of the options and their defaults
    return sorted("--" + dest.replace("_", "-") for dest, default in defaults.items()
                  if dest != "ink" and getattr(args, dest, default) != default)


def _thickness(text: str):
    """'1000' → 1000.0, '800,1000' → (800.0, 1000.0): nm, one per layer (top first)."""
    try:
        values = [float(t) for t in str(text).split(",")]
    except ValueError:
        raise ValueError(f"--thickness {text!r}: expected nm, e.g. 1000 or 800,1000") from None
    return values[0] if len(values) == 1 else tuple(values)


#: how the CLI reads each request option (solver.table.options.OPTIONS), by name: argparse
#: keywords and the conversion of the parsed value into table_request's
def _cli_spec() -> dict:
    w = WaveSettings()
    return {
        "ink": (dict(help="ink spec in volume percent: R15, Y7.5+B7.5, G30, clear; 'Y15/B15' prints Y15 over B15"), None),
        "particles": (dict(default="molecular", help=f"molecular | {PARTICLE_GRAMMAR} ({PARTICLE_GRAMMAR_KEY}); "
                           "'a/b' per layer of a stack"), None),
        "thickness_nm": (dict(metavar="NM[,NM…]", help="layer thickness in nm: one value for every layer, or one per "
                              f"layer of a stack, top first, e.g. 800,1000 (default {DEFAULT_THICKNESS_NM:g} each)"),
                         _thickness),
        "wavelengths_nm": (dict(metavar="START:STOP:STEP", help="wavelengths in nm (default 380:780:10 for molecular "
                                "inks, 380:780:20 for particles at the default accuracy)"), wavelength_range),
        "sigma_rad": (dict(type=int, metavar="COUNT", help="number of incidence angles, uniform from 0° to 90° "
                           "inclusive (default 46 for molecular inks; particles 0,15,30,45,60,70,80,90)"),
                      uniform_angles),
        "dphi_count": (dict(type=int, metavar="COUNT", help=f"azimuth-difference nodes of the BRDF over 0–180° "
                            f"(default {DPHI_COUNT})"), None),
        "polarisation": (dict(choices=POLARISATIONS, default=DEFAULT_POLARISATION, help="light the table is for (te: "
                              "the paper's scalar model, which also turns the local field off unless --local-field "
                              "is given)"), None),
        "local_field": (dict(help="pigments with their local-field permittivity: the dipole response of the grains "
                             "(and of dissolved pigment) that the scalar equation lacks, which makes the layer absorb "
                             "4–12 %% more, as Maxwell's equations do (docs/polarisation.md); the default with "
                             "unpolarised light"), None),
        "accuracy": (dict(choices=tuple(ACCURACY), default="default",
                          help="preset of the settings below (docs/tables.md: error and cost of each)"), None),
        "realizations": (dict(type=int, help=f"random cells per wavelength (default: the preset's, {_per_preset('realizations')})"), None),
        "target_se": (dict(type=float, help="add realizations until the largest standard error of Rbar and Tbar is "
                           "at most this (starting from --realizations, at most --max-realizations)"), None),
        "max_realizations": (dict(type=int, help=f"cap for --target-se (default {w.max_realizations})"), None),
        "azimuths": (dict(type=int, help=f"incidence azimuths per realization; 1: TE and TM alternate over the realizations "
                                       f"(default: the preset's, {_per_preset('azimuths')})"), None),
        "tolerance": (dict(type=float, help="allowed error in Rbar/Tbar/diffuse when choosing the cheapest tier "
                           f"(default {w.tolerance:g})"), None),
        "tier": (dict(choices=TIERS, help="model: auto (measured choice), effective-medium (mean-ε film), born "
                      "(first order), full (converged wave solve); default auto"), None),
        "cell_nm": (dict(type=float, help=f"lateral period of the cell, nm (default {w.cell_nm:g})"), None),
        "grid": (dict(type=int, nargs=3, metavar=("NX", "NY", "NZ"),
                      help="voxels of the cell (default {} {} {})".format(*w.grid)), tuple),
        "solver_tol": (dict(type=float, help=f"wave solver relative residual (default: the preset's, {_per_preset('solver_tol')})"), None),
        "seed": (dict(type=int, help=f"random seed of the realizations (default {w.seed})"), None),
        "wavelength_stride": (dict(type=int, metavar="K", help=f"solve the wave ensemble on every K-th wavelength "
                                   "(and the last) and interpolate its difference to the exact film of the ink "
                                   f"in between (docs/tables.md, 'Wavelength stride'; default {w.wavelength_stride}, fine 1)"), None),
    }


def add_request_arguments(p: argparse.ArgumentParser, ink_required: bool = True, names=None,
                          group: str = "particle inks (wave-optics tiers)") -> None:
    """The options that make a table request (shared by `build`, `show` and the figure commands),
    one per solver.table.options.OPTIONS entry (or those `names`); the particle inks' in `group`."""
    spec = _cli_spec()
    particle = p.add_argument_group(group)
    for option in OPTIONS:
        if names is not None and option.name not in names:
            continue
        kwargs, _ = spec[option.name]
        target = particle if option.wave or option.name == "accuracy" or names is not None else p
        if option.name == "local_field":
            pair = p.add_mutually_exclusive_group()
            pair.add_argument(option.cli, dest=option.dest, action="store_true", default=None, help=kwargs["help"])
            pair.add_argument("--no-" + option.cli.removeprefix("--"), dest=option.dest, action="store_false",
                              default=None, help="pigments with their bulk permittivity (the paper's volume mix); "
                                                 "the default with te")
            continue
        kwargs = {"default": None, **kwargs}
        if option.name == "ink":
            kwargs["required"] = ink_required
        target.add_argument(option.cli, dest=option.dest, **kwargs)


def add_cache_argument(p) -> None:
    p.add_argument("--cache", default=None, help="cache directory (default $INKBSDF_CACHE or ~/.cache/inkbsdf)")


def cache_from_args(args) -> TableCache:
    return TableCache(Path(args.cache)) if args.cache else TableCache.default()


def add_run_arguments(p: argparse.ArgumentParser) -> None:
    r = p.add_argument_group("running")
    r.add_argument("--workers", type=int, default=None,
                   help=f"local worker processes (default one per core, here {default_workers()}; 1 = in this process)")
    r.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler address: run the work units there instead of a local pool")
    add_cache_argument(r)
    r.add_argument("--no-progress", action="store_true", help="no progress bars")
    r.add_argument("--force", action="store_true",
                   help="build even what the up-front estimate says cannot fit this machine's memory or disk")


def add_parser(sub) -> None:
    p = sub.add_parser("build", help="compute a table for one ink", formatter_class=DefaultsFormatter)
    add_request_arguments(p)
    add_run_arguments(p)
    p.add_argument("-o", "--output", required=True, help="table file to write (.npz)")
    p.set_defaults(func=run, resumes=True)            # an interrupt keeps finished work units


def given_options(args) -> dict:
    """{table_request keyword: value} of the request options that `args` holds a value for,
    each converted as the CLI reads it."""
    spec = _cli_spec()
    given = {}
    for option in OPTIONS:
        value = getattr(args, option.dest, None)
        if value is not None:
            convert = spec[option.name][1]
            given[option.name] = convert(value) if convert else value
    return given


def request_from_args(args) -> TableRequest:
    """The request the options describe: only the options given override the defaults."""
    given = given_options(args)
    return table_request(given.pop("ink"), given.pop("particles", "molecular"), **given)


def options_from_args(args) -> BuildOptions:
    kw = {} if args.workers is None else {"workers": args.workers}
    return BuildOptions(scheduler=args.scheduler, progress=not args.no_progress, cache=cache_from_args(args),
                        force=args.force, **kw)


def _estimate_note(request, opts: BuildOptions, built: bool) -> str:
    """'; estimated 10 s for a quiet machine' beside a build's time (the preflight's model),
    nothing for a cache hit or a film (milliseconds)."""
    seconds = preflight.estimate(request, opts.workers).seconds if built else 0.0
    return f"; estimated {seconds:.0f} s for a quiet machine" if seconds >= 1 else ""


def run(args) -> int:
    request = request_from_args(args)
    opts = options_from_args(args)
    writable_output(args.output, ".npz", "-o")
    log.debug("request %s; cache key %s; cache %s; %s", request.describe(), request.key(), opts.cache.root,
              f"scheduler {opts.scheduler}" if opts.scheduler else f"{opts.workers} worker(s)")
    t0 = time.perf_counter()
    table, cached_path, built = get_or_build(request, opts)
    out = Path(args.output)
    if out.resolve() != Path(cached_path).resolve():
        atomic_copy(cached_path, out)
    meta = table.meta
    print(f"{out}: ink {request.ink_label}, particles {request.particles_label}, {meta['tier']} tier, "
          f"{table.wavelengths.size} wavelengths, {table.sigma.size} angles, {request.polarisation} "
          f"({'built' if built else 'from cache'} in {time.perf_counter() - t0:.1f} s{_estimate_note(request, opts, built)})")
    if built and meta.get("timings_s"):
        print("  stage seconds: " + ", ".join(f"{k} {v:.1f}" for k, v in meta["timings_s"].items()))
    if meta.get("tier_probe"):
        print("  tier probe (max deviation from full solve): " + ", ".join(
            f"{k} {v:.4f}" for k, v in meta["tier_probe"]["deviation"].items()))
    for line in estimate_lines(meta):
        print("  " + line)
    return 0


#: the energy closure's two keys in a table's meta errors (solver/table/wave_ensemble.py)
CLOSURE_KEYS = ("energy_closure_max", "energy_closure_exact_sampled_max")


def estimate_lines(meta: dict) -> list[str]:
    """The build summary's error estimates: the standard errors, and the energy closure
    R + T + A − 1 said for what it is (docs/tables.md, 'Energy'): in the full tier the solver's
    residual; in the born tier the first-order model's own imbalance (R + T from the scattered
    field, A by the midpoint rule), not a solver residual — what vouches for a Born table is
    the tier probe's measured deviation from full solves, where one ran."""
    errors = meta.get("errors", {})
    rest = {k: v for k, v in errors.items() if k.endswith("_max") and k not in CLOSURE_KEYS}
    lines = ["error estimates: " + ", ".join(f"{k} {'unknown (1 realization)' if v is None else f'{v:.2g}'}"
                                             for k, v in rest.items())] if rest else []
    closure = errors.get("energy_closure_max")
    if closure is None:
        return lines
    if meta.get("tier") == "born":
        probe = meta.get("tier_probe") or {}
        born = probe.get("deviation", {}).get("born")
        vouched = (f"the tier probe measured its Rbar, Tbar, diffuse R within {born:.2g} of full solves "
                   f"(tolerance {probe.get('tolerance'):g})" if born is not None else
                   "--tier born was asked for, so no probe measured its error: --tier auto measures it")
        lines.append(f"energy closure {closure:.2g} (first-order Born: the model's own imbalance, not a solver "
                     f"residual; {vouched})")
    else:
        exact = errors.get("energy_closure_exact_sampled_max")
        lines.append(f"energy closure {closure:.2g} (the solver's residual R+T+A−1"
                     + (f"; scheme-exact identity {exact:.2g} on one sampled solve per realization" if exact is not None
                        else "") + ")")
    return lines
