"""The map of the default tables against Maxwell on the same voxel grid (issue 22 item 3;
docs/vector_referee.md, "RCWA on the voxel grid").

Per case (an ink and its grains, as a table request of the project), realization, λ and σ:

* Maxwell: grcwa's RCWA (rcwa_layer.py) of the realization's voxel grid with the pigments'
  bulk ε (the local field is Maxwell's own doing), s and p;
* the default tables' scalar solve, as solver/table/wave_tier.py does it: the same voxels with
  the grains' local-field ε, ε_b and the faces' ε_f the layer's nominal ε, TE and TM with the
  default face forms (and, for the TM study, other presets: `variants`).

The colour is docs/design.md eq. (4) on paper r = 0.9 under diffuse light (compare.py: the
same reduction for both solvers), ΔE2000 of the unpolarised ink at each view θ = σ node.

Cost (2-core VM, one BLAS thread): a 790-nm cell on 24 × 24 × 32 voxels (33 × 33 × 31 nm,
the tables' default voxel), 69 RCWA orders: ≈ 3–8 s per (λ, σ) for both polarisations; the
scalar solves ≈ 0.2 s each.  Units are cached in out/bench/vector_voxel/.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.geometry import eps_grid
from solver.materials import default_materials
from solver.table.request import table_request
from solver.table.wave_tier import (GeometryUnit, cell_eps, face_eps, geometry_unit,
                                    nominal_eps, tm_faces)
from solver.wave import Cell, Incidence, bloch_vector, prepare, solve_prepared
from solver.wave.interfaces import mean_profile
from solver.wave.vecops import one_blas_thread

from .compare import Ensemble, albedo_on_paper, delta_e2000, lab_of
from .rcwa_layer import rcwa_rt

CACHE = Path("out/bench/vector_voxel")
WAVELENGTHS = (400.0, 430.0, 460.0, 490.0, 520.0, 560.0, 620.0, 700.0)   # a colour: 400–700
VIEWS_DEG = (0.0, 30.0, 45.0, 60.0, 75.0)
#: 790 nm, not 800: order (2, 0) of an 800-nm cell grazes at 400 nm and normal incidence
#: (k_z = 0 exactly), where grcwa's uniform layers are singular
CELL_NM, GRID = 790.0, (24, 24, 32)


@dataclass(frozen=True)
class MapCase:
    """One case of the map: ink (volume %), grains, realizations."""

    ink: str
    particles: str
    realizations: int = 1

    @property
    def label(self) -> str:
        return f"{self.ink} {self.particles}"

    @property
    def key(self) -> str:
        return f"{self.ink}_{self.particles}".replace(":", "-").replace("+", "p")

    def request(self):
        return table_request(self.ink, self.particles, cell_nm=CELL_NM, grid=GRID,
                             realizations=self.realizations)


def cases(realizations: int = 1) -> tuple[MapCase, ...]:
    """Spheres of 200 nm and isotropic cylinders of 100 nm, pigment Y at 15, 30, 50 %."""
    return tuple(MapCase(f"Y{c}", p, realizations) for p in ("sphere:200", "cylinder:100")
                 for c in (15, 30, 50))


CASES = cases()


def rough_cases(realizations: int = 1) -> tuple[MapCase, ...]:
    """Rough tops (200-nm Y spheres standing out of the binder) at 15 and 30 %: the strongest
    mean profile, air between the grains at the top."""
    return tuple(MapCase(f"Y{c}", "sphere:200:rough", realizations) for c in (15, 30))


def _path(case: MapCase, solver: str, r: int, lam: float, sig: float) -> Path:
    grid = "x".join(map(str, GRID))
    return CACHE / f"{case.key}_cell{CELL_NM:g}_{grid}" / f"{solver}_r{r}_l{lam:g}_s{sig:g}.npz"


def tm_conditions(req, lam: float, eps: np.ndarray, faces_kind: str):
    """The TM conditions of a scalar variant (scalar_solver): 'scalar' the default tables'
    (wave_tier.tm_faces), 'layer' each layer's own ε on its faces (wave_tier.face_eps: the
    tables' rule before rough tops got their profile), 'profile<merge>' the realization's mean
    profile merged by <merge> (solver.wave.interfaces.mean_profile; 'profile' = every z-cell)."""
    if faces_kind == "scalar":
        return tm_faces(req, lam, eps)
    if faces_kind == "layer":
        return face_eps(req, lam)
    return mean_profile(eps, float(faces_kind.removeprefix("profile") or 0.0))


def _scalar(req, vox, lam: float, sig: float, preset: str, faces_kind: str) -> np.ndarray:
    """[R_TE, R_TM], [T_TE, T_TM] of the scalar solves at azimuth 0 with the TM conditions of
    faces_kind (tm_conditions)."""
    cell = Cell(cell_eps(req, vox, lam), tuple(vox.period_nm), tuple(vox.z_range_nm))
    kx0, ky0 = bloch_vector(cell, Incidence(lam, math.radians(sig)))
    faces = tm_conditions(req, lam, cell.eps, faces_kind)
    out = np.zeros((2, 2))
    for i, pol in enumerate(("te", "tm")):
        op = prepare(cell, lam, kx0, ky0, eps_background=nominal_eps(req, lam),
                     eps_face=faces, polarisation=pol, tm_faces=preset)
        res = solve_prepared(op, tol=1e-5)
        out[:, i] = res.R, res.T
    return out


def unit(case: MapCase, solver: str, r: int, lam: float, sig: float) -> np.ndarray:
    """[[R_s, R_p], [T_s, T_p]] of one unit, cached; solver 'rcwa' or '<kind>:<preset>'
    (scalar_solver)."""
    path = _path(case, solver, r, lam, sig)
    if path.exists():
        return np.load(path)["rt"]
    req = case.request()
    vox = geometry_unit(GeometryUnit(req, r))
    with one_blas_thread():
        if solver == "rcwa":
            eps = eps_grid(vox, lam, default_materials())
            res = rcwa_rt(eps, tuple(vox.period_nm), float(np.diff(vox.z_range_nm)[0]), lam,
                          math.radians(sig))
            rt = np.array([res.R, res.T])
        else:
            kind, preset = solver.split(":", 1)
            rt = _scalar(req, vox, lam, sig, preset, kind)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, rt=rt)
    return rt


def ensemble(case: MapCase, solver: str, compute: bool) -> Ensemble | None:
    """The case's ensemble over its realizations (None when a unit is missing and not
    computed)."""
    nl, ns = len(WAVELENGTHS), len(VIEWS_DEG)
    R, T = np.full((nl, ns, 3), np.nan), np.full((nl, ns, 3), np.nan)
    for i, lam in enumerate(WAVELENGTHS):
        for j, sig in enumerate(VIEWS_DEG):
            rts = []
            for r in range(case.realizations):
                if not compute and not _path(case, solver, r, lam, sig).exists():
                    return None
                rts.append(unit(case, solver, r, lam, sig))
            mean = np.mean(rts, axis=0)
            R[i, j, :2], T[i, j, :2] = mean[0], mean[1]
    R[..., 2], T[..., 2] = R[..., :2].mean(axis=-1), T[..., :2].mean(axis=-1)
    nan = np.full_like(R, np.nan)
    return Ensemble(np.asarray(WAVELENGTHS), np.asarray(VIEWS_DEG), R, T, nan, nan, nan)


def delta_e(vec: Ensemble, sca: Ensemble) -> dict[str, np.ndarray]:
    """ΔE2000 per view: 's' (TE vs s), 'p' (TM vs p), 'unpol'."""
    return {name: delta_e2000(lab_of(vec, k), lab_of(sca, k)) for k, name in enumerate(("s", "p", "unpol"))}


def scalar_solver(variant: str) -> str:
    """The cache name of a scalar variant: '<preset>' is the tables' TM with that face preset,
    '<preset>/layer' each layer's own faces, '<preset>/profile[<merge>]' the mean profile
    (tm_conditions)."""
    preset, _, kind = variant.partition("/")
    try:
        if kind.startswith("profile"):
            kind = f"profile{float(kind.removeprefix('profile') or 0.0):g}"
        elif kind not in ("", "layer"):
            raise ValueError(kind)
    except ValueError:
        raise ValueError(f"a scalar variant is '<preset>', '<preset>/layer' or "
                         f"'<preset>/profile[<merge>]', got {variant!r}") from None
    return f"{kind or 'scalar'}:{preset}"


def run(cases=CASES, compute_until: float | None = None, presets=("brewster",)) -> list[dict]:
    """Rows per case and scalar variant (scalar_solver): ΔE per view and polarisation, the
    largest |ΔRbar|, |ΔTbar| per polarisation; missing rows (time up) are reported as such."""
    rows = []
    for case in cases:
        for preset in presets:
            compute = compute_until is None or time.monotonic() < compute_until
            t0 = time.perf_counter()
            vec = ensemble(case, "rcwa", compute)
            sca = ensemble(case, scalar_solver(preset), compute) if vec is not None else None
            if vec is None or sca is None:
                rows.append(dict(case=case.label, preset=preset, missing=True))
                continue
            de = delta_e(vec, sca)
            rows.append(dict(case=case.label, preset=preset, missing=False, de=de,
                             dR=np.nanmax(np.abs(sca.Rbar - vec.Rbar), axis=(0, 1)),
                             dT=np.nanmax(np.abs(sca.Tbar - vec.Tbar), axis=(0, 1)),
                             dR_by_view=np.nanmax(np.abs(sca.Rbar - vec.Rbar), axis=0),
                             albedo=(albedo_on_paper(vec, 2), albedo_on_paper(sca, 2)),
                             seconds=time.perf_counter() - t0))
    return rows


def picture(rows: list[dict], path: Path) -> None:
    """ΔE2000 (unpolarised) per case (rows) and view (columns), annotated."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    done = [r for r in rows if not r["missing"] and r["preset"] == "brewster"]
    if not done:
        return
    grid = np.array([r["de"]["unpol"] for r in done])
    fig, ax = plt.subplots(figsize=(6.4, 0.5 * len(done) + 1.4))
    im = ax.imshow(grid, cmap="RdYlGn_r", vmin=0.0, vmax=2.0, aspect="auto")
    for (i, j), v in np.ndenumerate(grid):
        ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=9)
    ax.set_xticks(range(len(VIEWS_DEG)), [f"{v:g}°" for v in VIEWS_DEG])
    ax.set_yticks(range(len(done)), [r["case"] for r in done])
    ax.set_xlabel("view angle")
    ax.set_title("ΔE2000, default tables vs Maxwell (RCWA, same voxels)", fontsize=10)
    fig.colorbar(im, ax=ax, label="ΔE2000")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


