"""Print an image with the project's inks: colour separation, halftoning, and a scene of the
printed page.

    python -m inkbsdf.print IMAGE [--inks process|R30,Y30,B30|C8.7@533,…] [--coverage-model auto|clapper-yule|murray-davies]
        [--dots AM:150|FM|none] [--dpi N] [--paper ALBEDO] [--size WxH] [--intent relative|absolute]
        [--black gcr|ucr] [--black-strength 0.7] [--black-start 0.2] [--tac 300] [--black-ink SPEC|none]
        [--gamut perceptual|clip] [--lut 33] [--characterisation OUT.txt] -o page.xml
    python -m inkbsdf.print --characterisation OUT.txt [--inks …]     (the chart only)

writes page.xml and, next to it, page_textures/ (one 8-bit coverage PNG per ink, white = full
ink; the sky; proof.png, the model's colours of the print as sRGB). Colours are separated as
the press measures them (45:0, D50, 2°): perceptual gamut mapping, black generation with a total
area coverage limit. `--characterisation OUT.txt` writes an IT8.7/4-style chart of the inks and
its predicted CIELAB as CGATS.17 text for ICC profilers. Render it with
`python -m inkbsdf.render page.xml --spp 64 -o page.exr --png page.png`. The method:
docs/printing.md. Bad input: one line on stderr, exit status 2, before any work; Ctrl-C: exit
status 130.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from solver.apps.cli import package_version
from solver.apps.cli.logs import add_verbose, configure_logging
from solver.apps.cli.parsing import DefaultsFormatter, OneLineParser, run_guarded, writable_output
from solver.interrupts import raising
from solver.paper import PAPER_ALBEDO, check_paper_albedo

MARGIN_CM = 1.5                     # white paper around the print on its sheet
SHEEN_UV = (0.84, 0.17)             # where the softbox's mirror image lands, fraction of the sheet
                                    # (the print's top-right corner: a glimpse of the inks' gloss)

#: the program as its usage and error lines name it
PROG = "python -m inkbsdf.print"


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

    p = _Parser(prog=PROG, description=__doc__.split("\n\n")[0],
                formatter_class=DefaultsFormatter)
    p.add_argument("--version", action="version", version=f"inkbsdf.print {package_version()}")
    add_verbose(p)
    from solver.apps.separation import BLACK_MODES, MAPPINGS, BlackGeneration, GamutSettings
    from solver.apps.separation.black import TAC_BOUNDS
    from solver.apps.separation.printset import DEFAULT_INK_LIST
    from solver.apps.separation.separate import DEFAULT_LUT_NODES

    black = BlackGeneration()
    p.add_argument("image", nargs="?", help="image file (PNG, JPEG, TIFF, …; sRGB unless it embeds an ICC profile)")
    p.add_argument("--inks", default=DEFAULT_INK_LIST,
                   help="1 to 4 molecular ink specs in printing order, e.g. R30,Y30,B30, each optionally "
                        "with its layer thickness in nm (C8.7@1500); process: the process inks K, C, M, Y")
    p.add_argument("--black", default=black.mode, choices=BLACK_MODES,
                   help="black generation: gcr (black takes the grey part of every colour) or ucr (black in "
                        "near-neutral shadows only)")
    p.add_argument("--black-strength", type=float, default=black.strength,
                   help="share of the grey component printed with black, 0 (least black) to 1")
    p.add_argument("--black-start", type=float, default=black.start,
                   help="black start: the share of the black's range, in [0, 1), below which no black is printed")
    p.add_argument("--tac", type=float, default=100 * black.tac,
                   help=f"total area coverage limit, percent, in {TAC_BOUNDS.text(100.0)}")
    p.add_argument("--black-ink", default=None,
                   help="which ink is the black (an ink of --inks, or none); default: the ink whose main pigment is K, else the "
                        "darkest neutral one")
    p.add_argument("--gamut", default=MAPPINGS[0], choices=MAPPINGS,
                   help="perceptual: hue-preserving compression toward the cusp (one ink: a monotone of the "
                        "image's lightness in it; two inks: the image mapped onto their surface of colours); clip: "
                        "the closest printable colour")
    p.add_argument("--gamut-knee", type=float, default=GamutSettings().knee,
                   help="share of the gamut left untouched by the perceptual mapping, in [0, 1)")
    p.add_argument("--lut", type=int, default=DEFAULT_LUT_NODES,
                   help="nodes per sRGB axis of the separation table used for images with more distinct "
                        "colours than its nodes (0: separate every colour; one or two inks never use one: they are separated "
                        "directly)")
    p.add_argument("--characterisation", default=None, metavar="OUT.txt",
                   help="also write an IT8.7/4-style chart and its predicted CIELAB (45:0, D50) as CGATS text")
    p.add_argument("--coverage-model", default=AUTO_MODEL, choices=(AUTO_MODEL,) + COVERAGE_MODELS,
                   help="model of the separation and the BSDF; auto: murray-davies for AM/FM dots "
                        "(what a render of binary dots shows), clapper-yule for --dots none")
    p.add_argument("--dots", default="none", help="AM:LPI (screen ruling, lines per inch), FM, or none (continuous)")
    p.add_argument("--dpi", type=float, default=None,
                   help=f"texture resolution, texels per inch (default: one per image pixel for --dots none, "
                        f"{ht.AM_TEXELS_PER_CELL} per screen period for AM, {ht.FM_DPI:g} for FM; at least "
                        f"{ht.AM_MIN_TEXELS_PER_CELL} per screen period for AM, {ht.FM_MIN_DPI:g} for FM)")
    p.add_argument("--paper", type=float, default=None,
                   help=f"paper albedo in [0, 1] (default: the process inks' paper for --inks process, else {PAPER_ALBEDO:g})")
    p.add_argument("--size", default="12", help="print size in cm: WIDTHxHEIGHT, or WIDTH (height from the image)")
    p.add_argument("--intent", default="relative", choices=INTENTS,
                   help="relative: the image's white prints as the paper; absolute: CIELAB against a perfect white")
    p.add_argument("-o", "--output", default=None, help="scene file to write (.xml); textures go next to it")
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
        if args.paper is not None:
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
                         size_cm=parse_size(args.size), dpi=args.dpi, intent=args.intent,
                         black=black_rule(args), black_ink=black_ink(args, inks), mapping=args.gamut,
                         gamut=gamut_settings(args), lut_nodes=lut_nodes(args))


# BlackGeneration's fields as the command's options: (option, what it is, scale, unit); the
# ranges themselves live in solver/apps/separation/black.py alone
BLACK_OPTIONS = {"mode": ("--black", "a black generation", 1.0, ""),
                 "strength": ("--black-strength", "a share", 1.0, ""),
                 "start": ("--black-start", "a share", 1.0, ""),
                 "tac": ("--tac", "a total area coverage limit", 100.0, " percent")}


def black_rule(args):
    """BlackGeneration from --black, --black-strength, --black-start, --tac (UsageError naming
    the option otherwise: the rule checks its fields, this maps its field to the option)."""
    from solver.apps.separation import BlackGeneration, BlackGenerationError

    try:
        return BlackGeneration(args.black, args.black_strength, args.black_start, args.tac / 100.0)
    except BlackGenerationError as exc:
        option, what, scale, unit = BLACK_OPTIONS[exc.field]
        if isinstance(exc.allowed, tuple):
            raise UsageError(f"{option}: give one of {', '.join(exc.allowed)}, got {exc.value!r}") from None
        raise UsageError(f"{option}: give {what} in {exc.allowed.text(scale)}{unit}, "
                         f"got {scale * exc.value:g}") from None


def black_ink(args, inks):
    if args.black_ink is None or args.black_ink == "none":
        return args.black_ink
    from solver.apps.separation.printset import split_ink
    from solver.inks import parse_ink

    try:
        label = parse_ink(split_ink(args.black_ink)[0]).label
    except ValueError as exc:
        raise UsageError(f"--black-ink {args.black_ink!r} must be an ink spec of --inks ({', '.join(inks)}) or none: "
                         f"{_not_an_ink(args.black_ink, inks, exc)}") from None
    if label not in [split_ink(x)[0] for x in inks]:
        raise UsageError(f"--black-ink: {args.black_ink} is not one of --inks ({', '.join(inks)}); name one "
                         "of them or none")
    return label


def _not_an_ink(text: str, inks, exc: ValueError) -> str:
    """Why `text` is not an ink spec: a bare pigment letter ('K') lacks its volume percent (and
    names the ink of `inks` made of that pigment, if one is), else the ink grammar's own words."""
    from solver.apps.separation.printset import dominant_pigment
    from solver.inks import parse_ink

    code = text.strip().upper()
    try:
        parse_ink(f"{code}1")
    except ValueError:
        return str(exc)
    if not code.isalpha():
        return str(exc)
    made_of = [ink for ink in inks if dominant_pigment(ink) == code]
    return (f"{code} is a pigment letter without its volume percent; "
            + (f"the ink of --inks made of it is {made_of[0]}" if made_of else f"no ink of --inks is made of {code}"))


