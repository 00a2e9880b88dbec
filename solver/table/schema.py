"""Table file, schema v2: the contract between the solver (writer) and the plugin (reader).

A `.npz` holding, per wavelength λ (nm) and incidence σ (rad):

    wavelengths [nλ]           strictly increasing, nm
    sigma       [nσ]           incidence polar angles, strictly increasing, from 0 to π/2
    theta       [nθ]           outgoing polar grid of R, from 0 to π/2
    dphi        [nφ]           azimuth difference grid of R, from 0 to π (mirror symmetry)
    R           [nλ, nσ, nθ, nφ]  diffuse BRDF factor of the layer alone (f_r = R/π), nodal
                                  values of a multilinear interpolant
    R_spec, T_coh, Rbar, Tbar, Rbar_below   [nλ, nσ]
    <name>_err  (optional, same shape as <name>): standard error across realizations
    <name>_jack (optional, float32 [N, *shape of <name>], N ≥ 2, for <name> in JACKKNIFE_COLUMNS):
                <name> of each leave-one-out ensemble of a wave table's N realizations (k: all
                but realization k, reduced and refined as the table is), from which a derived
                quantity's jackknife standard error is computed (solver/table/jackknife.py)
    meta        JSON string (schema_version, polarisation, ink, particles, thickness_nm,
                generator, settings, seeds, error estimates, tier, ...)

Rbar and Tbar include the coherent (00) orders; Rbar = R_spec + hemispherical integral of R.
All angular integrals use `solver.table.integrals` (exact for the linear interpolant).

Polarisation (v2; docs/polarisation.md).  meta "polarisation" is "unpolarised" (every column
is the mean (s + p)/2 of the s and p power fractions) or "te" (s light only: the scalar model
as it is); absent means "te" (the scalar wave tiers' tables).  An "unpolarised" table may add, in pairs:

    r_s, r_p        [nλ, nσ] complex128: amplitude reflection coefficients of the mirror beam,
                    in Mitsuba's `fresnel_polarized` convention (a_s, a_p: Verdet sign of a_p,
                    η = n − iκ phases), reference plane the layer's top face;
                    (|r_s|² + |r_p|²)/2 = R_spec
    Rbar_s, Rbar_p  [nλ, nσ] real: s and p parts of Rbar, (Rbar_s + Rbar_p)/2 = Rbar
    Tbar_s, Tbar_p  [nλ, nσ] real: s and p parts of Tbar, (Tbar_s + Tbar_p)/2 = Tbar

Version 1 files (no polarisation key, no s/p arrays) still read, as polarisation "te".
The `_jack` arrays are optional and additive: tables without them read as before (no
jackknife), and a reader that does not know them ignores them, so they need no version bump.
"""

from __future__ import annotations

import io
import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .atomic import atomic_savez
from .integrals import diffuse_albedo, hemispherical_mean

SCHEMA_VERSION = 2
READABLE_VERSIONS = (1, 2)
POLARISATIONS = ("unpolarised", "te")        # meta "polarisation" of a v2 table
UNSTATED_POLARISATION = "te"                 # v1 tables, and v2 tables without the key
COLUMNS = ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below")
GRIDS = ("wavelengths", "sigma", "theta", "dphi")
SP_AMPLITUDES = ("r_s", "r_p")                         # optional, complex [nλ, nσ]
SP_COLUMNS = ("Rbar_s", "Rbar_p", "Tbar_s", "Tbar_p")  # optional, real [nλ, nσ]
SP_PAIRS = (("r_s", "r_p"), ("Rbar_s", "Rbar_p"), ("Tbar_s", "Tbar_p"))
#: the columns a colour reads (solver/colour/measurement.py `reflectance`, and the transmitted
#: colour's Tbar), stored per leave-one-out ensemble as `<name>_jack` (optional)
JACKKNIFE_COLUMNS = ("R_spec", "T_coh", "Rbar", "Tbar", "Rbar_below", "R")
JACKKNIFE_SUFFIX = "_jack"
JACKKNIFE_DTYPE = np.float32          # the spread between replicas is ≥ 1e-4; float32 keeps 1e-7
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
    r_s: np.ndarray | None = None        # optional s/p split of an unpolarised table (see above)
    r_p: np.ndarray | None = None
    Rbar_s: np.ndarray | None = None
    Rbar_p: np.ndarray | None = None
    Tbar_s: np.ndarray | None = None
    Tbar_p: np.ndarray | None = None
    #: {column: [N, *column shape]}: the column in each leave-one-out ensemble (see above); None: none
    jackknife: dict | None = None

    @property
    def polarisation(self) -> str:
        """"unpolarised" or "te" (unstated, as in every version 1 table: "te", the scalar
        model's s light)."""
        return self.meta.get("polarisation", UNSTATED_POLARISATION)

    @property
    def sp_arrays(self) -> dict:
        """{name: array} of the optional s/p arrays this table holds."""
        return {n: getattr(self, n) for n in SP_AMPLITUDES + SP_COLUMNS if getattr(self, n) is not None}

    @property
    def has_diffuse(self) -> bool:
        """False when the layer scatters nothing diffusely (R ≡ 0): the plugin skips R then."""
        return bool(np.any(self.R != 0.0))

    def column(self, name: str) -> np.ndarray:
        return getattr(self, name)


