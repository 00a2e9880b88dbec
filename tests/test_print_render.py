"""A page printed with three overlapping coverage textures renders without NaN, and the
overprints look as they should (darker where inks overlap, each ink its hue)."""

import numpy as np
import pytest

from printing_tables import StackProvider, film
from solver.colour import lab_hue_chroma
from solver.colour.srgb import linear_to_lab
from solver.table import write_table

pytestmark = pytest.mark.render
RES = 64                                   # texture texels per side
WIDTH = HEIGHT = 72


def disc(cx, cy, radius, value):
    """Coverage texture: a disc of constant coverage `value` (continuous tone) on bare paper."""
    y, x = (np.mgrid[0:RES, 0:RES] + 0.5) / RES
    return np.where((x - cx) ** 2 + (y - cy) ** 2 < radius**2, value, 0.0)


def scene_dict(mi, paths, textures, model):
    """A sheet filling an orthographic view, lit by a uniform sky."""
    bsdf = {"type": "ink", "paper": 0.9, "coverage_model": model}
    for n, (path, tex) in enumerate(zip(paths, textures), start=1):
        bsdf[f"filename{n}"] = str(path)
        bsdf[f"coverage{n}"] = {"type": "bitmap", "filename": str(tex), "raw": True}
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {"type": "orthographic",
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": 16}},
        "sky": {"type": "constant", "radiance": 1.0},
        "sheet": {"type": "rectangle", "bsdf": bsdf},
    }


@pytest.mark.parametrize("model", ["clapper-yule", "murray-davies"])
def test_three_overlapping_textures_render(use_variant, tmp_path, model):
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.apps.imageio import write_png
    from inkbsdf.inks import stack_provider

    paths = [write_table(tmp_path / f"{ink}.npz", film(ink)) for ink in ("R30", "Y30", "B30")]
    centres = ((0.38, 0.40), (0.62, 0.40), (0.50, 0.62))
    textures = []
    for n, (cx, cy) in enumerate(centres):
        path = tmp_path / f"cov{n}.exr"
        mi.Bitmap(disc(cx, cy, 0.22, 0.8).astype(np.float32)[..., None], mi.Bitmap.PixelFormat.Y).write(str(path))
        textures.append(path)
    provider = StackProvider()
    with stack_provider(provider):
        scene = mi.load_dict(scene_dict(mi, paths, textures, model))
    assert sorted(provider.calls) == sorted([(2, 1), (3, 1), (3, 2), (3, 2, 1)])
    image = np.asarray(mi.render(scene, spp=16, seed=1), dtype=np.float64)
    write_png(tmp_path / "three_inks.png", image.astype(np.float32))
    assert image.shape == (HEIGHT, WIDTH, 3) and np.all(np.isfinite(image))
    assert (image @ [0.2126, 0.7152, 0.0722]).min() > -1e-3    # channels may dip < 0 out of gamut

    def at(u, v):                             # mean colour of a 5×5 pixel block at texture (u, v)
        # the rectangle spans [−1, 1]² and the orthographic view ±1 in x, y; v runs up the image
        px, py = int(u * WIDTH), int((1.0 - v) * HEIGHT)
        return image[py - 2:py + 3, px - 2:px + 3].reshape(-1, 3).mean(axis=0)

    paper, red, yellow = at(0.05, 0.05), at(0.25, 0.35), at(0.75, 0.35)
    centre = at(0.50, 0.47)                                   # all three inks
    lum = lambda rgb: float(rgb @ [0.2126, 0.7152, 0.0722])   # noqa: E731
    assert lum(centre) < min(lum(red), lum(yellow)) < lum(paper)
    hue_r, chroma_r = lab_hue_chroma(linear_to_lab(red))
    hue_y, _ = lab_hue_chroma(linear_to_lab(yellow))
    assert chroma_r > 10 and (hue_r > 300 or hue_r < 40) and 60 < hue_y < 110
