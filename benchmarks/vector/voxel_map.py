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
                                    nominal_eps)
from solver.wave import Cell, Incidence, bloch_vector, prepare, solve_prepared
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


def _path(case: MapCase, solver: str, r: int, lam: float, sig: float) -> Path:
    grid = "x".join(map(str, GRID))
    return CACHE / f"{case.key}_cell{CELL_NM:g}_{grid}" / f"{solver}_r{r}_l{lam:g}_s{sig:g}.npz"


def _scalar(req, vox, lam: float, sig: float, preset: str) -> np.ndarray:
    """[R_TE, R_TM], [T_TE, T_TM] of the default table's solves at azimuth 0."""
    cell = Cell(cell_eps(req, vox, lam), tuple(vox.period_nm), tuple(vox.z_range_nm))
    kx0, ky0 = bloch_vector(cell, Incidence(lam, math.radians(sig)))
    out = np.zeros((2, 2))
    for i, pol in enumerate(("te", "tm")):
        op = prepare(cell, lam, kx0, ky0, eps_background=nominal_eps(req, lam),
                     eps_face=face_eps(req, lam), polarisation=pol, tm_faces=preset)
        res = solve_prepared(op, tol=1e-5)
        out[:, i] = res.R, res.T
    return out


def unit(case: MapCase, solver: str, r: int, lam: float, sig: float) -> np.ndarray:
    """[[R_s, R_p], [T_s, T_p]] of one unit, cached; solver 'rcwa' or 'scalar:<preset>'."""
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
            rt = _scalar(req, vox, lam, sig, solver.split(":", 1)[1])
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


def run(cases=CASES, compute_until: float | None = None, presets=("brewster",)) -> list[dict]:
    """Rows per case and preset: ΔE per view and polarisation, the largest |ΔRbar|, |ΔTbar|
    per polarisation; missing rows (time up) are reported as such."""
    rows = []
    for case in cases:
        for preset in presets:
            compute = compute_until is None or time.monotonic() < compute_until
            t0 = time.perf_counter()
            vec = ensemble(case, "rcwa", compute)
            sca = ensemble(case, f"scalar:{preset}", compute) if vec is not None else None
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
OBLIQUE_PRESETS = ("brewster", "electric-propagating", "electric", "all")


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
                sca = unit(OBLIQUE_CASE, f"scalar:{preset}", 0, lam, sig)
                line += f" | {preset}: ΔR {sca[0, 1] - vec[0, 1]:+.4f} ΔT {sca[1, 1] - vec[1, 1]:+.4f}"
            print(line, flush=True)
