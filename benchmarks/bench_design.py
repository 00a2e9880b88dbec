"""`ink-tables design` against ISO 12647-2 PC1: what the process pigments reach, and what it costs.

    python -m benchmarks design [--quick]

1. one molecular ink designed alone (cyan, magenta, yellow, black on the PC1 paper): wall and
   CPU seconds, evaluations, ΔE2000 (issue 21: ≤ 10 s);
2. the whole set (`ink-tables design --aim iso12647-2`, joint refinement): each aim's ΔE2000
   against its target (solids and paper ≤ 3, overprints ≤ 6) and, for an aim out of reach, the
   pigments' absorption that decides it (k in the blue window, the overprint's reflectance);
3. the choices behind the pigments: magenta without its cyan shading, black without its
   toners, both model options (local field or bulk ε);
4. how much the SQIB data's gap (380–450 nm, held at the 450-nm values) can move the cyan: its
   colour with k there set to 0 and doubled;
5. the films' wavelength step: each designed ink's colour against a 1-nm film;
6. the optimiser's knobs (coarse-grid size, local starts): ΔE2000 against time.
Times are printed beside the machine's yardstick (seconds and yardsticks).
"""

from __future__ import annotations

import argparse
import dataclasses
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
_SHARED = ROOT.parent / "shared" / "bench" / "yardstick.py"
YARDSTICK = _SHARED if _SHARED.is_file() else ROOT / "benchmarks" / "yardstick.py"


def yardstick() -> float:
    out = subprocess.run([sys.executable, str(YARDSTICK)], check=True, capture_output=True, text=True)
    return float(out.stdout.split()[-1])


