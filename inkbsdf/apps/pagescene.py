"""Pieces of the printed-page scenes: a sheet on a dark table under a sky and a softbox, seen
from above at an angle — the look of the demo page (`scenes/make_assets.py`), for any sheet
size (`python -m inkbsdf.print` writes its pages with them).

    stage = Stage.for_sheet(21.0, 29.7)          # the demo's A4 stage; other sizes scale it
    xml = scene_document(comment, stage_xml(stage, sheen_uv_cm=(13.07, 9.28)) + shapes)

Units: cm. The sheet lies in the plane y = 0 with its top edge toward −z; (u, v) on the sheet
are measured from its left and top edges. Textures map with v downward (`bitmap_xml`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.paper import PAPER_ALBEDO

A4_CM = (21.0, 29.7)
#: the A4 stage: eye and target (cm), field of view (degrees), softbox height and half-size
CAMERA_EYE_CM = (0.0, 30.0, 33.0)        # looks at the page centre from ~42° above it
CAMERA_TARGET_CM = (0.0, 0.0, 0.3)
CAMERA_FOV_DEG = 40.0
SOFTBOX_HEIGHT_CM = 40.0
SOFTBOX_HALF_CM = (6.0, 3.5)
TABLE_HALF_CM = 80.0
SKY_SIZE = (256, 128)                    # lat-long width, height
SKY_TEXTURE = "sky.exr"
PATCH_LIFT_CM = 0.02
LANDSCAPE_WIDTH = 1.3                     # shapes lying on the sheet, a hair above it
DEFAULTS = {"width": 640, "height": 512, "spp": 64, "paper": PAPER_ALBEDO, "max_depth": 4}


@dataclass(frozen=True)
class Stage:
    """Sheet size and where camera and softbox stand (cm), for one scene."""

    sheet_cm: tuple[float, float]
    eye_cm: tuple[float, float, float]
    target_cm: tuple[float, float, float]
    softbox_height_cm: float
    softbox_half_cm: tuple[float, float]
    table_half_cm: float

    @classmethod
    def for_sheet(cls, width_cm: float, height_cm: float) -> "Stage":
        """The A4 stage scaled so that a sheet of this size fills the view about as A4 does
        (a landscape sheet may be 1.3 times wider than A4 at the same scale: seen at an angle
        it is shallower, and the view wider than high)."""
        s = max(width_cm / (LANDSCAPE_WIDTH * A4_CM[0]), height_cm / A4_CM[1])
        scale = lambda v: tuple(round(s * x, 6) for x in v)        # noqa: E731
        return cls((float(width_cm), float(height_cm)), scale(CAMERA_EYE_CM), scale(CAMERA_TARGET_CM),
                   round(s * SOFTBOX_HEIGHT_CM, 6), scale(SOFTBOX_HALF_CM), round(s * TABLE_HALF_CM, 6))

    def to_world(self, u_cm: float, v_cm: float, lift_cm: float = 0.0) -> np.ndarray:
        """World position of the sheet point (u, v), `lift_cm` above it."""
        return np.array([u_cm - self.sheet_cm[0] / 2, lift_cm, v_cm - self.sheet_cm[1] / 2])

    def softbox_origin(self, sheen_uv_cm) -> tuple:
        """(softbox centre, aim point): the softbox at its height whose mirror image, seen from
        the eye, lies at `sheen_uv_cm` on the sheet."""
        p = self.to_world(*sheen_uv_cm)
        eye = np.array(self.eye_cm)
        mirrored_eye = np.array([eye[0], -eye[1], eye[2]])
        box = mirrored_eye + (p - mirrored_eye) * (self.softbox_height_cm + eye[1]) / eye[1]
        return tuple(box), tuple(p)


def rect_transform(stage: Stage, u_cm, v_cm, half_w, half_h, lift_cm) -> str:
    """<transform> of a rectangle lying on the sheet: +y is up, the sheet's top toward −z."""
    x, _, z = stage.to_world(u_cm, v_cm)
    return (f'<transform name="to_world"><scale x="{half_w:g}" y="{half_h:g}"/>'
            f'<rotate x="1" angle="-90"/><translate x="{x:g}" y="{lift_cm:g}" z="{z:g}"/></transform>')


def sky_radiance(elevation_rad: np.ndarray) -> np.ndarray:
    """RGB radiance of an overcast-like sky by elevation: the zenith three times as bright as
    the horizon (CIE overcast gradient), cool above, warm low, a dim ground below."""
    zenith, horizon = np.array([0.92, 0.96, 1.00]), np.array([1.00, 0.96, 0.90])
    ground = np.array([0.12, 0.11, 0.10])
    e = elevation_rad[..., None]
    up = np.clip(np.sin(e), 0.0, 1.0)
    sky = (horizon + (zenith - horizon) * up) * (1.0 + 2.0 * up) / 3.0
    return np.where(e >= 0.0, sky, ground + (horizon / 3.0 - ground) * np.exp(8.0 * e))


def write_sky(path) -> Path:
    """Lat-long environment map for Mitsuba's `envmap` (+Y up, row 0 = zenith), float32 EXR."""
    import mitsuba as mi

    w, h = SKY_SIZE
    elevation = np.pi / 2 - (np.arange(h) + 0.5) / h * np.pi
    rgb = np.repeat(sky_radiance(elevation)[:, None, :], w, axis=1).astype(np.float32)
    mi.Bitmap(rgb, mi.Bitmap.PixelFormat.RGB).write(str(path))
    return Path(path)


