"""What TE-only tables cost in colour: unpolarised vs TE thin-film tables (docs/polarisation.md).

    python -m benchmarks.bench_polarisation      # ~10 s on 2 cores

For clear binder, molecular inks and one overprint (Y15/B15: 500 nm of Y15 on 500 nm of B15),
1000 nm thick, on paper r = 0.9 under uniform diffuse light: the colour seen at 0°, 45° and
75° (solver.table.evaluate.directional_albedo → CIELAB, D65) from the "te" and the
"unpolarised" table, and their CIEDE2000 difference.  Also: the clear binder's mirror
reflectance at 45° (s, p, unpolarised, spectral mean), the time to build each kind of table,
and how far the two film algorithms (Airy `slab`, the stack fold) are apart on random films.
Picture: out/bench/polarisation.png (s, p and unpolarised mirror reflectance against σ; swatches
of every ink from the te and the unpolarised table at each view).
Tables on 5-nm λ steps and 1° σ steps (finer than the request defaults, so that interpolation
does not blur the difference).
"""

from __future__ import annotations

import time

import numpy as np

from pathlib import Path

from solver.colour import spectra_to_lab
from solver.colour.srgb import spectra_to_srgb8
from solver.inks import parse_ink
from solver.table.evaluate import directional_albedo
from solver.table.thinfilm_tier import build_stack_table, build_thinfilm_table
from solver.thinfilm import slab, stack

WL = np.arange(380.0, 781.0, 5.0)
SIGMA = np.radians(np.arange(0.0, 90.5, 1.0))
PAPER = 0.9
THICKNESS_NM = 1000.0
VIEWS_DEG = (0.0, 45.0, 75.0)
INKS = ("clear", "R15", "Y15", "B15", "G30", "Y25+B5", "R50", "Y15/B15")
OUT = Path("out/bench")


def build(spec: str, polarisation: str):
    if "/" in spec:
        layers = [(parse_ink(s), THICKNESS_NM / 2) for s in spec.split("/")]
        return build_stack_table(layers, WL, SIGMA, polarisation=polarisation)
    return build_thinfilm_table(parse_ink(spec), THICKNESS_NM, WL, SIGMA, polarisation=polarisation)


def lab_seen(table, view_deg: float) -> np.ndarray:
    refl = directional_albedo(table, PAPER, np.radians(view_deg))
    return spectra_to_lab(table.wavelengths, refl, "D65", "2")


def main(argv=None) -> int:
    import colour

    clear_te, clear_un = build("clear", "te"), build("clear", "unpolarised")
    i45 = int(np.argmin(np.abs(SIGMA - np.pi / 4)))
    print(f"clear binder, {THICKNESS_NM:.0f} nm, mirror reflectance at 45° (mean over λ): "
          f"s {clear_un.Rbar_s[:, i45].mean():.3f}  p {clear_un.Rbar_p[:, i45].mean():.3f}  "
          f"unpolarised {clear_un.R_spec[:, i45].mean():.3f}  (te table: {clear_te.R_spec[:, i45].mean():.3f})")
    print(f"\nink on paper r = {PAPER}, diffuse light; L*a*b* from the te | unpolarised table, ΔE2000")
    print(f"{'ink':9s} " + "  ".join(f"{'view ' + format(v, '.0f') + '°':^44s}" for v in VIEWS_DEG))
    swatches = {}
    for spec in INKS:
        te, un = build(spec, "te"), build(spec, "unpolarised")
        swatches[spec] = [[spectra_to_srgb8(t.wavelengths, directional_albedo(t, PAPER, np.radians(v)))
                           for t in (te, un)] for v in VIEWS_DEG]
        cells = []
        for view in VIEWS_DEG:
            a, b = lab_seen(te, view), lab_seen(un, view)
            de = float(colour.delta_E(a, b, method="CIE 2000"))
            cells.append(f"{a[0]:5.1f} {a[1]:6.1f} {a[2]:6.1f} | {b[0]:5.1f} {b[1]:6.1f} {b[2]:6.1f}  ΔE {de:4.2f}")
        print(f"{spec:9s} " + "  ".join(cells), flush=True)
    print("\nbuild time per table (81 λ × 91 σ), best of 5:")
    for spec, pol in (("R15", "te"), ("R15", "unpolarised"), ("Y15/B15", "te"), ("Y15/B15", "unpolarised")):
        best = min(_timed(spec, pol) for _ in range(5))
        print(f"  {spec:8s} {pol:12s} {1e3 * best:6.1f} ms")
    _agreement()
    _picture(clear_un, build("R15", "unpolarised"), swatches)
    return 0


