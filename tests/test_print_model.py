"""The NumPy reference model of printed colour (solver.printing): Demichel weights, Clapper–Yule
against an independent formula, dot gain in CIELAB, several inks with overprints, energy."""

import numpy as np
import pytest

from oracles import CY, MD, cos_mean
from printing_tables import SIGMA_RAD, WAVELENGTHS_NM, film, incoherent_stack, stack_of
from solver.colour import lab_hue_chroma, spectra_to_lab
from solver.printing import (PrintedInks, ReflectancePredictor, all_subsets, brdf_smooth, demichel_weights,
                             directional_albedo, reflectance, specular_reflectance, stack_order)
from solver.table.evaluate import diffuse_brdf
from solver.table.evaluate import directional_albedo as table_albedo


@pytest.fixture(scope="module")
def films():
    return {ink: film(ink) for ink in ("R30", "Y30", "B30", "clear", "G30")}


def printed_with_stacks(tables):
    """PrintedInks with every overprint, stacked incoherently in printing order."""
    return PrintedInks.from_provider(tables, lambda s: stack_of([tables[i] for i in stack_order(s)]))


def test_demichel_weights():
    c = np.array([0.2, 0.7, 0.5])
    w = demichel_weights(c)
    subsets = all_subsets(3)
    assert subsets[0] == () and len(subsets) == 8
    np.testing.assert_allclose(w.sum(), 1.0, rtol=1e-15)
    assert w[subsets.index(())] == pytest.approx(0.8 * 0.3 * 0.5)
    assert w[subsets.index((0, 2))] == pytest.approx(0.2 * 0.3 * 0.5)
    assert w[subsets.index((0, 1, 2))] == pytest.approx(0.2 * 0.7 * 0.5)
    batch = demichel_weights(np.random.default_rng(0).random((5, 7, 4)))
    assert batch.shape == (5, 7, 16)
    np.testing.assert_allclose(batch.sum(-1), 1.0, rtol=1e-14)
    np.testing.assert_allclose(demichel_weights([[0.3]]), [[0.7, 0.3]])
    assert stack_order((0, 2, 3)) == (3, 2, 0)


@pytest.mark.parametrize("ink", ["R30", "Y30", "B30"])
def test_clapper_yule_matches_independent_formula(films, ink):
    """Albedo at c = 0.5 against r(cT̄(σ)+1−c)(cτ̄+1−c)/(1−rcρ̄) + cR_spec, integrals by trapezoid."""
    t = films[ink]
    c, r = 0.5, 0.85
    rho = cos_mean(t.sigma, t.Rbar_below)[:, None]
    tau = cos_mean(t.sigma, t.Tbar)[:, None]
    want = c * t.R_spec + r * (c * t.Tbar + 1 - c) * (c * tau + 1 - c) / (1 - r * c * rho)
    got = directional_albedo(PrintedInks((t,)), [c], r, t.sigma, CY)
    np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-10)
    md = c * (t.R_spec + r * t.Tbar * tau / (1 - r * rho)) + (1 - c) * r
    np.testing.assert_allclose(directional_albedo(PrintedInks((t,)), [c], r, t.sigma, MD), md,
                               rtol=1e-8, atol=1e-10)


@pytest.mark.parametrize("model", [CY, MD])
def test_full_and_no_coverage_are_eq4(films, model):
    """c = 1 is the ink's eq. (4) (solver.table.evaluate), c = 0 bare paper, in either model."""
    t = films["G30"]
    sig = np.radians([0.0, 33.0, 71.0, 89.0])
    th = np.radians([12.0, 50.0, 5.0, 80.0])
    p = PrintedInks((t,))
    np.testing.assert_allclose(directional_albedo(p, [1.0], 0.9, sig, model), table_albedo(t, 0.9, sig),
                               rtol=1e-12)
    np.testing.assert_allclose(brdf_smooth(p, [1.0], 0.9, sig, th, 1.0, model),
                               diffuse_brdf(t, 0.9, sig, th, 1.0) / np.pi, rtol=1e-12)
    np.testing.assert_allclose(directional_albedo(p, [0.0], 0.9, sig, model), 0.9, rtol=1e-12)
    np.testing.assert_allclose(brdf_smooth(p, [0.0], 0.9, sig, th, 1.0, model), 0.9 / np.pi, rtol=1e-12)


def test_dot_gain_darker_and_more_saturated(films):
    """At 50 % coverage Clapper–Yule (light crosses the ink on the way in or out) is darker and
    more saturated than Murray–Davies (optical dot gain), and lies between MD at 50 % and 100 %."""
    for ink in ("R30", "Y30", "B30"):
        p = PrintedInks((films[ink],))
        lab = {}
        for name, model, c in (("cy", CY, 0.5), ("md", MD, 0.5), ("full", MD, 1.0)):
            spectrum = directional_albedo(p, [c], 0.9, np.radians(8.0), model)
            lab[name] = spectra_to_lab(WAVELENGTHS_NM, spectrum, "D65", "2")
        chroma = {k: lab_hue_chroma(v)[1] for k, v in lab.items()}
        assert lab["cy"][0] < lab["md"][0] - 0.5, (ink, lab)
        assert chroma["cy"] > chroma["md"] + 1.0, (ink, chroma)
        assert lab["full"][0] < lab["cy"][0] and chroma["cy"] < chroma["full"]


def test_single_ink_in_a_set_of_three(films):
    """With the other coverages 0, three inks give the one ink's result (both models)."""
    tables = (films["R30"], films["Y30"], films["B30"])
    p = printed_with_stacks(tables)
    sig = np.radians([0.0, 40.0, 75.0])
    for model in (CY, MD):
        one = directional_albedo(PrintedInks((tables[1],)), [0.4], 0.9, sig, model)
        np.testing.assert_allclose(directional_albedo(p, [0.0, 0.4, 0.0], 0.9, sig, model), one, rtol=1e-12)


