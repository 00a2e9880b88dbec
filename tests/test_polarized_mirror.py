"""The `ink` BSDF in Mitsuba's polarized variants: the mirror lobe's Mueller matrix.

Oracles, all outside the plugin: Mitsuba's own `conductor` plugin (its C++ Mueller matrix and
Stokes-frame rotation) for a table of one binder face; for the clear film, the Airy sum of
Mitsuba's `fresnel_polarized` face amplitudes turned into a Mueller matrix by the textbook Jones →
Mueller map (pinned to `mi.mueller.specular_reflection` here) and rotated into the Stokes bases
with `mi.mueller.rotate_mueller_basis` as Mitsuba's specular plugins do; and the spectral
(unpolarized) variant for the intensity M00.
"""

from __future__ import annotations


import numpy as np
import pytest

from bsdf_probes import (POLARIZED, airy_film_amplitudes, as_numpy, at_polar_angles, compare_with_spectral,
                         delta_sample, in_stokes_bases, mitsuba_fresnel, surface_interaction, vector)
from conftest import BREWSTER_DEG, N_BINDER, interface_table
from oracles import jones_to_mueller
from solver.table import write_table
from solver.table.builder import build_table
from solver.table.request import table_request

FILM_NM = 1000.0


@pytest.fixture(scope="module")
def clear_table():
    """The exact Airy film of clear binder (1000 nm), unpolarised: (InkTable, path)."""
    table = build_table(table_request("clear", polarisation="unpolarised"))
    assert table.polarisation == "unpolarised" and table.r_s is not None
    return table


# ------------------------------------------------------------------------------- tests
def test_jones_map_is_mitsubas_specular_reflection(use_variant):
    """The test's Jones → Mueller map of fresnel_polarized's amplitudes is Mitsuba's
    mueller.specular_reflection (dielectric, Brewster, absorbing, total internal reflection)."""
    import drjit as dr

    mi = use_variant(POLARIZED)
    previous = mi.variant()
    cases = [(0.93, 1.558), (np.cos(np.radians(BREWSTER_DEG)), 1.558), (0.5, 1.4 + 0.8j),
             (0.2, 1.5 + 0.05j), (0.6, 1 / 1.558), (0.9, 1 / 1.558)]
    for cos_t, eta in cases:
        a_s, a_p = mitsuba_fresnel(mi, np.array([cos_t]), eta)
        mi.set_variant("scalar_rgb")
        try:
            ref = np.array(mi.mueller.specular_reflection(float(cos_t), dr.scalar.Complex2f(np.real(eta), np.imag(eta))))
        finally:
            mi.set_variant(previous)
        np.testing.assert_allclose(jones_to_mueller(a_s, a_p)[..., 0], ref, atol=2e-6, err_msg=str((cos_t, eta)))


def _both_modes(mi):
    return [(mi.TransportMode.Radiance, True), (mi.TransportMode.Importance, False)]


