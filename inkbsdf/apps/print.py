"""Print an image with the project's inks: colour separation, halftoning, and a scene of the
printed page.

    python -m inkbsdf.print IMAGE --inks R30,Y30,B30 [--coverage-model auto|clapper-yule|murray-davies]
        [--dots AM:150|FM|none] [--dpi N] [--paper 0.9] [--size WxH] [--intent relative|absolute]
        -o page.xml

writes page.xml and, next to it, page_textures/ (one 8-bit coverage PNG per ink, white = full
ink; the sky; proof.png, the model's colours of the print as sRGB). Render it with
`python -m inkbsdf.render page.xml --spp 64 -o page.exr --png page.png`. The method:
docs/printing.md. Bad input: one line on stderr, exit status 2, before any work; Ctrl-C: exit
status 130.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from solver.apps.cli.parsing import DefaultsFormatter, OneLineParser, run_guarded, writable_output
from solver.interrupts import raising
from solver.paper import PAPER_ALBEDO, check_paper_albedo

MARGIN_CM = 1.5                     # white paper around the print on its sheet
SHEEN_UV = (0.84, 0.17)             # where the softbox's mirror image lands, fraction of the sheet
                                    # (the print's top-right corner: a glimpse of the inks' gloss)


class UsageError(ValueError):
    """Bad command-line input; the message names the option and the fix."""


class _Parser(OneLineParser):
    usage_error = UsageError


def parse_size(text: str) -> tuple:
    """'12' (width, cm; height from the image) or '12x9' / '12x9cm' / '12×9' → (w, h or None)."""
    m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+)\s*(?:[x×]\s*([0-9]*\.?[0-9]+))?\s*(?:cm)?\s*", str(text))
    if not m:
        raise UsageError(f"--size: give WIDTHxHEIGHT in cm (e.g. 12x9) or a width (e.g. 12); got '{text}'")
    w, h = float(m.group(1)), (float(m.group(2)) if m.group(2) else None)
    if w <= 0 or (h is not None and h <= 0) or w > 500 or (h or 0) > 500:
        raise UsageError(f"--size: width and height must lie in (0, 500] cm; got '{text}'")
    return w, h


def build_parser() -> argparse.ArgumentParser:
    from solver.apps.separation import AUTO_MODEL, INTENTS
    from solver.apps.separation import halftone as ht
    from solver.printing import COVERAGE_MODELS

    p = _Parser(prog="python -m inkbsdf.print", description=__doc__.split("\n\n")[0],
                formatter_class=DefaultsFormatter)
    p.add_argument("image", help="image file (PNG, JPEG, TIFF, …; taken as sRGB)")
    p.add_argument("--inks", required=True, help="1 to 4 molecular ink specs in printing order, e.g. R30,Y30,B30")
    p.add_argument("--coverage-model", default=AUTO_MODEL, choices=(AUTO_MODEL,) + COVERAGE_MODELS,
                   help="model of the separation and the BSDF; auto: murray-davies for AM/FM dots "
                        "(what a render of binary dots shows), clapper-yule for --dots none")
    p.add_argument("--dots", default="none", help="AM:LPI (screen ruling, lines per inch), FM, or none (continuous)")
    p.add_argument("--dpi", type=float, default=None,
                   help=f"texture resolution, texels per inch (default: one per image pixel for --dots none, "
                        f"{ht.AM_TEXELS_PER_CELL} per screen period for AM, {ht.FM_DPI:g} for FM; at least "
                        f"{ht.AM_MIN_TEXELS_PER_CELL} per screen period for AM, {ht.FM_MIN_DPI:g} for FM)")
    p.add_argument("--paper", type=float, default=PAPER_ALBEDO, help="paper albedo in [0, 1]")
    p.add_argument("--size", default="12", help="print size in cm: WIDTHxHEIGHT, or WIDTH (height from the image)")
    p.add_argument("--intent", default="relative", choices=INTENTS,
                   help="relative: the image's white prints as the paper; absolute: CIELAB against a perfect white")
    p.add_argument("-o", "--output", required=True, help="scene file to write (.xml); textures go next to it")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def settings_from(args):
    """Typed settings from the parsed arguments (UsageError naming the option otherwise)."""
    from solver.apps.separation import DotsError, InkListError, PrintSettings, parse_dots, parse_ink_list
    from solver.apps.separation.halftone import check_dpi

    try:
        inks = parse_ink_list(args.inks)
        dots = parse_dots(args.dots)
    except (InkListError, DotsError) as exc:
        raise UsageError(f"--{exc}") from None          # messages start with the option's name
    try:
        check_paper_albedo(args.paper, what="--paper: the paper albedo")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.dpi is not None and not 1.0 <= args.dpi <= 20000.0:
        raise UsageError(f"--dpi: give a resolution in [1, 20000] texels per inch, got {args.dpi:g}")
    if args.dpi is not None:
        try:
            check_dpi(dots, args.dpi)                   # a dot must fit: before the image is read
        except DotsError as exc:
            raise UsageError(f"--{exc}") from None
    return PrintSettings(inks=inks, dots=dots, coverage_model=args.coverage_model, paper=args.paper,
                         size_cm=parse_size(args.size), dpi=args.dpi, intent=args.intent)


def scene_xml(result, texture_folder: str, texture_files) -> str:
    """The printed page: a sheet of paper (the print plus a margin) with the print on it."""
    from inkbsdf.apps.pagescene import Stage, print_shape_xml, scene_document, stage_xml

    s = result.settings
    w, h = result.grid.size_cm
    sheet = (w + 2 * MARGIN_CM, h + 2 * MARGIN_CM)
    stage = Stage.for_sheet(*sheet)
    sources = [f'<string name="ink" value="{ink}"/>' for ink in s.inks]
    files = [f"{texture_folder}/{Path(f).name}" for f in texture_files]
    what = (f"{', '.join(s.inks)} (printing order), {s.dots.label()}, {result.grid.shape[1]}×"
            f"{result.grid.shape[0]} texels, separated with {s.model}")
    body = stage_xml(stage, (SHEEN_UV[0] * sheet[0], SHEEN_UV[1] * sheet[1]), texture_folder)
    body += f"""
    <shape type="rectangle" id="page">
        {_sheet_transform(stage)}
        <bsdf type="diffuse"><float name="reflectance" value="$paper"/></bsdf>
    </shape>