def test_full_overprint_is_the_stack(films):
    """Coverages all 1: the surface is the stack (top = last ink), eq. (4) of the stack table."""
    tables = (films["R30"], films["Y30"], films["B30"])
    p = printed_with_stacks(tables)
    sig = np.radians([0.0, 30.0, 60.0])
    want = table_albedo(stack_of([tables[2], tables[1], tables[0]]), 0.8, sig)
    for model in (CY, MD):
        np.testing.assert_allclose(directional_albedo(p, [1, 1, 1], 0.8, sig, model), want, rtol=1e-12)
    other_order = table_albedo(stack_of(tables), 0.8, sig)
    assert np.max(np.abs(other_order - want)) > 1e-3        # the order matters


def test_white_furnace_and_energy_with_overprints():
    """Lossless clear layers (three thicknesses) and their lossless stacks on white paper reflect
    exactly 1 at any coverages in both models; absorbing inks reflect less."""
    from solver.inks import parse_ink
    from solver.table.thinfilm_tier import build_stack_table

    thick = (700.0, 1000.0, 1500.0)
    clear = tuple(film("clear", h) for h in thick)
    exact = PrintedInks.from_provider(clear, lambda s: build_stack_table(        # coherent multilayers
        [(parse_ink("clear"), thick[i]) for i in stack_order(s)], WAVELENGTHS_NM, SIGMA_RAD))
    rng = np.random.default_rng(4)
    sig = np.radians([0.0, 25.0, 50.0, 80.0])
    for p in (printed_with_stacks(clear), exact):
        for c in rng.random((6, 3)):
            for model in (CY, MD):
                np.testing.assert_allclose(directional_albedo(p, c, 1.0, sig, model), 1.0, atol=1e-9)
    inks = printed_with_stacks((film("R30"), film("Y30"), film("B30")))
    for c in rng.random((6, 3)):
        for model in (CY, MD):
            a = directional_albedo(inks, c, 1.0, SIGMA_RAD, model)
            assert a.max() <= 1.0 + 1e-12 and a.min() > 0.0


@pytest.mark.parametrize("model", [CY, MD])
def test_brdf_integrates_to_albedo_and_is_reciprocal(films, model):
    """∫ f cos θ dω (midpoint rule) + specular = directional albedo; f(σ,θ) = f(θ,σ) with
    asymmetric stacks (R̄_below ≠ R̄)."""
    tables = (films["R30"], films["clear"], films["B30"])
    p = printed_with_stacks(tables)
    c = [0.6, 0.3, 0.5]
    n_th = 4000
    th = (np.arange(n_th) + 0.5) * (np.pi / 2 / n_th)
    for deg in (0.0, 35.0, 70.0):
        s = np.radians(deg)
        f = brdf_smooth(p, c, 0.9, s, th, 0.0, model)            # azimuth-free (no diffuse lobes)
        smooth = 2 * np.pi * np.sum(f * np.cos(th) * np.sin(th), axis=-1) * (np.pi / 2 / n_th)
        want = directional_albedo(p, c, 0.9, s, model) - specular_reflectance(p, c, s)
        np.testing.assert_allclose(smooth, want, rtol=2e-4)
    a, b = np.radians([10.0, 40.0, 85.0]), np.radians([60.0, 5.0, 30.0])
    np.testing.assert_allclose(brdf_smooth(p, c, 0.9, a, b, 1.0, model),
                               brdf_smooth(p, c, 0.9, b, a, 1.0, model), rtol=1e-12)


def test_predictor_matches_albedo(films):
    """The vectorised predictor (coverages [..., k] → spectra [..., nλ]) equals directional_albedo."""
    tables = (films["R30"], films["Y30"], films["B30"])
    p = printed_with_stacks(tables)
    paper = np.linspace(0.8, 0.9, WAVELENGTHS_NM.size)
    view = np.radians(8.0)
    cov = np.random.default_rng(2).random((4, 5, 3))
    for model in (CY, MD):
        for specular in (True, False):
            got = ReflectancePredictor.build(p, paper, view, model, specular=specular)(cov)
            assert got.shape == (4, 5, WAVELENGTHS_NM.size)
            want = np.array([[directional_albedo(p, c, paper, view, model, specular=specular)
                              for c in row] for row in cov])
            np.testing.assert_allclose(got, want, rtol=1e-12)
    five = reflectance(p, cov, 0.9, view, CY, wavelengths_nm=[450.0, 555.0, 655.0])
    assert five.shape == (4, 5, 3)


def test_missing_overprint_is_refused(films):
    p = PrintedInks((films["R30"], films["B30"]))           # no stack table
    assert p.primaries() == ((), (0,), (1,))
    directional_albedo(p, [0.5, 0.0], 0.9, 0.0)             # no overlap: fine
    with pytest.raises(ValueError, match=r"overlap inks \(0, 1\)"):
        directional_albedo(p, [0.5, 0.2], 0.9, 0.0)
    with pytest.raises(ValueError, match="coverage_model"):
        directional_albedo(p, [0.5, 0.0], 0.9, 0.0, "yule-nielsen")
    with pytest.raises(ValueError, match="paper albedo"):
        directional_albedo(p, [0.5, 0.0], 1.5, 0.0)
    with pytest.raises(ValueError, match="2 values"):
        directional_albedo(p, [0.5], 0.9, 0.0)
    with pytest.raises(ValueError, match="at least two"):
        PrintedInks((films["R30"],), {(0,): films["R30"]})
    assert incoherent_stack(films["R30"], films["B30"]).Rbar.shape == films["R30"].Rbar.shape
