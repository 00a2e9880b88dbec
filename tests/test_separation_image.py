"""Images in (solver.apps.separation.image): modes Pillow reads become 8-bit sRGB (transparency over
white paper, 16-bit rounded, grey neutral); distinct colours index back to the pixels."""

import numpy as np
import pytest
from PIL import Image

from solver.apps.separation import ImageError, read_srgb8, unique_colours


def test_modes(tmp_path):
    rgba = np.zeros((2, 3, 4), dtype=np.uint8)
    rgba[..., :3] = (200, 10, 30)
    rgba[0, :, 3] = 255
    rgba[1, 0, 3] = 0
    rgba[1, 1:, 3] = 128
    Image.fromarray(rgba, "RGBA").save(tmp_path / "a.png")
    got = read_srgb8(tmp_path / "a.png")
    np.testing.assert_array_equal(got[0, 0], (200, 10, 30))
    np.testing.assert_array_equal(got[1, 0], (255, 255, 255))                 # transparent: paper
    np.testing.assert_array_equal(got[1, 1], np.round(np.array([200, 10, 30]) * 128 / 255 + 255 * 127 / 255))
    grey16 = (np.arange(6, dtype=np.uint16).reshape(2, 3) * 13107)            # 0 … 65535
    Image.fromarray(grey16).save(tmp_path / "g.png")
    g = read_srgb8(tmp_path / "g.png")
    np.testing.assert_array_equal(g[..., 0], np.round(grey16 / 65535 * 255))
    assert np.all(g[..., 0] == g[..., 2])
    Image.fromarray(rgba[..., :3]).convert("P").save(tmp_path / "p.png")
    assert read_srgb8(tmp_path / "p.png").shape == (2, 3, 3)
    Image.fromarray(rgba[..., :3]).save(tmp_path / "j.jpg", quality=95)
    assert np.abs(read_srgb8(tmp_path / "j.jpg").astype(int)[0, 0] - (200, 10, 30)).max() < 12


def test_unreadable(tmp_path):
    (tmp_path / "t.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 40)
    with pytest.raises(ImageError, match="t.png"):
        read_srgb8(tmp_path / "t.png")
    with pytest.raises(ImageError, match="not found"):
        read_srgb8(tmp_path / "none.png")


def test_unique_colours_index_back():
    img = np.random.default_rng(0).integers(0, 4, size=(30, 20, 3)).astype(np.uint8) * 60
    colours, index = unique_colours(img)
    assert len(colours) == len({tuple(p) for p in img.reshape(-1, 3)})
    np.testing.assert_array_equal(colours[index].reshape(img.shape), img)
