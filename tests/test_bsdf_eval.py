"""`ink` BSDF eval: against an independent NumPy/SciPy evaluation of DESIGN.md §1 (one ink, both
coverage models), reciprocity."""

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from conftest import surface_interaction
from solver.table import read_table

N_LANES = 4096


def _hemisphere(rng, n, lower_fraction=0.0):
    """Random unit vectors [3, n]; a fraction of them below the surface."""
    v = rng.normal(size=(3, n))
    v /= np.linalg.norm(v, axis=0)
    v[2] = np.abs(v[2])
    v[2, : int(lower_fraction * n)] *= -1.0
    return v


def _cos_mean(sigma, column):
    """2∫ f(s) cos s sin s ds of a piecewise-linear column, by a fine trapezoid (independent)."""
    s = np.linspace(0.0, np.pi / 2, 200001)
    vals = np.array([np.interp(s, sigma, row) for row in column])
    w = 2.0 * np.cos(s) * np.sin(s)
    return np.trapezoid(vals * w, s, axis=-1)


MODELS = ("clapper-yule", "murray-davies")


def ink_bsdf(mi, path, paper, coverage, model):
    return mi.load_dict({"type": "ink", "filename": str(path), "paper": paper, "coverage": coverage,
                         "coverage_model": model})


def reference_eval(table, wi, wo, lam, coverage, paper, model="clapper-yule"):
    """f(ωi, ωo)·cos θo of the smooth lobes, [4, N], written from DESIGN.md §1 with SciPy.

    Murray–Davies: c·f_ink + (1 − c)·r/π. Clapper–Yule: light enters through ink (c, ×T̄(σ)) or
    bare paper (1 − c), the paper's bounces see c·ρ̄, light leaves through ink (c, ×T̄(θ)) or not:
    c·R/π + r·(c T̄(σ) + 1 − c)(c T̄(θ) + 1 − c)/(π(1 − r c ρ̄))."""
    wl, sig = table.wavelengths, table.sigma
    lam = np.clip(lam, wl[0], wl[-1])
    s_i = np.arccos(np.clip(wi[2], 0, 1))       # below the surface: zeroed at the end
    s_o = np.arccos(np.clip(wo[2], 0, 1))
    grid2 = (wl, sig)
    t_in = RegularGridInterpolator(grid2, table.Tbar)((lam, np.broadcast_to(s_i, lam.shape)))
    t_out = RegularGridInterpolator(grid2, table.Tbar)((lam, np.broadcast_to(s_o, lam.shape)))
    rho = np.interp(lam, wl, _cos_mean(sig, table.Rbar_below))
    c = coverage
    if model == "murray-davies":
        f = c * paper * t_in * t_out / (1 - paper * rho) / np.pi + (1 - c) * paper / np.pi
    else:
        f = paper * (c * t_in + 1 - c) * (c * t_out + 1 - c) / (1 - paper * c * rho) / np.pi
    if table.has_diffuse:
        phi_i, phi_o = np.arctan2(wi[1], wi[0]), np.arctan2(wo[1], wo[0])
        dphi = np.abs(np.angle(np.exp(1j * (phi_i - phi_o))))           # folded into [0, π]
        pts = [np.broadcast_to(x, lam.shape) for x in (s_i, s_o, dphi)]
        R = RegularGridInterpolator((wl, sig, table.theta, table.dphi), table.R)((lam, *pts))
        f = f + coverage * R / np.pi
    ok = (wi[2] > 0) & (wo[2] > 0)
    return np.where(ok, f * np.clip(wo[2], 0, None), 0.0)


def _eval(mi, bsdf, wi, wo, lam):
    import drjit as dr

    si = surface_interaction(mi, wi, lam)
    wo_v = mi.Vector3f(*[mi.Float(c) for c in wo])
    value = bsdf.eval(mi.BSDFContext(), si, wo_v)
    return np.array([np.asarray(value[j]) for j in range(dr.size_v(mi.Spectrum))], dtype=np.float64)


CASES = [("clear", 1.0, 0.9), ("R30", 1.0, 0.9), ("G30", 0.6, 0.7), ("Y25+B5", 0.3, 1.0),
         ("lossless", 1.0, 0.9), ("absorbing", 0.75, 0.8)]


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("ink,coverage,paper", CASES)
def test_eval_matches_reference(use_variant, ink_tables, diffuse_tables, ink, coverage, paper, model):
    mi = use_variant("llvm_ad_spectral")
    path = {**ink_tables, **diffuse_tables}[ink]
    table = read_table(path)
    rng = np.random.default_rng(hash(ink) % 2**32)
    wi, wo = _hemisphere(rng, N_LANES, 0.1), _hemisphere(rng, N_LANES, 0.1)[:, ::-1].copy()
    lam = rng.uniform(350.0, 850.0, size=(4, N_LANES))       # beyond the table: clamps
    got = _eval(mi, ink_bsdf(mi, path, paper, coverage, model), wi, wo, lam)
    want = reference_eval(table, wi, wo, lam, coverage, paper, model)
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, want, rtol=2e-4, atol=2e-6)
    assert np.all(got[:, (wi[2] <= 0) | (wo[2] <= 0)] == 0.0)
    assert np.mean(got > 0) > 0.5                               # not trivially zero


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("ink,coverage,paper", CASES)
def test_reciprocity(use_variant, ink_tables, diffuse_tables, ink, coverage, paper, model):
    mi = use_variant("llvm_ad_spectral")
    bsdf = ink_bsdf(mi, {**ink_tables, **diffuse_tables}[ink], paper, coverage, model)
    rng = np.random.default_rng(7)
    a, b = _hemisphere(rng, N_LANES), _hemisphere(rng, N_LANES)
    lam = rng.uniform(360.0, 830.0, size=(4, N_LANES))
    f_ab = _eval(mi, bsdf, a, b, lam) / b[2]          # eval carries cos θo
    f_ba = _eval(mi, bsdf, b, a, lam) / a[2]
    np.testing.assert_allclose(f_ab, f_ba, rtol=2e-4, atol=1e-6)
    assert np.ptp(f_ab) > 1e-3                         # the BRDF does vary with direction


def test_diffuse_lobe_depends_on_azimuth(use_variant, diffuse_tables):
    """Δφ convention: R ∝ 1 + ½ sin σ sin θ cos Δφ is larger toward retro (Δφ = 0) than mirror (π)."""
    mi = use_variant("llvm_ad_spectral")
    bsdf = ink_bsdf(mi, diffuse_tables["lossless"], paper=0.0, coverage=1.0, model=MODELS[0])
    s = np.sin(np.radians(60.0)), np.cos(np.radians(60.0))
    wi = np.array([[s[0]], [0.0], [s[1]]])
    lam = np.full((4, 1), 550.0)
    retro = _eval(mi, bsdf, wi, wi, lam)
    mirror = _eval(mi, bsdf, wi, wi * np.array([[-1], [-1], [1]]), lam)
    ratio = (1 + 0.375) / (1 - 0.375)                 # ½ sin²60° = 0.375 on the table's nodes
    assert np.all(retro > 0.97 * ratio * mirror) and np.all(retro < 1.03 * ratio * mirror)
