"""Film-guided wavelength refinement: solve the wave ensemble on every k-th wavelength of the
table and interpolate the *difference to the exact molecular film* in between (docs/tables.md,
"Wavelength stride").

The particle layer's spectrum carries the pigments' absorption bands and the layer's thin-film
fringes; an exact film of the same thickness carries both and costs milliseconds per
wavelength.  The film of the ink's mean permittivity (the effective medium) absorbs far more
than grains of pigment do (the package effect: a grain's interior is shaded by its surface),
and that difference follows the absorption bands; the guide film therefore takes each
pigment's absorption flattened for grains of the layer's size (`guide_eps`: Duysens'
flattening over a mean chord ℓ = 2d/3).  What remains — the scattering and what the
flattening misses — varies slowly with λ, so it is interpolated linearly between the solved
wavelengths and the film is added back at every wavelength of the table:

    X(λ) = X_film(λ) + interp_λ(X_wave − X_film)(λ)

for the primary columns: the coherent amplitudes r_s, r_p (complex: the film's fringe phase
is carried by the film), or R_spec for a TE table; T_coh, Tbar (Tbar_s, Tbar_p) and
Rbar_below, each at most 1 − R̄ (1 − R̄_p per polarisation; Rbar_below at most 1 − T̄): the loss
is never negative, also where the fringes of the reflectance and the transmittance move apart
(uncapped, R̄ + T̄ reached 1.028: R15, 200-nm grains at preview).  Interpolating the loss
1 − R̄ − T̄ itself and deriving T̄ from it was tried: ΔE2000 0.10 / 0.46 / 0.60 at strides
2 / 3 / 4 against 0.18 / 0.32 / 0.58, max |ΔT̄| 0.020 / 0.036 / 0.065 against 0.022 / 0.028 /
0.032 (T̄ inherits R̄'s interpolation error at grazing incidence); dropped.
What the film lacks is interpolated itself: the diffuse BRDF R and the s and p diffuse parts
Rbar_s − |r_s|², Rbar_p − |r_p|².  The rest is derived so that the table's identities hold
exactly at every wavelength: R_spec = (|r_s|² + |r_p|²)/2, Rbar = R_spec + ∫R,
Rbar_s/p = |r_s/p|² + D_s/p with (D_s + D_p)/2 = ∫R, Tbar = (Tbar_s + Tbar_p)/2.  Standard
errors are interpolated linearly (no film).  A table's leave-one-out ensembles are refined by
this same function, each from its own coarse table (builder._reduce).  At the solved
wavelengths the table is the wave ensemble's, bit for bit.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .integrals import diffuse_albedo
from .schema import InkTable

def solved_indices(count: int, stride: int) -> tuple[int, ...]:
    """Indices of the wavelengths the wave ensemble solves: every `stride`-th of `count`, the
    last one always included (so the interpolation never extrapolates)."""
    if stride < 1 or count < 1:
        raise ValueError(f"stride and count must be ≥ 1, got {stride}, {count}")
    picked = list(range(0, count, stride))
    if picked[-1] != count - 1:
        picked.append(count - 1)
    return tuple(picked)


def _interp(wl: np.ndarray, solved: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Piecewise-linear interpolation along axis 0 from the solved wavelengths to all (real or
    complex values of any trailing shape)."""
    j = np.clip(np.searchsorted(solved, wl, side="right") - 1, 0, solved.size - 2)
    t = (wl - solved[j]) / (solved[j + 1] - solved[j])
    t = t.reshape((-1,) + (1,) * (values.ndim - 1))
    return (1.0 - t) * values[j] + t * values[j + 1]


