"""Energy of the ink-on-paper BRDF (numpy reference evaluator) and colour conversion."""

import numpy as np
import pytest

from solver.inks import parse_ink
from solver.table.evaluate import diffuse_brdf, directional_albedo
from conftest import PAPER_INKS
from solver.table.thinfilm_tier import build_thinfilm_table

WL = np.arange(380.0, 781.0, 20.0)
SIGMA = np.linspace(0, np.pi / 2, 46)


def test_white_furnace_lossless_film_on_white_paper_is_exactly_one():
    table = build_thinfilm_table(parse_ink("clear"), 1000.0, WL, SIGMA)
    albedo = directional_albedo(table, 1.0, np.radians(np.linspace(0, 89, 30)))
    np.testing.assert_allclose(albedo, 1.0, atol=1e-12)


def test_furnace_by_direct_quadrature_of_the_brdf():
    """Integrate the diffuse BRDF numerically over the hemisphere (independent of the weights)."""
    table = build_thinfilm_table(parse_ink("clear"), 1000.0, WL, SIGMA)
    theta = np.linspace(0, np.pi / 2, 4001)
    for sigma in np.radians([0.0, 40.0, 80.0]):
        f = diffuse_brdf(table, 1.0, sigma, theta, 0.0)               # π f, azimuth-independent
        diffuse = np.trapezoid(2 * f * np.cos(theta) * np.sin(theta), theta, axis=-1)
        spec = np.array([np.interp(sigma, table.sigma, row) for row in table.R_spec])
        np.testing.assert_allclose(diffuse + spec, 1.0, atol=2e-6)


@pytest.mark.parametrize("spec", PAPER_INKS + ["clear"])
def test_energy_at_most_one_for_every_ink(spec):
    table = build_thinfilm_table(parse_ink(spec), 1000.0, WL, SIGMA)
    albedo = directional_albedo(table, 1.0, SIGMA)
    assert np.all(albedo <= 1 + 1e-12) and np.all(albedo > 0)
