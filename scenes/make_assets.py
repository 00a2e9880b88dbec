"""Generate the demo scenes and their textures from page layouts.

    python scenes/make_assets.py          # writes scenes/*.xml, scenes/textures/*

printed_page.xml: an A4 sheet (cm) with a colour chart of six ink patches (R30, Y30, B30, G30,
the particle-free Y25+B5 mix and clear varnish), their labels, a title and a paragraph printed
in B30 through a coverage texture (white = ink), on a dark table under a sky-gradient
environment and a softbox at a low angle whose mirror image puts the inks' sheen on the far
row of patches.  Its inks are table files (`make tables`).
particle_inks.xml: the same page with one pigment load, Y7.5+B7.5, as a molecular mix and as
grains (30, 100 and 300 nm, clustered 100 nm, rough-top 300 nm) — the paper's size effect,
with the softbox's mirror image on the paragraph instead of the patches.  Its inks are named
in the scene (`ink`, `particles`): loading it builds the missing tables through the cache
(wave solver, minutes per table).
The outputs are committed; rerun after changing a layout.
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
PAGE_W_CM, PAGE_H_CM = 21.0, 29.7
TEXT_PX_PER_CM = 48
SKY_SIZE = (256, 128)                  # lat-long width, height
TEXT_INK = "B30"
PATCH_LIFT_CM = 0.02                   # patches lie on the page, a hair above it
TITLE_MAX_WIDTH_CM, LABEL_MAX_WIDTH_CM = 18.0, 5.0
CAMERA = (0.0, 30.0, 33.0)             # eye, cm; looks at the page centre from ~42° above it
SOFTBOX_HEIGHT_CM = 40.0


@dataclass(frozen=True)
class Patch:
    ink: str                 # ink spec; with particles=None also the table name (<ink>.npz)
    label: str
    u_cm: float              # centre, from the page's left edge
    v_cm: float              # centre, from the page's top edge
    size_cm: float = 5.0
    particles: str | None = None   # None: table file; else named in the scene (ink + particles)


@dataclass(frozen=True)
class Page:
    name: str                # scene file stem; texture textures/<name>_text.png
    title: str
    subtitle: str
    paragraph: str
    patches: tuple
    in_scene_inks: bool      # True: BSDFs name their inks; False: $tables/<ink>.npz files
    sheen_uv_cm: tuple       # (u, v) on the page where the softbox's mirror image lands


ROW1, ROW2 = 8.6, 15.4
PRINTED_PAGE = Page(
    "printed_page", "Printed ink on paper",
    "wave-optics tables of a 1 µm ink layer, rendered with Mitsuba 3",
    "Each coloured patch is a binder layer one micrometre thick holding 30 % pigment by volume. "
    "Its colour comes from light that crosses the layer, scatters in the paper and crosses "
    "it again; its sheen is the layer's coherent mirror reflection, tinted by thin-film "
    "interference. The green patch is a molecular mix of blue and yellow pigment; the "
    "yellow-green one mixes 25 % yellow with 5 % blue. Clear varnish shows only its gloss.",
    (Patch("R30", "R30", 5.0, ROW1), Patch("Y30", "Y30", 10.5, ROW1),
     Patch("clear", "clear varnish", 16.0, ROW1), Patch("B30", "B30", 5.0, ROW2),
     Patch("G30", "G30 (molecular)", 10.5, ROW2), Patch("Y25+B5", "Y25+B5 mix", 16.0, ROW2)),
    in_scene_inks=False, sheen_uv_cm=(13.07, 9.28))
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


def _fitting_em_cm(text: str, em_cm: float, max_width_cm: float) -> float:
    """em_cm, or less so that bold text (≈ 0.62 em per character) fits in max_width_cm."""
    return min(em_cm, max_width_cm / (0.62 * len(text)))


def make_text_texture(page: Page, path: Path) -> None:
    """The page's coverage texture: title, labels, paragraph, crop marks (1 = ink)."""
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
    lines = textwrap.wrap(page.paragraph, width=62)
    for k, line in enumerate(lines):
        ax.text(2.5, 21.4 + 0.85 * k, line, color="white", ha="left", va="baseline",
                fontsize=pt(0.5), family="DejaVu Serif")
    for cu, cv in ((1.0, 1.0), (PAGE_W_CM - 1.0, 1.0), (1.0, PAGE_H_CM - 1.0),
                   (PAGE_W_CM - 1.0, PAGE_H_CM - 1.0)):
        ax.plot([cu - 0.5, cu + 0.5], [cv, cv], color="white", lw=1.2)
        ax.plot([cu, cu], [cv - 0.5, cv + 0.5], color="white", lw=1.2)
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    plt.close(fig)
    gray = rgba[:, :, 0].astype(np.uint8)[:, :, None]
    import mitsuba as mi

    mi.Bitmap(np.ascontiguousarray(gray), mi.Bitmap.PixelFormat.Y).write(str(path))