def _agreement(n: int = 3000) -> None:
    """Airy (`slab`) against the stack fold, and one layer against the same layer split in two,
    on random films (n = 1–2.6, half of them absorbing with κ up to 4, d = 1 nm–100 µm,
    σ = 0–90°, λ = 380–780 nm), s and p."""
    rng = np.random.default_rng(7)
    kappa = rng.choice([0.0, 1.0], n) * rng.uniform(0, 2.0, n) ** 2
    eps = (rng.uniform(1.0, 2.6, n) + 1j * kappa) ** 2
    d, wl, sigma = 10 ** rng.uniform(0, 5, n), rng.uniform(380, 780, n), rng.uniform(0, np.pi / 2, n)
    print(f"\nagreement on {n} random films (max over R and T of |difference|):")
    for pol in ("te", "tm"):
        fold, split = 0.0, 0.0
        for e, t, w, s in zip(eps, d, wl, sigma):
            airy = slab(e, t, w, s, polarisation=pol)
            one = stack([e], [t], w, s, polarisation=pol)
            two = stack([e, e], [0.3 * t, 0.7 * t], w, s, polarisation=pol)
            fold = max(fold, abs(airy.R - one.R), abs(airy.T - one.T))
            split = max(split, abs(airy.R - two.R), abs(airy.T - two.T))
        print(f"  {pol}: Airy vs stack fold {fold:.1e}; vs the layer split in two {split:.1e}")


def _picture(clear, r15, swatches: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    OUT.mkdir(parents=True, exist_ok=True)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.6), gridspec_kw={"width_ratios": [1, 1.3]})
    li = int(np.argmin(np.abs(WL - 550.0)))
    deg = np.degrees(SIGMA)
    for table, name, style in ((clear, "clear", "-"), (r15, "R15", "--")):
        for col, label, c in (("Rbar_s", "s", "C0"), ("Rbar_p", "p", "C3"), ("R_spec", "unpolarised", "k")):
            ax.plot(deg, getattr(table, col)[li], style, color=c, label=f"{name} {label}")
    ax.set_xlabel("incidence σ (°)")
    ax.set_ylabel("mirror reflectance at 550 nm")
    ax.set_title("1000-nm film in air: s, p and their mean")
    ax.legend(fontsize=8)
    strip = np.zeros((len(INKS), 2 * len(VIEWS_DEG), 3), np.uint8)
    for i, spec in enumerate(INKS):
        for j, pair in enumerate(swatches[spec]):
            strip[i, 2 * j], strip[i, 2 * j + 1] = pair
    bx.imshow(strip, aspect="auto", interpolation="nearest")
    bx.set_yticks(range(len(INKS)), INKS)
    bx.set_xticks(range(2 * len(VIEWS_DEG)),
                  [f"{v:.0f}° {k}" for v in VIEWS_DEG for k in ("te", "unpol.")], fontsize=8)
    bx.set_title(f"on paper r = {PAPER}, diffuse light, seen at each view")
    fig.savefig(OUT / "polarisation.png", dpi=110, bbox_inches="tight")
    print(f"wrote {OUT / 'polarisation.png'}")


def _timed(spec: str, polarisation: str) -> float:
    t0 = time.perf_counter()
    build(spec, polarisation)
    return time.perf_counter() - t0


if __name__ == "__main__":
    raise SystemExit(main())
