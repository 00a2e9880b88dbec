"""The vector referee: a periodic cell of spheres in a binder slab, full Maxwell, with treams.

One solve = one wavelength and one incidence (σ in the x–z plane, from the air above the
layer); both polarisations share it.  The model (docs/vector_referee.md):

1. every sphere gets its Mie T-matrix in the binder (`treams.TMatrix.sphere`, degree ≤ lmax);
2. the cell's spheres are coupled to each other and to all their periodic images by the
   lattice sums of treams (`latticeinteraction.solve`): the cluster T-matrix of one cell of the
   2-D lattice, multiple scattering inside the binder complete;
3. that lattice becomes the S-matrix (plane-wave basis of diffraction orders in the binder) of
   the binder slab 0 ≤ z ≤ H that holds it, with its reference planes *at the slab's faces*:
   every exponential then decays (spheres lie strictly inside, see `cases.FACE_BUFFER_NM`);
4. the slab's S-matrix is stacked between the two flat binder/air faces (Fresnel S-matrices of
   treams) — the coupling of the spheres to the faces, evanescent orders included, is then
   exact up to the plane-wave cutoff.

The z axis of treams points along the incident light ("up" in treams is our +z, into the
layer); treams' parity basis: polarisation 0 = TE (s), 1 = TM (p).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import treams

POLS = ("s", "p")   # parity basis: 0 = TE (M waves, E ⟂ z and ⟂ plane of incidence), 1 = TM


@dataclass(frozen=True)
class VectorSettings:
    """Accuracy knobs of the vector model.

    lmax: largest multipole degree per sphere.
    pw_cutoff_per_nm: radius (in 1/nm) of the disc of lateral wavevectors kept in the plane-wave
        basis (diffraction orders); evanescent orders couple spheres to the faces.
    """

    lmax: int
    pw_cutoff_per_nm: float


@dataclass(frozen=True)
class VectorResult:
    """One (realization, λ, σ) solve.  Arrays over the incident polarisation (s, p).

    R, T: total reflectance / transmittance (all propagating orders, both polarisations out).
    r00, t00: (2, 2) coherent amplitudes of the 00 orders, [incident pol, outgoing pol],
        referenced at the layer's top (reflection) and bottom (transmission) faces.
    """

    R: np.ndarray
    T: np.ndarray
    r00: np.ndarray
    t00: np.ndarray
    n_modes: int
    n_plane_waves: int
    seconds_lattice: float
    seconds_total: float


def cluster_tmatrix(radii_nm, positions_nm, eps_sphere, eps_host, k0, lmax):
    """Block-diagonal T-matrix of isolated spheres (parity basis) at their positions."""
    host = treams.Material(eps_host)
    inner = treams.Material(eps_sphere)
    singles = {}
    tms = []
    for rad in np.asarray(radii_nm, dtype=float):
        key = round(float(rad), 9)
        if key not in singles:
            singles[key] = treams.TMatrix.sphere(lmax, k0, float(rad), [inner, host], poltype="parity")
        tms.append(singles[key])
    return treams.TMatrix.cluster(tms, np.asarray(positions_nm, dtype=float))


def lattice_solve(cluster, period_nm, kpar):
    """T-matrix of one cell with every periodic image coupled (treams' Ewald lattice sums)."""
    lattice = treams.Lattice([[period_nm[0], 0.0], [0.0, period_nm[1]]])
    return cluster.latticeinteraction.solve(lattice, list(kpar)), lattice


def min_cutoff(k0, eps_host, kpar, margin=1.05):
    """Smallest plane-wave cutoff (1/nm) that keeps every order propagating in the binder."""
    return margin * (k0 * math.sqrt(eps_host) + math.hypot(*kpar))


def plane_wave_basis(kpar, lattice, cutoff_per_nm):
    return treams.PlaneWaveBasisByComp.diffr_orders(list(kpar), lattice, cutoff_per_nm)


def _shifted(basis, dz):
    """The same spherical-wave modes with all positions moved by dz along z."""
    pos = np.array(basis.positions, dtype=float)
    pos[:, 2] += dz
    return treams.SphericalWaveBasis(zip(basis.pidx, basis.l, basis.m, basis.pol), pos)


def slab_smatrix(tsol, lattice, kpar, pwb, k0, eps_host, thickness_nm):
    """S-matrix blocks (uu, ud, du, dd) of the binder slab [0, H] with the sphere lattice
    inside, reference planes at z = 0 (treams' lower face: where our light enters) and z = H.

    Same structure as treams' `SMatrices.from_array`, but every plane wave is referenced at the
    face it crosses, so each factor e^{i k_z Δz} has Δz ≥ 0 (bounded for evanescent orders)."""
    host = treams.Material(eps_host)
    swb = tsol.basis
    at_top = _shifted(swb, -thickness_nm)        # positions relative to the face z = H
    common = dict(k0=k0, material=host, poltype="parity")
    # incoming plane waves (from the face they enter through) → regular waves at the spheres
    a_up = np.asarray(treams.expand((swb, pwb), "up", **common))
    a_down = np.asarray(treams.expand((at_top, pwb), "down", **common))
    # periodic outgoing waves of the spheres → plane waves leaving through a face
    p_up = np.asarray(treams.expandlattice(lattice, list(kpar), basis=(pwb, at_top), modetype="up", **common))
    p_down = np.asarray(treams.expandlattice(lattice, list(kpar), basis=(pwb, swb), modetype="down", **common))
    t = np.asarray(tsol)
    kz = pwb.kvecs(k0, host, "up")[2]
    free = np.diag(np.exp(1j * kz * thickness_nm))   # the bare slab between the two planes
    ta_up, ta_down = t @ a_up, t @ a_down
    return (free + p_up @ ta_up, p_up @ ta_down, p_down @ ta_up, free + p_down @ ta_down)


def interface_smatrix(pwb, k0, eps_below, eps_above):
    """Fresnel S-matrix blocks (uu, ud, du, dd) of a flat face, from treams (parity basis)."""
    sm = treams.SMatrices.interface(pwb, k0, [treams.Material(eps_below), treams.Material(eps_above)],
                                    poltype="parity")
    return tuple(np.asarray(sm[i, j]) for i, j in ((0, 0), (0, 1), (1, 0), (1, 1)))


def star(lower, upper):
    """Redheffer star product: the S-matrix of `lower` followed (in +z) by `upper`.

    Blocks (uu, ud, du, dd): up-going out = uu·(up in, from below) + ud·(down in, from above),
    down-going out = du·(up in) + dd·(down in)."""
    a_uu, a_ud, a_du, a_dd = lower
    b_uu, b_ud, b_du, b_dd = upper
    eye = np.eye(a_uu.shape[0])
    # waves bouncing between the two: up-going amplitude in the gap for unit input from below
    gap_up = np.linalg.solve(eye - a_ud @ b_du, a_uu)
    gap_down = np.linalg.solve(eye - b_du @ a_ud, b_dd)
    return (b_uu @ gap_up, b_ud + b_uu @ a_ud @ gap_down,
            a_du + a_dd @ b_du @ gap_up, a_dd @ gap_down)


def stack_layer(slab, pwb, k0, eps_host, eps_outside=1.0):
    """Air | binder slab (with spheres) | air, as plain S-matrix blocks."""
    top = interface_smatrix(pwb, k0, eps_outside, eps_host)
    bottom = interface_smatrix(pwb, k0, eps_host, eps_outside)
    return star(star(top, slab), bottom)


def incidence_kpar(k0, polar_rad, eps_outside=1.0):
    return (k0 * math.sqrt(eps_outside) * math.sin(polar_rad), 0.0)


def layer_response(total, pwb, kpar, k0, eps_outside=1.0):
    """R, T and the 00 amplitudes of a stacked layer for s and p incidence from the air side.

    Power of an order: |c|²·k_z/k_z,inc for propagating orders (treams' parity plane waves carry
    the flux Re(k_z)/(k·Z)·|c|²/4 for either polarisation; checked against `SMatrices.tr`)."""
    uu, _, du, _ = total
    kx, ky, kz = pwb.kvecs(k0, treams.Material(eps_outside), "up")
    kz = np.asarray(kz, dtype=complex)
    prop = (np.abs(kz.imag) < 1e-12 * k0) & (kz.real > 0)
    R, T = np.zeros(2), np.zeros(2)
    r00, t00 = np.zeros((2, 2), complex), np.zeros((2, 2), complex)
    for pol in (0, 1):
        i = pwb.index((kpar[0], kpar[1], pol))
        weight = np.where(prop, kz.real, 0.0) / kz[i].real
        T[pol] = float(np.sum(np.abs(uu[:, i]) ** 2 * weight))
        R[pol] = float(np.sum(np.abs(du[:, i]) ** 2 * weight))
        for out in (0, 1):
            j = pwb.index((kpar[0], kpar[1], out))
            t00[pol, out], r00[pol, out] = uu[j, i], du[j, i]
    return R, T, r00, t00


def clear_slab(wavelength_nm, polar_rad, eps_layer, thickness_nm, period_nm=(1000.0, 1000.0),
               cutoff_per_nm=0.0):
    """R, T, r00, t00 of a homogeneous film in air from treams' S-matrices (validation)."""
    k0 = 2 * math.pi / wavelength_nm
    kpar = incidence_kpar(k0, polar_rad)
    lattice = treams.Lattice([[period_nm[0], 0.0], [0.0, period_nm[1]]])
    pwb = plane_wave_basis(kpar, lattice, cutoff_per_nm)
    total = star(star(interface_smatrix(pwb, k0, 1.0, eps_layer),
                      _propagation(pwb, k0, eps_layer, thickness_nm)),
                 interface_smatrix(pwb, k0, eps_layer, 1.0))
    return layer_response(total, pwb, kpar, k0)


def _propagation(pwb, k0, eps, thickness_nm):
    kz = pwb.kvecs(k0, treams.Material(eps), "up")[2]
    free = np.diag(np.exp(1j * kz * thickness_nm))
    zero = np.zeros_like(free)
    return free, zero, zero, free


def solve_cell(radii_nm, centres_nm, eps_sphere, wavelength_nm, polar_rad, period_nm, thickness_nm,
               eps_host, settings: VectorSettings) -> VectorResult:
    """Full Maxwell response of one periodic cell of spheres inside the binder slab in air.

    centres_nm: (N, 3), z measured from the top face (where the light enters), 0 < z < H."""
    import time
    t0 = time.perf_counter()
    k0 = 2 * math.pi / wavelength_nm
    kpar = incidence_kpar(k0, polar_rad)
    cluster = cluster_tmatrix(radii_nm, centres_nm, eps_sphere, eps_host, k0, settings.lmax)
    t1 = time.perf_counter()
    tsol, lattice = lattice_solve(cluster, period_nm, kpar)
    t2 = time.perf_counter()
    if settings.pw_cutoff_per_nm < min_cutoff(k0, eps_host, kpar, 1.0):
        raise ValueError(f"pw_cutoff_per_nm {settings.pw_cutoff_per_nm} drops orders that propagate in the "
                         f"binder at λ {wavelength_nm:g} nm: use ≥ {min_cutoff(k0, eps_host, kpar):.4f}")
    pwb = plane_wave_basis(kpar, lattice, settings.pw_cutoff_per_nm)
    slab = slab_smatrix(tsol, lattice, kpar, pwb, k0, eps_host, thickness_nm)
    total = stack_layer(slab, pwb, k0, eps_host)
    R, T, r00, t00 = layer_response(total, pwb, kpar, k0)
    return VectorResult(R, T, r00, t00, int(cluster.shape[0]), len(pwb), t2 - t1, time.perf_counter() - t0)
