"""Generate the demo scenes and their textures from page layouts.

    .venv/bin/python scenes/make_assets.py   # writes scenes/*.xml, scenes/textures/* (the project installed)

printed_page.xml: an A4 sheet (cm) with a colour chart of six ink patches (R30, Y30, B30, G30,
the particle-free Y25+B5 mix and clear varnish), their labels, a title and a paragraph printed
in B30 through a coverage texture (white = ink), and a photograph (a still life the project
renders, `still_life.py`) printed with R30, Y30 and B30 as AM halftone dots — separated and
screened by `solver.apps.separation`, as `python -m inkbsdf.print` does — on a dark table under a
sky-gradient environment and a softbox at a low angle whose mirror image puts the inks' sheen
on the far row of patches.  Its inks are table files (`make tables`).
particle_inks.xml: the same page with one pigment load, Y7.5+B7.5, as a molecular mix and as
grains (30, 100 and 300 nm, clustered 100 nm, rough-top 300 nm) — the paper's size effect,
with the softbox's mirror image on the paragraph instead of the patches.  Its inks are named
in the scene (`ink`, `particles`): loading it builds the missing tables through the cache
(wave solver, minutes per table).
The outputs are committed; rerun after changing a layout (the photograph's separation takes
a few seconds; `--no-photo` keeps the committed photograph textures, `--render-photo` renders
the still life again).
Scene pieces shared with `python -m inkbsdf.print` live in `inkbsdf/apps/pagescene.py`.
"""

from __future__ import annotations

import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
from inkbsdf.apps.pagescene import (A4_CM, CAMERA_EYE_CM, SOFTBOX_HEIGHT_CM, PATCH_LIFT_CM,  # noqa: F401
                               Stage, bitmap_xml, ink_bsdf_xml, ink_source_xml, print_shape_xml, rect_transform,
                               scene_document, stage_xml, write_sky)
from solver.apps.separation.printset import process_set
from solver.paper import PAPER_ALBEDO

PAGE_W_CM, PAGE_H_CM = A4_CM
STAGE = Stage.for_sheet(PAGE_W_CM, PAGE_H_CM)
CAMERA = CAMERA_EYE_CM
TEXT_PX_PER_CM = 48
TEXT_INK = "B30"
TITLE_MAX_WIDTH_CM, LABEL_MAX_WIDTH_CM = 18.0, 5.0


@dataclass(frozen=True)
class Patch:
    ink: str                 # ink spec; with particles=None also the table name (<ink>.npz)
    label: str
    u_cm: float              # centre, from the page's left edge
    v_cm: float              # centre, from the page's top edge
    size_cm: float = 5.0
    particles: str | None = None   # None: table file; else named in the scene (ink + particles)


@dataclass(frozen=True)
class TextBox:
    """Where the paragraph goes: left edge and first baseline (cm), characters per line, em
    height and line spacing (cm)."""

    u_cm: float
    v_cm: float
    width_chars: int
    em_cm: float
    leading_cm: float


@dataclass(frozen=True)
class Photo:
    """A photograph printed on the page (textures/<page>_photo*.png)."""

    inks: tuple              # printing order (demo table files)
    dots: str                # solver.apps.separation.parse_dots
    u_cm: float              # centre
    v_cm: float
    width_cm: float          # height from the image's aspect ratio
    caption: str


@dataclass(frozen=True)
class Page:
    name: str                # scene file stem; texture textures/<name>_text.png
    title: str
    subtitle: str
    paragraph: str
    patches: tuple
    in_scene_inks: bool      # True: BSDFs name their inks; False: $tables/<ink>.npz files
    sheen_uv_cm: tuple       # (u, v) on the page where the softbox's mirror image lands
    text: TextBox = TextBox(2.5, 21.4, 62, 0.5, 0.85)
    photo: Photo | None = None