def _check(cond: bool, where: str, msg: str) -> None:
    if not cond:
        raise TableError(f"{where}: {msg}")


#: standard errors by which the from-below energy sum may exceed 1 (two independent estimates)
BELOW_SE_MULTIPLE = 2.0


def _closure(table: InkTable) -> float:
    """How far R + T may exceed 1: round-off plus the solver's energy closure stored in meta
    (one polarisation's totals carry the same closure as their mean)."""
    return _ENERGY_TOL * 10 + float(table.meta.get("errors", {}).get("energy_closure_max") or 0.0)


def energy_excess(table: InkTable) -> dict[str, np.ndarray]:
    """Per wavelength, how far the table breaks energy beyond what it may ({sum: [λ]}; ≤ 0 where
    it holds): R̄ + T̄ − 1 from above, and per polarisation where the table has s and p (worst σ),
    past the solver's closure; from below the cosine-weighted R̄_below + T̄ − 1 past the closure
    and its sampling allowance (key "Rbar_below + Tbar")."""
    closure = _closure(table)
    out = {"Rbar + Tbar": np.max(table.Rbar + table.Tbar - 1.0, axis=1) - closure}
    sp = table.sp_arrays
    for pol in ("s", "p"):
        if f"Rbar_{pol}" in sp and f"Tbar_{pol}" in sp:
            out[f"Rbar_{pol} + Tbar_{pol}"] = np.max(sp[f"Rbar_{pol}"] + sp[f"Tbar_{pol}"] - 1.0, axis=1) - closure
    # From below, per angle, Tbar (from above) is not the transmittance: for a layer whose faces
    # differ (a rough top, a stack) T_below(s) ≠ T_above(s).  Reciprocity equates them only
    # cosine-weighted over the hemisphere, which is what light coming back from the paper sees:
    # 2∫(Rbar_below + Tbar) cos s sin s ds ≤ 1 (docs/design.md §1).
    # Rbar_below and Tbar come from different solves (from below, from above) of the same cells,
    # so their sum is only as close to energy conservation as their standard errors allow.
    sampling = np.zeros(table.wavelengths.size)
    if "Rbar_below" in table.errors and "Tbar" in table.errors:
        both = np.nan_to_num(table.errors["Rbar_below"]) + np.nan_to_num(table.errors["Tbar"])
        sampling = BELOW_SE_MULTIPLE * hemispherical_mean(table.sigma, both)
    out["Rbar_below + Tbar"] = hemispherical_mean(table.sigma, table.Rbar_below + table.Tbar) - 1.0 - sampling - closure
    return out


def validate(table: InkTable, where: str = "table") -> InkTable:
    """Check shapes, finiteness, grids, physical ranges and version; return the table."""
    meta = table.meta
    _check(isinstance(meta, dict), where, "meta must be a JSON object")
    version = meta.get("schema_version")
    _check(not isinstance(version, (str, bool)), where,
           f"schema version {version!r} is a {type(version).__name__}; expected an integer "
           f"{' or '.join(map(str, READABLE_VERSIONS))}")
    _check(version in READABLE_VERSIONS, where, f"schema version {version!r} is not supported "
           f"(this reader reads versions {', '.join(map(str, READABLE_VERSIONS))})")
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
    _validate_jackknife(table, where)
    _validate_polarisation(table, where, version)      # the s/p arrays' kinds before their energy sums
    for total, coherent in (("Rbar", "R_spec"), ("Tbar", "T_coh")):
        excess = float(np.max(table.column(coherent) - table.column(total)))
        _check(excess <= _ENERGY_TOL, where, f"'{coherent}' exceeds '{total}' by {excess:.3g}")
    errors = meta.get("errors", {})
    closure = _closure(table)
    for total, excess in energy_excess(table).items():
        first, second = (f"'{n}'" for n in total.split(" + "))
        why = (f" under diffuse light from below (beyond {BELOW_SE_MULTIPLE:g} standard errors)"
               if total.startswith("Rbar_below") else "")
        _check(float(np.max(excess)) <= 0.0, where,
               f"{first} + {second} exceeds 1 by {float(np.max(excess)) + closure:.3g}{why}")
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