def sky_radiance(elevation_rad: np.ndarray) -> np.ndarray:
    """RGB radiance of an overcast-like sky by elevation: the zenith three times as bright as
    the horizon (CIE overcast gradient), cool above, warm low, a dim ground below."""
    zenith, horizon = np.array([0.92, 0.96, 1.00]), np.array([1.00, 0.96, 0.90])
    ground = np.array([0.12, 0.11, 0.10])
    e = elevation_rad[..., None]
    up = np.clip(np.sin(e), 0.0, 1.0)
    sky = (horizon + (zenith - horizon) * up) * (1.0 + 2.0 * up) / 3.0
    return np.where(e >= 0.0, sky, ground + (horizon / 3.0 - ground) * np.exp(8.0 * e))


def make_sky(path: Path) -> None:
    """Lat-long environment map for Mitsuba's `envmap` (+Y up, row 0 = zenith), float32 EXR."""
    import mitsuba as mi

    w, h = SKY_SIZE
    elevation = np.pi / 2 - (np.arange(h) + 0.5) / h * np.pi
    rgb = np.repeat(sky_radiance(elevation)[:, None, :], w, axis=1).astype(np.float32)
    mi.Bitmap(rgb, mi.Bitmap.PixelFormat.RGB).write(str(path))


def _rect(u_cm, v_cm, half_w, half_h, lift_cm):
    """<transform> of a rectangle lying on the page: +y is up, page top toward −z."""
    x, z = u_cm - PAGE_W_CM / 2, v_cm - PAGE_H_CM / 2
    return (f'<transform name="to_world"><scale x="{half_w:g}" y="{half_h:g}"/>'
            f'<rotate x="1" angle="-90"/><translate x="{x:g}" y="{lift_cm:g}" z="{z:g}"/></transform>')


def _ink_source(page: Page, ink: str, particles: str | None) -> str:
    """The BSDF parameters naming an ink: a table file, or the ink itself (cache)."""
    if not page.in_scene_inks:
        return f'<string name="filename" value="$tables/{ink}.npz"/>'
    out = f'<string name="ink" value="{ink}"/>'
    if particles:
        out += (f'<string name="particles" value="{particles}"/>'
                f'<integer name="realizations" value="{PARTICLE_PAGE_REALIZATIONS}"/>')
    return out


def softbox_origin(page: Page) -> tuple:
    """Softbox centre at SOFTBOX_HEIGHT_CM whose mirror image, seen from CAMERA, is at sheen_uv_cm."""
    u, v = page.sheen_uv_cm
    p = np.array([u - PAGE_W_CM / 2, 0.0, v - PAGE_H_CM / 2])
    mirrored_eye = np.array([CAMERA[0], -CAMERA[1], CAMERA[2]])
    return tuple(mirrored_eye + (p - mirrored_eye) * (SOFTBOX_HEIGHT_CM + CAMERA[1]) / CAMERA[1]), tuple(p)


