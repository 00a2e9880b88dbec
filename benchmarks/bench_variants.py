"""The `ink` BSDF in RGB and mono variants against spectral rendering: the colour error of the
tables' reduction to the variant's channels (`inkbsdf.colour_space`), in ΔE2000 (D65, 2°).

    python -m benchmarks variants

For each demo ink at coverage 1 and 0.5 on paper 0.9, and a few geometries (σ, θo, Δφ): the
smooth lobe's reflectance factor π·f/cos θo and the mirror lobe's reflectance, computed by the
BSDF in `llvm_ad_spectral` on a 5-nm grid (→ CIELAB under D65, 2°, ASTM E308) and by the BSDF in
`llvm_ad_rgb` (linear sRGB → CIELAB, sRGB white = the D65 white); in `llvm_ad_mono` the
luminance Y against the spectral Y (ΔL*). tests/test_bsdf_rgb.py asserts the bounds.

Then the demo scene (scenes/printed_page.xml, small) rendered in `llvm_ad_spectral` and
`llvm_ad_rgb`: ΔE2000 between the two per block of BLOCK×BLOCK pixels (linear sRGB means →
CIELAB, D65), beside the same
between two spectral renders with other seeds (the Monte Carlo noise floor), and the render
times.
"""

from __future__ import annotations

import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

INKS = ("R30", "Y30", "B30", "G30", "Y25+B5")
COVERAGES = (1.0, 0.5)
PAPER = 0.9
GEOMETRIES_DEG = ((10.0, 20.0, 90.0), (30.0, 30.0, 90.0), (45.0, 0.0, 0.0), (60.0, 45.0, 150.0))
WAVELENGTHS_NM = np.arange(380.0, 781.0, 5.0)
BLOCK = 4                   # demo images compared in BLOCK×BLOCK pixel means (Monte Carlo noise down)


@dataclass(frozen=True)
class Row:
    ink: str
    coverage: float
    smooth_de: np.ndarray       # ΔE2000 per geometry, smooth lobe (RGB variant)
    mirror_de: np.ndarray       # ΔE2000 per geometry, mirror lobe (RGB variant)
    smooth_dl: np.ndarray       # |ΔL*| per geometry, smooth lobe (mono variant)
    smooth_gamut_de: np.ndarray # ΔE2000 per geometry between the spectral colour and its sRGB
                                # (linear channels clipped at 0): what no RGB rendering can show


def _directions():
    g = np.radians(np.asarray(GEOMETRIES_DEG))
    wi = np.stack([np.sin(g[:, 0]), np.zeros(len(g)), np.cos(g[:, 0])])
    wo = np.stack([np.sin(g[:, 1]) * np.cos(g[:, 2]), np.sin(g[:, 1]) * np.sin(g[:, 2]), np.cos(g[:, 1])])
    return wi, wo


def _lobes(mi, bsdf, wi, wo, wavelengths=None):
    """(π f/cos θo, mirror reflectance) per lane and channel: [n_channels, N] each."""
    import drjit as dr

    n = wi.shape[1]
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(*[mi.Float(c) for c in wi])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    if wavelengths is not None:
        si.wavelengths = mi.UnpolarizedSpectrum(*[mi.Float(wavelengths) for _ in range(4)])
    ctx = mi.BSDFContext()
    f = bsdf.eval(ctx, si, mi.Vector3f(*[mi.Float(c) for c in wo]))
    ctx.type_mask = +mi.BSDFFlags.DeltaReflection
    half = mi.Float(np.full(n, 0.5))
    _, spec = bsdf.sample(ctx, si, half, mi.Point2f(half, half))
    channels = dr.size_v(mi.Spectrum)
    as_np = lambda v: np.array([np.broadcast_to(np.asarray(v[k], dtype=np.float64), (n,))   # noqa: E731
                                for k in range(channels)])
    return np.pi * as_np(f) / wo[2], as_np(spec)


def compare(tables: dict, inks=INKS) -> list[Row]:
    """One Row per ink of `inks` and coverage (variants switched inside; the previous one
    restored)."""
    import mitsuba as mi

    from solver.colour.cie import bradford, delta_e2000, spectra_to_lab, spectra_to_xyz, white_xyz, xyz_to_lab
    from solver.colour.srgb import SRGB_WHITE, XYZ_TO_LINEAR, linear_to_lab

    previous = mi.variant()
    import inkbsdf

    wi, wo = _directions()
    n_geo, n_lam = wi.shape[1], WAVELENGTHS_NM.size
    wi_l, wo_l = np.repeat(wi, n_lam, axis=1), np.repeat(wo, n_lam, axis=1)
    lam_l = np.tile(WAVELENGTHS_NM, n_geo)
    out = {}
    try:
        for variant in ("llvm_ad_spectral", "llvm_ad_rgb", "llvm_ad_mono"):
            mi.set_variant(variant)
            inkbsdf.register()
            for ink in inks:
                for c in COVERAGES:
                    bsdf = mi.load_dict({"type": "ink", "filename": str(tables[ink]), "coverage": c, "paper": PAPER})
                    if variant == "llvm_ad_spectral":
                        s, m = _lobes(mi, bsdf, wi_l, wo_l, lam_l)
                        out[variant, ink, c] = (s[0].reshape(n_geo, n_lam), m[0].reshape(n_geo, n_lam))
                    else:
                        out[variant, ink, c] = _lobes(mi, bsdf, wi, wo)
    finally:
        if previous is not None:
            mi.set_variant(previous)
    white = white_xyz("D65", "2")
    rows = []
    for ink in inks:
        for c in COVERAGES:
            smooth, mirror = out["llvm_ad_spectral", ink, c]
            lab_s = spectra_to_lab(WAVELENGTHS_NM, smooth, "D65", "2")
            lab_m = spectra_to_lab(WAVELENGTHS_NM, mirror, "D65", "2")
            rgb_s, rgb_m = out["llvm_ad_rgb", ink, c]
            mono_s, _ = out["llvm_ad_mono", ink, c]
            l_mono = xyz_to_lab(np.stack([mono_s[0] * white[0], mono_s[0] * white[1], mono_s[0] * white[2]], axis=-1),
                                white)[:, 0]
            l_spec = xyz_to_lab(spectra_to_xyz(WAVELENGTHS_NM, smooth, "D65", "2"), white)[:, 0]
            to_srgb = (XYZ_TO_LINEAR @ bradford(white, SRGB_WHITE)).T
            in_gamut = np.maximum(spectra_to_xyz(WAVELENGTHS_NM, smooth, "D65", "2") @ to_srgb, 0.0)
            rows.append(Row(ink, c,
                            delta_e2000(lab_s, linear_to_lab(rgb_s.T)),
                            delta_e2000(lab_m, linear_to_lab(rgb_m.T)),
                            np.abs(l_mono - l_spec),
                            delta_e2000(lab_s, linear_to_lab(in_gamut))))
    return rows


