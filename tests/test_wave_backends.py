"""The array seam of the wave solver (issue 25 item 4; solver/wave/fftback.py): every backend
this machine can run gives the host reference's answer, and no solve mixes the backend's arrays
with host arrays behind its back.

CuPy is an optional path: its parameter is skipped only when CuPy (or a GPU) is absent.  The
seam itself is checked without a GPU by a strict stand-in device: arrays of an ndarray subclass
whose arithmetic refuses plain host arrays, as CuPy's does, so that any array a solve forgets to
move through the backend fails the test.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
import scipy.fft as sfft

from solver.wave import Cell, Incidence, solve
from solver.wave import fftback
from solver.wave.validation import random_layer

BACKENDS = ("scipy", "fftw", "cupy")
WAVE = Path(fftback.__file__).parent


def _cell() -> Cell:
    return random_layer(1.4 + 0.2j, fraction=0.3, shape=(16, 16, 8))


def _solve(fft: str, pol: str, **kw):
    return solve(_cell(), Incidence(500.0, 0.5, 0.3), polarisation=pol, tol=1e-6, fft=fft,
                 exact_energy=True, **kw)


@pytest.mark.parametrize("pol", ["te", "tm"])
@pytest.mark.parametrize("name", BACKENDS)
def test_every_available_backend_gives_the_host_answer(name, pol):
    if name not in fftback.available():
        pytest.skip(f"{name} is not installed here (optional)")
    ref, got = _solve("scipy", pol), _solve(name, pol)
    assert isinstance(got.solution, np.ndarray)                   # results come back to the host
    np.testing.assert_allclose(got.reflected.amplitude, ref.reflected.amplitude, atol=2e-6)
    np.testing.assert_allclose(got.transmitted.amplitude, ref.transmitted.amplitude, atol=2e-6)
    assert abs(got.absorbed - ref.absorbed) < 2e-6 and abs(got.energy_error) < 1e-5


def _plain(a):
    """Device arrays (in lists and tuples too) as plain views; TypeError for a host array."""
    if isinstance(a, (list, tuple)):
        return type(a)(_plain(x) for x in a)
    if type(a) is np.ndarray:
        raise TypeError("a host array mixed with device arrays")
    return a.view(np.ndarray) if isinstance(a, Device) else a


def _device(res):
    if isinstance(res, tuple):
        return tuple(_device(r) for r in res)
    return res.view(Device) if type(res) is np.ndarray else res


class Device(np.ndarray):
    """A stand-in device array: its ufuncs and NumPy functions refuse host (plain ndarray)
    operands, as CuPy's do, and return device arrays."""

    def __array_function__(self, func, types, args, kwargs):
        return _device(func(*_plain(args), **{k: _plain(v) for k, v in kwargs.items()}))

    def __array_ufunc__(self, ufunc, method, *inputs, out=None, **kw):
        args = list(inputs) + list(out or ())
        if any(type(a) is np.ndarray for a in args):
            raise TypeError(f"{ufunc.__name__}: a host array mixed with device arrays")
        plain = [a.view(np.ndarray) if isinstance(a, Device) else a for a in inputs]
        if out is not None:
            kw["out"] = tuple(o.view(np.ndarray) for o in out)
        res = getattr(ufunc, method)(*plain, **kw)
        if out is not None:
            return out[0] if len(out) == 1 else out
        return res.view(Device) if isinstance(res, np.ndarray) else res


@dataclass(frozen=True, eq=False)
class StrictDevice(fftback.FFT):
    """fftback.FFT with Device arrays: allocation, moves and transforms as a GPU backend's."""

    def empty(self, shape, dtype):
        return np.empty(shape, dtype).view(Device)

    def zeros(self, shape, dtype):
        return np.zeros(shape, dtype).view(Device)

    def asarray(self, a, dtype=None):
        return np.ascontiguousarray(np.asarray(a, dtype=dtype)).view(Device)

    def to_host(self, a):
        return np.array(a).view(np.ndarray)

    def lateral(self, a, inverse=False):
        f = sfft.ifft2 if inverse else sfft.fft2
        res = f(a.view(np.ndarray), axes=(-2, -1), overwrite_x=True)
        return res.view(Device)


@pytest.mark.parametrize("pol", ["te", "tm"])
@pytest.mark.parametrize("method", ["gmres", "bicgstab", "born", "layered"])
def test_a_solve_moves_every_array_through_the_backend(monkeypatch, pol, method):
    """The strict stand-in device gives the host answer with every Krylov method and with the
    layered preconditioner (a host array in device arithmetic would raise)."""
    from solver.wave import operator

    monkeypatch.setattr(operator, "get_fft", lambda name, workers: StrictDevice("strict", 1, True))
    kw = dict(method=method) if method not in ("born", "layered") else (
        dict(method="born", tol=1e-6) if method == "born" else dict(method="gmres", preconditioner="layered"))
    if method == "born":                                          # a dilute layer: Born converges
        cell = random_layer(1.45 + 0.01j, fraction=0.05, shape=(16, 16, 8))
        got = solve(cell, Incidence(500.0, 0.5), polarisation=pol, exact_energy=True, **kw)
        monkeypatch.undo()
        ref = solve(cell, Incidence(500.0, 0.5), polarisation=pol, exact_energy=True, **kw)
    else:
        got = _solve("scipy", pol, **kw)
        monkeypatch.undo()
        ref = _solve("scipy", pol, **kw)
    assert type(got.solution) is np.ndarray and type(got.reflected.amplitude) is np.ndarray
    np.testing.assert_allclose(got.reflected.amplitude, ref.reflected.amplitude, atol=1e-9)
    assert abs(got.absorbed - ref.absorbed) < 1e-9


def test_the_stand_in_device_catches_a_host_array():
    with pytest.raises(TypeError, match="host array"):
        StrictDevice("strict", 1, True).zeros(3, complex) + np.ones(3)


def test_only_the_backend_module_imports_an_fft_or_array_library():
    """No module of solver/wave but fftback.py imports scipy.fft, pyFFTW or CuPy: the FFTs of
    the operator, the orders and the energy all go through the operator's backend."""
    offenders = []
    for path in sorted(WAVE.glob("*.py")):
        if path.name in ("fftback.py", "oracles.py"):     # oracles: independent references
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            offenders += [f"{path.name}: {n}" for n in names
                          if n.startswith(("scipy.fft", "pyfftw", "cupy", "numpy.fft"))]
    assert not offenders, offenders