def refine(coarse: InkTable, film: InkTable, solved: tuple[int, ...], meta: dict | None = None) -> InkTable:
    """The table on the film's wavelengths from the wave table `coarse` on the solved subset
    `solved` (indices into the film's wavelengths), guided by the exact film `film` (same σ
    grid and polarisation).  meta: the refined table's meta (default: coarse's)."""
    if coarse.jackknife is not None:
        raise ValueError("refine the leave-one-out tables themselves, before attaching them "
                         "(jackknife.reduce_with_replicas): a table's jackknife columns cannot be refined alone")
    wl = np.asarray(film.wavelengths, float)
    idx = np.asarray(solved)
    sw = wl[idx]
    if not np.allclose(np.asarray(coarse.wavelengths, float), sw):
        raise ValueError("the coarse table's wavelengths are not the film's at the solved indices")

    def guided(wave: np.ndarray, flat: np.ndarray | None) -> np.ndarray:
        """film + interpolated (wave − film); flat None: plain interpolation (the film has none)."""
        if flat is None:
            return _interp(wl, sw, np.asarray(wave))
        flat = np.asarray(flat)
        return flat + _interp(wl, sw, np.asarray(wave) - flat[idx])

    def place(coarse_values: np.ndarray, refined: np.ndarray) -> np.ndarray:
        out = np.array(refined, dtype=np.result_type(coarse_values, refined))
        out[idx] = coarse_values             # the solved wavelengths: the ensemble's own numbers
        return out

    power = lambda k: place(getattr(coarse, k), np.clip(guided(getattr(coarse, k), getattr(film, k)), 0.0, 1.0))

    R = place(coarse.R, np.maximum(guided(coarse.R, None), 0.0))
    diffuse = diffuse_albedo(coarse.theta, coarse.dphi, R)             # ∫R, [λ, σ]
    cols = {"T_coh": power("T_coh")}
    extra = {}
    if coarse.r_s is not None:
        # coherent amplitudes (the film's fringe phase carried by the film), the s and p diffuse
        # parts Rbar_p − |r_p|² (the film has none) and the s and p transmittances
        for k in ("r_s", "r_p"):
            r = guided(getattr(coarse, k), getattr(film, k))
            r = r / np.maximum(np.abs(r), 1.0)          # |r| ≤ 1 (grazing incidence: |r| → 1)
            extra[k] = place(getattr(coarse, k), r)
        spec = {k: np.abs(extra[f"r_{k}"]) ** 2 for k in "sp"}
        dif = {k: np.maximum(guided(getattr(coarse, f"Rbar_{k}") - np.abs(getattr(coarse, f"r_{k}")) ** 2, None), 0.0)
               for k in "sp"}
        scale = np.divide(2.0 * diffuse, dif["s"] + dif["p"], out=np.zeros_like(diffuse),
                          where=dif["s"] + dif["p"] > 0)                  # (D_s + D_p)/2 = ∫R exactly
        for k in "sp":
            extra[f"Rbar_{k}"] = place(getattr(coarse, f"Rbar_{k}"), spec[k] + scale * dif[k])
            extra[f"Tbar_{k}"] = place(getattr(coarse, f"Tbar_{k}"), np.clip(np.minimum(   # loss ≥ 0
                guided(getattr(coarse, f"Tbar_{k}"), getattr(film, f"Tbar_{k}")), 1.0 - extra[f"Rbar_{k}"]), 0.0, 1.0))
        r_spec = 0.5 * (spec["s"] + spec["p"])
        cols["R_spec"] = place(coarse.R_spec, r_spec)
        cols["Rbar"] = place(coarse.Rbar, cols["R_spec"] + diffuse)
        cols["Tbar"] = place(coarse.Tbar, 0.5 * (extra["Tbar_s"] + extra["Tbar_p"]))
    else:
        cols["R_spec"] = place(coarse.R_spec, np.clip(guided(coarse.R_spec, film.R_spec), 0.0, 1.0))
        cols["Rbar"] = place(coarse.Rbar, cols["R_spec"] + diffuse)
        cols["Tbar"] = place(coarse.Tbar, np.clip(np.minimum(guided(coarse.Tbar, film.Tbar), 1.0 - cols["Rbar"]),
                                                  0.0, 1.0))
    cols["T_coh"] = np.minimum(cols["T_coh"], cols["Tbar"])
    if np.array_equal(coarse.Rbar_below, coarse.Rbar):      # a symmetric layer: R̄ from below is R̄
        cols["Rbar_below"] = cols["Rbar"].copy()
    else:                                                   # from below: no more than 1 − T̄ either
        cols["Rbar_below"] = place(coarse.Rbar_below, np.clip(np.minimum(
            guided(coarse.Rbar_below, film.Rbar_below), 1.0 - cols["Tbar"]), 0.0, 1.0))
    errors = {k: place(v, np.maximum(guided(v, None), 0.0)) for k, v in coarse.errors.items()}
    return dataclasses.replace(coarse, wavelengths=wl, R=R, errors=errors,
                               meta=dict(coarse.meta if meta is None else meta), **cols, **extra)