def test_face_matches_mitsuba_conductor(use_variant, tmp_path):
    """A table of one binder face (σ nodes at the test's angles, Brewster's among them) gives
    exactly the Mueller matrix, directions and frames of Mitsuba's smooth `conductor` with
    η = 1.558, κ = 0, in radiance and importance transport."""
    nodes = [0.0, 10.0, 25.0, 40.0, BREWSTER_DEG, 70.0, 80.0, 89.0, 90.0]
    path = write_table(tmp_path / "face.npz", interface_table(nodes))
    mi = use_variant(POLARIZED)
    ink = mi.load_dict({"type": "ink", "filename": str(path), "paper": 0.9})
    conductor = mi.load_dict({"type": "conductor", "eta": N_BINDER, "k": 0.0})
    rng = np.random.default_rng(3)
    wi = at_polar_angles(np.repeat(nodes[:-1], 6), rng)
    lam = rng.uniform(400.0, 700.0, (4, wi.shape[1]))
    for mode, _ in _both_modes(mi):
        got, wo, pdf = delta_sample(mi, ink, wi, lam, mode)
        ctx = mi.BSDFContext(mode)
        n = wi.shape[1]
        bs, ref = conductor.sample(ctx, surface_interaction(mi, wi, lam), mi.Float(np.full(n, 0.5)),
                                   mi.Point2f(mi.Float(np.full(n, 0.5)), mi.Float(np.full(n, 0.5))))
        ref = as_numpy(mi, ref)
        np.testing.assert_allclose(wo, [np.asarray(bs.wo[i]) for i in range(3)], atol=1e-6)
        np.testing.assert_allclose(pdf, 1.0)
        np.testing.assert_allclose(got, ref, atol=1e-5, err_msg=str(mode))
        assert np.max(np.abs(ref[0, 2])) > 0.02 and np.max(np.abs(ref[2, 3])) < 1e-6   # frames matter
        brewster = np.isclose(np.degrees(np.arccos(wi[2])), BREWSTER_DEG)
        np.testing.assert_allclose(np.hypot(got[0, 1], got[0, 2])[:, brewster], got[0, 0][:, brewster],
                                   rtol=1e-5)                   # fully polarised at Brewster's angle


def test_film_matches_airy_oracle(use_variant, clear_table, tmp_path):
    """The clear 1000-nm film: the delta lobe's Mueller matrix at table nodes equals the Airy
    film of Mitsuba's face amplitudes (Jones → Mueller, rotated into the Stokes bases), in both
    transport modes; between wavelength nodes it is the mean of the neighbours' matrices
    (element-wise linear interpolation, as R_spec is interpolated)."""
    path = write_table(tmp_path / "clear.npz", clear_table)
    mi = use_variant(POLARIZED)
    ink = mi.load_dict({"type": "ink", "filename": str(path), "paper": 0.9})
    rng = np.random.default_rng(5)
    angles = np.repeat([0.0, 20.0, 40.0, 56.0, 58.0, 70.0, 80.0, 88.0], 3)
    nodes = clear_table.wavelengths[(clear_table.wavelengths >= 400) & (clear_table.wavelengths <= 700)]
    assert np.all(np.isin(np.radians(angles), clear_table.sigma) | np.isclose(
        np.radians(angles)[:, None], clear_table.sigma[None, :]).any(axis=1))
    wi = at_polar_angles(angles, rng)
    lam = rng.choice(nodes[:-1], (4, wi.shape[1]))
    step = float(nodes[1] - nodes[0])
    for mode, radiance in _both_modes(mi):
        got, wo, _ = delta_sample(mi, ink, wi, lam, mode)
        oracle = in_stokes_bases(mi, jones_to_mueller(*airy_film_amplitudes(mi, lam, np.radians(angles), FILM_NM, N_BINDER)),
                                 wi, wo, radiance)
        np.testing.assert_allclose(got, oracle, atol=2e-5, err_msg=str(mode))
        assert np.max(np.abs(oracle[2:, 2:] - oracle[0, 0] * np.eye(2)[:, :, None, None])) > 0.05
        mid, _, _ = delta_sample(mi, ink, wi, lam + 0.5 * step, mode)
        ends = [jones_to_mueller(*airy_film_amplitudes(mi, lam + d, np.radians(angles), FILM_NM, N_BINDER)) for d in (0.0, step)]
        mean = in_stokes_bases(mi, 0.5 * (ends[0] + ends[1]), wi, wo, radiance)
        np.testing.assert_allclose(mid, mean, atol=2e-5, err_msg=f"{mode}, between λ nodes")


def test_intensity_equals_spectral_variant(use_variant, clear_table, tmp_path):
    """Clear film on paper 0.9 at coverage 0.7: M00 of eval, eval_pdf and sample equals the
    spectral variant's value on the same lanes (same sampled lobes and directions); the smooth
    lobe's matrix is an ideal depolariser; the mirror lobe's is not."""
    path = write_table(tmp_path / "clear.npz", clear_table)
    w, comp, _ = compare_with_spectral(use_variant, {"type": "ink", "filename": str(path), "paper": 0.9,
                                                     "coverage": 0.7})
    assert np.max(np.abs(w[0, 1:][..., comp == 0])) > 0.05