def _validate_jackknife(table: InkTable, where: str) -> None:
    """The optional leave-one-out columns: known names, one count N ≥ 2 of replicas, each shaped
    like its column, finite."""
    jack = table.jackknife
    if jack is None:
        return
    _check(isinstance(jack, dict) and bool(jack), where, "'jackknife' must be a non-empty dict of arrays or None")
    counts = set()
    for name, arr in jack.items():
        _check(name in JACKKNIFE_COLUMNS, where, f"unknown jackknife column '{name}{JACKKNIFE_SUFFIX}' "
               f"(known: {', '.join(JACKKNIFE_COLUMNS)})")
        shape = table.column(name).shape
        _check(np.ndim(arr) == len(shape) + 1 and np.shape(arr)[1:] == shape, where,
               f"'{name}{JACKKNIFE_SUFFIX}' has shape {np.shape(arr)}, expected (replicas, *{shape})")
        _check(bool(np.all(np.isfinite(arr))), where, f"'{name}{JACKKNIFE_SUFFIX}' has non-finite values")
        counts.add(np.shape(arr)[0])
    _check(len(counts) == 1 and min(counts) >= 2, where,
           f"the jackknife arrays must share one replica count ≥ 2, got {sorted(counts)}")


def _validate_polarisation(table: InkTable, where: str, version: int) -> None:
    """meta "polarisation" and the optional s/p arrays: shapes, finiteness, ranges, and their
    consistency with the unpolarised columns (docs/polarisation.md)."""
    sp = table.sp_arrays
    if version == 1:
        _check("polarisation" not in table.meta and not sp, where,
               "a schema version 1 table has no polarisation data (write it as version 2)")
        return
    pol = table.polarisation
    _check(pol in POLARISATIONS, where, f"meta 'polarisation' is {pol!r}; expected one of "
           f"{', '.join(map(repr, POLARISATIONS))}")
    _check(pol == "unpolarised" or not sp, where,
           f"a '{pol}' table cannot hold s/p arrays ({', '.join(sp)})")
    shape = table.R_spec.shape
    for a, b in SP_PAIRS:
        _check((a in sp) == (b in sp), where, f"'{a}' and '{b}' come in pairs; only '{a if a in sp else b}' given")
    for name, arr in sp.items():
        _check(np.shape(arr) == shape, where, f"'{name}' has shape {np.shape(arr)}, expected {shape}")
        _check(np.iscomplexobj(arr) == (name in SP_AMPLITUDES), where,
               f"'{name}' must be {'complex' if name in SP_AMPLITUDES else 'real'}, dtype is {np.asarray(arr).dtype}")
        bad = ~np.isfinite(arr)
        _check(not bad.any(), where, f"'{name}' has {int(bad.sum())} non-finite values")
        power = np.abs(arr) ** 2 if name in SP_AMPLITUDES else np.asarray(arr)
        _check(float(power.min()) >= -_ENERGY_TOL and float(power.max()) <= 1 + _ENERGY_TOL, where,
               f"'{name}' {'|·|² ' if name in SP_AMPLITUDES else ''}is outside [0, 1] "
               f"(range {power.min():.6g}..{power.max():.6g})")
    checks = [("Rbar_s", "Rbar_p", "Rbar", lambda x: x), ("Tbar_s", "Tbar_p", "Tbar", lambda x: x),
              ("r_s", "r_p", "R_spec", lambda x: np.abs(x) ** 2)]
    for s_name, p_name, column, power in checks:
        if s_name in sp:
            mean = 0.5 * (power(sp[s_name]) + power(sp[p_name]))
            off = float(np.max(np.abs(mean - table.column(column))))
            what = f"(|{s_name}|² + |{p_name}|²)/2" if s_name in SP_AMPLITUDES else f"({s_name} + {p_name})/2"
            _check(off <= _ENERGY_TOL, where, f"{what} differs from '{column}' by {off:.3g}")
    for pol_ in ("s", "p"):
        if f"r_{pol_}" in sp and f"Rbar_{pol_}" in sp:
            excess = float(np.max(np.abs(sp[f"r_{pol_}"]) ** 2 - sp[f"Rbar_{pol_}"]))
            _check(excess <= _ENERGY_TOL, where, f"'|r_{pol_}|²' exceeds 'Rbar_{pol_}' by {excess:.3g}")


