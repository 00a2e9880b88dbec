"""A uniform print's tables mixed once into one (NumPy; docs/plugin.md, "Several inks").

Under Clapper–Yule every quantity of the BSDF is a Demichel-weighted sum over the printed
primaries S, bare paper included (T̄ = τ̄ = 1, everything else 0 for S = ∅):

    Σ_S a_S R_spec,S,  Σ_S a_S T̄_S(σ),  Σ_S a_S T̄_S(θ),  Σ_S a_S ρ̄_S,  Σ_S a_S τ̄_S,
    Σ_S a_S R_S(σ, θ, Δφ),  Σ_S a_S R_diff,S(σ),  Σ_S a_S (b, C, S)_S

and the paper enters only through r·(Σ a T̄(σ))(Σ a T̄(θ))/(1 − r Σ a ρ̄), per lane (`inkbsdf.mixing`).
When the coverages are the same everywhere (numbers, not textures) the weights a_S are numbers,
so the sums can be taken on the tables themselves: one table that the BSDF evaluates as a
single ink of coverage 1 over no bare paper, whatever the number of inks — the same result
(each sum is linear in the tables' nodal values, and the interpolation is linear in them too)
at one ink's cost. Tables on different grids are first resampled onto the union of their
nodes, axis by axis, which is exact: a piecewise-linear (multilinear) interpolant, clamped
beyond its ends, is reproduced by its values on any finer grid that holds its nodes. Murray–Davies couples each primary to the paper separately and is not a sum
of this kind: it keeps the per-primary evaluation, as do spatially varying coverages.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from solver.printing.demichel import demichel_weights

from .lut import InkLUT


def _union(grids) -> np.ndarray | None:
    """The sorted union of the grids' nodes; None when `inkbsdf.interp` cannot locate on it
    (too irregular for a cell table)."""
    from .interp import cell_table, uniform_step

    nodes = np.unique(np.concatenate([np.asarray(g, dtype=np.float64) for g in grids]))
    if uniform_step(nodes) is None:
        try:
            cell_table(nodes)
        except ValueError:
            return None
    return nodes


def _resample(values: np.ndarray, axis: int, old: np.ndarray, new: np.ndarray) -> np.ndarray:
    """`values` piecewise-linear along `axis` on nodes `old`, at nodes `new` (clamped ends)."""
    if np.array_equal(old, new):
        return values
    moved = np.moveaxis(values, axis, -1)
    flat = moved.reshape(-1, old.size)
    out = np.stack([np.interp(new, old, row) for row in flat]).reshape(moved.shape[:-1] + (new.size,))
    return np.moveaxis(out, -1, axis)


def on_grid(lut: InkLUT, wl, sigma, theta=None, dphi=None) -> InkLUT:
    """`lut` resampled exactly onto finer grids that hold its nodes (see the module docstring)."""
    def lam_sig(q):
        return _resample(_resample(q, 0, lut.wavelengths_nm, wl), 1, lut.sigma_rad, sigma)

    R = None
    if lut.has_diffuse:
        R = _resample(_resample(lam_sig(lut.R), 2, lut.theta_rad, theta), 3, lut.dphi_rad, dphi)
    mirror = None if lut.mirror_sp is None else lam_sig(lut.mirror_sp)
    return replace(lut, wavelengths_nm=wl, sigma_rad=sigma, R_spec=lam_sig(lut.R_spec), Tbar=lam_sig(lut.Tbar),
                   R_diff=lam_sig(lut.R_diff), rho_bar=_resample(lut.rho_bar, 0, lut.wavelengths_nm, wl),
                   tau_bar=_resample(lut.tau_bar, 0, lut.wavelengths_nm, wl),
                   theta_rad=theta if lut.has_diffuse else lut.theta_rad,
                   dphi_rad=dphi if lut.has_diffuse else lut.dphi_rad, R=R, mirror_sp=mirror)


def common_grid(luts) -> list | None:
    """The tables on the union of their grids (unchanged where they agree), or None."""
    diffuse = [l for l in luts if l.has_diffuse]
    grids = [_union([l.wavelengths_nm for l in luts]), _union([l.sigma_rad for l in luts])]
    if diffuse:
        grids += [_union([l.theta_rad for l in diffuse]), _union([l.dphi_rad for l in diffuse])]
    else:
        grids += [None, None]
    if any(g is None for g in grids[: 4 if diffuse else 2]):
        return None
    return [on_grid(l, *grids) for l in luts]


def premixed_lut(coverages, primaries) -> InkLUT | None:
    """The one table of a uniform print: `coverages` numbers in [0, 1] (printing order),
    `primaries` ((subset, InkLUT), ...) for the printed primaries S ≠ ∅ that can occur; None
    when their grids have no common refinement that `inkbsdf.interp` can locate on (the BSDF
    then evaluates them one by one)."""
    luts = common_grid([lut for _, lut in primaries]) if primaries else None
    if luts is None:
        return None
    subsets = [()] + [tuple(s) for s, _ in primaries]
    weights = demichel_weights(np.asarray(coverages, dtype=np.float64), subsets)
    bare, weights = float(weights[0]), [float(w) for w in weights[1:]]

    def total(field, start=0.0):
        return sum((w * getattr(lut, field) for w, lut in zip(weights, luts)), start)

    diffuse = [lut for lut in luts if lut.has_diffuse]
    R = None
    if diffuse:
        shape = diffuse[0].R.shape
        R = sum((w * lut.R for w, lut in zip(weights, luts) if lut.has_diffuse), np.zeros(shape))
    mirror = None
    if all(lut.mirror_sp is not None for lut in luts):
        mirror = total("mirror_sp")
    grid = diffuse[0] if diffuse else luts[0]
    names = " + ".join(f"{w:.4g}·{lut.source}" for w, lut in zip(weights, luts))
    return replace(luts[0], source=f"premixed({names})", R_spec=total("R_spec"), Tbar=total("Tbar", bare),
                   R_diff=total("R_diff"), rho_bar=total("rho_bar"), tau_bar=total("tau_bar", bare),
                   theta_rad=grid.theta_rad, dphi_rad=grid.dphi_rad, R=R, mirror_sp=mirror)
