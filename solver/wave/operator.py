"""The discretised Lippmann–Schwinger operator of one cell, prepared in two parts.

Field u = e^{i(kx0·x + ky0·y)}·w(x, y, z) with w periodic; unknowns: w at the lateral voxel
centres × Legendre moments in every z-cell (shape (nb, nx, ny, nz); nb = z_order + 1; moment
0 is the cell average).  Lateral: pseudo-spectral (DFT, exact Bloch harmonics
kx = kx0 + 2πm/Lx, ky = ky0 + 2πn/Ly).  z: Galerkin with the exact layered-background Green's
function (kernel1d.py), applied by recursions along z (zkernels.py).

Layouts: the public arrays (unknowns, solutions, face profiles) are (nb, nx, ny, nz); the
iteration runs on the z-major layout (nb, nz, nx, ny) (`to_zmajor`, `from_zmajor`), where the
lateral FFTs transform contiguous axes and a z-cell is one contiguous row of harmonics
(`scatter_zmajor`, `system_zmajor`; docs/wave_solver.md, "Performance").

    w − G·(V·w) = w_b,      V = k0²(ε − ε_b)   (1/nm²),   w_b = background (Airy) field.

`Background` (prepare_background) is everything that depends on (λ, Bloch vector, ε_b, grid,
cell size, half-spaces, polarisation) only: one preparation serves every realization of a
layer when the caller fixes ε_b.  `LayerOperator` (prepare, with_contrast) adds one cell's
contrast.  Both serve incidence from above and from below with the same (kx0, ky0).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .faces import (DEFAULT_TM_FACES, TMFaces, face_coefficients, harmonic_forms,
                    parse_tm_faces)
from .interfaces import FaceLayers, Interfaces, build as build_interfaces, green_moments
from .fftback import DEFAULT_FFT, FFT, aligned_empty, default_workers, get_fft
from .scratch import borrow, give_back
from .kernel1d import SlabGreen, face_profiles, slab_green, vertical_wavenumber
from .types import Cell
from .zkernels import ZKernels, ZWork, z_kernels

#: default minimum Im ε_b of the background slab (fictitious loss that keeps the guided-mode
#: poles of a lossless film off the real axis; the contrast carries −i·δ back).  See docs.
DEFAULT_MIN_LOSS = 0.01
POLARISATIONS = ("te", "tm")

__all__ = ["Background", "LayerOperator", "prepare_background", "prepare", "with_contrast",
           "choose_background", "apply_system", "apply_scattering", "apply_green", "Workspace",
           "scatter_zmajor", "system_zmajor", "to_zmajor", "from_zmajor",
           "default_workers", "DEFAULT_MIN_LOSS", "POLARISATIONS", "DEFAULT_TM_FACES"]


@dataclass(frozen=True, eq=False)
class Background:
    """The layered background of one (λ, Bloch vector): Green's function kernels, face profiles.

    shape (nx, ny, nz); period_nm (Lx, Ly); thickness_nm H; eps_above / eps_below: the
    half-spaces; eps_background: ε_b of the slab as used (Im raised to min_loss);
    eps_nominal: ε_b as asked (before min_loss); polarisation 'te' | 'tm'; eps_face: (top,
    bottom) ε_f of the TM face conditions, each face its own (None for TE); tm_faces: the TM face forms per class of harmonic
    (faces.TMFaces; None for TE).  Arrays of shape (nx, ny) are per lateral harmonic in FFT
    order (order indices m, n).  zk: the z-recursion constants (zkernels.py); ptop, pbot
    (computed on demand; the solver needs neither): moments of the face profiles
    (kernel1d.face_profiles), (nb, nx, ny, nz) in dtype; fft: the FFT backend (fftback.py;
    its normalisation is folded into zk).  interfaces: the TM correction for the inner
    interfaces of a stack (interfaces.py; None for one layer and for TE).
    """

    shape: tuple[int, int, int]
    period_nm: tuple[float, float]
    thickness_nm: float
    eps_above: float
    eps_below: float
    wavelength_nm: float
    kx0: float
    ky0: float
    eps_background: complex
    eps_nominal: complex
    polarisation: str
    eps_face: tuple[complex, complex] | None
    m: np.ndarray
    n: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    green: SlabGreen
    zk: ZKernels
    dtype: np.dtype
    workers: int
    fft: FFT
    tm_faces: TMFaces | None = None
    interfaces: Interfaces | None = None

    @property
    def k0(self) -> float:
        return 2 * math.pi / self.wavelength_nm

    @property
    def nb(self) -> int:
        """Legendre functions per z-cell (z_order + 1)."""
        return self.green.nb

    @property
    def ptop(self) -> np.ndarray:
        return face_profiles(self.green)[0].astype(self.dtype)

    @property
    def pbot(self) -> np.ndarray:
        return face_profiles(self.green)[1].astype(self.dtype)

    @property
    def unknown_shape(self) -> tuple[int, int, int, int]:
        return (self.nb,) + self.shape

    @property
    def zmajor_shape(self) -> tuple[int, int, int, int]:
        """(nb, nz, nx, ny): the layout of the iteration (module doc)."""
        nx, ny, nz = self.shape
        return (self.nb, nz, nx, ny)

    @property
    def lateral_phase(self) -> np.ndarray:
        """e^{−iπ(m/nx + n/ny)}: maps DFT coefficients of node values (voxel centres) to
        Fourier coefficients referenced to x = y = 0."""
        nx, ny, _ = self.shape
        return np.exp(-1j * math.pi * (self.m / nx + self.n / ny))


@dataclass(frozen=True, eq=False)
class LayerOperator:
    """A Background plus one cell's contrast = k0²(ε − ε_b) in 1/nm², shape (nx, ny, nz), and
    the same in the z-major layout (nz, nx, ny)."""

    background: Background
    cell: Cell
    contrast: np.ndarray
    contrast_zmajor: np.ndarray

    def __getattr__(self, name: str):
        # the background's fields (green, zk, ptop, pbot, kx, ky, m, n, k0, nb, …) read through
        if name in ("background", "cell", "contrast", "contrast_zmajor"):
            raise AttributeError(name)
        return getattr(self.background, name)

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.cell.shape

    @property
    def dtype(self) -> np.dtype:
        return self.contrast.dtype


def face_layers(value: "complex | FaceLayers", nz: int) -> FaceLayers:
    """eps_face as FaceLayers: one permittivity is one layer of nz cells."""
    return value if isinstance(value, FaceLayers) else FaceLayers((nz,), (complex(value),))


def choose_background(eps: np.ndarray, min_loss: float) -> complex:
    """Volume mean of ε with Im ε_b raised to at least min_loss."""
    mean = complex(np.mean(eps))
    return complex(mean.real, max(mean.imag, float(min_loss)))


def _check_common(wavelength_nm: float, min_loss: float, z_order: int, polarisation: str,
                  dtype) -> np.dtype:
    if not (wavelength_nm > 0 and math.isfinite(wavelength_nm)):
        raise ValueError(f"wavelength_nm must be positive, got {wavelength_nm}")
    if min_loss <= 0:
        raise ValueError("min_loss must be positive (it keeps the background's poles complex)")
    if z_order not in (0, 1):
        raise ValueError("z_order must be 0 or 1")
    if polarisation not in POLARISATIONS:
        raise ValueError(f"polarisation must be 'te' or 'tm', got {polarisation!r}")
    dt = np.dtype(dtype)
    if dt not in (np.dtype(np.complex64), np.dtype(np.complex128)):
        raise ValueError(f"dtype must be complex64 or complex128, got {dt}")
    return dt


def prepare_background(shape: tuple[int, int, int], period_nm: tuple[float, float],
                       thickness_nm: float, wavelength_nm: float, kx0: float, ky0: float,
                       eps_background: complex, *, eps_above: float = 1.0,
                       eps_below: float = 1.0, polarisation: str = "te",
                       eps_face: "complex | FaceLayers | None" = None,
                       min_loss: float = DEFAULT_MIN_LOSS,
                       z_order: int = 1, dtype: type = np.complex64,
                       workers: int | None = None, fft: str = DEFAULT_FFT,
                       tm_faces: "str | TMFaces" = DEFAULT_TM_FACES) -> Background:
    """The background of a grid `shape` = (nx, ny, nz) over a cell of `period_nm` (Lx, Ly) and
    `thickness_nm`, at `wavelength_nm` and Bloch vector (kx0, ky0) in 1/nm.

    eps_background: ε_b of the slab; its imaginary part is raised to min_loss if smaller.
    eps_above / eps_below: real, positive half-space permittivities.  polarisation: 'te' (the
    scalar model is exact TE at the faces) or 'tm' (u and ∂_z u/ε continuous at the faces, with
    ε_f = eps_face for the slab: one value for both faces, or a stack's FaceLayers (each layer's
    z-cells and ε_f, top first: each face its own layer's permittivity, and the TM conditions
    at the inner interfaces, interfaces.py); default: eps_background as given, without
    min_loss).
    tm_faces: TM only, which face form each lateral harmonic gets (faces.py): a preset name
    ('brewster', the default: u = E_x for harmonics below Brewster's wavevector, H_y above
    it up to the light line, TE conditions for evanescent ones; 'all': H_y everywhere, the
    first TM model; 'mean', 'propagating', 'electric', 'electric-mean',
    'electric-propagating', 'hybrid') or a faces.TMFaces.
    z_order: polynomial degree per z-cell (1: O(h⁴) in z where ε is piecewise constant on
    z-cells; 0: cell averages only, O(h²)).  dtype: complex64 (default) or complex128 for the
    operator arrays and Krylov vectors (kernels are computed in complex128).  workers: FFT
    threads (default: all cores, at most 8; one per process is best in a process pool).
    fft: the array backend (fftback.py): 'auto' (default: FFTW where pyFFTW is installed, else
    scipy), 'scipy', 'fftw' (pyFFTW, optional) or 'cupy' (CuPy on a GPU, optional).
    """
    dt = _check_common(wavelength_nm, min_loss, z_order, polarisation, dtype)
    nx, ny, nz = (int(s) for s in shape)
    if min(nx, ny, nz) < 1:
        raise ValueError(f"shape must be three positive integers, got {shape}")
    lx, ly = (float(p) for p in period_nm)
    if not (lx > 0 and ly > 0 and thickness_nm > 0):
        raise ValueError("period_nm and thickness_nm must be positive")
    ea, ec = float(complex(eps_above).real), float(complex(eps_below).real)
    if not (ea > 0 and ec > 0) or complex(eps_above).imag or complex(eps_below).imag:
        raise ValueError("eps_above and eps_below must be real and positive")
    nominal = complex(eps_background)
    eb = complex(nominal.real, max(nominal.imag, min_loss))
    ef, faces = None, parse_tm_faces(tm_faces)
    if polarisation != "tm":
        faces = None
    else:
        layers = face_layers(nominal if eps_face is None else eps_face, nz)
        ef = (complex(layers.eps[0]), complex(layers.eps[-1]))
    k0 = 2 * math.pi / wavelength_nm
    m = np.rint(np.fft.fftfreq(nx, 1.0 / nx)).astype(int)[:, None] * np.ones((1, ny), int)
    n = np.rint(np.fft.fftfreq(ny, 1.0 / ny)).astype(int)[None, :] * np.ones((nx, 1), int)
    kx = kx0 + 2 * math.pi * m / lx
    ky = ky0 + 2 * math.pi * n / ly
    kt2 = kx * kx + ky * ky
    k2 = k0 * k0
    kap = vertical_wavenumber(k2 * eb, kt2)
    ka = vertical_wavenumber(k2 * ea, kt2)
    kc = vertical_wavenumber(k2 * ec, kt2)
    face_coefs = None
    if faces is not None:
        form = harmonic_forms(faces, kt2, ka if ea >= ec else kc, ea, ec, ef, k0)
        face_coefs = (face_coefficients(form, kap, ka, kt2, ea, ef[0], k0, top=True),
                      face_coefficients(form, kap, kc, kt2, ec, ef[1], k0, top=False))
    sg = slab_green(kap, ka, kc, float(thickness_nm), nz, z_order + 1, faces=face_coefs)
    w = default_workers() if workers is None else int(workers)
    backend = get_fft(fft, w)
    zk = z_kernels(sg, dt, normalised=backend.normalised, backend=backend)
    inner = None if faces is None else build_interfaces(sg, layers, face_coefs[0].form, kt2, k0,
                                                        dt, backend)
    return Background((nx, ny, nz), (lx, ly), float(thickness_nm), ea, ec,
                      float(wavelength_nm), float(kx0), float(ky0), eb, nominal, polarisation, ef,
                      m, n, kx, ky, sg, zk, dt, w, backend, faces, inner)


def with_contrast(bg: Background, cell: Cell) -> LayerOperator:
    """The operator of `cell` on the prepared background (ε_b fixed by the background)."""
    if cell.shape != bg.shape:
        raise ValueError(f"cell shape {cell.shape} does not match the background's {bg.shape}")
    if not (np.allclose(cell.period_nm, bg.period_nm, rtol=1e-12)
            and math.isclose(cell.thickness_nm, bg.thickness_nm, rel_tol=1e-12)):
        raise ValueError("cell period_nm / thickness do not match the background's; prepare a "
                         "background for this cell")
    if (complex(cell.eps_above).real, complex(cell.eps_below).real) != (bg.eps_above,
                                                                       bg.eps_below):
        raise ValueError("cell eps_above / eps_below do not match the background's")
    contrast = bg.fft.asarray(bg.k0 ** 2 * (np.asarray(cell.eps) - bg.eps_background), bg.dtype)
    return LayerOperator(bg, cell, contrast, to_zmajor(contrast, bg.fft))


def prepare(cell: Cell, wavelength_nm: float, kx0: float, ky0: float, *,
            eps_background: complex | None = None, min_loss: float = DEFAULT_MIN_LOSS,
            z_order: int = 1, dtype: type = np.complex64, workers: int | None = None,
            polarisation: str = "te", eps_face: "complex | FaceLayers | None" = None,
            background: Background | None = None, fft: str = DEFAULT_FFT,
            tm_faces: "str | TMFaces" = DEFAULT_TM_FACES) -> LayerOperator:
    """Build the operator for one cell, wavelength (nm) and Bloch vector (kx0, ky0) in 1/nm.

    eps_background: ε_b of the background slab (default: volume mean of ε); its imaginary part
    is raised to min_loss if smaller.  eps_face (TM): one ε_f for both faces or FaceLayers,
    default the cell's own volume mean ε whatever ε_b (a homogeneous film is then its own face
    permittivity; a stack's caller passes its layers).
    polarisation, tm_faces, z_order, dtype,
    workers, fft: see prepare_background.  background: a prepared Background to reuse (then ε_b, polarisation,
    z_order, dtype and workers are the background's, and the other arguments must not
    contradict it).
    """
    if background is not None:
        if (background.wavelength_nm, background.kx0, background.ky0) != (
                float(wavelength_nm), float(kx0), float(ky0)):
            raise ValueError("background was prepared for another wavelength / Bloch vector")
        return with_contrast(background, cell)
    eps = np.asarray(cell.eps)
    mean = complex(np.mean(eps))
    nominal = mean if eps_background is None else complex(eps_background)
    bg = prepare_background(cell.shape, cell.period_nm, cell.thickness_nm, wavelength_nm, kx0,
                            ky0, nominal, eps_above=complex(cell.eps_above).real,
                            eps_below=complex(cell.eps_below).real, polarisation=polarisation,
                            eps_face=mean if eps_face is None else eps_face,
                            min_loss=min_loss, z_order=z_order, dtype=dtype,
                            workers=workers, fft=fft, tm_faces=tm_faces)
    return with_contrast(bg, cell)


def to_zmajor(a: np.ndarray, backend: FFT | None = None) -> np.ndarray:
    """(…, nx, ny, nz) → a new C-contiguous array (…, nz, nx, ny) of the backend (fftback.py;
    None: host NumPy, aligned), from a host or backend array."""
    shape = a.shape[:-3] + (a.shape[-1],) + a.shape[-3:-1]
    out = aligned_empty(shape, a.dtype) if backend is None else backend.empty(shape, a.dtype)
    if backend is not None:
        a = backend.asarray(a)
    np.copyto(out, np.moveaxis(a, -1, -3))
    return out


def from_zmajor(a: np.ndarray) -> np.ndarray:
    """(…, nz, nx, ny) → a new C-contiguous array (…, nx, ny, nz) (same backend)."""
    return np.ascontiguousarray(np.moveaxis(a, -3, -1))


class Workspace:
    """Scratch arrays of one solve, reused by every operator application (one per thread),
    borrowed from the thread's scratch pool (scratch.py) until release()."""

    def __init__(self, op: LayerOperator | Background):
        nx, ny, nz = op.shape
        self.backend = op.fft
        self.f = borrow(op.zmajor_shape, op.dtype, op.fft)
        self.z = ZWork(nz, nx * ny, op.dtype, op.fft)

    def release(self) -> None:
        give_back(self.f, backend=self.backend)
        self.z.release()
        del self.f, self.z


