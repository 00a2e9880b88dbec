"""Piecewise-linear lookups in Dr.Jit, identical in scalar and JIT (llvm/cuda) variants.

`Axis` locates a coordinate on a 1-D grid of nodes (uniform grids by arithmetic, others with a
cell table: both exact and O(1)); `NodeTable` interpolates multilinearly the nodal values of a
tensor-product grid with several channels per node, gathering each channel at one flat index.
Coordinates outside a grid clamp to its ends (e.g. Mitsuba's 360–830 nm on a 380–780 nm table).

Objects are built with the Mitsuba variant that is active at construction and must be used with
that variant (the BSDF builds them in its constructor).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product

import drjit as dr
import mitsuba as mi
import numpy as np

_UNIFORM_RTOL = 1e-9        # relative spacing deviation below which a grid counts as uniform
_MAX_CELLS = 1 << 16        # size limit of a non-uniform grid's cell table


def is_jit() -> bool:
    """True in llvm/cuda variants, False in scalar ones (their arrays are Python numbers)."""
    return dr.is_jit_v(mi.Float)


def opaque(value, kind=None):
    """A grid's number as an opaque JIT variable (a kernel input, not a literal compiled into
    the kernel), so that tables on different grids share kernels; the number itself in
    scalar variants."""
    if not is_jit():
        return value
    kind = kind or (mi.UInt32 if isinstance(value, int) else mi.Float)
    return dr.opaque(kind, value)


class Buffer:
    """A read-only float buffer that `gather` reads with per-lane indices in any variant."""

    def __init__(self, values: np.ndarray):
        flat = np.ascontiguousarray(values, dtype=np.float64).ravel()
        self.size = int(flat.size)
        if is_jit():
            self._data = mi.Float(flat.astype(np.float32 if dr.type_v(mi.Float) == dr.VarType.Float32
                                              else np.float64))
        else:
            self._data = [float(v) for v in flat]

    def gather(self, index, active=True):
        if is_jit():
            return dr.gather(mi.Float, self._data, index, active)
        return self._data[int(index)]


@dataclass(frozen=True)
class CellTable:
    """O(1) locator of a non-uniform grid: the cell of `nodes` holding each fine uniform bin.

    With a bin width no larger than the smallest node spacing a bin holds at most one node, so
    the true cell is `cells[bin]` or the next one (one comparison).
    """

    x0: float
    inv_width: float
    cells: np.ndarray           # int, [n_bins]


def uniform_step(nodes: np.ndarray) -> float | None:
    """The spacing of a uniform grid, or None when the spacing varies."""
    steps = np.diff(nodes)
    step = (nodes[-1] - nodes[0]) / (nodes.size - 1)
    return float(step) if np.all(np.abs(steps - step) <= _UNIFORM_RTOL * abs(step)) else None


def cell_table(nodes: np.ndarray) -> CellTable:
    """Cell table of a strictly increasing grid (see CellTable)."""
    span = float(nodes[-1] - nodes[0])
    n_bins = int(np.ceil(span / float(np.min(np.diff(nodes))))) + 1
    if n_bins > _MAX_CELLS:
        raise ValueError(f"grid too irregular for a cell table ({n_bins} bins > {_MAX_CELLS}): "
                         f"smallest spacing {np.min(np.diff(nodes)):.3g} on a span of {span:.3g}")
    inv_width = (n_bins - 1) / span
    starts = nodes[0] + np.arange(n_bins) / inv_width
    cells = np.clip(np.searchsorted(nodes, starts, side="right") - 1, 0, nodes.size - 2)
    return CellTable(float(nodes[0]), float(inv_width), cells.astype(np.int64))


class Axis:
    """One grid axis: `locate(x)` → (i, t) with i ∈ [0, n−2], t ∈ [0, 1], x ≈ (1−t)·x_i + t·x_{i+1}."""

    def __init__(self, nodes):
        nodes = np.asarray(nodes, dtype=np.float64)
        if nodes.ndim != 1 or nodes.size < 2 or np.any(np.diff(nodes) <= 0):
            raise ValueError("an interpolation axis needs a strictly increasing grid of ≥ 2 nodes")
        self.size = int(nodes.size)
        self.key = nodes.tobytes()          # equal grids locate equally (shared by the models)
        self.lo, self.hi = opaque(float(nodes[0])), opaque(float(nodes[-1]))
        self._last, self._last_f = opaque(self.size - 2), opaque(float(self.size - 2))
        step = uniform_step(nodes)
        self.uniform = step is not None
        if self.uniform:
            self._inv_step = opaque(1.0 / step)
        else:
            table = cell_table(nodes)
            self._x0, self._inv_bin = opaque(table.x0), opaque(table.inv_width)
            self._n_bins = opaque(int(table.cells.size))
            self._cells = Buffer(table.cells.astype(np.float64))
            self._nodes = Buffer(nodes)
            self._inv_len = Buffer(np.append(1.0 / np.diff(nodes), 1.0))

    def _clamp(self, x):
        # Plain selects: dr.clip would propagate a NaN, these map it to the grid's start.
        x = dr.select(x > self.lo, x, self.lo)
        return dr.select(x < self.hi, x, self.hi)

    def locate(self, x):
        x = self._clamp(x)
        last = self._last
        if self.uniform:
            u = (x - self.lo) * self._inv_step
            i = mi.UInt32(dr.select(u < self._last_f, dr.floor(u), self._last_f))
            t = u - mi.Float(i)
        else:
            b = mi.UInt32(dr.floor((x - self._x0) * self._inv_bin))
            b = dr.select(b < self._n_bins, b, self._n_bins - 1)
            i = mi.UInt32(self._cells.gather(b))
            i = dr.select((i < last) & (x >= self._nodes.gather(i + 1)), i + 1, i)
            t = (x - self._nodes.gather(i)) * self._inv_len.gather(i)
        t = dr.select(t > 0, t, 0.0)
        return i, dr.select(t < 1, t, 1.0)


class NodeTable:
    """Multilinear interpolant of nodal values `values[n_0, …, n_{d−1}, C]` (C channels), or
    with `stacked`, of several such tables on one grid, `values[P, n_0, …, C]`, one buffer
    (`lerp(…, block=p)` reads table p; p may differ per lane)."""

    def __init__(self, values, stacked: bool = False):
        values = np.asarray(values, dtype=np.float64)
        if values.ndim < 2 + int(stacked):
            raise ValueError("NodeTable values need ≥ 1 grid axis and a channel axis")
        self.shape = values.shape[1 if stacked else 0:-1]
        self.channels = int(values.shape[-1])
        strides, s = [], self.channels
        for n in reversed(self.shape):
            strides.append(s)
            s *= n
        self._strides = tuple(opaque(int(v)) for v in reversed(strides))   # flat-index stride per axis
        self._block = opaque(int(s))                                      # flat size of one table
        self._buf = Buffer(values)

    def lerp(self, coords, channels=None, block=0):
        """Values at located coordinates [(i, t) per axis] of table `block` (stacked tables);
        returns one array per channel."""
        if len(coords) != len(self.shape):
            raise ValueError(f"{len(self.shape)} coordinates expected, got {len(coords)}")
        channels = range(self.channels) if channels is None else channels
        base = block * self._block if not (isinstance(block, int) and block == 0) else 0
        for (i, _), stride in zip(coords, self._strides):
            base = base + i * stride
        out = [0.0 for _ in channels]
        for corner in product((0, 1), repeat=len(coords)):
            offset, weight = 0, 1.0
            for bit, (_, t), stride in zip(corner, coords, self._strides):
                if bit:
                    offset = offset + stride
                weight = weight * (t if bit else 1.0 - t)
            for k, c in enumerate(channels):
                out[k] = out[k] + weight * self._buf.gather(base + offset + c)
        return out