#: the oblique TM study (issue 22 item 2): a dilute layer of 200-nm Y spheres (≈ 10 %), a
#: transparent and an absorbing wavelength, σ from below to beyond Brewster's angle (≈ 57°)
OBLIQUE_CASE = MapCase("Y10", "sphere:200")
OBLIQUE_PRESETS = ("brewster", "brewster/profile", "electric-propagating", "electric", "all")


#: the merge tolerances of a rough top's mean profile measured by rough_profile_study
ROUGH_MERGES = (0.0, 0.02, 0.05, 0.1, 0.2)


def rough_profile_study(realizations: int = 2, merges=ROUGH_MERGES) -> list[dict]:
    """The rough top's TM conditions as an accuracy knob: per merge tolerance, the unpolarised
    ΔE2000 against Maxwell (the rough cases, max over the views), the TM layers and the cost of
    one TM solve pair (above and below) on the default table's grid (Y30 sphere:200:rough,
    560 nm, 45° and 75°, its tolerance); the layer's own faces ('layer') for comparison."""
    from solver.apps.figures.cells import FigureSettings

    req = FigureSettings("default").request("Y30", "sphere:200:rough")
    vox = geometry_unit(GeometryUnit(req, 0))
    lam = 560.0
    cell = Cell(cell_eps(req, vox, lam), tuple(vox.period_nm), tuple(vox.z_range_nm))
    rows = []
    for kind in ("layer",) + tuple(f"profile{m:g}" for m in merges):
        faces = tm_conditions(req, lam, cell.eps, kind)
        seconds, apps = 0.0, 0
        with one_blas_thread():
            for sig in (45.0, 75.0):
                kx0, ky0 = bloch_vector(cell, Incidence(lam, math.radians(sig)))
                t0 = time.process_time()
                op = prepare(cell, lam, kx0, ky0, eps_background=nominal_eps(req, lam),
                             eps_face=faces, polarisation="tm", workers=1)
                for below in (False, True):
                    apps += solve_prepared(op, below, tol=req.wave.solver_tol).applications
                seconds += time.process_time() - t0
        de = {}
        for case in rough_cases(realizations):
            vec, sca = ensemble(case, "rcwa", True), ensemble(case, f"{kind}:brewster", True)
            de[case.label] = delta_e(vec, sca)["unpol"]
        rows.append(dict(kind=kind, layers=len(faces.cells), seconds=seconds / 2, applications=apps / 2, de=de))
    return rows


def oblique_study(wavelengths=(700.0, 470.0), angles=(30.0, 50.0, 60.0, 70.0),
                  presets=OBLIQUE_PRESETS) -> None:
    """p-polarised R, T of Maxwell (RCWA) and the scalar TM error per face preset: which face
    form of which class of harmonics carries the oblique error."""
    print(f"oblique TM: {OBLIQUE_CASE.label}, cell {CELL_NM:g} nm, grid {GRID}, realization 0, "
          f"azimuth 0; Δ = scalar TM (local field, preset) − Maxwell p")
    for lam in wavelengths:
        for sig in angles:
            vec = unit(OBLIQUE_CASE, "rcwa", 0, lam, sig)
            line = f"λ {lam:g} σ {sig:g}: Maxwell p R {vec[0, 1]:.4f} T {vec[1, 1]:.4f}"
            for preset in presets:
                sca = unit(OBLIQUE_CASE, scalar_solver(preset), 0, lam, sig)
                line += f" | {preset}: ΔR {sca[0, 1] - vec[0, 1]:+.4f} ΔT {sca[1, 1] - vec[1, 1]:+.4f}"
            print(line, flush=True)