ROW1, ROW2 = 8.6, 15.4
PHOTO_SIZE_PX = (360, 270)             # the still life (still_life.py), width × height
PRINTED_PAGE = Page(
    "printed_page", "Printed ink on paper",
    "wave-optics tables of a 1 µm ink layer, rendered with Mitsuba 3",
    "Each coloured patch is a binder layer one micrometre thick holding 30 % pigment by volume. "
    "Its colour comes from light that crosses the layer, scatters in the paper and crosses "
    "it again; its sheen is the layer's coherent mirror reflection, tinted by thin-film "
    "interference. G30 is a molecular mix of blue and yellow pigment. The photograph is "
    "printed with the four process inks in halftone dots; where dots overlap, they lie in layers.",
    (Patch("R30", "R30", 5.0, ROW1), Patch("Y30", "Y30", 10.5, ROW1),
     Patch("clear", "clear varnish", 16.0, ROW1), Patch("B30", "B30", 5.0, ROW2),
     Patch("G30", "G30 (molecular)", 10.5, ROW2), Patch("Y25+B5", "Y25+B5 mix", 16.0, ROW2)),
    in_scene_inks=False, sheen_uv_cm=(13.07, 9.28),
    text=TextBox(1.9, 20.7, 44, 0.42, 0.68),
    photo=Photo(process_set(), "AM:20", 15.45, 23.2, 8.1, "process inks K, C, M, Y, AM 20 lpi"))
PARTICLE_PAGE = Page(
    "particle_inks", "Same pigment, different grains",
    "7.5 % yellow + 7.5 % blue by volume in a 1 µm layer: wave-optics tables",
    "Every patch holds the same pigment load. Dissolved molecularly it is a deep green; as "
    "30-nm grains it looks the same (the solver finds an effective-medium film accurate "
    "enough); as 100-nm grains it is a little paler, as 300-nm grains much paler and "
    "yellower: between large grains light finds paths that cross little pigment. Clustered "
    "100-nm grains behave like larger ones; a rough top, grains standing out of the binder, "
    "changes little. The lighter band across this text is the softbox's mirror image in the ink.",
    (Patch("Y7.5+B7.5", "molecular", 5.0, ROW1),
     Patch("Y7.5+B7.5", "30 nm grains", 10.5, ROW1, particles="sphere:30"),
     Patch("Y7.5+B7.5", "100 nm grains", 16.0, ROW1, particles="sphere:100"),
     Patch("Y7.5+B7.5", "300 nm grains", 5.0, ROW2, particles="sphere:300"),
     Patch("Y7.5+B7.5", "100 nm clustered", 10.5, ROW2, particles="sphere:100:agglutinated"),
     Patch("Y7.5+B7.5", "300 nm rough top", 16.0, ROW2, particles="sphere:300:rough")),
    in_scene_inks=True, sheen_uv_cm=(10.5, 23.6))
PAGES = (PRINTED_PAGE, PARTICLE_PAGE)
#: realizations per wavelength for the particle page's tables (fewer than the default 4: the
#: first load took 39 min in one process on 2 cores instead of over an hour; docs/tables.md)
PARTICLE_PAGE_REALIZATIONS = 2


def patch_id(p: Patch) -> str:
    """Shape id of a patch in the scene (tests find patches by it)."""
    tail = "" if p.particles is None else "_" + p.particles.replace(":", "_")
    return "patch_" + p.ink.replace("+", "_").replace(".", "p") + tail


def photo_size_cm(photo: Photo) -> tuple:
    """(width, height) of the printed photograph."""
    return photo.width_cm, photo.width_cm * PHOTO_SIZE_PX[1] / PHOTO_SIZE_PX[0]


def photo_texture_files(page: Page) -> list:
    """The photograph's coverage textures (relative to scenes/), printing order."""
    from solver.apps.separation.job import texture_name

    return [f"textures/{texture_name(page.name + '_photo', i, ink)}" for i, ink in enumerate(page.photo.inks)]


def _fitting_em_cm(text: str, em_cm: float, max_width_cm: float) -> float:
    """em_cm, or less so that bold text (≈ 0.62 em per character) fits in max_width_cm."""
    return min(em_cm, max_width_cm / (0.62 * len(text)))


