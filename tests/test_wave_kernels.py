"""The exact z-integrals of the layered Green's function against brute-force quadrature.

The oracle is the Green's function written out from its definition (oracles.layered_green: a
point source in a slab with the two interface reflections, summed as a geometric series),
integrated with scipy.integrate.quad; it shares no code with solver/wave/kernel1d.py.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning

from oracles import complex_quad, layered_green
from solver.wave import zbasis
from solver.wave.kernel1d import (background_amplitudes, circulant_blocks, face_profiles,
                                  face_weights, slab_green, vertical_wavenumber)


PHI = [lambda t: 1.0 + 0 * t, lambda t: math.sqrt(3) * (2 * t - 1)]
# quad warns about round-off when a part is ~1e-17 of the whole; the asserted tolerances
# (1e-12 absolute, 1e-10 relative) are what counts.
pytestmark = pytest.mark.filterwarnings("ignore", category=IntegrationWarning)


@pytest.mark.parametrize("x", [1e-3 + 0.02j, -0.1 + 0.45j, -0.2 + 0.6j, -3 + 0.5j, -0.51, 2j])
def test_basis_integrals_match_quadrature(x):
    xa = np.array([x])
    ints = zbasis.single_integrals(xa, 2)
    for q in range(2):
        assert abs(ints[q][0] - complex_quad(lambda t: PHI[q](t) * np.exp(x * t), 0, 1)) < 1e-13
    for p in range(2):
        for q in range(2):
            for sgn in (1, -1):
                got = zbasis.diag_galerkin(p, q, sgn * xa, np.ones(1, complex), np.exp(sgn * xa))[0]
                ref = complex_quad(lambda t: complex_quad(lambda s: PHI[p](t) * PHI[q](s)
                                            * np.exp(sgn * x * abs(t - s)), 0, 1, [t]), 0, 1)
                assert abs(got - ref) < 1e-12
    for tau in (0.0, 0.3, 1.0):
        for q in range(2):
            lq, rq = zbasis.diag_point(q, tau, xa)
            ref = complex_quad(lambda s: PHI[q](s) * np.exp(x * abs(tau - s)), 0, 1, [tau])
            assert abs(lq[0] + rq[0] - ref) < 1e-12


def test_green_oracle_solves_the_layered_problem():
    """g'' + κ²g = 0 off the source, g′ jumps by −1, outgoing/decaying conditions at both faces
    (checked by finite differences on the oracle, so the kernel tests rest on physics)."""
    k0, big_h = 2 * math.pi / 500, 300.0
    for kt in (0.3 * k0, 1.2 * k0):
        kap = complex(np.sqrt(k0 ** 2 * (2.3 + 0.3j) - kt ** 2))
        ka, kc = (complex(np.sqrt(k0 ** 2 * e - kt ** 2 + 0j)) for e in (1.0, 1.2))
        ka, kc = (k if k.imag >= 0 else -k for k in (ka, kc))
        g = layered_green(kap, ka, kc, big_h)
        zp, d = 110.0, 0.1
        for z in (40.0, 200.0):
            second = (g(z + d, zp) - 2 * g(z, zp) + g(z - d, zp)) / d ** 2
            assert abs(second + kap ** 2 * g(z, zp)) < 1e-6 * abs(kap ** 2 * g(z, zp))

        def slope(z, step):  # one-sided, second order
            return (-3 * g(z, zp) + 4 * g(z + step, zp) - g(z + 2 * step, zp)) / (2 * step)
        jump = slope(zp, d) - slope(zp, -d)
        assert jump == pytest.approx(-1.0, abs=1e-4)
        # above: u ∝ e^{−i ka z} ⇒ u′ = −i ka u at z = 0;  below: u′ = i kc u at z = H
        assert slope(0.0, d) == pytest.approx(-1j * ka * g(0.0, zp), rel=1e-4)
        assert slope(big_h, -d) == pytest.approx(1j * kc * g(big_h, zp), rel=1e-4)


@pytest.mark.parametrize("kt_over_k0", [0.3, 1.0, 3.0])
def test_galerkin_and_point_kernels_match_quadrature(kt_over_k0):
    k0, big_h, nz = 2 * math.pi / 500, 300.0, 3
    h = big_h / nz
    kt2 = np.array([(kt_over_k0 * k0) ** 2])
    kap = vertical_wavenumber(k0 ** 2 * (2.3 + 0.3j), kt2)
    ka = vertical_wavenumber(k0 ** 2 * 1.0, kt2)
    kc = vertical_wavenumber(k0 ** 2 * 1.2, kt2)
    sg = slab_green(kap, ka, kc, big_h, nz, 2)
    g = layered_green(kap[0], ka[0], kc[0], big_h)
    phi = [lambda z, l: 1.0, lambda z, l: math.sqrt(3) * (2 * (z / h - l) - 1)]
    blocks = {(p, q): (t[0], hk[0]) for p, q, t, hk in circulant_blocks(sg)}
    scale = 0.0
    worst = 0.0
    for (p, q), (toe, han) in blocks.items():
        for k in range(nz):
            for l in range(nz):
                got = toe[(k - l) % (2 * nz)] + han[k + l]
                ref = complex_quad(lambda z: phi[p](z, k) * complex_quad(
                    lambda zp: g(z, zp) * phi[q](zp, l), l * h, (l + 1) * h,
                    [z] if l * h < z < (l + 1) * h else None), k * h, (k + 1) * h) / h
                worst, scale = max(worst, abs(got - ref)), max(scale, abs(ref))
    assert worst < 1e-10 * scale
    s = 0.3 * h
    for _, q, toe, han in circulant_blocks(sg, s):
        for k in range(nz):
            for l in range(nz):
                got = toe[0, (k - l) % (2 * nz)] + han[0, k + l]
                ref = complex_quad(lambda zp: g(k * h + s, zp) * phi[q](zp, l), l * h, (l + 1) * h,
                            [k * h + s] if l == k else None)
                assert abs(got - ref) < 1e-10 * scale
    ptop, pbot = face_profiles(sg)
    ctop, cbot = face_weights(sg)
    for q in range(2):
        for l in range(nz):
            assert abs(ctop[0] * ptop[q, 0, l] - complex_quad(
                lambda zp: g(0.0, zp) * phi[q](zp, l), l * h, (l + 1) * h)) < 1e-10 * scale
            assert abs(cbot[0] * pbot[q, 0, l] - complex_quad(
                lambda zp: g(big_h, zp) * phi[q](zp, l), l * h, (l + 1) * h)) < 1e-10 * scale


def test_background_amplitudes_are_airy():
    """The background's response (slab ε_b between two half-spaces) is the Airy formula."""
    from solver.wave.oracles import airy_te
    k0, big_h, sigma = 2 * math.pi / 600, 250.0, 0.5
    eps_b = (1.5 + 0.1j) ** 2
    kt2 = np.array([(k0 * math.sin(sigma)) ** 2])
    kap = vertical_wavenumber(k0 ** 2 * eps_b, kt2)
    ka = vertical_wavenumber(k0 ** 2 * 1.0, kt2)
    kc = vertical_wavenumber(k0 ** 2 * 1.0, kt2)
    sg = slab_green(kap, ka, kc, big_h, 4, 2)
    _, refl, trans = background_amplitudes(sg, from_below=False)
    r, t, _, _ = airy_te(1.0, 1.5 + 0.1j, 1.0, big_h, 600.0, sigma)
    assert abs(refl[0] - r) < 1e-13 and abs(trans[0] - t) < 1e-13


def test_wood_anomaly_wavenumber_is_exactly_zero():
    k0 = 2 * math.pi / 600
    kt = k0 * (1 - 1e-15)
    kz = vertical_wavenumber(k0 ** 2, np.array([kt ** 2, (2 * k0) ** 2]))
    assert kz[0] == 0 and kz[1].imag > 0 and kz[1].real == 0
