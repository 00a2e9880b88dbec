"""The z-recursions (zkernels.py) against the unreduced Toeplitz/Hankel blocks of
kernel1d.circulant_blocks (themselves checked against quadrature in test_wave_kernels.py), and
one operator application against a dense reference built harmonic by harmonic."""
from __future__ import annotations

import math

import numpy as np
import pytest

from solver.wave import Cell, prepare
from solver.wave.kernel1d import circulant_blocks, slab_green, vertical_wavenumber
from solver.wave.operator import Workspace, apply_scattering, apply_system
from solver.wave.vecops import one_blas_thread, set_blas_threads_local
from solver.wave.zkernels import ZWork, apply_z, z_kernels


def _dense_blocks(sg):
    """Dense Galerkin matrices M[p, q][..., k, l] from the unreduced circulant blocks."""
    nz = sg.nz
    k, l = np.meshgrid(np.arange(nz), np.arange(nz), indexing="ij")
    out = {}
    for p, q, toe, han in circulant_blocks(sg):
        out[p, q] = toe[..., (k - l) % (2 * nz)] + han[..., k + l]
    return out


@pytest.mark.parametrize("nb", [1, 2])
@pytest.mark.parametrize("nz", [1, 2, 5, 16])
@pytest.mark.parametrize("tm", [False, True])
def test_reduced_kernels_equal_the_galerkin_matrix(nb, nz, tm):
    rng = np.random.default_rng(nz + 10 * nb)
    k0 = 2 * math.pi / 500
    kt2 = (rng.uniform(0, 3, (5, 4)) * k0) ** 2           # propagating and evanescent
    kap = vertical_wavenumber(k0 ** 2 * (2.3 + 0.3j), kt2)
    ka = vertical_wavenumber(k0 ** 2, kt2)
    kc = vertical_wavenumber(k0 ** 2 * 1.2, kt2)
    ratios = dict(face_ratio_above=2.3 + 0.2j, face_ratio_below=(2.3 + 0.2j) / 1.2) if tm else {}
    sg = slab_green(kap, ka, kc, 300.0, nz, nb, **ratios)
    x = rng.standard_normal((nb, 5, 4, nz)) + 1j * rng.standard_normal((nb, 5, 4, nz))
    dense = _dense_blocks(sg)
    ref = np.zeros_like(x)
    for (p, q), m in dense.items():
        ref[p] += np.einsum("...kl,...l->...k", m, x[q])
    zk = z_kernels(sg, np.complex128)
    xz = np.ascontiguousarray(np.moveaxis(x, -1, 1).reshape(nb, nz, 20))   # z-major
    got = apply_z(zk, xz, ZWork(nz, 20, np.complex128))
    got = np.moveaxis(got.reshape(nb, nz, 5, 4), 1, -1)
    assert np.abs(got - ref).max() <= 1e-13 * np.abs(ref).max()


def test_operator_application_matches_a_dense_reference():
    """(I − G V)·w for a small cell: lateral DFT, dense z-matrix per harmonic, inverse DFT."""
    rng = np.random.default_rng(4)
    eps = 2.4 + 0.3 * rng.random((4, 3, 3)) + 0.1j * rng.random((4, 3, 3))
    cell = Cell(eps, (700.0, 600.0), (0.0, 400.0))
    op = prepare(cell, 500.0, 0.002, -0.001, dtype=np.complex128)
    w = rng.standard_normal(op.unknown_shape) + 1j * rng.standard_normal(op.unknown_shape)
    f = op.contrast * w
    fh = np.fft.fft2(f, axes=(1, 2))
    dense = _dense_blocks(op.green)
    yh = np.zeros_like(fh)
    for (p, q), m in dense.items():
        yh[p] += np.einsum("...kl,...l->...k", m, fh[q])
    ref = w - np.fft.ifft2(yh, axes=(1, 2))
    ws = Workspace(op)
    assert np.allclose(apply_system(op, w, ws), ref, rtol=0, atol=1e-13 * np.abs(ref).max())
    out = np.empty_like(w)
    scat = apply_scattering(op, w, ws, out)
    assert scat is out and np.allclose(w - out, ref, atol=1e-13 * np.abs(ref).max())


def test_one_blas_thread_restores_the_thread_count():
    before = set_blas_threads_local(3)
    if before is None:
        pytest.skip("NumPy is not linked to an OpenBLAS with a thread-local setting")
    try:
        with one_blas_thread():
            assert set_blas_threads_local(1) == 1          # inside: one thread
        assert set_blas_threads_local(3) == 3              # restored on exit
    finally:
        set_blas_threads_local(max(before, 1))


@pytest.mark.parametrize("z_order", [0, 1])
def test_fftw_backend_equals_scipy(z_order):
    """The optional FFTW backend (unnormalised inverse transforms, 1/n folded into the
    kernels; aligned and unaligned plans) gives the scipy results to rounding, for every
    method; fft='auto' picks it when installed.  Without pyFFTW (an optional extra): a clear
    error for fft='fftw', and 'auto' is scipy."""
    from solver.wave import Incidence, solve
    from solver.wave.fftback import fftw_available
    from solver.wave.validation import random_layer

    cell = random_layer(1.5 + 0.05j, shape=(16, 12, 8))       # weak: the Born series converges
    inc = Incidence(500.0, 0.4, 0.3)
    if not fftw_available():
        with pytest.raises(ValueError, match="pip install pyfftw"):
            solve(cell, inc, fft="fftw")
        assert prepare(cell, 500.0, 0.0, 0.0, fft="auto").fft.name == "scipy"
        return
    for method in ("gmres", "bicgstab", "born"):
        kw = dict(tol=1e-6, method=method, z_order=z_order, dtype=np.complex128)
        ref = solve(cell, inc, **kw)
        got = solve(cell, inc, fft="fftw", **kw)
        assert np.allclose(got.reflected.amplitude, ref.reflected.amplitude, atol=1e-9)
        assert np.allclose(got.transmitted.amplitude, ref.transmitted.amplitude, atol=1e-9)
        assert got.applications == ref.applications
    assert prepare(cell, 500.0, 0.0, 0.0, fft="auto").fft.name == "fftw"


def test_unknown_fft_backend_is_refused():
    cell = Cell(np.full((2, 2, 2), 2.0 + 0.1j), (100.0, 100.0), (0.0, 100.0))
    with pytest.raises(ValueError, match="fft must be one of"):
        prepare(cell, 500.0, 0.0, 0.0, fft="mkl")


def test_background_pickles_for_process_pools():
    """A prepared background (kernels, FFT backend without its plans) survives pickling and
    gives the same operator."""
    import pickle

    from solver.wave import prepare_background, with_contrast

    bg = prepare_background((8, 8, 4), (500.0, 500.0), 200.0, 500.0, 0.001, 0.0, 2.2 + 0.05j)
    bg2 = pickle.loads(pickle.dumps(bg))
    cell = Cell(np.full((8, 8, 4), 2.4 + 0.1j), (500.0, 500.0), (0.0, 200.0))
    w = np.ones(bg.unknown_shape, np.complex64)
    a = apply_system(with_contrast(bg, cell), w)
    b = apply_system(with_contrast(bg2, cell), w)
    assert np.array_equal(a, b) and bg2.fft.name == bg.fft.name
