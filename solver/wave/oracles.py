"""Independent reference solutions for validating the wave solver (imports no solver code).

Shared by the tests (tests/test_wave_*.py, which also check these oracles themselves in
tests/test_wave_oracles.py) and the accuracy tables of benchmarks/bench_wave.py:

- airy_te: exact reflection/transmission of a homogeneous slab (scalar = TE), any media.
- mie_scalar_amplitude: exact partial-wave scattering amplitude of a penetrable sphere for
  u'' + k²n²u = 0 (scalar Mie), from scipy.special spherical Bessel functions.
- rcwa_te: rigorous coupled-wave analysis of a lamellar (y-invariant) grating, TE, exact
  Fourier coefficients of the step profile, boundary matching solved as one linear system.
- voxel fractions of spheres (supersampling) and of planar layers (exact), for test grids.

Conventions as the solver's (docs/design.md §1, §4): nm, radians, e^(−iωt), z downward.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import eval_legendre, spherical_jn, spherical_yn


def _kz(k0sq_eps, kt):
    kz = np.sqrt(k0sq_eps - np.asarray(kt) ** 2 + 0j)
    return np.where(np.imag(kz) < 0, -kz, kz)


def airy_te(n_in, n_slab, n_out, d_nm, lam_nm, sigma):
    """(r, t, R, T) of a slab of index n_slab and thickness d between n_in (incidence side) and
    n_out; r referenced to the entry face, t to the exit face; polar angle sigma in n_in."""
    k0 = 2 * math.pi / lam_nm
    kt = k0 * np.real(n_in) * math.sin(sigma)
    k1, k2, k3 = (_kz(k0 ** 2 * n ** 2, kt) for n in (n_in, n_slab, n_out))
    r12, r23 = (k1 - k2) / (k1 + k2), (k2 - k3) / (k2 + k3)
    t12, t23 = 2 * k1 / (k1 + k2), 2 * k2 / (k2 + k3)
    e = np.exp(1j * k2 * d_nm)
    den = 1 + r12 * r23 * e * e
    r, t = (r12 + r23 * e * e) / den, t12 * t23 * e / den
    big_t = (k3.real / k1.real) * abs(t) ** 2 if np.imag(k3) == 0 else 0.0
    return complex(r), complex(t), float(abs(r) ** 2), float(big_t)


def mie_scalar_coefficients(m, x, lmax):
    """Partial-wave coefficients a_l, l = 0 … lmax, of a penetrable sphere in the scalar
    model (u and ∂u/∂r continuous at its surface): size parameter x = k·a in the host, relative
    index m; the scattered wave is Σ (2l + 1) i^l a_l h_l(kr) P_l(cos θ)."""
    ell = np.arange(int(lmax) + 1)
    j, jp = spherical_jn(ell, x), spherical_jn(ell, x, True)
    h = j + 1j * spherical_yn(ell, x)
    hp = jp + 1j * spherical_yn(ell, x, True)
    jm, jmp = spherical_jn(ell, m * x), spherical_jn(ell, m * x, True)
    return (m * jmp * j - jp * jm) / (hp * jm - m * h * jmp)


def mie_scalar_amplitude(m, k, a, cos_theta, lmax=None):
    """Far-field amplitude f(θ) (nm) of a sphere of radius a (nm), relative index m, in a
    medium of wavenumber k (1/nm): u_s → f(θ) e^{ikr}/r for a unit plane wave."""
    x = k * a
    lmax = lmax or int(x + 4 * x ** (1 / 3) + 10)
    coef = mie_scalar_coefficients(m, x, lmax)
    f = sum((2 * ell + 1) * coef[ell] * eval_legendre(ell, cos_theta)
            for ell in range(lmax + 1))
    return -1j / k * f


def rcwa_te(eps_in, eps_out, eps_strip, eps_host, a_nm, b_nm, period_nm, h_nm, lam_nm, sigma,
            n_harm, azimuth=0.0):
    """Lamellar grating: eps_strip on [a, b) (mod period in x), eps_host elsewhere, invariant in
    y, thickness h, under ∇²u + k0²ε(x)u = 0 with incidence from eps_in at polar angle sigma and
    azimuth φ (conical when φ ≠ 0: k_y = const enters as k0²ε − k_y²).
    Returns (m, r_m, t_m, kz_in_m, kz_out_m): amplitudes referenced to the top / bottom face."""
    k0 = 2 * math.pi / lam_nm
    big_m = n_harm
    m = np.arange(-big_m, big_m + 1)
    kt = k0 * math.sqrt(eps_in) * math.sin(sigma)
    ky = kt * math.sin(azimuth)
    kx = kt * math.cos(azimuth) + 2 * math.pi * m / period_nm
    n = np.arange(-2 * big_m, 2 * big_m + 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(n == 0, (b_nm - a_nm) / period_nm,
                     (np.exp(-2j * math.pi * n * b_nm / period_nm)
                      - np.exp(-2j * math.pi * n * a_nm / period_nm)) / (-2j * math.pi * n))
    eps_hat = (eps_strip - eps_host) * c
    eps_hat[2 * big_m] += eps_host
    toep = eps_hat[(m[:, None] - m[None, :]) + 2 * big_m]
    lam_e, w = np.linalg.eig(np.diag(kx ** 2 + ky ** 2) - k0 ** 2 * toep)
    q = np.sqrt(-lam_e + 0j)
    q = np.where(q.imag < 0, -q, q)
    kxy = np.sqrt(kx ** 2 + ky ** 2)
    ka, kc = _kz(k0 ** 2 * eps_in, kxy), _kz(k0 ** 2 * eps_out, kxy)
    x = np.exp(1j * q * h_nm)
    wq, kaw, kcw = w * q, ka[:, None] * w, kc[:, None] * w
    inc = (m == 0).astype(complex)
    system = np.block([[wq + kaw, (-wq + kaw) * x[None, :]],
                       [(wq - kcw) * x[None, :], -wq - kcw]])
    sol = np.linalg.solve(system, np.concatenate([2 * ka * inc, np.zeros(len(m))]))
    up, down = sol[:len(m)], sol[len(m):]
    return m, w @ (up + x * down) - inc, w @ (x * up + down), ka, kc


def layer_fraction(z_edges_lo, z_edges_hi, top_nm, bottom_nm):
    """Exact fraction of each z-cell [lo, hi) inside the layer [top, bottom]."""
    lo, hi = np.asarray(z_edges_lo, float), np.asarray(z_edges_hi, float)
    return np.clip(np.minimum(hi, bottom_nm) - np.maximum(lo, top_nm), 0, None) / (hi - lo)


def sphere_fractions(centres, radius, period, z_range, shape, ss=4):
    """Volume fraction of voxels inside any of the spheres (lateral periodic), by ss³ samples
    per voxel; overlapping spheres are counted once."""
    nx, ny, nz = shape
    z0, z1 = z_range
    dx, dy, dz = period[0] / nx, period[1] / ny, (z1 - z0) / nz
    o = (np.arange(ss) + 0.5) / ss
    xs = ((np.arange(nx)[:, None] + o) * dx).ravel()
    ys = ((np.arange(ny)[:, None] + o) * dy).ravel()
    zs = z0 + ((np.arange(nz)[:, None] + o) * dz).ravel()
    inside = np.zeros((nx * ss, ny * ss, nz * ss), dtype=bool)
    for c in np.atleast_2d(centres):
        ddx = xs - c[0]
        ddx -= period[0] * np.round(ddx / period[0])
        ddy = ys - c[1]
        ddy -= period[1] * np.round(ddy / period[1])
        inside |= (ddx[:, None, None] ** 2 + ddy[None, :, None] ** 2
                   + (zs - c[2])[None, None, :] ** 2) <= radius ** 2
    return inside.reshape(nx, ss, ny, ss, nz, ss).mean(axis=(1, 3, 5))


def random_spheres(rng, n, period, z_range, radius):
    """n sphere centres, uniformly random (overlaps allowed), fully inside the z-range."""
    lo = [0.0, 0.0, z_range[0] + radius]
    hi = [period[0], period[1], z_range[1] - radius]
    return rng.uniform(lo, hi, size=(n, 3))
