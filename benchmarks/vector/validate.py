"""Checks of the vector referee against independent physics (`bench_vector --validate`).

1. Clear film (no spheres), s and p, absorbing and not, σ = 0…80°: the whole S-matrix chain
   (treams' Fresnel faces, our propagation, star product, order fluxes) against `airy_film`.
2. One sphere: treams' Mie T-matrix cross sections against `mie_cross_sections`.
3. A dilute absorbing sphere lattice in unbounded binder: absorption A = 1 − R − T against the
   single-sphere C_abs/(L² cos σ_b) (Mie), i.e. lattice, plane-wave coupling and fluxes together.
4. Lossless spheres (k = 0) in the layer in air: R + T = 1 per polarisation.
5. Our order fluxes against treams' own `SMatrices.tr` on a layer with spheres.
6. Convergence on a layer with spheres: plane-wave cutoff and multipole degree.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

import treams

from . import treams_layer as tl
from .cases import Case, host_eps, lmax_for, realization, sphere_eps
from .oracles import airy_film, mie_cross_sections

H = 1000.0


def check_film() -> float:
    worst = 0.0
    films = ((450.0, complex(sphere_eps(Case(100, 0.1, 1000, ()), 450.0))), (600.0, host_eps()))
    for lam, eps in films:
        for deg in (0.0, 30.0, 60.0, 80.0):
            R, T, r, _ = tl.clear_slab(lam, math.radians(deg), eps, H)
            for i, pol in enumerate("sp"):
                Ra, Ta, ra, _ = airy_film(lam, math.radians(deg), eps, H, pol)
                worst = max(worst, abs(R[i] - Ra), abs(T[i] - Ta), abs(r[i, i] - ra))
    print(f"1. homogeneous 1000-nm film in air vs Airy (s, p; pigment Y at 450 nm, ε = {films[0][1]:.3f}, "
          f"and binder at 600 nm; σ 0/30/60/80°): max |ΔR|, |ΔT|, |Δr| = {worst:.1e}")
    return worst


def check_mie() -> float:
    worst = 0.0
    print("2. one sphere in binder, treams T-matrix vs Mie oracle (λ 450 nm, pigment Y):")
    for d in (100.0, 300.0):
        lam = 450.0
        eps = sphere_eps(Case(d, 0.1, 1000, ()), lam)
        k0 = 2 * math.pi / lam
        tm = treams.TMatrix.sphere(12, k0, d / 2, [treams.Material(eps), treams.Material(host_eps())],
                                   poltype="parity")
        ext, sca, _ = mie_cross_sections(d / 2, lam, np.sqrt(eps), math.sqrt(host_eps()))
        rel = max(abs(tm.xs_ext_avg - ext) / ext, abs(tm.xs_sca_avg - sca) / sca)
        worst = max(worst, rel)
        print(f"   D = {d:g} nm: C_ext {tm.xs_ext_avg:.2f} vs {ext:.2f} nm², C_sca {tm.xs_sca_avg:.2f} vs "
              f"{sca:.2f} nm² (max rel. diff {rel:.1e})")
    return worst


def check_dilute_absorption() -> float:
    """A/A_Mie − 1 oscillates around 0 with the period (the images' coherent coupling, a
    slowly decaying lattice sum in 2-D); a systematic error would not."""
    lam, d = 450.0, 100.0
    eps = sphere_eps(Case(d, 0.1, 1000, ()), lam)
    k0 = 2 * math.pi / lam
    _, _, c_abs = mie_cross_sections(d / 2, lam, np.sqrt(eps), math.sqrt(host_eps()))
    rel = []
    for period in (700.0, 1000.0, 1300.0, 1700.0):
        for deg in ((0.0, 30.0) if period == 1000.0 else (0.0,)):
            kpar = tl.incidence_kpar(k0, math.radians(deg), host_eps())
            cl = tl.cluster_tmatrix([d / 2], [[0.3 * period, 0.4 * period, H / 2]], eps, host_eps(), k0, 4)
            tsol, lat = tl.lattice_solve(cl, (period, period), kpar)
            pwb = tl.plane_wave_basis(kpar, lat, tl.min_cutoff(k0, host_eps(), kpar))
            slab = tl.slab_smatrix(tsol, lat, kpar, pwb, k0, host_eps(), H)
            R, T, _, _ = tl.layer_response(slab, pwb, kpar, k0, host_eps())
            expect = c_abs / (period * period * math.cos(math.radians(deg)))
            rel += [(period, deg, pol, (1 - R[i] - T[i]) / expect - 1) for i, pol in enumerate("sp")]
    print(f"3. one {d:g}-nm sphere per cell in unbounded binder (λ {lam:g}), A/(C_abs,Mie/(L² cos σ_b)) − 1: " +
          ", ".join(f"L {p:g} σ {s:g}° {q}: {x:+.3f}" for p, s, q, x in rel))
    mean = float(np.mean([x for *_, x in rel]))
    print(f"   mean over periods and angles {mean:+.4f}")
    return max(abs(mean), max(abs(x) for *_, x in rel) / 3)


def _few_spheres(case, count, lam, eps):
    real = realization(case, 0)
    return real.radii_nm[:count], real.centres_nm[:count], eps


def check_lossless_and_tr() -> tuple[float, float]:
    case = Case(300.0, 0.15, 1000.0, (500.0,))
    lam, deg = 500.0, 30.0
    radii, centres, _ = _few_spheres(case, 3, lam, None)
    k0 = 2 * math.pi / lam
    kpar = tl.incidence_kpar(k0, math.radians(deg))
    settings = tl.VectorSettings(lmax_for(float(radii.max()), lam, 1.4 ** 2), case.pw_cutoff_per_nm)
    res = tl.solve_cell(radii, centres, 1.4 ** 2 + 0j, lam, math.radians(deg), (1000.0, 1000.0), H,
                        host_eps(), settings)
    closure = float(np.max(np.abs(res.R + res.T - 1)))
    print(f"4. lossless spheres (3 × {2 * radii[0]:.0f} nm, n = 1.4, λ {lam:g}, σ {deg:g}°, lmax {settings.lmax}): "
          f"R + T − 1 = {res.R[0] + res.T[0] - 1:.1e} (s), {res.R[1] + res.T[1] - 1:.1e} (p)")
    # 5. the same layer with an absorbing pigment, fluxes vs treams' tr()
    eps = sphere_eps(case, lam)
    cl = tl.cluster_tmatrix(radii, centres, eps, host_eps(), k0, settings.lmax)
    tsol, lat = tl.lattice_solve(cl, (1000.0, 1000.0), kpar)
    pwb = tl.plane_wave_basis(kpar, lat, case.pw_cutoff_per_nm)
    total = tl.stack_layer(tl.slab_smatrix(tsol, lat, kpar, pwb, k0, host_eps(), H), pwb, k0, host_eps())
    R, T, _, _ = tl.layer_response(total, pwb, kpar, k0)
    sm = treams.SMatrices([[total[0], total[1]], [total[2], total[3]]], k0=k0, basis=pwb,
                          material=treams.Material(), poltype="parity")
    diff = 0.0
    for pol in (0, 1):
        inc = treams.plane_wave(list(kpar), pol, k0=k0, basis=pwb, material=treams.Material(),
                                modetype="up", poltype="parity")
        Tt, Rt = sm.tr(inc)
        diff = max(diff, abs(Tt - T[pol]), abs(Rt - R[pol]))
    print(f"5. order fluxes vs treams SMatrices.tr (same layer, pigment Y): max diff {diff:.1e}")
    # 6. convergence in the plane-wave cutoff and lmax
    base = (R, T)
    for cut in (0.03, 0.08):
        pwb2 = tl.plane_wave_basis(kpar, lat, cut)
        tot2 = tl.stack_layer(tl.slab_smatrix(tsol, lat, kpar, pwb2, k0, host_eps(), H), pwb2, k0, host_eps())
        R2, T2, _, _ = tl.layer_response(tot2, pwb2, kpar, k0)
        print(f"6. pw cutoff {cut}/nm ({len(pwb2)} plane waves) vs {case.pw_cutoff_per_nm}/nm ({len(pwb)}): "
              f"max |ΔR|, |ΔT| = {max(np.abs(R2 - base[0]).max(), np.abs(T2 - base[1]).max()):.1e}")
    up = tl.solve_cell(radii, centres, eps, lam, math.radians(deg), (1000.0, 1000.0), H, host_eps(),
                       tl.VectorSettings(settings.lmax + 2, case.pw_cutoff_per_nm))
    print(f"   lmax {settings.lmax + 2} vs {settings.lmax} (Mie tail < 1e-3): max |ΔR|, |ΔT| = "
          f"{max(np.abs(up.R - R).max(), np.abs(up.T - T).max()):.1e}")
    return closure, diff


def main() -> int:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        film = check_film()
        mie = check_mie()
        dil = check_dilute_absorption()
        closure, trdiff = check_lossless_and_tr()
    ok = film < 1e-10 and mie < 1e-6 and dil < 0.03 and closure < 1e-6 and trdiff < 1e-10
    print(f"validation {'passed' if ok else 'FAILED'} in {time.perf_counter() - t0:.0f} s")
    return 0 if ok else 1


def knobs() -> int:
    """Accuracy knobs on small sub-cells of the cases (`bench_vector --knobs`, ~2 min)."""
    from solver.geometry import eps_grid, voxelize
    from solver.wave import Cell, Incidence, solve

    t0 = time.perf_counter()
    lam = 420.0
    k0 = 2 * math.pi / lam
    print(f"vector lmax (first 3 spheres of the 300-nm 15 % realization, λ {lam:g}, σ 0, cutoff 0.05/nm):")
    case = Case(300.0, 0.15, 1000.0, (lam,))
    real = realization(case, 0)
    eps = sphere_eps(case, lam)
    for lmax in (3, 4, 5, 6, 7):
        res = tl.solve_cell(real.radii_nm[:3], real.centres_nm[:3], eps, lam, 0.0, (1000.0, 1000.0), H,
                            host_eps(), tl.VectorSettings(lmax, 0.05))
        print(f"   lmax {lmax}: R_s {res.R[0]:.5f} T_s {res.T[0]:.5f} R_p {res.R[1]:.5f} T_p {res.T[1]:.5f}"
              f"  ({res.seconds_total:.1f} s){'  ← Mie-tail rule' if lmax == lmax_for(real.radii_nm.max(), lam, eps) else ''}")
    print(f"vector plane-wave cutoff (the 8 spheres nearest the top face of the 100-nm 15 % realization, "
          f"its 500-nm cell, λ {lam:g}, σ 30°, lmax 2):")
    case = Case(100.0, 0.15, 500.0, (lam,))
    real = realization(case, 0)
    near = np.argsort(real.centres_nm[:, 2] - real.radii_nm)[:8]
    print(f"   their gaps to the face: {np.round(np.sort(real.centres_nm[near, 2] - real.radii_nm[near]), 1)} nm")
    kpar = tl.incidence_kpar(k0, math.radians(30.0))
    cl = tl.cluster_tmatrix(real.radii_nm[near], real.centres_nm[near], sphere_eps(case, lam), host_eps(), k0, 2)
    tsol, lat = tl.lattice_solve(cl, (500.0, 500.0), kpar)
    for cut in (0.04, 0.05, 0.08, 0.12, 0.18):
        pwb = tl.plane_wave_basis(kpar, lat, cut)
        tot = tl.stack_layer(tl.slab_smatrix(tsol, lat, kpar, pwb, k0, host_eps(), H), pwb, k0, host_eps())
        R, T, _, _ = tl.layer_response(tot, pwb, kpar, k0)
        print(f"   cutoff {cut}/nm ({len(pwb)} plane waves): R_s {R[0]:.7f} T_s {T[0]:.7f} R_p {R[1]:.7f} T_p {T[1]:.7f}")
    print(f"scalar grid (the cases' first realization, λ {lam:g}, σ 0, tol 1e-5):")
    for d, cell_nm, grids in ((100.0, 500.0, ((32, 32, 64), (48, 48, 96), (64, 64, 128))),
                              (300.0, 1000.0, ((32, 32, 32), (64, 64, 64), (96, 96, 96)))):
        real = realization(Case(d, 0.15, cell_nm, (lam,)), 0)
        for g in grids:
            vox = voxelize(real, g)
            res = solve(Cell(eps_grid(vox, lam), (cell_nm, cell_nm), vox.z_range_nm), Incidence(lam, 0.0), tol=1e-5)
            print(f"   {d:g} nm spheres, {g[0]}×{g[1]}×{g[2]} (voxel {cell_nm / g[0]:.1f} nm): "
                  f"R {res.R:.5f} T {res.T:.5f} R_spec {res.R_spec:.5f}")
    print(f"knobs: {time.perf_counter() - t0:.0f} s")
    return 0
