"""A print with one chromatic ink (no neutral below the paper) renders an image as a one-colour
print — the most ink where the image is darkest, the image's black at the solid's L* (a monotone:
docs/printing.md, "One ink: a monotone"; tests/test_monotone.py checks its lightness). Before the
black-point compensation took the print's darkest colour, whatever its hue, the black was the
darkest *neutral*, the paper itself: the image was compressed into L* 99.7–100 and Y30 printed
nothing."""

import numpy as np
import pytest

from solver.apps.separation import PrintColourModel, Separator, printed_inks, separate_image


@pytest.mark.parametrize("ink", ["Y30", "B30"])
def test_one_chromatic_ink_prints_the_image_darkness(ink):
    model = PrintColourModel.build(printed_inks((ink,)), 0.9, "clapper-yule")
    separator = Separator.build(model)
    solid_l = float(model.lab(np.ones(1))[0])
    grey = np.linspace(0, 255, 18).round().astype(np.uint8)
    ramp = np.repeat(grey[:, None], 3, axis=1)[None]                       # black → white
    red = np.stack([np.linspace(40, 255, 18), np.full(18, 20), np.full(18, 20)], -1).round().astype(np.uint8)[None]
    sep = separate_image(separator, np.concatenate([ramp, red]))
    cov = sep.coverages[..., 0]
    # the mapped lightness range reaches the solid's L* (the print's black: its darkest colour)
    black, white = sep.report.lightness_range
    assert black < solid_l + 1.0 and white == pytest.approx(100.0, abs=0.5), (black, solid_l)
    assert sep.printed_lab[0, 0, 0] < solid_l + 1.0                          # the image's black prints solid-dark
    # a non-blank separation whose coverage rises with the image's darkness
    assert cov[0, 0] > 0.8 and cov[0, -1] < 0.02
    assert np.all(np.diff(cov[0]) <= 1e-3), np.diff(cov[0])                  # grey ramp: less ink as it lightens
    assert np.all(np.diff(cov[1]) <= 1e-3), np.diff(cov[1])                  # a coloured ramp too
    assert np.all(np.diff(sep.printed_lab[0, :, 0]) >= -0.02)                # and prints monotone in L*