def gamut_settings(args):
    from solver.apps.separation import GamutSettings

    try:                               # the range lives in GamutSettings; the knee is all the CLI sets
        return GamutSettings(knee=args.gamut_knee)
    except ValueError as exc:
        raise UsageError(f"--gamut-knee: {exc}") from None


def lut_nodes(args) -> int:
    if args.lut != 0 and not 2 <= args.lut <= 129:
        raise UsageError(f"--lut: give 0 (no table) or 2 to 129 nodes per axis, got {args.lut}")
    return args.lut


def scene_xml(result, texture_folder: str, texture_files) -> str:
    """The printed page: a sheet of paper (the print plus a margin) with the print on it."""
    from inkbsdf.apps.pagescene import Stage, ink_source_xml, print_shape_xml, scene_document, stage_xml

    s = result.settings
    w, h = result.grid.size_cm
    sheet = (w + 2 * MARGIN_CM, h + 2 * MARGIN_CM)
    stage = Stage.for_sheet(*sheet)
    sources = [ink_source_xml(ink) for ink in s.inks]
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
        return run_guarded(lambda: _main(argv), PROG, f"\n{PROG}: {{interrupted}}: stopped")


def _main(argv) -> int:
    from solver.apps.separation import DotsError, print_image, printed_inks, read_image, write_textures
    from solver.apps.separation import DuotoneError, MonotoneError

    args = build_parser().parse_args(argv)
    configure_logging(args.verbose, builds=True)
    settings = settings_from(args)
    if args.image is None and args.characterisation is None:
        raise UsageError("give an IMAGE to print (with -o page.xml), or --characterisation OUT.txt")
    if args.image is not None and args.output is None:
        raise UsageError("-o/--output: give the scene file to write (e.g. -o page.xml)")
    if args.image is None and args.output is not None:
        raise UsageError("-o/--output: there is no IMAGE to print; give one, or leave -o out")
    chart = (writable_output(args.characterisation, ".txt", "--characterisation", make_folder=True)
             if args.characterisation is not None else None)
    output = writable_output(args.output, ".xml", "-o/--output") if args.output is not None else None
    if chart is not None:
        write_characterisation(settings, chart)
    if args.image is None:
        return 0
    image = read_image(args.image)
    for note in image.notes:
        print(f"{args.image}: {note}")
    rgb8 = image.rgb8
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
    except (MonotoneError, DuotoneError) as exc:
        raise UsageError(f"--inks: {exc}") from None
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


def write_characterisation(settings, path: Path) -> None:
    """The IT8.7/4-style chart of the inks and its predicted colour, as CGATS text."""
    from solver.apps.separation import printed_inks
    from solver.apps.separation.characterisation import characterisation_text
    from solver.apps.separation.job import print_model

    model, black = print_model(settings, printed_inks(settings.inks))
    text = characterisation_text(model, settings.inks, black)
    path.write_text(text)
    sets = text.split("BEGIN_DATA\n")[1].split("END_DATA")[0].count("\n")
    print(f"wrote {path} ({sets:,} patches, CGATS.17, {model.measurement.label} absolute CIELAB)")


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
