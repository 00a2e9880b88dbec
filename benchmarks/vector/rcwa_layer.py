"""A full-vector RCWA of a voxel grid: Maxwell on the very cells the scalar solver sees
(docs/vector_referee.md, "RCWA on the voxel grid").

grcwa (Jin et al., MIT licence, PyPI; an optional extra, `pip install -e '.[vector]'`) solves
Maxwell's equations in a stack of laterally periodic layers, each given as a grid of ε: every
z-cell of the voxel grid is one such layer (thickness h, its (nx, ny) slice of ε), between air
above and below.  Its ε Fourier matrices come from the DFT of the grid's values (the samples,
as the scalar solver's pseudo-spectral products use them), so both solvers see the same ε(x, y)
per z-cell — staircasing is not what is compared.  Truncation: the `orders` lowest lateral
orders (circular), at most what the grid resolves (|m|, |n| < nx/4 keeps the convolution
indices G_i − G_j inside the DFT without aliasing).

Incidence at polar σ, azimuth φ from the air above; s (TE) and p (TM) share one
eigendecomposition per layer.  Returned: R, T (totals, all propagating orders) for s and p,
and the powers of the 00 orders.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RcwaResult:
    """[s, p] arrays: R, T (totals) and R00, T00 (the 00 orders' powers); orders used."""

    R: np.ndarray
    T: np.ndarray
    R00: np.ndarray
    T00: np.ndarray
    orders: int


def max_orders(shape: tuple[int, int, int]) -> int:
    """The most lateral orders a grid resolves without aliasing in the convolution matrices:
    a circular set with |m|, |n| < nx/4 (π(nx/4)² orders)."""
    r = min(shape[0], shape[1]) // 4 - 1
    return int(sum(1 for m in range(-r, r + 1) for n in range(-r, r + 1) if m * m + n * n <= r * r))


def rcwa_rt(eps: np.ndarray, period_nm: tuple[float, float], thickness_nm: float,
            wavelength_nm: float, polar_rad: float, azimuth_rad: float = 0.0,
            orders: int | None = None) -> RcwaResult:
    """R, T of the voxel grid eps (nx, ny, nz) (z downward, air above and below) for s and p
    (one S-matrix for both; run it on one BLAS thread: threaded BLAS was 8× slower on the
    shared 2-core machine)."""
    import grcwa
    from grcwa import rcwa

    grcwa.set_backend("numpy")
    nx, ny, nz = eps.shape
    orders = max_orders(eps.shape) if orders is None else int(orders)
    # grcwa: c = 1, frequency 1/λ with lengths in nm, e^(−iωt) like the scalar solver
    obj = grcwa.obj(orders, [period_nm[0], 0.0], [0.0, period_nm[1]], 1.0 / wavelength_nm,
                    polar_rad, azimuth_rad, verbose=0)
    obj.Add_LayerUniform(0.0, 1.0)
    h = thickness_nm / nz
    for _ in range(nz):
        obj.Add_LayerGrid(h, nx, ny)
    obj.Add_LayerUniform(0.0, 1.0)
    obj.Init_Setup(Gmethod=0)
    obj.GridLayer_geteps(np.concatenate([np.asarray(eps[:, :, k], complex).ravel()
                                         for k in range(nz)]))
    out = {k: np.zeros(2) for k in ("R", "T", "R00", "T00")}
    s11, _, s21, _ = rcwa.GetSMatrix(0, obj.Layer_N - 1, obj.q_list, obj.phi_list, obj.kp_list,
                                     obj.thickness_list)      # once for both polarisations
    for i, (p_amp, s_amp) in enumerate(((0.0, 1.0), (1.0, 0.0))):         # s, then p
        obj.MakeExcitationPlanewave(p_amp, 0.0, s_amp, 0.0, order=0)
        a_n, b_0 = s11 @ obj.a0, s21 @ obj.a0                   # nothing incident from below
        _, back = rcwa.GetZPoyntingFlux(obj.a0, b_0, obj.omega, obj.kp_list[0], obj.phi_list[0],
                                        obj.q_list[0], byorder=1)
        fwd, _ = rcwa.GetZPoyntingFlux(a_n, obj.bN, obj.omega, obj.kp_list[-1], obj.phi_list[-1],
                                       obj.q_list[-1], byorder=1)
        big_r, big_t = -np.real(back) * obj.normalization, np.real(fwd) * obj.normalization
        out["R"][i], out["T"][i] = big_r.sum(), big_t.sum()
        out["R00"][i], out["T00"][i] = big_r[0], big_t[0]          # order 0: G = (0, 0)
    return RcwaResult(out["R"], out["T"], out["R00"], out["T00"], obj.nG)


def film_check(wavelength_nm: float = 450.0, eps_film: complex = 1.82 + 1.06j) -> float:
    """max |ΔR|, |ΔT| of a homogeneous 1000-nm film (as a 4×4×8 grid) against the exact s/p
    film (solver.thinfilm) at 0, 30, 60, 80°."""
    from solver.thinfilm import slab

    worst = 0.0
    for deg in (0.0, 30.0, 60.0, 80.0):
        res = rcwa_rt(np.full((8, 8, 8), eps_film), (500.0, 500.0), 1000.0, wavelength_nm,
                      math.radians(deg), orders=5)
        for i, pol in enumerate(("te", "tm")):
            film = slab(eps_film, 1000.0, wavelength_nm, math.radians(deg), polarisation=pol)
            worst = max(worst, abs(res.R[i] - float(film.R)), abs(res.T[i] - float(film.T)))
    return worst


def grating_check(nx: int = 24, lam: float = 500.0, angles=(0.0, 60.0)) -> list[tuple]:
    """A y-invariant lamellar grating (period 800 nm, 35 % of 1.4 + 0.2i lamellae in binder,
    400 nm, nx × nx × 16 voxels): grcwa's s against the scalar solver's TE on the same voxels,
    equal under Maxwell's equations (E ∥ the lamellae).  Rows (σ°, orders, R_s, R_TE, T_s, T_TE)."""
    from solver.wave import Cell, Incidence, solve

    x = (np.arange(nx) + 0.5) / nx
    eps1 = 1.558 ** 2 + ((1.4 + 0.2j) ** 2 - 1.558 ** 2) * ((x > 0.2) & (x < 0.55))
    eps = np.broadcast_to(eps1[:, None, None], (nx, nx, 16)).copy()
    rows = []
    for deg in angles:
        res = rcwa_rt(eps, (800.0, 800.0), 400.0, lam, math.radians(deg))
        te = solve(Cell(eps, (800.0, 800.0), (0.0, 400.0)), Incidence(lam, math.radians(deg)),
                   tol=1e-8, dtype=np.complex128)
        rows.append((deg, res.orders, res.R[0], te.R, res.T[0], te.T))
    return rows
