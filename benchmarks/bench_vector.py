"""Vector Maxwell referee (treams) against the scalar wave solver, in colour (not a test).

Needs the optional extra: `pip install -e '.[test,vector]'` (treams).  Docs:
docs/vector_referee.md.

    python -m benchmarks.bench_vector                  # table of every case from the cache
    python -m benchmarks.bench_vector --compute 600    # compute missing units for ≤ 600 s first
    python -m benchmarks.bench_vector --quick          # one small unit (~1–2 min), both solvers
    python -m benchmarks.bench_vector --validate       # the referee's checks (~1–2 min)
    python -m benchmarks.bench_vector --knobs          # lmax, plane-wave cutoff, scalar grid
    python -m benchmarks.bench_vector --case 1 --compute 3000   # one case only
    python -m benchmarks.bench_vector --faces          # TM face forms vs the referee (cache)
    python -m benchmarks.bench_vector --voxel-map 3600 # default tables vs RCWA on the same voxels
    python -m benchmarks.bench_vector --voxel-map 0 --presets brewster,all,electric-mean
    python -m benchmarks.bench_vector --lamellae       # TM across lamellae: the local field's direction
    python -m benchmarks.bench_vector --tm-oblique     # the oblique TM error per face form (~3 min)
    python -m benchmarks.bench_vector --rough-profile  # a rough top's TM profile: ΔE and time per merge
    python -m benchmarks.bench_vector --rcwa-validate  # the RCWA referee's checks (~1 min)

Vector units are cached in out/bench/vector/ (one .npz per realization, λ, σ); the table lists
what the cache holds and names the units still missing.  `--compute` works through CASES in
order (cheapest first) and stops starting new units when its time is up.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.vector import compare, runs
from benchmarks.vector.cases import Case, host_eps, sphere_eps
from solver.wave import DEFAULT_TM_FACES

COLOUR_WAVELENGTHS = (420.0, 470.0, 520.0, 580.0, 660.0)

#: The comparison cases, cheapest first.  Cells are as large as the lattice sums allow on the
#: 2-core VM (docs/vector_referee.md: cost ∝ pairs of spheres × (2·lmax + 1)²).
#: The two colour cases have 5 and 2 realizations (docs/vector_referee.md, realization noise).
CASES = (
    Case(300.0, 0.15, 1000.0, COLOUR_WAVELENGTHS, realizations=5),
    Case(100.0, 0.15, 500.0, (420.0, 470.0, 520.0, 660.0), pw_cutoff_per_nm=0.08,
         realizations=2),
    Case(300.0, 0.50, 1000.0, (470.0, 550.0), polar_deg=(0.0,)),
    Case(100.0, 0.50, 400.0, (470.0, 550.0), polar_deg=(0.0,), pw_cutoff_per_nm=0.08),
)
QUICK = Case(300.0, 0.15, 1000.0, (500.0,), polar_deg=(0.0,))
#: scalar variants of the main table: (pigment ε model, TM face preset)
DEFAULT_VARIANTS = (("volume", DEFAULT_TM_FACES), ("localfield", DEFAULT_TM_FACES))


def units_of(case: Case, *, compute_until: float | None = None,
             variants: tuple[tuple[str, str], ...] = DEFAULT_VARIANTS):
    """[λ][σ] lists over realizations of the vector units and, per scalar variant (material
    model, TM face preset), the scalar units; missing vector units are computed while
    time.monotonic() < compute_until, else listed in `missing`."""
    vec, missing = [], []
    sca = {v: [] for v in variants}
    for lam in case.wavelengths_nm:
        vrow, srows = [], {v: [] for v in variants}
        for sig in case.polar_deg:
            vs, ss = [], {v: [] for v in variants}
            for r in range(case.realizations):
                go = compute_until is not None and time.monotonic() < compute_until
                u = runs.vector_unit(case, r, lam, sig, compute=go)
                if u is None:
                    missing.append((r, lam, sig))
                    continue
                vs.append(u)
                for v in variants:
                    ss[v].append(runs.scalar_unit(case, r, lam, sig, *v))
            vrow.append(vs)
            for v in variants:
                srows[v].append(ss[v])
        vec.append(vrow)
        for v in variants:
            sca[v].append(srows[v])
    return vec, sca, missing


def _fmt(x, nd=4):
    return "  n/a " if not np.isfinite(x) else f"{x:.{nd}f}"


def _colour(case, ev, es, what) -> dict:
    out = {}
    for p, name in enumerate(compare.POL_NAMES):
        if not np.all(np.isfinite(es.Rbar[..., p])):
            print(f"    {name:5s}: scalar solver lacks this polarisation (TM pending)")
            continue
        lab_v, lab_s = compare.lab_of(ev, p), compare.lab_of(es, p)
        de = compare.delta_e2000(lab_v, lab_s)
        out[name] = de
        for j, sig in enumerate(case.polar_deg):
            print(f"    {name:5s} view {sig:4.0f}°: vector L*a*b* {lab_v[j, 0]:6.2f} {lab_v[j, 1]:6.2f} "
                  f"{lab_v[j, 2]:6.2f}  {what} {lab_s[j, 0]:6.2f} {lab_s[j, 1]:6.2f} {lab_s[j, 2]:6.2f}"
                  f"  ΔE2000 {de[j]:.2f}")
    if "s" in out:
        de = compare.delta_e2000(compare.lab_of(ev, 2), compare.lab_of(es, 0))
        print(f"    {what} TE-only (a TE table) against the unpolarised vector layer: ΔE2000 " +
              ", ".join(f"{sig:g}°: {d:.2f}" for sig, d in zip(case.polar_deg, de)))
        out["te_vs_unpol"] = de
    return out


def mie_matched_study(cases) -> None:
    """The Mie-matched local fields that were tried (`vector.mie_matched`): one sphere's
    absorption efficiency with each ε', then each variant's colour error against the referee."""
    from benchmarks.vector.mie_matched import MODES, matched_eps, scalar_sphere_efficiencies
    from benchmarks.vector.oracles import mie_cross_sections
    from solver.materials import local_field_eps

    for case in cases:
        if len(case.polar_deg) < 2:
            continue
        a, eh = case.diameter_nm / 2, host_eps()
        print(f"\n--- {case.label}: one sphere's Q_abs (Mie | scalar bulk ε | dipole ε' | mieabs) and ε'")
        for lam in case.wavelengths_nm:
            ep = sphere_eps(case, lam)
            x = 2 * np.pi * np.sqrt(eh) / lam * a
            q = lambda e: scalar_sphere_efficiencies(x, np.sqrt(e / eh))[0]   # noqa: E731
            mie = float(np.real(mie_cross_sections(a, lam, np.sqrt(ep), np.sqrt(eh))[2])) / (np.pi * a * a)
            dip = local_field_eps(ep, eh)
            matched = {m: matched_eps(ep, eh, a, lam, m) for m in MODES}
            print(f"    {lam:4.0f} nm: {mie:.4f} | {q(ep):.4f} | {q(dip):.4f} | {q(matched['mieabs']):.4f}"
                  f"   ε' dipole {dip:.3f}, " + ", ".join(f"{m} {e:.3f}" for m, e in matched.items()))
        variants = tuple((m, DEFAULT_TM_FACES) for m in ("localfield",) + MODES)
        vec, sca, missing = units_of(case, variants=variants)
        if missing:
            print(f"    vector units missing ({len(missing)}): run with --compute")
            continue
        ev = compare.reduce_units(vec, case.wavelengths_nm, case.polar_deg)
        for v in variants:
            es = compare.reduce_units(sca[v], case.wavelengths_nm, case.polar_deg)
            de = compare.delta_e2000(compare.lab_of(ev, 2), compare.lab_of(es, 2))
            print(f"    {v[0]:10s} unpolarised ΔE2000 at " + ", ".join(f"{sig:g}°: {d:.2f}" for sig, d in zip(case.polar_deg, de))
                  + f";  max |ΔTbar| {np.max(np.abs(es.Tbar[..., 2] - ev.Tbar[..., 2])):.4f}")


def small_particle_limit(case: Case) -> str:
    """Quasi-static limit: the scalar equation's effective medium is the volume mean of ε (ε enters
    as a potential), Maxwell's is Maxwell Garnett (spheres polarise: local-field factor)."""
    parts = []
    for lam in case.wavelengths_nm:
        ep, eh, f = sphere_eps(case, lam), host_eps(), case.fraction
        beta = (ep - eh) / (ep + 2 * eh)
        mg = eh * (1 + 2 * f * beta) / (1 - f * beta)
        mean = (1 - f) * eh + f * ep
        field = abs(3 * eh / (ep + 2 * eh)) ** 2
        ratio = f"{mg.imag / mean.imag:.3f}" if mean.imag > 1e-9 else "(no loss)"
        parts.append(f"{lam:g}: Im ε MG/mean {ratio}, |E_in/E_0|² {field:.3f}")
    return "; ".join(parts)


