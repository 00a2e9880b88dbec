"""Thin-film tables under unpolarised light, TE-only tables, and tables of layer stacks, against
the oracles of oracles.py (the Airy formula with explicit Fresnel r_s, r_p; the characteristic
matrix)."""

import numpy as np
import pytest

from oracles import abeles, airy_slab
from solver.inks import molecular_eps, parse_ink
from solver.table import read_table, write_table
from solver.table.thinfilm_tier import build_stack_table, build_thinfilm_table

WL = np.linspace(380.0, 780.0, 81)
SIGMA = np.linspace(0.0, np.pi / 2, 19)


def airy_film(eps, d, wl, sigma):
    """{s, p}: (r, R, T) of a film of permittivity ε in air (oracles.airy_slab; p: H-field sign)."""
    out = {}
    for name, pol in (("s", "te"), ("p", "tm")):
        r, _, R, T = airy_slab(1.0, np.sqrt(eps + 0j), 1.0, d, wl, sigma, pol)
        out[name] = (r, R, T)
    return out


def test_clear_varnish_is_the_unpolarised_airy_film():
    table = build_thinfilm_table(parse_ink("clear"), 1000.0, WL, SIGMA, polarisation="unpolarised")
    film = airy_film(1.558**2, 1000.0, WL[:, None], SIGMA[None, :])
    s, p = film["s"], film["p"]
    assert table.polarisation == "unpolarised" and table.meta["polarisation"] == "unpolarised"
    for name, want in (("R_spec", (s[1] + p[1]) / 2), ("T_coh", (s[2] + p[2]) / 2), ("Rbar", (s[1] + p[1]) / 2),
                       ("Tbar", (s[2] + p[2]) / 2), ("Rbar_below", (s[1] + p[1]) / 2),
                       ("Rbar_s", s[1]), ("Rbar_p", p[1]), ("Tbar_s", s[2]), ("Tbar_p", p[2])):
        np.testing.assert_allclose(getattr(table, name), want, atol=1e-6, err_msg=name)
    # amplitudes in Mitsuba's convention: the complex conjugate of the e^(−iωt) ones
    np.testing.assert_allclose(table.r_s, np.conj(s[0]), atol=1e-6)
    np.testing.assert_allclose(table.r_p, np.conj(p[0]), atol=1e-6)
    # the numbers the brief quotes: 45°, mirror reflectance s vs unpolarised (clear binder)
    i45 = np.argmin(np.abs(SIGMA - np.pi / 4))
    assert np.all(table.Rbar_s[:, i45] > 1.6 * table.R_spec[:, i45])
    np.testing.assert_allclose(table.R_spec + table.Tbar, 1.0, atol=1e-12)   # lossless


@pytest.mark.parametrize("spec", ["R15", "Y7.5+B7.5", "G30", "B50"])
def test_ink_tables_are_the_mean_of_s_and_p(spec):
    ink = parse_ink(spec)
    table = build_thinfilm_table(ink, 1000.0, WL, SIGMA, polarisation="unpolarised")
    film = airy_film(molecular_eps(ink, WL)[:, None], 1000.0, WL[:, None], SIGMA[None, :])
    np.testing.assert_allclose(table.R_spec, (film["s"][1] + film["p"][1]) / 2, atol=1e-6)
    np.testing.assert_allclose(table.Tbar, (film["s"][2] + film["p"][2]) / 2, atol=1e-6)
    np.testing.assert_allclose(table.r_p, np.conj(film["p"][0]), atol=1e-6)
    np.testing.assert_array_equal(table.Rbar_below, table.Rbar)     # one film: up-down symmetric
    assert not table.has_diffuse and np.all(table.R_spec + table.Tbar < 1 + 1e-12)


def old_te_slab(eps, d, wl, sigma):
    """The TE Airy formula exactly as solver.thinfilm.slab evaluated it before polarisation."""
    k0 = 2.0 * np.pi / wl
    k_par = k0 * np.sqrt(complex(1.0)).real * np.sin(sigma)

    def kz(e):
        v = np.sqrt(np.asarray(k0**2 * e - k_par**2, dtype=complex))
        return np.where(v.imag < 0, -v, v)

    def face(a, b):
        a, b = np.broadcast_arrays(a, b)
        den = a + b
        ok = den != 0
        safe = np.where(ok, den, 1.0)
        return np.where(ok, (a - b) / safe, 0.0), np.where(ok, 2.0 * a / safe, 1.0)

    k_in, k_l, k_out = kz(1.0), kz(np.asarray(eps, dtype=complex)), kz(1.0)
    r01, t01 = face(k_in, k_l)
    r12, t12 = face(k_l, k_out)
    phase = np.exp(1j * k_l * d)
    denom = 1.0 + r01 * r12 * phase**2
    r = (r01 + r12 * phase**2) / denom
    t = t01 * t12 * phase / denom
    ratio = np.divide(k_out.real, k_in.real, out=np.zeros(np.broadcast(k_out, k_in).shape), where=k_in.real > 0)
    return np.abs(r) ** 2, ratio * np.abs(t) ** 2


