"""The committed scenes are what the layout description generates, and the softbox's mirror
image lands where the layout asks (checked by reflecting the eye ray, not by the formula)."""
from pathlib import Path

import numpy as np
import pytest

from conftest import scene_script

ma = scene_script("make_assets")


@pytest.mark.parametrize("page", ma.PAGES, ids=lambda p: p.name)
def test_committed_scene_matches_layout(page):
    committed = (Path(ma.HERE) / f"{page.name}.xml").read_text()
    assert committed == ma.scene_xml(page), f"run `python scenes/make_assets.py`: {page.name}.xml is stale"


@pytest.mark.parametrize("page", ma.PAGES, ids=lambda p: p.name)
def test_sheen_lands_where_asked(page):
    box, target = (np.array(v) for v in ma.softbox_origin(page))
    eye = np.array(ma.CAMERA)
    assert box[1] == pytest.approx(ma.SOFTBOX_HEIGHT_CM)
    # ray eye -> target, mirrored at the page plane y = 0, must pass through the softbox centre
    d = target - eye
    d_reflected = d * np.array([1.0, -1.0, 1.0])
    t = (box[1] - target[1]) / d_reflected[1]
    assert t > 0
    np.testing.assert_allclose(target + t * d_reflected, box, atol=1e-9)
    u, v = page.sheen_uv_cm
    assert 0 < u < ma.PAGE_W_CM and 0 < v < ma.PAGE_H_CM


def test_patches_are_distinct_on_the_page_and_do_not_overlap():
    for page in ma.PAGES:
        ids = [ma.patch_id(p) for p in page.patches]
        assert len(set(ids)) == len(ids), ids
        for p in page.patches:
            assert p.size_cm / 2 < p.u_cm < ma.PAGE_W_CM - p.size_cm / 2
            assert p.size_cm / 2 < p.v_cm < ma.PAGE_H_CM - p.size_cm / 2
        for a in page.patches:
            for b in page.patches:
                if a is not b:    # no overlap
                    assert max(abs(a.u_cm - b.u_cm), abs(a.v_cm - b.v_cm)) >= (a.size_cm + b.size_cm) / 2