def print_case(case: Case, vec, sca, missing) -> dict | None:
    print(f"\n--- {case.label}: λ {list(case.wavelengths_nm)} nm, σ {list(case.polar_deg)}°, "
          f"{case.realizations} realization(s), pw cutoff {case.pw_cutoff_per_nm}/nm")
    print(f"    small-particle limit, vector/scalar: {small_particle_limit(case)}")
    if missing:
        print(f"    vector units missing ({len(missing)}): " +
              ", ".join(f"r{r} λ{lam:g} σ{sig:g}" for r, lam, sig in missing[:8]) +
              (" ..." if len(missing) > 8 else "") + "  (run with --compute SECONDS)")
        return None
    secs = [u.seconds for row in vec for us in row for u in us]
    info = vec[0][0][0].info
    print(f"    vector: {info.get('info', info)}; {np.mean(secs):.0f} s per unit "
          f"(all units {np.sum(secs) / 60:.1f} min, 2-core VM shared with other jobs)")
    cross = max(float(np.abs(u.r00[0, 1]) ** 2 + np.abs(u.r00[1, 0]) ** 2) / 2
                for row in vec for us in row for u in us)
    print(f"    vector, cross-polarised mirror beam (s→p, p→s) of one realization: ≤ {cross:.1e} of the incident power")
    ev = compare.reduce_units(vec, case.wavelengths_nm, case.polar_deg)
    es = compare.reduce_units(sca[DEFAULT_VARIANTS[0]], case.wavelengths_nm, case.polar_deg)
    el = compare.reduce_units(sca[DEFAULT_VARIANTS[1]], case.wavelengths_nm, case.polar_deg)
    print("    λ     σ  pol  |  Rbar vec  scal    diff |  Tbar vec  scal    diff | Rspec vec  scal    diff"
          " | A scal/vec | default (local field): ΔRbar  ΔTbar")
    for i, lam in enumerate(case.wavelengths_nm):
        for j, sig in enumerate(case.polar_deg):
            for p, name in enumerate(compare.POL_NAMES):
                cells = []
                for q in ("Rbar", "Tbar", "R_spec"):
                    a, b = getattr(ev, q)[i, j, p], getattr(es, q)[i, j, p]
                    cells.append(f"{_fmt(a)} {_fmt(b)} {_fmt(b - a):>7}")
                a_v = 1 - ev.Rbar[i, j, p] - ev.Tbar[i, j, p]
                a_s = 1 - es.Rbar[i, j, p] - es.Tbar[i, j, p]
                ratio = a_s / a_v if a_v > 1e-3 else np.nan
                lf = (f"{_fmt(el.Rbar[i, j, p] - ev.Rbar[i, j, p]):>7} "
                      f"{_fmt(el.Tbar[i, j, p] - ev.Tbar[i, j, p]):>7}")
                print(f"  {lam:4.0f} {sig:4.0f}  {name:5s}| " + " | ".join(cells) +
                      f" | {_fmt(ratio, 3):>9} | {lf}")
    out = {}
    if len(case.wavelengths_nm) >= 3 and len(case.polar_deg) >= 2:
        print("    ink on paper (r = 0.9) under diffuse light, CIELAB (D65) and ΔE2000 to the vector layer;\n"
              "    scalar with the bulk pigment ε (the paper's volume mix: --no-local-field, --polarisation te):")
        out["plain"] = _colour(case, ev, es, "scalar")
        print("    the tables' default: the local-field pigment ε (TableRequest.layer_materials), same faces:")
        out["localfield"] = _colour(case, ev, el, "scalar-LF")
    out["ensembles"] = (ev, es, el)
    return out