@pytest.mark.parametrize("spec", ["clear", "R15", "Y7.5+B7.5", "G50", "B50"])
def test_te_mode_is_the_old_table_exactly(spec):
    ink = parse_ink(spec)
    table = build_thinfilm_table(ink, 1000.0, WL, SIGMA, polarisation="te")
    R, T = old_te_slab(molecular_eps(ink, WL)[:, None], 1000.0, WL[:, None], SIGMA[None, :])
    for name, want in (("R_spec", R), ("Rbar", R), ("Rbar_below", R), ("T_coh", T), ("Tbar", T)):
        np.testing.assert_array_equal(getattr(table, name), want, err_msg=name)
    assert table.meta["polarisation"] == "te" and table.sp_arrays == {}


def test_stack_table_against_the_characteristic_matrix_from_both_sides():
    """Y15 printed over B15: Rbar from above, Rbar_below from the paper side (they differ),
    one Tbar for both directions (reciprocity), s and p parts."""
    y, b = parse_ink("Y15"), parse_ink("B15")
    wl = np.array([420.0, 500.0, 560.0, 650.0, 740.0])
    table = build_stack_table([(y, 600.0), (b, 400.0)], wl, SIGMA, polarisation="unpolarised")
    assert table.meta["ink"] == "Y15/B15" and table.meta["thickness_nm"] == [600.0, 400.0]
    assert table.meta["pigments"] == [[["Y", 0.15]], [["B", 0.15]]]
    eps = [molecular_eps(y, wl), molecular_eps(b, wl)]
    for i, w in enumerate(wl):
        for j, s in enumerate(SIGMA[:-1]):
            down = {p: abeles([e[i] for e in eps], [600.0, 400.0], w, s, p) for p in ("te", "tm")}
            up = {p: abeles([e[i] for e in eps[::-1]], [400.0, 600.0], w, s, p) for p in ("te", "tm")}
            assert table.Rbar_s[i, j] == pytest.approx(down["te"][1], abs=1e-10)
            assert table.Rbar_p[i, j] == pytest.approx(down["tm"][1], abs=1e-10)
            assert table.r_p[i, j] == pytest.approx(np.conj(down["tm"][0]), abs=1e-10)
            assert table.Tbar[i, j] == pytest.approx((down["te"][2] + down["tm"][2]) / 2, abs=1e-10)
            assert table.Tbar[i, j] == pytest.approx((up["te"][2] + up["tm"][2]) / 2, abs=1e-10)
            assert table.Rbar_below[i, j] == pytest.approx((up["te"][1] + up["tm"][1]) / 2, abs=1e-10)
    assert np.max(np.abs(table.Rbar_below - table.Rbar)) > 1e-3


def test_stack_of_one_layer_and_of_split_layers_is_the_film():
    ink = parse_ink("G30")
    film = build_thinfilm_table(ink, 1000.0, WL, SIGMA, polarisation="unpolarised")
    one = build_stack_table([(ink, 1000.0)], WL, SIGMA, polarisation="unpolarised")
    split = build_stack_table([(ink, 250.0), (ink, 750.0)], WL, SIGMA, polarisation="unpolarised")
    for name in ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below", "r_s", "r_p", "Rbar_p", "Tbar_p"):
        np.testing.assert_array_equal(getattr(one, name), getattr(film, name))
        np.testing.assert_allclose(getattr(split, name), getattr(film, name), atol=1e-13)


def test_stack_tables_round_trip(tmp_path):
    table = build_stack_table([(parse_ink("Y15"), 500.0), (parse_ink("B15"), 500.0)], WL, SIGMA, polarisation="unpolarised")
    back = read_table(write_table(tmp_path / "yb.npz", table))
    for name in ("R_spec", "Rbar_below", "r_s", "r_p", "Rbar_s", "Tbar_p"):
        np.testing.assert_array_equal(getattr(back, name), getattr(table, name))
    assert back.r_s.dtype == np.complex128 and back.meta == table.meta


@pytest.mark.parametrize("call, message", [
    (lambda: build_thinfilm_table(parse_ink("R15"), 1000.0, WL, SIGMA, polarisation="tm"), "polarisation must be one of"),
    (lambda: build_stack_table([], WL, SIGMA), "at least one"),
    (lambda: build_stack_table([(parse_ink("R15"), 500.0), (parse_ink("B15"), 0.0)], WL, SIGMA),
     "thickness must be > 0 nm, got 0.0 for B15"),
])
def test_bad_arguments_are_refused(call, message):
    with pytest.raises(ValueError, match=message):
        call()