def make_text_texture(page: Page, path: Path) -> None:
    """The page's coverage texture: title, labels, paragraph, caption, crop marks (1 = ink)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    dpi = TEXT_PX_PER_CM * 2.54
    fig = plt.figure(figsize=(PAGE_W_CM / 2.54, PAGE_H_CM / 2.54), dpi=dpi, facecolor="black")
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, PAGE_W_CM)
    ax.set_ylim(PAGE_H_CM, 0)
    ax.set_facecolor("black")
    ax.axis("off")
    pt = lambda cm: cm / 2.54 * 72.0          # noqa: E731  font size for a given em height
    ax.text(PAGE_W_CM / 2, 3.3, page.title, color="white", ha="center", va="baseline",
            fontsize=pt(_fitting_em_cm(page.title, 1.45, TITLE_MAX_WIDTH_CM)), fontweight="bold", family="DejaVu Serif")
    ax.text(PAGE_W_CM / 2, 4.5, page.subtitle, color="white", ha="center", va="baseline",
            fontsize=pt(0.52), family="DejaVu Sans", style="italic")
    for p in page.patches:
        ax.text(p.u_cm, p.v_cm + p.size_cm / 2 + 0.75, p.label, color="white", ha="center",
                va="baseline", fontsize=pt(_fitting_em_cm(p.label, 0.6, LABEL_MAX_WIDTH_CM)),
                family="DejaVu Sans", fontweight="bold")
    box = page.text
    for k, line in enumerate(textwrap.wrap(page.paragraph, width=box.width_chars)):
        ax.text(box.u_cm, box.v_cm + box.leading_cm * k, line, color="white", ha="left", va="baseline",
                fontsize=pt(box.em_cm), family="DejaVu Serif")
    if page.photo is not None:
        _, h = photo_size_cm(page.photo)
        ax.text(page.photo.u_cm, page.photo.v_cm + h / 2 + 0.6, page.photo.caption, color="white",
                ha="center", va="baseline", fontsize=pt(0.38), family="DejaVu Sans", style="italic")
    for cu, cv in ((1.0, 1.0), (PAGE_W_CM - 1.0, 1.0), (1.0, PAGE_H_CM - 1.0),
                   (PAGE_W_CM - 1.0, PAGE_H_CM - 1.0)):
        ax.plot([cu - 0.5, cu + 0.5], [cv, cv], color="white", lw=1.2)
        ax.plot([cu, cu], [cv - 0.5, cv + 0.5], color="white", lw=1.2)
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    plt.close(fig)
    import mitsuba as mi

    gray = rgba[:, :, 0].astype(np.uint8)[:, :, None]
    mi.Bitmap(np.ascontiguousarray(gray), mi.Bitmap.PixelFormat.Y).write(str(path))


def make_photo_textures(page: Page, render: bool) -> None:
    """Separate and halftone the photograph (solver.apps.separation), write the textures; `render`
    (or no photograph yet): render the still life first (LLVM's multithreaded film sums are
    not bit-reproducible, so the committed photograph is kept otherwise)."""
    from still_life import render_still_life

    from solver.apps.separation import (PrintSettings, parse_dots, print_image, printed_inks, read_srgb8,
                                   write_rgb_png)

    photo = page.photo
    source = HERE / "textures" / f"{page.name}_photo.png"
    if render or not source.is_file():
        write_rgb_png(source, render_still_life(*PHOTO_SIZE_PX))
    rgb8 = read_srgb8(source)
    settings = PrintSettings(inks=photo.inks, dots=parse_dots(photo.dots), size_cm=photo_size_cm(photo),
                             paper=PAPER_ALBEDO)            # the page's paper ($paper's default)
    result = print_image(rgb8, settings, printed_inks(photo.inks))
    for line in result.separation.report.lines():
        print(f"{page.name} photograph: {line}")
    for name, texture in zip(photo_texture_files(page), result.textures):
        from solver.apps.separation import write_grey_png

        write_grey_png(HERE / name, texture)


def softbox_origin(page: Page) -> tuple:
    """Softbox centre at SOFTBOX_HEIGHT_CM whose mirror image, seen from CAMERA, is at sheen_uv_cm."""
    return STAGE.softbox_origin(page.sheen_uv_cm)


def _ink_source(page: Page, ink: str, particles: str | None) -> str:
    """The BSDF parameters naming an ink: a table file, or the ink itself (cache)."""
    if not page.in_scene_inks:
        return f'<string name="filename" value="$tables/{ink}.npz"/>'
    out = f'<string name="ink" value="{ink}"/>'
    if particles:
        out += (f'<string name="particles" value="{particles}"/>'
                f'<integer name="realizations" value="{PARTICLE_PAGE_REALIZATIONS}"/>')
    return out


def _photo_xml(page: Page) -> str:
    from solver.apps.separation import PrintSettings, parse_dots

    photo = page.photo
    settings = PrintSettings(inks=photo.inks, dots=parse_dots(photo.dots), paper=PAPER_ALBEDO)
    # the photograph's inks are named in the scene (their tables and overprints through the cache)
    return "\n" + print_shape_xml(
        STAGE, (photo.u_cm, photo.v_cm), photo_size_cm(photo),
        [ink_source_xml(ink) for ink in photo.inks], photo_texture_files(page),
        settings.dots.binary, None if settings.dots.binary else settings.model,
        comment=f"the photograph: {', '.join(photo.inks)} (printing order), {settings.dots.label()}, "
                f"separated with {settings.model}")


def scene_xml(page: Page) -> str:
    patches = "\n".join(
        f'    <shape type="rectangle" id="{patch_id(p)}">\n'
        f'        {rect_transform(STAGE, p.u_cm, p.v_cm, p.size_cm / 2, p.size_cm / 2, PATCH_LIFT_CM)}\n'
        f'        <bsdf type="ink">{_ink_source(page, p.ink, p.particles)}'
        f'<float name="paper" value="$paper"/></bsdf>\n    </shape>' for p in page.patches)
    inks = ("inks named in the scene (built through the table cache)" if page.in_scene_inks
            else "tables (folder of <ink>.npz)")
    text = bitmap_xml("coverage", f"textures/{page.name}_text.png")
    body = stage_xml(STAGE, page.sheen_uv_cm) + f"""
    <!-- the sheet: paper everywhere, {TEXT_INK} ink where the coverage texture is white -->
    <shape type="rectangle" id="page">
        {rect_transform(STAGE, PAGE_W_CM / 2, PAGE_H_CM / 2, PAGE_W_CM / 2, PAGE_H_CM / 2, 0.0)}
{ink_bsdf_xml([_ink_source(page, TEXT_INK, None)], [text])}
    </shape>

{patches}
""" + (_photo_xml(page) if page.photo is not None else "")
    return scene_document(f"A printed page: generated by scenes/make_assets.py, edit the layout there.\n"
                          f"     Inks: {inks}.  Parameters: width, height, spp, paper (albedo). Units: cm.",
                          body, tables=None if page.in_scene_inks else "../out/tables")


def main(argv=None) -> None:
    import mitsuba as mi

    args = sys.argv[1:] if argv is None else argv
    mi.set_variant("scalar_rgb")
    (HERE / "textures").mkdir(exist_ok=True)
    write_sky(HERE / "textures" / "sky.exr")
    for page in PAGES:
        make_text_texture(page, HERE / "textures" / f"{page.name}_text.png")
        if page.photo is not None and "--no-photo" not in args:
            make_photo_textures(page, render="--render-photo" in args)
        (HERE / f"{page.name}.xml").write_text(scene_xml(page))
        print(f"wrote {HERE / (page.name + '.xml')} and textures/{page.name}_*")


if __name__ == "__main__":
    main()