def plot(results, path=Path("out/bench/vector_spectra.png")) -> None:
    """Albedo of the ink on paper seen at 0° and 60° against λ, per complete case."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    done = [(c, e) for c, e in results
            if e is not None and len(c.wavelengths_nm) >= 3 and len(c.polar_deg) >= 2]
    if not done:
        return
    fig, axes = plt.subplots(1, len(done), figsize=(5.5 * len(done), 4), squeeze=False)
    for ax, (case, (ev, es, el)) in zip(axes[0], done):
        for j, sig in enumerate(case.polar_deg):
            if sig not in (0.0, 60.0):
                continue
            ls = "-" if sig == 0.0 else "--"
            ax.plot(case.wavelengths_nm, compare.albedo_on_paper(ev, 2)[:, j], "k" + ls, label=f"vector unpol. {sig:g}°")
            ax.plot(case.wavelengths_nm, compare.albedo_on_paper(ev, 0)[:, j], "b" + ls, lw=0.8, label=f"vector s {sig:g}°")
            ax.plot(case.wavelengths_nm, compare.albedo_on_paper(es, 0)[:, j], "r" + ls, label=f"scalar TE {sig:g}°")
            ax.plot(case.wavelengths_nm, compare.albedo_on_paper(el, 0)[:, j], "g" + ls, lw=0.8,
                    label=f"scalar TE, local-field ε {sig:g}°")
            if np.all(np.isfinite(es.Rbar[..., 2])):
                ax.plot(case.wavelengths_nm, compare.albedo_on_paper(es, 2)[:, j], "m" + ls,
                        label=f"scalar unpol. (TE+TM) {sig:g}°")
                ax.plot(case.wavelengths_nm, compare.albedo_on_paper(el, 2)[:, j], "c" + ls,
                        label=f"scalar unpol., local-field ε {sig:g}°")
        ax.set_title(case.label, fontsize=9)
        ax.set_xlabel("wavelength (nm)")
        ax.set_ylabel("ink on paper (r = 0.9): albedo, diffuse light")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"\nplot: {path}")


def quick() -> int:
    t0 = time.monotonic()
    vec, sca, missing = units_of(QUICK, compute_until=time.monotonic() + 1e9)
    print_case(QUICK, vec, sca, missing)
    print(f"\n--quick: {time.monotonic() - t0:.0f} s (cached units are read, not recomputed)")
    return 0


def _grcwa_missing() -> bool:
    """True (and one line on stderr saying how to install it) when grcwa, the RCWA referee of the
    optional `vector` extra, is not installed."""
    try:
        import grcwa  # noqa: F401
    except ImportError:
        print("grcwa is not installed: pip install -e '.[vector]' (optional extra)", file=sys.stderr)
        return True
    return False


def voxel_map_study(seconds: float, presets: tuple[str, ...], realizations: int = 1,
                    rough: bool = False) -> int:
    """Print the voxel-grid map (benchmarks/vector/voxel_map.py) and draw its picture."""
    if seconds > 0 and _grcwa_missing():
        return 2
    from benchmarks.vector import voxel_map as vm

    t0 = time.monotonic()
    until = t0 + seconds if seconds > 0 else t0
    print(f"RCWA (grcwa) vs the default tables' scalar solves on the same voxels: cell "
          f"{vm.CELL_NM:g} nm, grid {vm.GRID}, λ {vm.WAVELENGTHS} nm, views {vm.VIEWS_DEG}°, "
          f"pigment bulk ε for Maxwell, local field for the scalar; paper r = 0.9, diffuse light; "
          f"{realizations} realization(s) per case, incidence azimuth 0")
    cases = vm.cases(realizations) + (vm.rough_cases(realizations) if rough else ())
    rows = vm.run(cases, compute_until=until, presets=presets)
    views = " ".join(f"{v:>5g}°" for v in vm.VIEWS_DEG)
    print(f"\n{'case':<22} {'tm_faces':<14} {'pol':<6} ΔE2000 at {views}   max|ΔRbar|  max|ΔTbar|")
    for row in rows:
        if row["missing"]:
            print(f"{row['case']:<22} {row['preset']:<14} (units missing: rerun with more seconds)")
            continue
        for k, pol in enumerate(("s", "p", "unpol")):
            de = " ".join(f"{v:6.2f}" for v in row["de"][pol])
            print(f"{row['case']:<22} {row['preset']:<14} {pol:<6} {' ' * 10}{de}   "
                  f"{row['dR'][k]:9.4f}  {row['dT'][k]:9.4f}")
        per_view = " ".join(f"{v:.4f}" for v in row["dR_by_view"][:, 1])
        print(f"{'':<22} {'':<14} p: max|ΔRbar| per view {per_view}")
    vm.picture(rows, Path("out/bench/vector_voxel_map.png"))
    took = time.monotonic() - t0
    from benchmarks.yardstick import yardstick_s

    ys = yardstick_s()
    print(f"\n--voxel-map: {took:.0f} s, yardstick {ys:.2f} s ({took / ys:.0f} yardsticks); "
          f"picture out/bench/vector_voxel_map.png")
    return 0


def rough_profile(realizations: int) -> int:
    """Print the rough top's TM profile study (voxel_map.rough_profile_study)."""
    if _grcwa_missing():
        return 2
    from benchmarks.vector import voxel_map as vm
    from benchmarks.yardstick import yardstick_s

    t0 = time.monotonic()
    rows = vm.rough_profile_study(max(realizations, 2))
    print("a rough top's TM conditions: unpolarised ΔE2000 against RCWA (voxel map's rough cases, "
          f"views {vm.VIEWS_DEG}°, max over the views) and one TM solve pair (above + below) of the "
          "default table (Y30 sphere:200:rough, 48×48×24, 560 nm, mean of 45° and 75°, CPU s)")
    print(f"{'TM conditions':<16} {'layers':>6} {'CPU s':>7} {'apps':>6}  " +
          "  ".join(f"{label:>22}" for label in rows[0]["de"]))
    for row in rows:
        des = "  ".join(f"{max(v):6.2f} ({' '.join(f'{x:.2f}' for x in v)})" for v in row["de"].values())
        print(f"{row['kind']:<16} {row['layers']:>6} {row['seconds']:>7.3f} {row['applications']:>6.1f}  {des}")
    took = time.monotonic() - t0
    ys = yardstick_s()
    print(f"\n--rough-profile: {took:.0f} s, yardstick {ys:.2f} s ({took / ys:.0f} yardsticks)")
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_vector", description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="one small unit, both solvers")
    ap.add_argument("--validate", action="store_true", help="run the referee's validation checks")
    ap.add_argument("--knobs", action="store_true", help="accuracy knobs: lmax, plane-wave cutoff, scalar grid")
    ap.add_argument("--compute", type=float, default=0.0, metavar="SECONDS",
                    help="compute missing vector units, starting new ones for at most this long")
    ap.add_argument("--faces", action="store_true",
                    help="evaluate every TM face-form preset (and the local-field ε) against the "
                         "cached vector units, with reciprocity and Wood-anomaly checks")
    ap.add_argument("--mie-matched", action="store_true",
                    help="the Mie-matched local fields that were tried, against the cached vector units")
    ap.add_argument("--case", type=int, action="append", metavar="N",
                    help="only case N of CASES (0-based; repeatable), e.g. to compute cases in parallel")
    ap.add_argument("--voxel-map", type=float, default=None, metavar="SECONDS",
                    help="the map of the default tables against Maxwell (grcwa's RCWA on the same "
                         "voxel grid: spheres and cylinders at 15/30/50 %%), computing missing units "
                         "for at most this long (0: from the cache only)")
    ap.add_argument("--realizations", type=int, default=1,
                    help="realizations per case of --voxel-map (default 1)")
    ap.add_argument("--presets", default="brewster",
                    help="scalar TM variants for --voxel-map, comma-separated: a face preset "
                         "(the tables' TM with it), or PRESET/profile for the layer's mean profile "
                         "with Maxwell's TM conditions (default: brewster)")
    ap.add_argument("--rough", action="store_true",
                    help="add rough tops (200-nm spheres at 15 and 30 %%) to --voxel-map")
    ap.add_argument("--lamellae", action="store_true",
                    help="lamellar gratings in TM against RCWA: bulk ε and local fields by field "
                         "direction (~3 min)")
    ap.add_argument("--tm-oblique", action="store_true",
                    help="the oblique TM error of a dilute sphere layer against RCWA, per face preset")
    ap.add_argument("--rough-profile", action="store_true",
                    help="a rough top's mean-profile TM conditions per merge tolerance: ΔE2000 "
                         "against RCWA (two realizations) and the cost of a TM solve (~5 min)")
    ap.add_argument("--rcwa-validate", action="store_true",
                    help="the RCWA referee's checks: exact film, lamellar grating s = scalar TE")
    args = ap.parse_args(argv)
    if args.rcwa_validate:
        from benchmarks.vector import rcwa_layer
        from solver.wave.vecops import one_blas_thread
        with one_blas_thread():
            print(f"homogeneous 1000-nm film (1.82 + 1.06i, 450 nm, 0–80°, s and p) vs the exact film: "
                  f"max |ΔR|, |ΔT| = {rcwa_layer.film_check():.1e}")
            for nx in (24, 32):
                for deg, orders, r_s, r_te, t_s, t_te in rcwa_layer.grating_check(nx):
                    print(f"lamellar grating, {nx}×{nx}×16 voxels, σ {deg:g}°, {orders} orders: R_s {r_s:.5f} "
                          f"vs scalar TE {r_te:.5f}, T_s {t_s:.5f} vs {t_te:.5f}")
        return 0
    if args.tm_oblique:
        from benchmarks.vector import voxel_map
        t0 = time.monotonic()
        voxel_map.oblique_study()
        print(f"\n--tm-oblique: {time.monotonic() - t0:.0f} s")
        return 0
    if args.rough_profile:
        return rough_profile(args.realizations)
    if args.lamellae:
        from benchmarks.vector import lamellae
        t0 = time.monotonic()
        lamellae.print_study(lamellae.study())
        print(f"\n--lamellae: {time.monotonic() - t0:.0f} s")
        return 0
    if args.voxel_map is not None:
        return voxel_map_study(args.voxel_map, tuple(args.presets.split(",")), args.realizations,
                               args.rough)
    try:
        import treams  # noqa: F401
    except ImportError:
        if args.validate or args.knobs or args.quick or args.compute > 0:
            print("treams is not installed: pip install -e '.[vector]' (optional extra)", file=sys.stderr)
            return 2
        print("(treams not installed: showing cached vector units only)")
    if args.validate:
        from benchmarks.vector import validate
        return validate.main()
    if args.knobs:
        from benchmarks.vector import validate
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return validate.knobs()
    if args.quick:
        return quick()
    if args.mie_matched:
        mie_matched_study(CASES if not args.case else [CASES[i] for i in args.case])
        return 0
    if args.faces:
        from benchmarks.vector import faces_eval
        chosen = CASES if not args.case else [CASES[i] for i in args.case]
        t0 = time.monotonic()
        faces_eval.evaluate(chosen)
        faces_eval.physics_checks(CASES[0], dense=CASES[2])
        print(f"\n--faces: {time.monotonic() - t0:.0f} s (scalar units cached in out/bench/vector/)")
        return 0
    until = time.monotonic() + args.compute if args.compute > 0 else None
    print(f"scalar solver: TE and TM (tm_faces={DEFAULT_TM_FACES!r}); "
          f"scalar grid voxel {runs.SCALAR_VOXEL_NM:.1f} nm, tol {runs.SCALAR_TOL:g}")
    chosen = CASES if not args.case else [CASES[i] for i in args.case]
    results = []
    for case in chosen:
        vec, sca, missing = units_of(case, compute_until=until)
        out = print_case(case, vec, sca, missing)
        results.append((case, (out or {}).get("ensembles")))
    plot(results)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
