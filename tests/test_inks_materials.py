"""Ink spec parsing, pigment spectra and the molecular mixing rule."""

import numpy as np
import pytest

from conftest import PAPER_INKS
from solver.inks import InkSpecError, molecular_eps, parse_ink
from solver.materials import BINDER_INDEX, pigment_eps, pigment_k


@pytest.mark.parametrize("spec", PAPER_INKS)
def test_paper_inks_parse_and_round_trip(spec):
    ink = parse_ink(spec)
    assert ink.label == spec
    assert parse_ink(ink.label) == ink
    assert 0.0 < ink.total_fraction <= 0.5 + 1e-12


def test_clear_is_binder_only():
    ink = parse_ink("clear")
    assert ink.components == () and ink.label == "clear"
    np.testing.assert_allclose(molecular_eps(ink, [400, 700]), BINDER_INDEX**2)


@pytest.mark.parametrize("spec, words", [
    ("X10", ["unknown pigment", "'X'"]),
    ("R-5", ["negative", "R"]),
    ("R60+B50", ["110%", "exceeds 100%"]),
    ("R", ["bad ink term"]),
    ("", ["empty"]),
    ("R10+R5", ["twice"]),
])
def test_bad_inks_give_one_clear_error(spec, words):
    with pytest.raises(InkSpecError) as info:
        parse_ink(spec)
    for word in words:
        assert word in str(info.value)


def test_pigment_spectra_match_the_data_readme_key_numbers():
    # Independent numbers from shared/data/pigments/README.md ("Key numbers in 380–780 nm").
    assert pigment_k("R", 530) == pytest.approx(0.79, abs=0.02)
    assert pigment_k("Y", 465) == pytest.approx(0.38, abs=0.02)
    assert pigment_k("B", 690) == pytest.approx(0.88, abs=0.02)
    assert pigment_k("Y", 600) < 1e-3            # F8BT transparent in the red
    # clamped outside the tabulated range
    assert pigment_k("R", 300) == pigment_k("R", 360)
    assert pigment_k("B", 900) == pigment_k("B", 830)


def test_green_is_the_molecular_mix_and_equals_y_plus_b_molecular():
    wl = np.linspace(380, 780, 9)
    np.testing.assert_allclose(pigment_eps("G", wl), 0.5 * (pigment_eps("Y", wl) + pigment_eps("B", wl)))
    np.testing.assert_allclose(molecular_eps(parse_ink("G30"), wl), molecular_eps(parse_ink("Y15+B15"), wl))


def test_mixing_rule_is_linear_in_eps():
    wl = np.array([450.0, 550.0])
    eps = molecular_eps(parse_ink("R20"), wl)
    expected = 0.8 * BINDER_INDEX**2 + 0.2 * (1.4 + 1j * pigment_k("R", wl)) ** 2
    np.testing.assert_allclose(eps, expected)
    assert np.all(eps.imag >= 0)
