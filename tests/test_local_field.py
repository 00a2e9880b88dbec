"""The pigments' local field (docs/polarisation.md, "Local field"): depolarisation factors against
their integral definition, orientation weights against sampled axes, and each layer of a stack
computed with its own grains' field."""

import dataclasses

import numpy as np
import pytest

from solver.geometry import eps_grid, parse_particles
from solver.geometry.depolarisation import local_field_of, mean_axis_z_squared, spheroid_axial_factor
from solver.geometry.orientation import sample_orientations
from solver.geometry.stacking import split_cells
from solver.materials import SPHERE_FIELD, LocalField, default_materials, local_field_eps
from solver.table.request import table_request
from solver.table.wave_tier import GeometryUnit, cell_eps, geometry_unit

from oracles import depolarisation_integral


@pytest.mark.parametrize("aspect", [0.2, 0.5, 0.999, 1.0, 1.001, 2.0, 3.0, 10.0])
def test_spheroid_factor_is_the_integral(aspect):
    axial = spheroid_axial_factor(aspect)
    assert axial == pytest.approx(depolarisation_integral(aspect, 1.0, 1.0), rel=1e-7)
    assert 0.5 * (1 - axial) == pytest.approx(depolarisation_integral(1.0, aspect, 1.0), rel=1e-7)


@pytest.mark.parametrize("spec", ["cylinder:100", "cylinder:100:vertical", "cylinder:100:inplane",
                                  "cylinder:100:vertical:tilt=30", "cylinder:100:inplane:tilt=20"])
def test_axis_weights_match_the_sampled_orientations(spec):
    p = parse_particles(spec)
    axes = sample_orientations(p.orientation, 200_000, np.random.default_rng(3), p.tilt_rad)
    assert mean_axis_z_squared(p) == pytest.approx(np.mean(axes[:, 2] ** 2), abs=3e-3)
    field = local_field_of(p)
    # unpolarised in-plane field e: weight of the axis = ⟨(e·a)²⟩ = ⟨a_x² + a_y²⟩ / 2
    assert field.pairs[0][0] == pytest.approx(0.5 * np.mean(1 - axes[:, 2] ** 2), abs=3e-3)
    assert sum(w for w, _ in field.pairs) == pytest.approx(1.0)


def test_shapes_order_the_response_as_physics_says():
    """The pigment is optically thinner than the binder (Re ε_p < ε_h): a field along a needle
    (small L) sees the bulk contrast, across it the depolarised one; a sphere lies between.
    Isotropic cylinders average the three axes; vertical columns see only the cross field."""
    eps_h, eps_p = 1.558**2 + 0j, (1.4 + 0.3j) ** 2
    needle = local_field_eps(eps_p, eps_h, LocalField(((1.0, 0.0),)))
    assert needle == pytest.approx(eps_p)                        # L = 0: no depolarisation
    sphere = local_field_eps(eps_p, eps_h)
    assert sphere == pytest.approx(eps_h + 3 * eps_h * (eps_p - eps_h) / (eps_p + 2 * eps_h))
    vertical = local_field_eps(eps_p, eps_h, local_field_of(parse_particles("cylinder:100:vertical")))
    inplane = local_field_eps(eps_p, eps_h, local_field_of(parse_particles("cylinder:100:inplane")))
    assert vertical.imag > sphere.imag > inplane.imag > eps_p.imag  # L⊥ 0.446 > 1/3 > mix of L∥ 0.109
    with pytest.raises(ValueError):
        LocalField(((0.5, 0.3),))


def test_stack_cells_take_each_layers_field():
    req = table_request("Y15/Y15", "cylinder:100:vertical/sphere:100", grid=(16, 16, 8), realizations=1)
    vox = geometry_unit(GeometryUnit(req, 0))
    eps = cell_eps(req, vox, 450.0)
    cells = split_cells([l.thickness_nm for l in req.layers], 8)
    top = dataclasses.replace(vox, fractions=vox.fractions[..., :cells[0]])
    bottom = dataclasses.replace(vox, fractions=vox.fractions[..., cells[0]:])
    data = default_materials()
    np.testing.assert_allclose(eps[..., :cells[0]],
                               eps_grid(top, 450.0, data.with_local_field(local_field_of(req.layers[0].particles))))
    np.testing.assert_allclose(eps[..., cells[0]:], eps_grid(bottom, 450.0, data.with_local_field(SPHERE_FIELD)))
    plain = table_request("Y15/Y15", "cylinder:100:vertical/sphere:100", grid=(16, 16, 8), realizations=1,
                          local_field=False)
    np.testing.assert_allclose(cell_eps(plain, vox, 450.0), eps_grid(vox, 450.0, data))


def test_dissolved_mixes_are_one_material_grains_of_a_mix_are_not():
    """A molecular G30 and Y15+B15 share one key, so they must be one material with the local
    field too (each base pigment's molecules in their own cavity); a G grain polarises as one
    body of the Y–B mix, unlike separate Y and B grains."""
    from solver.inks import molecular_eps

    wl = np.linspace(400.0, 700.0, 7)
    g, yb = table_request("G30"), table_request("Y15+B15")
    assert g.key() == yb.key()
    np.testing.assert_allclose(molecular_eps(g.layer.ink, wl, g.layer_materials()),
                               molecular_eps(yb.layer.ink, wl, yb.layer_materials()), rtol=1e-13)
    gg, ybg = table_request("G30", "sphere:100"), table_request("Y15+B15", "sphere:100")
    assert gg.key() != ybg.key()
    assert np.max(np.abs(molecular_eps(gg.layer.ink, wl, gg.layer_materials())
                         - molecular_eps(ybg.layer.ink, wl, ybg.layer_materials()))) > 1e-4


@pytest.mark.parametrize("field", [SPHERE_FIELD, local_field_of(parse_particles("cylinder:100:vertical")),
                                   local_field_of(parse_particles("cylinder:100:inplane:tilt=30"))])
def test_local_field_stays_passive_and_finite_for_any_absorption(field):
    """Strong absorption (k up to 5, Re ε_p < 0) and transparent grains: ε' is finite and never
    gains energy (Im ε' ≥ 0; = 0 for a lossless grain), the denominators ε_h + L(ε_p − ε_h)
    never vanish for a passive pigment in a real binder."""
    eps_h = 1.558**2 + 0j
    k = np.concatenate([[0.0], np.geomspace(1e-6, 5.0, 400)])
    eps_p = (1.4 + 1j * k) ** 2
    eps = local_field_eps(eps_p, eps_h, field)
    assert np.all(np.isfinite(eps)) and np.all(eps.imag >= 0) and eps[0].imag == 0
    assert np.all(np.diff(eps.imag[k < 0.5]) > 0)          # more pigment loss, more layer loss