def scene_xml(page: Page) -> str:
    patches = "\n".join(
        f'    <shape type="rectangle" id="{patch_id(p)}">\n'
        f'        {_rect(p.u_cm, p.v_cm, p.size_cm / 2, p.size_cm / 2, PATCH_LIFT_CM)}\n'
        f'        <bsdf type="ink">{_ink_source(page, p.ink, p.particles)}'
        f'<float name="paper" value="$paper"/></bsdf>\n    </shape>' for p in page.patches)
    tables_param = '' if page.in_scene_inks else '\n    <default name="tables" value="../out/tables"/>'
    (sx, sy, sz), (px, py, pz) = softbox_origin(page)
    inks = ("inks named in the scene (built through the table cache)" if page.in_scene_inks
            else "tables (folder of <ink>.npz)")
    return f"""<!-- A printed page: generated by scenes/make_assets.py, edit the layout there.
     Inks: {inks}.  Parameters: width, height, spp, paper (albedo). Units: cm. -->
<scene version="3.0.0">{tables_param}
    <default name="width" value="640"/>
    <default name="height" value="512"/>
    <default name="spp" value="64"/>
    <default name="paper" value="0.9"/>
    <default name="max_depth" value="4"/>

    <integrator type="path"><integer name="max_depth" value="$max_depth"/></integrator>

    <sensor type="perspective" id="camera">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="{CAMERA[0]:g}, {CAMERA[1]:g}, {CAMERA[2]:g}" target="0, 0, 0.3" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="$width"/><integer name="height" value="$height"/>
            <rfilter type="gaussian"/>
        </film>
    </sensor>

    <emitter type="envmap" id="sky">
        <string name="filename" value="textures/sky.exr"/>
        <float name="scale" value="1.3"/>
    </emitter>

    <!-- softbox: its mirror image, the sheen, lands at ({page.sheen_uv_cm[0]:g}, {page.sheen_uv_cm[1]:g}) cm on the page -->
    <shape type="rectangle" id="softbox">
        <transform name="to_world">
            <scale x="6" y="3.5"/>
            <lookat origin="{sx:.1f}, {sy:.1f}, {sz:.1f}" target="{px:.1f}, {py:g}, {pz:.1f}" up="0, 1, 0"/>
        </transform>
        <emitter type="area"><rgb name="radiance" value="3.0, 3.0, 3.0"/></emitter>
    </shape>

    <shape type="rectangle" id="table">
        {_rect(PAGE_W_CM / 2, PAGE_H_CM / 2, 80, 80, -0.05)}
        <bsdf type="diffuse"><rgb name="reflectance" value="0.16, 0.11, 0.08"/></bsdf>
    </shape>

    <!-- the sheet: paper everywhere, {TEXT_INK} ink where the coverage texture is white -->
    <shape type="rectangle" id="page">
        {_rect(PAGE_W_CM / 2, PAGE_H_CM / 2, PAGE_W_CM / 2, PAGE_H_CM / 2, 0.0)}
        <bsdf type="ink">
            {_ink_source(page, TEXT_INK, None)}
            <float name="paper" value="$paper"/>
            <texture type="bitmap" name="coverage">
                <string name="filename" value="textures/{page.name}_text.png"/>
                <boolean name="raw" value="true"/>
                <transform name="to_uv"><scale y="-1"/><translate y="1"/></transform>
            </texture>
        </bsdf>
    </shape>

{patches}
</scene>
"""


def main() -> None:
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    (HERE / "textures").mkdir(exist_ok=True)
    make_sky(HERE / "textures" / "sky.exr")
    for page in PAGES:
        make_text_texture(page, HERE / "textures" / f"{page.name}_text.png")
        (HERE / f"{page.name}.xml").write_text(scene_xml(page))
        print(f"wrote {HERE / (page.name + '.xml')} and textures/{page.name}_text.png")


if __name__ == "__main__":
    main()
