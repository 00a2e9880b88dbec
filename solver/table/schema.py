"""Table file, schema v1: the contract between the solver (writer) and the plugin (reader).

A `.npz` holding, per wavelength λ (nm) and incidence σ (rad):

    wavelengths [nλ]           strictly increasing, nm
    sigma       [nσ]           incidence polar angles, strictly increasing, from 0 to π/2
    theta       [nθ]           outgoing polar grid of R, from 0 to π/2
    dphi        [nφ]           azimuth difference grid of R, from 0 to π (mirror symmetry)
    R           [nλ, nσ, nθ, nφ]  diffuse BRDF factor of the layer alone (f_r = R/π), nodal
                                  values of a multilinear interpolant
    R_spec, T_coh, Rbar, Tbar, Rbar_below   [nλ, nσ]
    <name>_err  (optional, same shape as <name>): standard error across realizations
    meta        JSON string (schema_version, ink, particles, thickness_nm, generator,
                settings, seeds, error estimates, tier, ...)

Rbar and Tbar include the coherent (00) orders; Rbar = R_spec + hemispherical integral of R.
All angular integrals use `solver.table.integrals` (exact for the linear interpolant).
"""

from __future__ import annotations

import io
import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .atomic import atomic_savez
from .integrals import diffuse_albedo

SCHEMA_VERSION = 1
COLUMNS = ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")
GRIDS = ("wavelengths", "sigma", "theta", "dphi")
_ANGLE_TOL = 1e-9
_ENERGY_TOL = 1e-6          # round-off tolerance on physical bounds
_DEFAULT_SUM_TOL = 2e-3     # Rbar vs R_spec + ∫R, when meta gives no error estimate


class TableError(ValueError):
    """A table file that cannot be used; the message names the file and the problem."""


@dataclass(frozen=True)
class InkTable:
    wavelengths: np.ndarray
    sigma: np.ndarray
    theta: np.ndarray
    dphi: np.ndarray
    R: np.ndarray
    R_spec: np.ndarray
    T_coh: np.ndarray
    Rbar: np.ndarray
    Tbar: np.ndarray
    Rbar_below: np.ndarray
    meta: dict = field(default_factory=dict)
    errors: dict = field(default_factory=dict)   # name -> standard-error array (optional)

    @property
    def has_diffuse(self) -> bool:
        """False when the layer scatters nothing diffusely (R ≡ 0): the plugin skips R then."""
        return bool(np.any(self.R != 0.0))

    def column(self, name: str) -> np.ndarray:
        return getattr(self, name)


def _check(cond: bool, where: str, msg: str) -> None:
    if not cond:
        raise TableError(f"{where}: {msg}")