"""
    # binary dots: each texel is 0 or 1 (nearest filtering), where both coverage models agree
    body += print_shape_xml(stage, (sheet[0] / 2, sheet[1] / 2), (w, h), sources, files, s.dots.binary,
                            None if s.dots.binary else s.model, comment=what)
    comment = ("A printed image: written by python -m inkbsdf.print.\n     Inks named in the scene (built "
               "through the table cache). Parameters: width, height, spp, paper (albedo). Units: cm.")
    return scene_document(comment, body, defaults={"paper": f"{s.paper:g}"})


def _sheet_transform(stage) -> str:
    from inkbsdf.apps.pagescene import rect_transform

    w, h = stage.sheet_cm
    return rect_transform(stage, w / 2, h / 2, w / 2, h / 2, 0.0)


def main(argv=None) -> int:
    """The command; returns the exit status (2: bad input, told in one line on stderr)."""
    with raising():                        # SIGTERM: like Ctrl-C, "terminated", exit 143
        return run_guarded(lambda: _main(argv), interrupted="\n{interrupted}: stopped")


def _main(argv) -> int:
    from solver.apps.separation import DotsError, print_image, printed_inks, read_srgb8, write_textures

    args = build_parser().parse_args(argv)
    settings = settings_from(args)
    output = writable_output(args.output, ".xml", "-o/--output")
    rgb8 = read_srgb8(args.image)
    try:
        grid = settings.grid(rgb8.shape[:2])
    except DotsError as exc:
        raise UsageError(str(exc)) from None
    print(f"{args.image}: {rgb8.shape[1]}×{rgb8.shape[0]} px → {grid.size_cm[0]:.3g}×{grid.size_cm[1]:.3g} cm "
          f"with {', '.join(settings.inks)}, {settings.dots.label()} ({grid.shape[1]}×{grid.shape[0]} texels, "
          f"{grid.dpi:.0f} dpi), {settings.model}", flush=True)
    printed = printed_inks(settings.inks)
    bar = ColourProgress(args.quiet)
    try:
        result = print_image(rgb8, settings, printed, progress=bar, grid=grid)
    finally:
        bar.close()
    for line in result.separation.report.lines():
        print(line)
    texture_folder = output.stem + "_textures"
    folder = output.parent / texture_folder
    files = write_textures(result, folder, "ink")
    _write_extras(result, folder)
    output.write_text(scene_xml(result, texture_folder, files))
    if settings.dots.kind == "AM":
        print("screen angles: " + ", ".join(f"{ink} {a:g}°" for ink, a in zip(settings.inks, result.angles_deg)))
    print(f"wrote {output} and {folder}/ ({', '.join(f.name for f in files)}, proof.png)")
    return 0


class ColourProgress:
    """tqdm over the distinct colours (created when their number is known)."""

    def __init__(self, quiet: bool):
        self.quiet, self.bar = quiet, None

    def __call__(self, done: int, total: int) -> None:
        if self.quiet:
            return
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=total, unit=" colours", desc="separating", file=sys.stderr, disable=None)
        self.bar.update(done - self.bar.n)
        if done >= total:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _write_extras(result, folder: Path) -> None:
    """The sky of the scene and proof.png (the model's colour of each pixel)."""
    from inkbsdf.apps.pagescene import SKY_TEXTURE, write_sky
    from solver.apps.separation import lab_to_srgb8, write_rgb_png

    import mitsuba as mi

    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    write_sky(folder / SKY_TEXTURE)
    write_rgb_png(folder / "proof.png", lab_to_srgb8(result.separation.printed_lab))


if __name__ == "__main__":
    sys.exit(main())
