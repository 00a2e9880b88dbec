"""The scalar solver's TM face forms (solver.wave.faces presets) against the vector referee.

Printed by `python -m benchmarks.bench_vector --faces` (docs/vector_referee.md, "TM faces"):

1. per preset and pigment ε model ('volume', 'localfield'), on every cached case: the p (TM)
   errors of Rbar, Tbar, R_spec against Maxwell's p (max and rms over λ, σ); the normal-
   incidence symmetry max_λ |R_spec(TM) − R_spec(TE)| (Maxwell: |p − s|, the cell's own
   anisotropy); the ink-on-paper ΔE2000 (unpolarised and p) at the computed view angles;
2. per realization, where a case has several in the cache: the ΔE2000 of each, and between
   the vector realizations themselves (the noise of one realization's colour);
3. physics checks of each preset on small random cells: reciprocity of the diffuse orders'
   powers, averaged over realizations (P(a→b)/P(b̄→ā) should be 1), and the jump of R across
   a Wood anomaly (σ_W ± 1e-7 rad) on the 300-nm, 15 % referee cell at 470 nm.
"""
from __future__ import annotations

import math

import numpy as np

from solver.wave import Cell, Incidence, TM_FACE_PRESETS, solve
from solver.wave.validation import random_layer

from . import compare, runs
from .cases import Case

POL_P, POL_UNPOL = 1, 2


def cached_realizations(case: Case, limit: int = 8) -> int:
    """How many realizations (0, 1, …) have every vector unit of the case in the cache."""
    n = 0
    while n < limit and all(runs.vector_unit(case, n, lam, sig, compute=False) is not None
                            for lam in case.wavelengths_nm for sig in case.polar_deg):
        n += 1
    return n


def _ensemble(case: Case, units_fn, realizations) -> compare.Ensemble:
    units = [[[units_fn(r, lam, sig) for r in realizations] for sig in case.polar_deg]
             for lam in case.wavelengths_nm]
    return compare.reduce_units(units, case.wavelengths_nm, case.polar_deg)


def is_colour_case(case: Case) -> bool:
    return len(case.wavelengths_nm) >= 3 and len(case.polar_deg) >= 2


def metrics(case: Case, ev: compare.Ensemble, es: compare.Ensemble) -> dict:
    out = {}
    for q in ("Rbar", "Tbar", "R_spec"):
        d = getattr(es, q)[..., POL_P] - getattr(ev, q)[..., POL_P]
        out[q] = (float(np.max(np.abs(d))), float(np.sqrt(np.mean(d ** 2))))
    j0 = list(case.polar_deg).index(0.0)
    out["sym"] = float(np.max(np.abs(es.R_spec[:, j0, 1] - es.R_spec[:, j0, 0])))
    out["sym_vector"] = float(np.max(np.abs(ev.R_spec[:, j0, 1] - ev.R_spec[:, j0, 0])))
    if is_colour_case(case):
        for pol, name in ((POL_UNPOL, "dE_unpol"), (POL_P, "dE_p")):
            out[name] = compare.delta_e2000(compare.lab_of(ev, pol), compare.lab_of(es, pol))
    return out


def evaluate(cases, presets=tuple(TM_FACE_PRESETS), materials=("volume", "localfield")) -> dict:
    """Print table 1 (and 2 where a case has several realizations); returns the metrics
    {(case index, material, preset): dict}."""
    results = {}
    for ci, case in enumerate(cases):
        n_real = cached_realizations(case)
        if n_real == 0:
            print(f"\n--- {case.label}: vector units missing (run --compute first)")
            continue
        reals = range(n_real)
        ev = _ensemble(case, lambda r, lam, sig: runs.vector_unit(case, r, lam, sig, compute=False),
                       reals)
        print(f"\n--- {case.label}: λ {list(case.wavelengths_nm)} nm, σ {list(case.polar_deg)}°, "
              f"{n_real} realization(s); p = TM vs Maxwell's p; sym = max_λ |R_spec TM − TE| at "
              f"σ 0 (Maxwell |p − s|)")
        head = (f"  {'ε model':10s} {'tm_faces':21s}| Rbar max   rms | Tbar max   rms | Rspec max  "
                f"rms |  sym (vector)")
        if is_colour_case(case):
            head += " | ΔE2000 unpol " + "/".join(f"{s:g}°" for s in case.polar_deg) + " | ΔE2000 p"
        print(head)
        for material in materials:
            for preset in presets:
                es = _ensemble(case, lambda r, lam, sig: runs.scalar_unit(
                    case, r, lam, sig, material, preset), reals)
                m = metrics(case, ev, es)
                results[(ci, material, preset)] = m
                line = (f"  {material:10s} {preset:21s}| " + " | ".join(
                    f"{m[q][0]:.4f} {m[q][1]:.4f}" for q in ("Rbar", "Tbar", "R_spec")) +
                    f" | {m['sym']:.4f} ({m['sym_vector']:.4f})")
                if "dE_unpol" in m:
                    line += (" | " + " ".join(f"{x:5.2f}" for x in m["dE_unpol"]) + " | " +
                             " ".join(f"{x:5.2f}" for x in m["dE_p"]))
                print(line)
        if n_real > 1 and is_colour_case(case):
            per_realization(case, n_real, presets, materials)
    return results