def clocked(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    value = fn()
    return value, time.perf_counter() - w0, time.process_time() - c0


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_design", description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="skip the knob study and the joint refinement")
    args = p.parse_args(argv)
    import warnings

    warnings.simplefilter("ignore")
    from solver.colour.aims import ISO12647_2_PC1
    from solver.colour.cie import delta_e2000
    from solver.design import FilmColour, InkTemplate, design_ink, design_paper, design_process_set
    from solver.design import optimise
    from solver.design.optimise import default_tolerance
    from solver.design.recipe import PROCESS_PIGMENTS
    from solver.table.request import table_request

    ys = yardstick()
    print(f"yardstick {ys:.2f} s (times below: seconds, and yardsticks in brackets)")
    aims = {a.colour: a for a in ISO12647_2_PC1.values()}
    colour = FilmColour()
    paper = design_paper(aims["paper"], colour, colour.wavelengths_nm)
    on_paper = dataclasses.replace(colour, paper=paper.paper)

    print(f"\n1. one ink alone, on the PC1 paper (albedo {paper.paper:.4f})")
    print(f"{'ink':8} {'recipe':26} {'L*a*b*':>22} {'ΔE2000':>7} {'evals':>6} {'wall s':>8} {'CPU s':>7}")
    for name in ("cyan", "magenta", "yellow", "black"):
        fc = dataclasses.replace(on_paper, _tables={})
        r, wall, cpu = clocked(lambda: design_ink(aims[name], InkTemplate(PROCESS_PIGMENTS[name]), fc))
        lab = ", ".join(f"{v:.1f}" for v in r.lab)
        print(f"{name:8} {r.recipe.label:26} {lab:>22} {r.de2000:7.2f} {r.evaluations:6d} "
              f"{wall:8.2f} {cpu:7.2f} [{cpu / ys:.1f}]")

    print("\n2. the whole set, designed at once" + (" (no joint refinement: --quick)" if args.quick else ""))
    (results, fc), wall, cpu = clocked(lambda: design_process_set(ISO12647_2_PC1.values(), FilmColour(),
                                                                    joint=not args.quick))
    print(f"   {wall:.1f} s wall, {cpu:.1f} s CPU [{cpu / ys:.1f}], {fc.films} film tables")
    print(f"{'aim':8} {'recipe':48} {'L*a*b*':>22} {'aim':>16} {'ΔE2000':>7} {'target':>6}")
    for name, r in results.items():
        lab = ", ".join(f"{v:.1f}" for v in r.lab)
        aim = ", ".join(f"{v:g}" for v in r.aim.lab)
        verdict = "ok" if r.de2000 <= default_tolerance(r.aim) else "OUT"
        print(f"{name:8} {r.recipe_label:48} {lab:>22} {aim:>16} {r.de2000:7.2f} {default_tolerance(r.aim):6.0f} {verdict}")
    materials = table_request("C10", local_field=False).layer_materials(0)
    print("   the blue window (why C + M overprints are dark): k at 420/450/480 nm, and its share of the peak")
    for code in ("C", "M", "Y"):
        wl = np.arange(380.0, 781.0, 5.0)
        k = materials.pigment_k(code, wl)
        at = [float(materials.pigment_k(code, w)) for w in (420.0, 450.0, 480.0)]
        print(f"   {code}: k {at[0]:.3f} / {at[1]:.3f} / {at[2]:.3f}; peak {k.max():.2f} at {wl[k.argmax()]:.0f} nm "
              f"({100 * at[1] / k.max():.0f} % at 450 nm)")
    for name in ("red", "green", "blue"):
        r = results[name]
        if r.stack:
            table = fc.table(r.stack)
            refl = fc.reflectance(table)
            wl = table.wavelengths
            print(f"   {name} overprint reflectance at 420/450/500/550/600/650 nm: "
                  + " / ".join(f"{np.interp(w, wl, refl):.3f}" for w in (420, 450, 500, 550, 600, 650)))

    print("\n3. the pigment choices (each designed alone on the PC1 paper)")
    for label, name, pigments, lf in (("magenta, Rhodamine 6G alone", "magenta", ("M",), None),
                                      ("magenta, R6G + cyan shading", "magenta", ("M", "C"), None),
                                      ("magenta, R6G alone, bulk ε", "magenta", ("M",), False),
                                      ("magenta, the paper's R (n = 1.4)", "magenta", ("R",), None),
                                      ("black, carbon alone", "black", ("K",), None),
                                      ("black, carbon + C + M", "black", ("K", "C", "M"), None),
                                      ("cyan, bulk ε", "cyan", ("C",), False)):
        fc2 = dataclasses.replace(on_paper, local_field=lf, _tables={})
        r = design_ink(aims[name], InkTemplate(pigments), fc2)
        lab = ", ".join(f"{v:.1f}" for v in r.lab)
        print(f"   {label:34} {r.recipe.label:28} ({lab})  ΔE2000 {r.de2000:.2f}"
              + (f"  at bounds: {'; '.join(r.at_bounds)}" if r.at_bounds else ""))

    print("\n4. the SQIB gap 380–450 nm (k held at its 450-nm value), at the designed cyan recipe")
    cyan = results["cyan"].recipe
    base = table_request(cyan.ink, thickness_nm=cyan.thickness_nm).layer_materials(0)
    ref_lab = fc.lab(cyan)
    for factor in (0.0, 2.0):
        k = dict(base.k)
        k["C"] = np.where(base.wavelengths_nm < 450.0, factor * base.k["C"], base.k["C"])
        edited = dataclasses.replace(base, k=k)
        from solver.table.thinfilm_tier import build_thinfilm_table

        film = build_thinfilm_table(cyan.ink, cyan.thickness_nm, fc.wavelengths_nm,
                                    table_request("C10").grids.sigma_rad, edited)
        lab = fc.measurement.lab_of_spectra(film.wavelengths, fc.reflectance(film))
        print(f"   k(380–450 nm) × {factor:g}: L*a*b* ({lab[0]:.2f}, {lab[1]:.2f}, {lab[2]:.2f}), "
              f"ΔE2000 {float(delta_e2000(lab, ref_lab)):.2f} from the held data")

    print("\n5. the films' wavelength step (the tables' default 10 nm) at the designed recipes: ΔE2000 "
          "against a 1-nm film")
    from solver.table.request import FILM_WAVELENGTH_STEP_NM
    from solver.table.thinfilm_tier import build_thinfilm_table as film

    sigma = table_request("C10").grids.sigma_rad
    print(f"   {'ink':8} " + " ".join(f"{step:>8g} nm" for step in (20.0, FILM_WAVELENGTH_STEP_NM, 5.0, 2.0)))
    for name in ("cyan", "magenta", "yellow", "black"):
        r = results[name].recipe
        data = table_request(r.ink, thickness_nm=r.thickness_nm).layer_materials(0)

        def lab_at(step):
            t = film(r.ink, r.thickness_nm, np.arange(380.0, 780.0 + step / 2, step), sigma, data)
            return fc.measurement.lab_of_spectra(t.wavelengths, fc.reflectance(t))

        ref = lab_at(1.0)
        print(f"   {name:8} " + " ".join(f"{float(delta_e2000(lab_at(step), ref)):11.3f}"
                                        for step in (20.0, FILM_WAVELENGTH_STEP_NM, 5.0, 2.0)))

    if not args.quick:
        print("\n6. optimiser knobs: coarse-grid size and local starts (black: 4 free parameters)")
        print(f"   {'grid':>5} {'starts':>6} {'ΔE2000 cyan':>12} {'ΔE2000 black':>13} {'CPU s':>7}")
        for grid, starts in ((9, 1), (25, 1), (100, 1), (100, 3), (400, 3)):
            old = optimise.GRID_SIZE, optimise.STARTS
            optimise.GRID_SIZE, optimise.STARTS = grid, starts
            try:
                fc3 = dataclasses.replace(on_paper, _tables={})
                (rc, rk), _, cpu = clocked(lambda: (design_ink(aims["cyan"], InkTemplate(("C",)), fc3),
                                                    design_ink(aims["black"], InkTemplate(("K", "C", "M")), fc3)))
            finally:
                optimise.GRID_SIZE, optimise.STARTS = old
            print(f"   {grid:5d} {starts:6d} {rc.de2000:12.3f} {rk.de2000:13.3f} {cpu:7.2f} [{cpu / ys:.1f}]")
    print(f"\nyardstick after: {yardstick():.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
