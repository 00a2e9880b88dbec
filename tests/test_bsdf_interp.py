"""Dr.Jit lookups of the `ink` BSDF: exact piecewise-linear interpolation, clamping, no NaN."""

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator


def _np(x):
    return np.asarray(x, dtype=np.float64)


@pytest.mark.parametrize("nodes", [np.linspace(380.0, 780.0, 41),
                                   np.array([0.0, 0.1, 0.15, 0.5, 0.52, 1.2, 1.5707963]),
                                   np.array([2.0, 3.0])])
def test_axis_locate_matches_numpy(use_variant, nodes):
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.interp import Axis

    axis = Axis(nodes)
    assert axis.uniform == bool(np.allclose(np.diff(nodes), np.diff(nodes)[0]))
    span = nodes[-1] - nodes[0]
    x = np.concatenate([np.linspace(nodes[0] - 0.1 * span, nodes[-1] + 0.1 * span, 5001), nodes])
    i, t = axis.locate(mi.Float(x))
    i, t = _np(i).astype(int), _np(t)
    assert np.all((i >= 0) & (i <= nodes.size - 2)) and np.all((t >= 0) & (t <= 1))
    got = (1 - t) * nodes[i] + t * nodes[i + 1]
    np.testing.assert_allclose(got, np.clip(x, nodes[0], nodes[-1]), atol=2e-6 * max(1.0, abs(nodes[-1])))
    values = np.sin(3 * nodes)                              # interpolating any column is exact
    np.testing.assert_allclose((1 - t) * values[i] + t * values[i + 1],
                               np.interp(x, nodes, values), atol=1e-5)


def test_axis_maps_nan_into_the_grid(use_variant):
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.interp import Axis

    for nodes in (np.linspace(0, 1, 5), np.array([0.0, 0.2, 0.7, 1.0])):
        i, t = Axis(nodes).locate(mi.Float([np.nan, np.inf, -np.inf]))
        assert np.all(np.isfinite(_np(t))) and np.all(_np(i) <= nodes.size - 2)


def test_node_table_multilinear(use_variant):
    mi = use_variant("llvm_ad_spectral")
    from inkbsdf.interp import Axis, NodeTable

    rng = np.random.default_rng(0)
    grids = [np.linspace(380, 780, 6), np.array([0.0, 0.3, 0.4, 1.0, 1.5707963]), np.linspace(0, np.pi, 4)]
    values = rng.random((6, 5, 4, 3))
    table = NodeTable(values)
    pts = [rng.uniform(g[0], g[-1], 2000) for g in grids]
    coords = [Axis(g).locate(mi.Float(p)) for g, p in zip(grids, pts)]
    for c in range(3):
        want = RegularGridInterpolator(grids, values[..., c])(np.stack(pts, axis=-1))
        got = _np(table.lerp(coords, channels=(c,))[0])
        np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-6)