def per_realization(case: Case, n_real: int, presets, materials) -> None:
    """ΔE2000 (unpolarised) per realization, and between the vector realizations."""
    vec = [_ensemble(case, lambda r, lam, sig: runs.vector_unit(case, r, lam, sig,
                                                                 compute=False), [r])
           for r in range(n_real)]
    labs = [compare.lab_of(e, POL_UNPOL) for e in vec]
    print("  realization noise: ΔE2000 (unpolarised) between the vector realizations r0 and "
          "r{1…}: " + "; ".join(f"r{r}: " + " ".join(f"{x:.2f}" for x in
                                                     compare.delta_e2000(labs[0], labs[r]))
                                for r in range(1, n_real)))
    print("  per realization, ΔE2000 unpolarised scalar vs vector at " +
          "/".join(f"{s:g}°" for s in case.polar_deg) + ":")
    for material in materials:
        for preset in presets:
            parts = []
            for r in range(n_real):
                es = _ensemble(case, lambda rr, lam, sig: runs.scalar_unit(
                    case, rr, lam, sig, material, preset), [r])
                de = compare.delta_e2000(labs[r], compare.lab_of(es, POL_UNPOL))
                parts.append(f"r{r} " + " ".join(f"{x:5.2f}" for x in de))
            print(f"    {material:10s} {preset:21s}| " + " | ".join(parts))


#: (σ, φ, order) pairs of the reciprocity check: order (m, n) of incidence (σ, φ) in radians
RECIPROCITY_PAIRS = ((0.3, 0.4, (1, 0)), (0.3, 0.4, (-1, 1)), (0.0, 0.0, (1, 1)),
                     (1.0, 0.2, (-1, 0)), (0.6, 1.0, (0, -1)))


def reciprocity(preset: str, seeds: int = 12, wavelength_nm: float = 500.0) -> np.ndarray:
    """Σ_realizations P(a→b) / Σ P(b̄→ā) for the reflected orders of RECIPROCITY_PAIRS on
    validation.random_layer(1.4 + 0.1i) cells (24×24×12), TM with `preset`."""
    k0 = 2 * math.pi / wavelength_nm
    fw, bw = np.zeros(len(RECIPROCITY_PAIRS)), np.zeros(len(RECIPROCITY_PAIRS))
    for seed in range(seeds):
        cell = random_layer(1.4 + 0.1j, seed=seed, shape=(24, 24, 12))
        for c, (sig, phi, (m, n)) in enumerate(RECIPROCITY_PAIRS):
            a = solve(cell, Incidence(wavelength_nm, sig, phi), tol=1e-6, polarisation="tm",
                      tm_faces=preset).reflected
            i = a.index(m, n)
            back = Incidence(wavelength_nm, math.asin(min(1.0, math.hypot(a.kx[i], a.ky[i]) / k0)),
                             math.atan2(a.ky[i], a.kx[i]) + math.pi)
            b = solve(cell, back, tol=1e-6, polarisation="tm", tm_faces=preset).reflected
            fw[c] += a.power[i]
            bw[c] += b.power[b.index(m, n)]
    return fw / bw


def wood_jump(case: Case, preset: str, wavelength_nm: float = 470.0) -> tuple[float, float, float]:
    """(R at σ_W − 1e-7, R at σ_W + 1e-7, R at σ_W + 0.01) for order (1, 0) of the case's cell
    (realization 0, scalar grid), σ_W = asin(1 − λ/L): the model's jump against its slope."""
    cell: Cell = runs.scalar_cell(case, 0, wavelength_nm)
    sig_w = math.asin(1 - wavelength_nm / case.cell_nm)
    return tuple(solve(cell, Incidence(wavelength_nm, sig_w + d), tol=1e-7, polarisation="tm",
                       tm_faces=preset, dtype=np.complex128).R for d in (-1e-7, 1e-7, 0.01))


def brewster_jump(case: Case, wavelength_nm: float, preset: str = "brewster"
                  ) -> tuple[complex, float, float]:
    """(ε_f, R at σ_B − 1e-7, R at σ_B + 1e-7) on the case's cell (realization 0, scalar grid),
    σ_B = asin √Re(ε_f/(ε_f + 1)): where the default switches the 00 harmonic from E_x to H_y."""
    cell: Cell = runs.scalar_cell(case, 0, wavelength_nm)
    ef = complex(np.mean(cell.eps))
    sig_b = math.asin(math.sqrt((ef / (ef + 1)).real))
    lo, hi = (solve(cell, Incidence(wavelength_nm, sig_b + d), tol=1e-7, polarisation="tm",
                    tm_faces=preset, dtype=np.complex128).R for d in (-1e-7, 1e-7))
    return ef, lo, hi


def physics_checks(case: Case, presets=tuple(TM_FACE_PRESETS), dense: Case | None = None
                   ) -> None:
    print("\n--- physics of the presets: ensemble reciprocity P(a→b)/P(b̄→ā) of reflected "
          "orders (12 random cells, 5 pairs; 1 = reciprocal) and R across a Wood anomaly "
          f"({case.label}, 470 nm, order (1, 0))")
    for preset in presets:
        ratio = reciprocity(preset)
        lo, hi, far = wood_jump(case, preset)
        print(f"  {preset:21s}| reciprocity " + " ".join(f"{x:.3f}" for x in ratio) +
              f" | Wood: R {lo:.5f} → {hi:.5f} (jump {hi - lo:+.5f}; 0.01 rad further "
              f"{far - hi:+.5f})")
    print("  'brewster' at Brewster's angle σ_B ± 1e-7 rad (its E_x → H_y switch of the 00 harmonic):")
    for c, lam in [(case, 470.0), (case, 660.0)] + ([(dense, 470.0)] if dense else []):
        ef, lo, hi = brewster_jump(c, lam)
        print(f"    {c.label}, {lam:g} nm, ε_f = {ef.real:.3f}{ef.imag:+.3f}i: R {lo:.5f} → {hi:.5f} "
              f"(jump {hi - lo:+.5f})")
