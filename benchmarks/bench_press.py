"""Separation like a press (solver.apps.separation): ColorChecker, gradients, speed, table error.

    python -m benchmarks.bench_press [--quick] [--inks R30,Y30,B30]

1. the 24 ColorChecker patches (colour-science's "ColorChecker 2005" reference, D50) printed
   from their 8-bit sRGB values (perceptual gamut mapping, relative colorimetry, 45:0 D50 2°):
   ΔE2000 of each print against the reference, mean and max, and for each patch over 3 the
   reason: outside the sRGB gamut (its 8-bit value is not the reference), or outside the
   print's gamut (the mapping moved it: by how much);
2. smooth gradients (blue→white, black→dark blue, black→grey, green→black, red→white, 256
   steps): monotone in L* after separation? largest step over the median step (ΔE2000 between
   neighbours), the same for clipping to the closest printable colour (the old separation);
3. a 12-Mpixel photograph (the demo photograph enlarged to 4000×3000 with 1-level noise, so
   that it has hundreds of thousands of distinct colours) separated through the 3-D table:
   wall time (table build and per-pixel interpolation) beside the machine yardstick;
4. the 3-D table against separating every colour: ΔE2000 between the two prints of 20,000
   random sRGB colours (median, 95th percentile, max) and the table's build time, per node count;
5. the perceptual mapping's knobs (focal point's lightness weight, knee, margin): ColorChecker
   ΔE2000 and the worst gradient's monotonicity and largest step;
6. black generation (none, UCR, GCR 0.7, GCR 1, a 260 % TAC) on the photograph's colours: ink
   totals, black and chromatic ink, the print's miss;
7. the gamut boundary's knobs (hue slices, face samples, the check against the print, the hue
   smoothing): build time, table nodes the solver misses, ColorChecker.

Timings under load are not README numbers (the lead re-measures on a quiet machine).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PHOTO = ROOT / "scenes" / "textures" / "printed_page_photo.png"
RAMPS = {"blue→white": ((0, 0, 255), (255, 255, 255)), "black→dark blue": ((0, 0, 0), (0, 0, 128)),
         "black→grey": ((0, 0, 0), (128, 128, 128)), "green→black": ((0, 255, 0), (0, 0, 0)),
         "red→white": ((255, 0, 0), (255, 255, 255))}


def _yardstick() -> float:
    from benchmarks.yardstick import yardstick_s

    return yardstick_s()


def colorchecker_srgb8():
    """(names, reference CIELAB D50 [24, 3], 8-bit sRGB [24, 3], in sRGB gamut [24])."""
    import colour

    cc = colour.CCS_COLOURCHECKERS["ColorChecker 2005"]
    names = list(cc.data.keys())
    xyY = np.array(list(cc.data.values()))
    xyz = colour.xyY_to_XYZ(xyY)
    lab = colour.XYZ_to_Lab(xyz, cc.illuminant)
    rgb = colour.XYZ_to_sRGB(xyz, illuminant=cc.illuminant, chromatic_adaptation_transform="Bradford")
    inside = np.all((rgb >= 0) & (rgb <= 1), axis=1)
    return names, lab, np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8), inside


def colorchecker(separator) -> None:
    from solver.apps.separation import delta_e2000, srgb8_to_lab

    names, ref, rgb8, inside = colorchecker_srgb8()
    sep, source = separator.separate_srgb(rgb8 / 255.0)
    de = delta_e2000(sep.printed_lab, ref)
    moved = delta_e2000(sep.target_lab, source)
    de_srgb = delta_e2000(srgb8_to_lab(rgb8), ref)
    print(f"\n1. ColorChecker 2005 (24 patches) printed from 8-bit sRGB: ΔE2000 print vs reference mean "
          f"{de.mean():.2f}, max {de.max():.2f} (aims: mean ≤ 3, max ≤ 8)")
    print("   patch                 ΔE2000  sRGB-8 vs ref  moved by mapping  why")
    for i in np.argsort(-de):
        if de[i] <= 3.0:
            continue
        why = []
        if not inside[i]:
            why.append("outside sRGB")
        if moved[i] > 0.5:
            why.append(f"outside the print's gamut (mapped {moved[i]:.1f})")
        print(f"   {names[i]:20s} {de[i]:7.2f}  {de_srgb[i]:13.2f}  {moved[i]:16.2f}  {', '.join(why) or '-'}")


def _ramp(a, b, n=256):
    t = np.linspace(0.0, 1.0, n)[:, None]
    return np.round(np.asarray(a, float) * (1 - t) + np.asarray(b, float) * t)


def gradients(separator) -> None:
    from solver.apps.separation import delta_e2000, separate_lab, srgb8_to_lab

    print("\n2. gradients (256 steps): monotone in L*? largest / median step ΔE2000 (perceptual | clip)")
    for name, (a, b) in RAMPS.items():
        rgb = _ramp(a, b)
        source = srgb8_to_lab(rgb)
        sep, _ = separator.separate_srgb(rgb / 255.0)
        clip = separate_lab(separator.model, source)
        row = []
        for printed in (sep.printed_lab, clip.printed_lab):
            dl = np.diff(printed[:, 0]) * np.sign(source[-1, 0] - source[0, 0])
            st = delta_e2000(printed[1:], printed[:-1])
            row.append(f"monotone {'yes' if dl.min() > -0.02 else 'NO '} (min ΔL* {dl.min():+.3f}), "
                       f"max/median step {st.max() / np.median(st):5.2f}")
        print(f"   {name:16s} {row[0]} | {row[1]}")


def big_image(width=4000, height=3000):
    from PIL import Image

    im = Image.open(PHOTO).convert("RGB").resize((width, height), Image.Resampling.BILINEAR)
    a = np.asarray(im, dtype=np.int16)
    noise = np.random.default_rng(0).integers(-1, 2, a.shape, dtype=np.int16)
    return np.clip(a + noise, 0, 255).astype(np.uint8)


def speed(separator, quick: bool) -> None:
    from dataclasses import replace

    from solver.apps.separation import separate_image
    from solver.apps.separation.image import unique_colours

    img = big_image(2000, 1500) if quick else big_image()
    n_colours = unique_colours(img)[0].shape[0]
    y0 = _yardstick()
    print(f"\n3. a {img.shape[1]}×{img.shape[0]} image ({img.shape[0] * img.shape[1] / 1e6:.0f} Mpixel, "
          f"{n_colours:,} distinct colours); yardstick {y0:.2f} s")
    for nodes in (17, 33):
        s = replace(separator, lut_nodes=nodes)
        t0 = time.perf_counter()
        result = separate_image(s, img)
        dt = time.perf_counter() - t0
        print(f"   {nodes}³ table: {dt:6.1f} s ({dt / y0:.1f} yardsticks); " + " | ".join(result.report.lines()))
    print(f"   yardstick after: {_yardstick():.2f} s")


def table_error(separator, quick: bool) -> None:
    from solver.apps.separation import SeparationLUT, delta_e2000, srgb8_to_lab

    x = np.random.default_rng(5).random((4000 if quick else 20000, 3))
    t0 = time.perf_counter()
    direct, _ = separator.separate_srgb(x)
    t_direct = time.perf_counter() - t0
    print(f"\n4. 3-D table vs separating every colour ({len(x):,} random sRGB colours, direct {t_direct:.1f} s):")
    for nodes in (9, 17, 33):
        t0 = time.perf_counter()
        lut, _ = SeparationLUT.build(separator, nodes)
        t_build = time.perf_counter() - t0
        t0 = time.perf_counter()
        cov = lut(x)
        t_use = time.perf_counter() - t0
        de = delta_e2000(separator.model.lab(cov), direct.printed_lab)
        worst = np.inf
        for a, b in RAMPS.values():                # the gradients of section 2 through the table
            rgb = _ramp(a, b)
            source = srgb8_to_lab(rgb)
            dl = np.diff(separator.model.lab(lut(rgb / 255.0))[:, 0]) * np.sign(source[-1, 0] - source[0, 0])
            worst = min(worst, dl.min())
        print(f"   {nodes:2d}³ nodes: build {t_build:6.1f} s, interpolate {t_use * 1e3:6.1f} ms; ΔE2000 median "
              f"{np.median(de):.3f}, p95 {np.percentile(de, 95):.3f}, max {de.max():.2f}; the five ramps through it: "
              f"smallest ΔL* step {worst:+.3f}")


def mapping_knobs(separator) -> None:
    """The perceptual mapping's knobs against what they buy: ColorChecker ΔE2000 and the worst
    gradient (its smallest ΔL* along the ramp, its largest step over the median one)."""
    from dataclasses import replace

    from solver.apps.separation import GamutSettings, delta_e2000, srgb8_to_lab

    names, ref, rgb8, _ = colorchecker_srgb8()
    print("\n5. mapping knobs: lightness weight w (focal point), knee k, margin m → ColorChecker ΔE2000 mean/max; "
          "over the five ramps: smallest ΔL*, largest max/median step; time of the 5 ramps + 24 patches")
    for w, knee, margin in ((0.5, 0.8, 1.5), (0.7, 0.8, 1.5), (0.85, 0.8, 1.5), (0.7, 0.7, 1.5), (0.7, 0.9, 1.5),
                            (0.7, 0.8, 0.5)):
        s = replace(separator, gamut=GamutSettings(knee=knee, lightness_weight=w, margin_de=margin))
        t0 = time.perf_counter()
        sep, _ = s.separate_srgb(rgb8 / 255.0)
        de = delta_e2000(sep.printed_lab, ref)
        worst_dl, worst_step = np.inf, 0.0
        for a, b in RAMPS.values():
            rgb = _ramp(a, b)
            source = srgb8_to_lab(rgb)
            r, _ = s.separate_srgb(rgb / 255.0)
            dl = np.diff(r.printed_lab[:, 0]) * np.sign(source[-1, 0] - source[0, 0])
            st = delta_e2000(r.printed_lab[1:], r.printed_lab[:-1])
            worst_dl, worst_step = min(worst_dl, dl.min()), max(worst_step, st.max() / np.median(st))
        print(f"   w {w:4.2f} k {knee:3.1f} m {margin:3.1f}: CC {de.mean():.2f} / {de.max():.2f}; min ΔL* {worst_dl:+.3f}, "
              f"max/median step {worst_step:4.2f}; {time.perf_counter() - t0:.1f} s")


def black_rules(separator) -> None:
    """What black generation buys: on 3000 colours of the demo photograph, the mean and largest
    total ink, the mean black and chromatic ink, and the print's ΔE2000 to the mapped colours."""
    from solver.apps.separation import BlackGeneration, read_srgb8
    from solver.apps.separation.image import unique_colours

    if separator.objective.black is None:
        return
    colours, _ = unique_colours(read_srgb8(PHOTO))
    pick = colours[np.random.default_rng(2).choice(len(colours), 3000, replace=False)] / 255.0
    k = separator.objective.black
    print("\n6. black generation on 3000 photograph colours: total ink mean / max (%), black mean, chromatic mean, "
          "ΔE76 to the mapped colour p99")
    for rule in (BlackGeneration(strength=0.0), BlackGeneration("ucr"), BlackGeneration(), BlackGeneration(strength=1.0),
                 BlackGeneration(tac=2.6)):
        s = separator.with_rule(rule)
        t0 = time.perf_counter()
        sep, _ = s.separate_srgb(pick)
        total = 100 * sep.coverages.sum(axis=1)
        chromatic = 100 * (sep.coverages.sum(axis=1) - sep.coverages[:, k])
        print(f"   {rule.label():40s} {total.mean():5.1f} / {total.max():5.1f}; K {100 * sep.coverages[:, k].mean():5.1f}; "
              f"CMY {chromatic.mean():5.1f}; p99 {np.percentile(sep.delta_e76, 99):.2f}; {time.perf_counter() - t0:.1f} s")