def unsolved_breaking_energy(table: InkTable, solved) -> list[int]:
    """Indices of the refined table's interpolated (unsolved) wavelengths at which it breaks
    energy beyond the solver's closure (schema.energy_excess: from above, per polarisation, from below): where a
    pigment's band is sharper than the solved wavelengths resolve, the film-guided difference
    can put R̄ + T̄ above 1 (R15 with 200-nm grains at 20-nm steps: by 0.028).  The caller solves
    them; an empty list when the refinement holds."""
    from .schema import energy_excess

    worst = np.max(np.stack(list(energy_excess(table).values())), axis=0)
    done = set(int(i) for i in solved)
    return [int(i) for i in np.flatnonzero(worst > 0) if int(i) not in done]


def flattening(alpha_chord: np.ndarray) -> np.ndarray:
    """The package effect (Duysens' flattening): a grain's absorption relative to the same
    pigment dissolved, Q(x)/(2x/3) with Q(x) = 1 + 2e^{−x}/x + 2(e^{−x} − 1)/x² the absorption
    efficiency of a sphere of optical thickness x = α·ℓ in geometric optics (→ 1 for x → 0)."""
    x = np.maximum(np.asarray(alpha_chord, float), 1e-3)
    q = 1.0 + 2.0 * np.exp(-x) / x + 2.0 * np.expm1(-x) / x ** 2
    return np.where(np.asarray(alpha_chord) > 1e-3, q / (2.0 * x / 3.0), 1.0)


#: the guide's grain path length ℓ in units of the grains' (volume-equivalent) diameter: the
#: mean chord of a sphere, 2d/3 (4V/S); measured the best of 0–5/3·d on the default ink
#: (`python -m benchmarks.bench_tables --stride-curve`, docs/tables.md "Wavelength stride")
CHORD_PER_DIAMETER = 2.0 / 3.0


def guide_eps(request, index: int, wavelengths_nm, chord_per_diameter: float = CHORD_PER_DIAMETER) -> np.ndarray:
    """The guide film's permittivity of layer `index`: its molecular mix (with the request's
    pigment field) with each pigment's absorption flattened for grains of path length
    ℓ = chord_per_diameter·d (a molecular layer, or ℓ = 0: the mix itself)."""
    from ..inks import molecular_eps

    layer, data = request.layers[index], request.layer_materials(index)
    wl = np.asarray(wavelengths_nm, float)
    if layer.particles is None:
        return molecular_eps(layer.ink, wl, data)
    chord = chord_per_diameter * layer.particles.diameter_nm
    eps = (1.0 - layer.ink.total_fraction) * data.binder_eps(wl)
    for code, fraction in layer.ink.components:
        e = data.pigment_eps(code, wl)
        alpha = 4.0 * np.pi * np.sqrt(e).imag / wl                  # in the grain, 1/nm
        eps = eps + fraction * (e.real + 1j * flattening(alpha * chord) * e.imag)
    return eps


def guide_film(request, chord_per_diameter: float = CHORD_PER_DIAMETER) -> InkTable:
    """The exact film that guides the refinement of a request's table: its layers as films of
    `guide_eps`, on the request's grids, in its polarisation."""
    from .thinfilm_tier import film_table

    wl = np.asarray(request.grids.wavelengths_nm, float)
    return film_table([guide_eps(request, i, wl, chord_per_diameter) for i in range(len(request.layers))],
                      [layer.thickness_nm for layer in request.layers], wl, request.grids.sigma_rad,
                      request.polarisation, {"schema_version": 2, "polarisation": request.polarisation})


__all__ = ["solved_indices", "refine", "unsolved_breaking_energy", "guide_film", "guide_eps", "flattening", "CHORD_PER_DIAMETER"]