def validate(table: InkTable, where: str = "table") -> InkTable:
    """Check shapes, finiteness, grids, physical ranges and version; return the table."""
    meta = table.meta
    _check(isinstance(meta, dict), where, "meta must be a JSON object")
    version = meta.get("schema_version")
    _check(version == SCHEMA_VERSION, where,
           f"schema version {version!r} is not supported (this reader reads version {SCHEMA_VERSION})")
    for name in GRIDS:
        g = np.asarray(getattr(table, name))
        _check(g.ndim == 1 and g.size >= 2, where, f"'{name}' must be a 1-D grid of ≥ 2 values, shape {g.shape}")
        _check(bool(np.all(np.isfinite(g))), where, f"'{name}' has non-finite values")
        _check(bool(np.all(np.diff(g) > 0)), where, f"'{name}' must be strictly increasing")
    wl = table.wavelengths
    _check(wl[0] > 0, where, f"wavelengths must be positive nm, first is {wl[0]}")
    for name, hi in (("sigma", np.pi / 2), ("theta", np.pi / 2), ("dphi", np.pi)):
        g = getattr(table, name)
        _check(abs(g[0]) < _ANGLE_TOL and abs(g[-1] - hi) < _ANGLE_TOL, where,
               f"'{name}' must run from 0 to {hi:.6f} rad, got {g[0]:.6g}..{g[-1]:.6g}")
    nl, ns, nt, nf = wl.size, table.sigma.size, table.theta.size, table.dphi.size
    _check(table.R.shape == (nl, ns, nt, nf), where,
           f"'R' has shape {table.R.shape}, expected (wavelengths, sigma, theta, dphi) = {(nl, ns, nt, nf)}")
    for name in COLUMNS + ("R",):
        a = table.column(name)
        if name != "R":
            _check(a.shape == (nl, ns), where, f"'{name}' has shape {a.shape}, expected {(nl, ns)}")
        bad = ~np.isfinite(a)
        _check(not bad.any(), where, f"'{name}' has {int(bad.sum())} non-finite values")
        _check(float(a.min()) >= -_ENERGY_TOL, where, f"'{name}' has negative values (min {a.min():.3g})")
    for name in COLUMNS:
        a = table.column(name)
        _check(float(a.max()) <= 1 + _ENERGY_TOL, where, f"'{name}' exceeds 1 (max {a.max():.6g})")
    for name, arr in table.errors.items():
        _check(name in COLUMNS + ("R",), where, f"unknown error column '{name}_err'")
        _check(np.shape(arr) == table.column(name).shape, where, f"'{name}_err' shape mismatch")
    for total, coherent in (("Rbar", "R_spec"), ("Tbar", "T_coh")):
        excess = float(np.max(table.column(coherent) - table.column(total)))
        _check(excess <= _ENERGY_TOL, where, f"'{coherent}' exceeds '{total}' by {excess:.3g}")
    errors = meta.get("errors", {})
    closure = _ENERGY_TOL * 10 + float(errors.get("energy_closure_max", 0.0))
    for total in ("Rbar", "Rbar_below"):
        over = float(np.max(table.column(total) + table.Tbar - 1.0))
        _check(over <= closure, where, f"'{total}' + 'Tbar' exceeds 1 by {over:.3g}")
    scale = max(1.0, float(np.max(table.R)))
    for axis, grid in ((1, table.sigma), (2, table.theta)):     # no azimuth reference at a normal
        normal = np.take(table.R, 0, axis=axis)
        spread = float(np.max(np.ptp(normal, axis=-1)))
        _check(spread <= 1e-9 * scale, where, f"'R' depends on Δφ at {('sigma', 'theta')[axis - 1]} = 0 "
               f"(spread {spread:.3g}); a normal direction has no azimuth")
    if table.theta.shape == table.sigma.shape and np.allclose(table.theta, table.sigma):
        asym = float(np.max(np.abs(table.R - np.swapaxes(table.R, 1, 2))))
        _check(asym <= 1e-9 * scale, where, f"'R' is not reciprocal: R(σ,θ) − R(θ,σ) up to {asym:.3g}")
    tol = float(errors.get("energy_sum_tol", _DEFAULT_SUM_TOL))
    mismatch = np.abs(table.Rbar - table.R_spec - diffuse_albedo(table.theta, table.dphi, table.R))
    _check(float(mismatch.max()) <= tol, where,
           f"'Rbar' differs from R_spec + ∫R by {mismatch.max():.3g} (> {tol:.3g})")
    return table


def write_table(path, table: InkTable) -> Path:
    """Validate and write atomically (temp file + rename: readers never see a partial file)."""
    path = Path(path)
    validate(table, str(path))
    arrays = {name: np.asarray(getattr(table, name), dtype=np.float64) for name in GRIDS + COLUMNS}
    arrays["R"] = np.asarray(table.R, dtype=np.float64)
    for name, arr in table.errors.items():
        arrays[f"{name}_err"] = np.asarray(arr, dtype=np.float64)
    arrays["meta"] = np.array(json.dumps(table.meta, sort_keys=True))
    atomic_savez(path, arrays, compressed=True)
    return path


def read_table(path) -> InkTable:
    """Read and validate a table; raise TableError saying exactly what is wrong."""
    path = Path(path)
    where = str(path)
    if not path.is_file():
        raise TableError(f"{where}: table file not found")
    try:
        raw = path.read_bytes()
        with np.load(io.BytesIO(raw), allow_pickle=False) as npz:
            data = {k: npz[k] for k in npz.files}
    except (zipfile.BadZipFile, EOFError, OSError, ValueError) as exc:
        raise TableError(f"{where}: not a readable .npz table (truncated or corrupt: {exc})") from None
    missing = [k for k in GRIDS + COLUMNS + ("R", "meta") if k not in data]
    _check(not missing, where, f"missing arrays: {', '.join(missing)}")
    try:
        meta = json.loads(str(data["meta"]))
    except json.JSONDecodeError as exc:
        raise TableError(f"{where}: 'meta' is not valid JSON ({exc})") from None
    errors = {k[:-4]: data[k] for k in data if k.endswith("_err")}
    table = InkTable(**{k: data[k].astype(np.float64) for k in GRIDS + COLUMNS + ("R",)},
                     meta=meta, errors=errors)
    return validate(table, where)