def boundary_knobs(settings, printed) -> None:
    """The gamut boundary's accuracy knobs (module constants of solver.apps.separation.gamut and
    separate, set here for the study): build time, the share of 17³ table nodes the solver
    misses by more than ΔE76 0.5 (the boundary overestimated) and the ColorChecker mean."""
    from solver.apps.separation import SeparationLUT, delta_e2000
    from solver.apps.separation import gamut
    from solver.apps.separation.job import build_separator

    _, ref, rgb8, _ = colorchecker_srgb8()
    saved = (gamut.HUE_BINS, gamut.FACE_NODES, gamut.REFINE_STEP_L, gamut.HUE_SMOOTHING_BINS)
    print("\n7. gamut boundary knobs: hue slices, face samples per axis, check step (L*; off: no check against the print), "
          "hue smoothing σ (slices) → build s, 17³ nodes missed by > 0.5 ΔE76 (max), ColorChecker mean")
    try:
        sd = saved[3]                                       # the default hue smoothing
        for hue_bins, face, step, sigma in ((180, 49, 3.0, sd), (90, 49, 3.0, sd), (360, 49, 3.0, sd), (180, 33, 3.0, sd),
                                            (180, 65, 3.0, sd), (180, 49, 1.5, sd), (180, 49, 1000.0, sd),
                                            (180, 49, 3.0, sd / 2), (180, 49, 3.0, 2 * sd)):
            gamut.HUE_BINS, gamut.FACE_NODES, gamut.REFINE_STEP_L, gamut.HUE_SMOOTHING_BINS = hue_bins, face, step, sigma
            t0 = time.perf_counter()
            s = build_separator(settings, printed)
            dt = time.perf_counter() - t0
            _, nodes = SeparationLUT.build(s, 17)
            miss = nodes.delta_e76 > 0.5
            cc, _ = s.separate_srgb(rgb8 / 255.0)
            print(f"   {hue_bins:3d} slices, {face:2d} face nodes, check {'off' if step > 100 else f'{step:g} L*':7s}, "
                  f"σ {sigma:4.2f}: {dt:5.1f} s; missed {miss.mean():6.1%} (max {nodes.delta_e76.max():.2f}); "
                  f"CC {delta_e2000(cc.printed_lab, ref).mean():.2f}")
    finally:
        gamut.HUE_BINS, gamut.FACE_NODES, gamut.REFINE_STEP_L, gamut.HUE_SMOOTHING_BINS = saved


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="a 3-Mpixel image, fewer colours")
    p.add_argument("--inks", default=None, help="ink specs (default: the print command's)")
    args = p.parse_args(argv if argv is not None else sys.argv[1:] if __name__ == "__main__" else [])
    from solver.apps.separation import PrintSettings, printed_inks
    from solver.apps.separation.job import build_separator
    from solver.apps.separation.printset import default_inks, parse_ink_list

    inks = parse_ink_list(args.inks) if args.inks else default_inks()
    settings = PrintSettings(inks=inks)
    t0 = time.perf_counter()
    separator = build_separator(settings, printed_inks(inks))
    b = separator.objective.black
    print(f"inks {', '.join(inks)} (black: {inks[b] if b is not None else 'none'}), {settings.model}, paper "
          f"{settings.paper:g}, {separator.model.measurement.label}, relative; gamut + start grid "
          f"{time.perf_counter() - t0:.1f} s; print's black L* {separator.boundary.black_l:.1f}")
    colorchecker(separator)
    gradients(separator)
    mapping_knobs(separator)
    black_rules(separator)
    boundary_knobs(settings, printed_inks(inks))
    table_error(separator, args.quick)
    speed(separator, args.quick)


if __name__ == "__main__":
    main()