def test_tables_without_amplitudes_are_refused(use_variant, tmp_path):
    """A 'te' table (s light only, no r_s/r_p) in a polarized variant: one clear error at load,
    naming the table, what is missing and the two ways out; fine in the spectral variant."""
    te = write_table(tmp_path / "te.npz", build_table(table_request("clear", polarisation="te")))
    pol = write_table(tmp_path / "pol.npz", build_table(table_request("R30", polarisation="unpolarised")))
    mi = use_variant("llvm_ad_spectral")
    mi.load_dict({"type": "ink", "filename": str(te)})
    mi = use_variant(POLARIZED)
    for scene in ({"type": "ink", "filename": str(te)},
                  {"type": "ink", "filename1": str(pol), "filename2": str(te), "coverage2": 0.0}):
        with pytest.raises(Exception) as info:
            mi.load_dict(scene)
        message = str(info.value)
        for needle in ("te.npz", "r_s, r_p", "polarisation 'te'", "'unpolarised'", "'llvm_ad_spectral'"):
            assert needle in message, (needle, message)
        assert len(message.splitlines()) <= 4, message               # short, no caller stack


def test_hard_directions_are_finite(use_variant, clear_table, tmp_path):
    """Normal incidence (no plane of incidence), grazing, barely above and below the surface,
    in both transport modes and for either lobe alone: finite Mueller matrices, zero below the
    surface and at grazing incidence, and the mirror exact at normal incidence (b = 0, S = 0)."""
    path = write_table(tmp_path / "clear.npz", clear_table)
    mi = use_variant(POLARIZED)
    bsdf = mi.load_dict({"type": "ink", "filename": str(path), "paper": 0.9, "coverage": 0.9})
    wi = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.6, 0.8, 1e-7], [0.6, 0.8, 1e-4],
                   [0.0, 0.0, -1.0], [0.6, 0.0, -0.8], [0.6, 0.8, -1e-7]]).T
    wi /= np.linalg.norm(wi, axis=0)
    lam = np.tile([[400.0], [500.0], [600.0], [700.0]], (1, wi.shape[1]))
    for mode, _ in _both_modes(mi):
        for mask in (mi.BSDFFlags.DeltaReflection, mi.BSDFFlags.DiffuseReflection, mi.BSDFFlags.All):
            ctx = mi.BSDFContext(mode)
            ctx.type_mask = +mask
            for u in (0.01, 0.5, 0.99):
                n = wi.shape[1]
                si = surface_interaction(mi, wi, lam)
                _, w = bsdf.sample(ctx, si, mi.Float(np.full(n, u)), mi.Point2f(mi.Float(np.full(n, u)),
                                                                             mi.Float(np.full(n, 0.3))))
                f = bsdf.eval(ctx, si, vector(mi, wi[:, [3] * n]))
                w, f = as_numpy(mi, w, n), as_numpy(mi, f, n)
                assert np.all(np.isfinite(w)) and np.all(np.isfinite(f)), (mode, mask, u)
                assert np.all(w[..., [1, 4, 5, 6]] == 0) and np.all(f[..., [1, 4, 5, 6]] == 0)
    normal, _, _ = delta_sample(mi, bsdf, wi[:, :1], lam[:, :1])
    a = normal[0, 0]
    assert np.all(a > 0.01)
    np.testing.assert_allclose(np.abs(normal[1, 1]) + np.abs(normal[1, 2]), a, rtol=1e-5)   # |rotation| · a
    np.testing.assert_allclose(np.abs(normal[3, 3]), a, rtol=1e-5)                            # C = −a, S = 0
    np.testing.assert_allclose(normal[0, 1:], 0.0, atol=1e-7)                                 # b = 0
