"""The paper's findings (§3.3, DESIGN §6) reproduced with reduced-accuracy tables (a study).

    python -m benchmarks.bench_findings      # ~10–15 min on 2 cores

Each case is a table (21 λ; σ = 0, 30, 60, 80, 90°; 3 realizations × 1 azimuth; 48×48×24 grid —
the grid's bias here is ≈ 0.005 in Rbar/Tbar, bench_tables) rendered as the colour of the ink on
paper (r = 0.9) under diffuse light seen at 0°.  Checks printed (✓/✗):
  1. colour saturates with concentration (Y7.5+B7.5 → Y15+B15, 300 nm and molecular);
  2. and with smaller particles (300 → 100 → 30 nm → molecular, at 15 %);
     ("saturated" as CIELAB saturation s = C*/L*: a denser layer is darker at similar chroma)
  3. the size effect is strongest at low concentration (15 % vs 30 %);
  4. agglutinated 100-nm grains look like bigger grains (chroma between 100 and 300 nm or below);
  5. the Y+B particle mix approaches molecular Green as size shrinks;
  6. a rough top changes little (ΔE small compared with the size effect).
Swatches: out/bench/findings.png.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from solver.colour import lab_hue_chroma
from solver.apps.figures.cell_colour import cell_lab, cell_srgb8, delta_e, saturation
from solver.table.builder import BuildOptions, build_table
from solver.table.cache import TableCache
from solver.table.request import table_request

OUT = Path("out/bench")
SETTINGS = dict(sigma_rad=tuple(np.radians([0, 30, 60, 80, 90])), realizations=3, azimuths=1,
                grid=(48, 48, 24), tier="full")
CASES = [("Y7.5+B7.5", p) for p in ("molecular", "sphere:30", "sphere:100", "sphere:300",
                                     "sphere:100:agglutinated", "sphere:300:rough")]
CASES += [("Y15+B15", p) for p in ("molecular", "sphere:100", "sphere:300")]


def colour(table) -> tuple[np.ndarray, np.ndarray]:
    """CIELAB and sRGB8 of the ink on paper r = 0.9 under uniform diffuse light, seen at 0°
    (the colour of a figure cell: solver.apps.figures.cell_colour)."""
    return cell_lab(table), cell_srgb8(table)


def main(argv=None) -> int:
    cache = TableCache(Path(tempfile.mkdtemp(prefix="findings_")))
    labs, rgbs = {}, {}
    for ink, particles in CASES:
        t0 = time.perf_counter()
        settings = {} if particles == "molecular" else SETTINGS
        table = build_table(table_request(ink, particles, **settings),
                            BuildOptions(progress=False, cache=cache))
        labs[ink, particles], rgbs[ink, particles] = colour(table)
        lab = labs[ink, particles]
        hue, chroma = lab_hue_chroma(lab)
        print(f"{ink:10s} {particles:24s} L* {lab[0]:5.1f} a* {lab[1]:6.1f} b* {lab[2]:6.1f} "
              f"C* {chroma:5.1f} s {chroma / lab[0]:4.2f} h {hue:5.1f}°   ({time.perf_counter() - t0:.0f} s)",
              flush=True)
    green = colour(build_table(table_request("G15"), BuildOptions(progress=False, cache=cache)))[0]
    C = lambda ink, p: float(lab_hue_chroma(labs[ink, p])[1])
    S = lambda ink, p: float(saturation(labs[ink, p]))              # CIELAB saturation C*/L*
    dE = lambda a, b: float(delta_e(a, b))
    low, high = "Y7.5+B7.5", "Y15+B15"
    checks = [
        ("1. saturation C*/L* grows with concentration (300 nm; 100 nm; molecular)",
         all(S(high, p) > S(low, p) for p in ("sphere:300", "sphere:100", "molecular"))),
        ("2. saturation grows as grains shrink (15 %: 300 < 100 < 30 nm ≤ molecular)",
         S(low, "sphere:300") < S(low, "sphere:100") < S(low, "sphere:30") <= S(low, "molecular") + 0.005),
        ("3. size effect stronger at 15 % than at 30 % (ΔE molecular↔300 nm)",
         dE(labs[low, "molecular"], labs[low, "sphere:300"]) > dE(labs[high, "molecular"], labs[high, "sphere:300"])),
        ("4. agglutinated 100 nm is less saturated than dispersed 100 nm (looks bigger)",
         C(low, "sphere:100:agglutinated") < C(low, "sphere:100")),
        ("5. Y+B grains approach molecular G15 as size shrinks (ΔE 300 > 100 > 30 nm)",
         dE(labs[low, "sphere:300"], green) > dE(labs[low, "sphere:100"], green) > dE(labs[low, "sphere:30"], green)),
        ("6. rough top changes little (ΔE rough↔flat < ΔE 300↔100 nm)",
         dE(labs[low, "sphere:300:rough"], labs[low, "sphere:300"]) < dE(labs[low, "sphere:300"], labs[low, "sphere:100"])),
    ]
    print(f"molecular G15: L* {green[0]:.1f} a* {green[1]:.1f} b* {green[2]:.1f}")
    for text, ok in checks:
        print(f"  {'✓' if ok else '✗'} {text}")
    _swatches(rgbs)
    return 0


def _swatches(rgbs: dict) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    OUT.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(12, 2.8))
    for i, ((ink, particles), rgb) in enumerate(rgbs.items()):
        ax.add_patch(plt.Rectangle((i, 0), 0.9, 1, color=np.asarray(rgb) / 255))
        label = particles.replace(":agglutinated", "\nagglutinated").replace(":rough", "\nrough top")
        ax.text(i + 0.45, -0.08, f"{ink}\n{label}", ha="center", va="top", fontsize=7)
    ax.set_xlim(-0.1, len(rgbs))
    ax.set_ylim(-0.6, 1.05)
    ax.axis("off")
    ax.set_title("ink on paper (r = 0.9), diffuse light, 0° view")
    fig.savefig(OUT / "findings.png", dpi=120, bbox_inches="tight")
    print(f"wrote {OUT / 'findings.png'}")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