def demo_images(tables_dir: Path, width: int, height: int, spp: int) -> None:
    """Print the demo scene's ΔE2000 RGB vs spectral, the noise floor and the times."""
    import mitsuba as mi

    from inkbsdf.apps.render import render_scene
    from solver.colour.cie import delta_e2000
    from solver.colour.srgb import linear_to_lab

    scene = Path(__file__).resolve().parents[1] / "scenes" / "printed_page.xml"
    previous = mi.variant()
    images, times = {}, {}
    try:
        for variant, seed in (("llvm_ad_spectral", 0), ("llvm_ad_spectral", 1), ("llvm_ad_rgb", 0)):
            mi.set_variant(variant)
            render_scene(scene, tables=tables_dir, spp=4, width=width, height=height)    # compile
            got = render_scene(scene, tables=tables_dir, spp=spp, width=width, height=height, seed=seed)
            img = np.asarray(got.image, dtype=np.float64)[:, :, :3]
            h, w = (img.shape[0] // BLOCK) * BLOCK, (img.shape[1] // BLOCK) * BLOCK
            blocks = img[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, 3).mean(axis=(1, 3))
            images[variant, seed] = linear_to_lab(blocks.reshape(-1, 3))
            times[variant] = got.render_s
    finally:
        if previous is not None:
            mi.set_variant(previous)
    rgb = delta_e2000(images["llvm_ad_spectral", 0], images["llvm_ad_rgb", 0])
    noise = delta_e2000(images["llvm_ad_spectral", 0], images["llvm_ad_spectral", 1])
    print(f"demo scene {width}×{height}, {spp} spp, {BLOCK}×{BLOCK}-pixel blocks averaged (noise down): "
          f"ΔE2000 RGB vs spectral median {np.median(rgb):.2f}, "
          f"95th percentile {np.percentile(rgb, 95):.2f}; spectral vs spectral (other seed) median "
          f"{np.median(noise):.2f}, 95th {np.percentile(noise, 95):.2f}; render "
          f"{times['llvm_ad_spectral']:.2f} s spectral, {times['llvm_ad_rgb']:.2f} s RGB")


def main(argv) -> None:
    import argparse

    from inkbsdf.apps.demo_tables import DEMO_INKS, build_tables

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--width", type=int, default=128)
    parser.add_argument("--height", type=int, default=96)
    parser.add_argument("--spp", type=int, default=512)
    args = parser.parse_args(argv)
    folder = Path(tempfile.mkdtemp())
    tables = build_tables(folder, inks=tuple(dict.fromkeys(INKS + tuple(DEMO_INKS))))
    rows = compare(tables)
    geos = ", ".join(f"({s:g}°, {t:g}°, {p:g}°)" for s, t, p in GEOMETRIES_DEG)
    print(f"RGB / mono variants against spectral (D65, 2°), paper {PAPER}; geometries (σ, θo, Δφ): {geos}")
    print("ΔE00 smooth: RGB variant against spectral; gamut: the spectral colour against its sRGB clipped "
          "to non-negative channels (the part no RGB rendering can show)")
    print(f"{'ink':8s} {'cov':>4s}  {'ΔE00 smooth (max)':>18s} {'gamut (max)':>12s} {'ΔE00 mirror (max)':>18s} "
          f"{'mono |ΔL*| (max)':>17s}")
    for r in rows:
        print(f"{r.ink:8s} {r.coverage:4.2f}  {r.smooth_de.max():18.2f} {r.smooth_gamut_de.max():12.2f} "
              f"{r.mirror_de.max():18.2f} {r.smooth_dl.max():17.2f}")
    print(f"overall max: ΔE00 smooth {max(r.smooth_de.max() for r in rows):.2f}, "
          f"mirror {max(r.mirror_de.max() for r in rows):.2f}; mono |ΔL*| {max(r.smooth_dl.max() for r in rows):.2f}")
    demo_images(folder, args.width, args.height, args.spp)


if __name__ == "__main__":
    main(sys.argv[1:])