def _green_zmajor(op: LayerOperator, f: np.ndarray, ws: Workspace) -> np.ndarray:
    """Galerkin moments of G·f for z-major source moments f (nb, nz, nx, ny); f is
    overwritten with the result (returned; f itself unless the FFT library copied)."""
    nb, nz, nx, ny = f.shape
    fh = op.fft.lateral(f)
    flat = fh.reshape(nb, nz, nx * ny)
    green_moments(op.zk, op.interfaces, flat, ws.z)
    return op.fft.lateral(fh, inverse=True)


def scatter_zmajor(op: LayerOperator, w: np.ndarray, ws: Workspace,
                   out: np.ndarray | None = None) -> np.ndarray:
    """G V·w for z-major w (nb, nz, nx, ny): the Born-series map without the source, into
    out (C-contiguous) or a new array."""
    if out is None:
        out = op.fft.empty(w.shape, op.dtype)
    g = _green_zmajor(op, np.multiply(op.contrast_zmajor, w, out=out), ws)
    if not op.fft.same_buffer(g, out):            # the FFTs transform in place (fftback)
        np.copyto(out, g)
    return out


def system_zmajor(op: LayerOperator, w: np.ndarray, ws: Workspace,
                  out: np.ndarray | None = None) -> np.ndarray:
    """(I − G V)·w for z-major w: one operator application (into out, or a new array)."""
    g = _green_zmajor(op, np.multiply(op.contrast_zmajor, w, out=ws.f), ws)
    return np.subtract(w, g, out=out)