def write_table(path, table: InkTable) -> Path:
    """Validate and write atomically (temp file + rename: readers never see a partial file)."""
    path = Path(path)
    validate(table, str(path))
    arrays = {name: np.asarray(getattr(table, name), dtype=np.float64) for name in GRIDS + COLUMNS}
    arrays["R"] = np.asarray(table.R, dtype=np.float64)
    for name, arr in table.errors.items():
        arrays[f"{name}_err"] = np.asarray(arr, dtype=np.float64)
    for name, arr in table.sp_arrays.items():
        arrays[name] = np.asarray(arr, dtype=np.complex128 if name in SP_AMPLITUDES else np.float64)
    for name, arr in (table.jackknife or {}).items():
        arrays[f"{name}{JACKKNIFE_SUFFIX}"] = np.asarray(arr, dtype=JACKKNIFE_DTYPE)
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
    except OSError as exc:
        raise TableError(f"{where}: cannot read the table ({exc.strerror})") from None
    if not raw.startswith(b"PK"):                     # not a zip: np.load would talk of pickles
        kind = ("empty" if not raw else "a PNG image" if raw.startswith(b"\x89PNG") else
                "a single NumPy array (.npy)" if raw.startswith(b"\x93NUMPY") else "not a zip archive")
        raise TableError(f"{where}: not an ink table (.npz, written by `ink-tables build`): the file is {kind}")
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as npz:
            data = {k: npz[k] for k in npz.files}
    except (zipfile.BadZipFile, EOFError, OSError, ValueError) as exc:
        raise TableError(f"{where}: not a readable .npz table (truncated or corrupt: {exc})") from None
    missing = [k for k in GRIDS + COLUMNS + ("R", "meta") if k not in data]
    _check(not missing, where, f"missing arrays: {', '.join(missing)}")
    _check(data["meta"].dtype.kind in "US" and data["meta"].ndim == 0, where,
           f"'meta' must be one JSON string, got dtype {data['meta'].dtype}, shape {data['meta'].shape}")
    try:
        meta = json.loads(str(data["meta"]))
    except json.JSONDecodeError as exc:
        raise TableError(f"{where}: 'meta' is not valid JSON ({exc})") from None
    real = GRIDS + COLUMNS + ("R",) + tuple(k for k in SP_COLUMNS if k in data)
    errors = {k[:-4]: _numbers(data[k], k, where, complex_ok=False) for k in data if k.endswith("_err")}
    arrays = {k: _numbers(data[k], k, where, complex_ok=False) for k in real}
    arrays.update({k: _numbers(data[k], k, where, complex_ok=True) for k in SP_AMPLITUDES if k in data})
    jack = {k[:-len(JACKKNIFE_SUFFIX)]: _numbers(data[k], k, where, complex_ok=False).astype(JACKKNIFE_DTYPE)
            for k in data if k.endswith(JACKKNIFE_SUFFIX)}
    return validate(InkTable(**arrays, meta=meta, errors=errors, jackknife=jack or None), where)


def _numbers(arr: np.ndarray, name: str, where: str, complex_ok: bool) -> np.ndarray:
    """A stored array as float64 (complex128 where `complex_ok`), refusing strings, booleans
    and a complex array where a real one belongs (its imaginary part would be lost)."""
    kind = arr.dtype.kind
    _check(kind not in "USO", where, f"'{name}' holds text (dtype {arr.dtype}); expected numbers")
    _check(kind in "iufc", where, f"'{name}' has dtype {arr.dtype}; expected numbers")
    if complex_ok:
        return arr.astype(np.complex128)
    _check(kind != "c", where, f"'{name}' is complex (dtype {arr.dtype}); it must be real "
           "(reading it would drop the imaginary part)")
    return arr.astype(np.float64)
