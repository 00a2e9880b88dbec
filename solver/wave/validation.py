"""Validation experiments: the solver against the oracles of oracles.py on fixed test cases.

One home for the cases that the tests assert (tests/test_wave_convergence.py, _grating.py,
_mie.py, _energy.py, _hard.py) and that benchmarks/bench_wave.py tabulates under refinement:

- slab_error: 1000-nm slab, λ = 500, σ = 0.4: |Δr| + |Δt| against Airy (z-discretisation);
- grating_errors: lamellar grating against TE RCWA (lateral discretisation);
- mie_relative_errors: one weak sphere per cell against scalar Mie single scattering;
- random_layer: a cell of random (overlapping) spheres in binder, voxelised by supersampling;
- hard_cells: random hard cells (contrast, load, angle, λ, polarisation) for the convergence
  sweep (benchmarks/bench_convergence.py, tests/test_wave_retry.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .vecops import one_blas_thread
from .oracles import (airy_te, layer_fraction, mie_scalar_amplitude, random_spheres, rcwa_te,
                      sphere_fractions)
from .solve import solve
from .types import Cell, Incidence

E_BINDER = 1.558 ** 2
SLAB_LAM, SLAB_SIGMA = 500.0, 0.4


def slab_error(eta, n, *, half_voxels, z_order=1):
    """|Δr| + |Δt| against Airy for a 1000-nm slab on n cells per 1000 nm (λ = 500, σ = 0.4).

    half_voxels: the slab sits on the grid [−h/2, 1000 + h/2], both face voxels half filled
    (own, volume-mean background); else it fills the grid and is carried by the contrast to a
    forced air background (ε_b = 1 + 0.01i)."""
    r, t, _, _ = airy_te(1.0, eta, 1.0, 1000.0, SLAB_LAM, SLAB_SIGMA)
    kz = 2 * math.pi / SLAB_LAM * math.cos(SLAB_SIGMA)
    if half_voxels:
        h = 1000.0 / n
        lo = -h / 2 + np.arange(n + 1) * h
        eps = 1 + (eta ** 2 - 1) * layer_fraction(lo, lo + h, 0.0, 1000.0)
        cell = Cell(np.broadcast_to(eps, (1, 1, n + 1)).copy(), (300.0, 300.0),
                    (-h / 2, 1000.0 + h / 2))
        res = solve(cell, Incidence(SLAB_LAM, SLAB_SIGMA), tol=1e-10, z_order=z_order)
        phase = np.exp(2j * kz * h / 2)          # the grid's faces lie h/2 outside the slab
    else:
        cell = Cell(np.full((1, 1, n), eta ** 2), (300.0, 300.0), (0.0, 1000.0))
        res = solve(cell, Incidence(SLAB_LAM, SLAB_SIGMA), tol=1e-11,
                    eps_background=1.0 + 0.01j, z_order=z_order)
        phase = 1.0
    return (abs(res.reflected.amp(0, 0) - r * phase)
            + abs(res.transmitted.amp(0, 0) - t * phase))


GRATING_LAM, GRATING_PERIOD, GRATING_THICK = 500.0, 800.0, 400.0


def grating_cell(eps_strip, a, b, nx, nz=16):
    """Strip eps_strip on [a, b) nm (sub-voxel averaged) in binder, y-invariant, 400 nm."""
    dx = GRATING_PERIOD / nx
    lo = np.arange(nx) * dx
    frac = np.clip(np.minimum(lo + dx, b) - np.maximum(lo, a), 0, dx) / dx
    eps = E_BINDER + (eps_strip - E_BINDER) * frac
    return Cell(np.broadcast_to(eps[:, None, None], (nx, 1, nz)).copy(),
                (GRATING_PERIOD, GRATING_PERIOD), (0.0, GRATING_THICK))


def grating_errors(eps_strip, a, b, nx, sigma=0.3, azimuth=0.0):
    """(max |Δamplitude| over propagating orders, |ΔR|, result) against RCWA (2·60+1
    harmonics)."""
    res = solve(grating_cell(eps_strip, a, b, nx), Incidence(GRATING_LAM, sigma, azimuth),
                tol=1e-9, exact_energy=True)
    with one_blas_thread():      # a threaded 121×121 eigenproblem stalls on a busy machine
        m, r, t, ka, kc = rcwa_te(1.0, 1.0, eps_strip, E_BINDER, a, b, GRATING_PERIOD, GRATING_THICK,
                                  GRATING_LAM, sigma, 60, azimuth)
    errs = []
    for i in np.flatnonzero(ka.imag == 0):
        errs.append(abs(res.reflected.amp(int(m[i]), 0) - r[i]))
        errs.append(abs(res.transmitted.amp(int(m[i]), 0) - t[i]))
    power = (ka.real * abs(r) ** 2 * (ka.imag == 0)).sum() / ka[60].real
    return max(errs), abs(res.R - power), res


MIE_LAM, MIE_RADIUS, MIE_INDEX = 500.0, 60.0, 1.05 + 0.01j
MIE_PERIOD, MIE_DEPTH, MIE_ZC = 400.0, 200.0, 100.0


def mie_relative_errors(shape):
    """Relative error of every propagating order of a square lattice of one sphere
    (a = 60 nm, 1.05 + 0.01i, period 400, depth 200) against the single-scattering relation
    (tests/test_wave_mie.py gives the relation and its tolerance budget)."""
    centre = np.array([0.37 * MIE_PERIOD, 0.61 * MIE_PERIOD, MIE_ZC])
    frac = sphere_fractions(centre[None], MIE_RADIUS, (MIE_PERIOD, MIE_PERIOD), (0.0, MIE_DEPTH),
                            shape, ss=6)
    cell = Cell(1 + (MIE_INDEX ** 2 - 1) * frac, (MIE_PERIOD, MIE_PERIOD), (0.0, MIE_DEPTH))
    res = solve(cell, Incidence(MIE_LAM, math.radians(20), 0.3), tol=1e-7)
    k = 2 * math.pi / MIE_LAM
    kt0 = np.array([res.kx0, res.ky0])
    kz_in = math.sqrt(k * k - kt0 @ kt0)
    errors = []
    for side, orders in (("R", res.reflected), ("T", res.transmitted)):
        for i in np.flatnonzero(orders.propagating):
            kt = np.array([orders.kx[i], orders.ky[i]])
            kz = orders.kz[i].real
            lateral = np.exp(1j * (kt0 - kt) @ centre[:2])
            amp = orders.amplitude[i]
            if side == "R":
                cos_t = (kt0 @ kt - kz_in * kz) / k ** 2
                phase = lateral * np.exp(1j * (kz_in + kz) * MIE_ZC)
            else:
                cos_t = (kt0 @ kt + kz_in * kz) / k ** 2
                phase = lateral * np.exp(1j * kz_in * MIE_ZC + 1j * kz * (MIE_DEPTH - MIE_ZC))
                if orders.m[i] == 0 and orders.n[i] == 0:
                    amp = amp - np.exp(1j * kz_in * MIE_DEPTH)
            f = mie_scalar_amplitude(MIE_INDEX, k, MIE_RADIUS, cos_t)
            pred = 2j * math.pi / (MIE_PERIOD ** 2 * kz) * f * phase
            errors.append(abs(amp - pred) / abs(pred))
    return np.array(errors)


LAYER_PERIOD, LAYER_THICK = (1000.0, 1000.0), 500.0


def random_layer(eta_particle, fraction=0.2, diameter=200.0, seed=7, shape=(24, 24, 12),
                 thickness=LAYER_THICK):
    """Random (overlapping) spheres of η_particle in binder filling ≈ `fraction` of a
    1000×1000-nm cell, voxelised by 3³ supersampling."""
    rng = np.random.default_rng(seed)
    n = int(round(fraction * LAYER_PERIOD[0] * LAYER_PERIOD[1] * thickness
                  / (math.pi / 6 * diameter ** 3)))
    centres = random_spheres(rng, n, LAYER_PERIOD, (0.0, thickness), diameter / 2)
    frac = sphere_fractions(centres, diameter / 2, LAYER_PERIOD, (0.0, thickness), shape, ss=3)
    return Cell(E_BINDER + (eta_particle ** 2 - E_BINDER) * frac, LAYER_PERIOD, (0.0, thickness))


@dataclass(frozen=True)
class HardCell:
    """One case of the convergence sweep: a random layer and one incidence on it."""

    index: int
    cell: Cell
    incidence: Incidence
    polarisation: str
    eta: complex
    fill: float

    def describe(self) -> str:
        return (f"#{self.index}: η {self.eta.real:.2f}{self.eta.imag:+.2f}i, fill {self.fill:.0%}, "
                f"λ {self.incidence.wavelength_nm:.0f} nm, σ {math.degrees(self.incidence.polar_rad):.0f}°, "
                f"{self.polarisation.upper()}")


def hard_cells(count: int, shape=(16, 16, 8), seed: int = 22):
    """`count` random hard cases (a generator): spheres of 200 nm with index n ∈ [1.0, 3.5],
    k ∈ {0 (half of them), [0, 1.5]}, filling 5–50 % of a 1000 × 1000 × 500-nm cell of binder
    (random_layer), λ 380–780 nm, σ 0–85°, TE or TM."""
    rng = np.random.default_rng(seed)
    for i in range(count):
        eta = complex(rng.uniform(1.0, 3.5), 0.0 if rng.random() < 0.5 else rng.uniform(0.0, 1.5))
        fill = float(rng.uniform(0.05, 0.5))
        cell = random_layer(eta, fraction=fill, shape=shape, seed=int(rng.integers(1 << 30)))
        inc = Incidence(float(rng.uniform(380.0, 780.0)), math.radians(float(rng.uniform(0.0, 85.0))),
                        float(rng.uniform(0.0, math.pi / 2)))
        yield HardCell(i, cell, inc, ("te", "tm")[int(rng.integers(2))], eta, fill)


def explicit_residual(case: HardCell, res) -> float:
    """‖w_b − (I − GV)·w‖/‖w_b‖ of a result's solution, recomputed in complex128 by one
    explicit application of a freshly prepared operator (not the solver's own estimate)."""
    from .operator import apply_system, prepare
    from .solve import source
    from .types import bloch_vector

    op = prepare(case.cell, case.incidence.wavelength_nm, *bloch_vector(case.cell, case.incidence),
                 polarisation=case.polarisation, dtype=np.complex128)
    b = source(op, case.incidence.from_below)
    r = b - apply_system(op, np.asarray(res.solution, dtype=np.complex128))
    return float(np.linalg.norm(r) / np.linalg.norm(b))