def apply_green(op: LayerOperator, f: np.ndarray, ws: Workspace | None = None) -> np.ndarray:
    """Galerkin moments of G·f for source moments f (nb, nx, ny, nz) at the nodes.  f is
    overwritten: it holds the result, which is returned."""
    ws = Workspace(op) if ws is None else ws
    np.copyto(ws.f, to_zmajor(f, op.fft))
    f[...] = op.fft.to_host(from_zmajor(_green_zmajor(op, ws.f, ws)))
    return f


def apply_scattering(op: LayerOperator, w: np.ndarray, ws: Workspace | None = None,
                     out: np.ndarray | None = None) -> np.ndarray:
    """G V·w (the Born-series map without the source) for w (nb, nx, ny, nz), into out or a
    new array."""
    return _in_natural_layout(scatter_zmajor, op, w, ws, out)


def apply_system(op: LayerOperator, w: np.ndarray, ws: Workspace | None = None,
                 out: np.ndarray | None = None) -> np.ndarray:
    """(I − G V)·w for w (nb, nx, ny, nz): one operator application (into out, or a new
    array)."""
    return _in_natural_layout(system_zmajor, op, w, ws, out)


def _in_natural_layout(zmajor_map, op: LayerOperator, w: np.ndarray, ws: Workspace | None,
                       out: np.ndarray | None) -> np.ndarray:
    """zmajor_map applied to w (nb, nx, ny, nz), the result in the same layout (into out)."""
    g = op.fft.to_host(from_zmajor(zmajor_map(op, to_zmajor(w, op.fft),
                                              Workspace(op) if ws is None else ws)))
    if out is None:
        return g
    np.copyto(out, g)
    return out