def bitmap_xml(name: str, filename: str, nearest: bool = False) -> str:
    """A raw (linear, 0..1) bitmap texture parameter `name`, v downward on the sheet;
    `nearest`: no filtering between texels (binary halftone dots stay 0 or 1)."""
    filt = '<string name="filter_type" value="nearest"/>' if nearest else ""
    return (f'<texture type="bitmap" name="{name}">'
            f'<string name="filename" value="{filename}"/><boolean name="raw" value="true"/>{filt}'
            '<transform name="to_uv"><scale y="-1"/><translate y="1"/></transform></texture>')


def ink_source_xml(label: str) -> str:
    """The `ink` BSDF parameters naming one ink of a print by its label (`solver.apps.separation
    .printset`: a spec, with its layer thickness after '@' when it has one); the table comes
    through the cache."""
    from solver.apps.separation.printset import split_ink

    spec, thickness_nm = split_ink(label)
    xml = f'<string name="ink" value="{spec}"/>'
    return xml if thickness_nm is None else xml + f'<float name="thickness" value="{thickness_nm:g}"/>'


def ink_bsdf_xml(sources, coverages, paper: str = "$paper", coverage_model: str | None = None,
                 indent: str = "        ") -> str:
    """An `ink` BSDF with inks 1..k: `sources[i]` is the XML naming ink i+1's table with
    single-ink names (`<string name="ink" …/>` or `filename`), numbered here when k > 1;
    `coverages[i]` the XML of its coverage (a texture named `coverage`, numbered likewise) or
    None (full coverage)."""
    import re

    lines = [f'{indent}<bsdf type="ink">']
    for n, (source, coverage) in enumerate(zip(sources, coverages), start=1):
        number = str(n) if len(sources) > 1 else ""
        lines.append(indent + "    " + re.sub(r'name="(ink|filename|thickness)"', rf'name="\g<1>{number}"', source))
        if coverage is not None:
            lines.append(indent + "    " + coverage.replace('name="coverage"', f'name="coverage{number}"', 1))
    lines.append(f'{indent}    <float name="paper" value="{paper}"/>')
    if coverage_model:
        lines.append(f'{indent}    <string name="coverage_model" value="{coverage_model}"/>')
    lines.append(f"{indent}</bsdf>")
    return "\n".join(lines)


def stage_xml(stage: Stage, sheen_uv_cm, textures: str = "textures") -> str:
    """Integrator, camera, sky, softbox (its mirror image at `sheen_uv_cm`) and the table."""
    (sx, sy, sz), (px, py, pz) = stage.softbox_origin(sheen_uv_cm)
    ex, ey, ez = stage.eye_cm
    tx, ty, tz = stage.target_cm
    bw, bh = stage.softbox_half_cm
    w, h = stage.sheet_cm
    return f"""    <integrator type="path"><integer name="max_depth" value="$max_depth"/></integrator>

    <sensor type="perspective" id="camera">
        <float name="fov" value="{CAMERA_FOV_DEG:g}"/>
        <transform name="to_world"><lookat origin="{ex:g}, {ey:g}, {ez:g}" target="{tx:g}, {ty:g}, {tz:g}" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="$width"/><integer name="height" value="$height"/>
            <rfilter type="gaussian"/>
        </film>
    </sensor>

    <emitter type="envmap" id="sky">
        <string name="filename" value="{textures}/{SKY_TEXTURE}"/>
        <float name="scale" value="1.3"/>
    </emitter>

    <!-- softbox: its mirror image, the sheen, lands at ({sheen_uv_cm[0]:g}, {sheen_uv_cm[1]:g}) cm on the page -->
    <shape type="rectangle" id="softbox">
        <transform name="to_world">
            <scale x="{bw:g}" y="{bh:g}"/>
            <lookat origin="{sx:.1f}, {sy:.1f}, {sz:.1f}" target="{px:.1f}, {py:g}, {pz:.1f}" up="0, 1, 0"/>
        </transform>
        <emitter type="area"><rgb name="radiance" value="3.0, 3.0, 3.0"/></emitter>
    </shape>

    <shape type="rectangle" id="table">
        {rect_transform(stage, w / 2, h / 2, stage.table_half_cm, stage.table_half_cm, -0.05)}
        <bsdf type="diffuse"><rgb name="reflectance" value="0.16, 0.11, 0.08"/></bsdf>
    </shape>
"""


def scene_document(comment: str, body: str, defaults: dict | None = None, tables: str | None = None) -> str:
    """A whole scene file: the comment, `<default>`s (DEFAULTS updated by `defaults`; `tables`
    adds `$tables` with that default), then `body`."""
    values = {**DEFAULTS, **(defaults or {})}
    head = (f'\n    <default name="tables" value="{tables}"/>' if tables is not None else "")
    head += "".join(f'\n    <default name="{k}" value="{v}"/>' for k, v in values.items())
    return f"""<!-- {comment} -->
<scene version="3.0.0">{head}

{body}</scene>
"""


def print_shape_xml(stage: Stage, center_uv_cm, size_cm, sources, coverage_files, nearest: bool,
                    coverage_model: str | None, shape_id: str = "photo", comment: str = "") -> str:
    """A printed image lying on the sheet: a rectangle of `size_cm` (width, height) centred at
    `center_uv_cm`, an `ink` BSDF with the inks `sources` (see `ink_bsdf_xml`) and their
    coverage textures `coverage_files` (paths relative to the scene file)."""
    (u, v), (w, h) = center_uv_cm, size_cm
    coverages = [bitmap_xml("coverage", f, nearest) for f in coverage_files]
    note = f"    <!-- {comment} -->\n" if comment else ""
    return (f'{note}    <shape type="rectangle" id="{shape_id}">\n'
            f'        {rect_transform(stage, u, v, w / 2, h / 2, PATCH_LIFT_CM)}\n'
            f'{ink_bsdf_xml(sources, coverages, coverage_model=coverage_model)}\n    </shape>\n')
