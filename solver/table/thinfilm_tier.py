"""The exact tier: homogeneous (molecular or clear) ink layers are thin films.

No particles, so no diffuse scattering: R ≡ 0, Rbar = R_spec, Tbar = T_coh.  Exact at every λ
and σ, for s and p light (solver.thinfilm; docs/design.md §1, docs/polarisation.md).

- One layer (air above, air gap below) is up-down symmetric: Rbar_below = Rbar.
- A stack of layers (an ink printed over another, "Y15/B15" = Y15 on top of B15) is not:
  Rbar_below is computed for light from the paper side.  Its transmittance is reciprocal,
  so one Tbar serves both directions.

`polarisation` "unpolarised" (default): every column is (s + p)/2, and the table adds the
mirror beam's complex r_s, r_p (Mitsuba's `fresnel_polarized` convention) and the s/p parts
Rbar_s, Rbar_p, Tbar_s, Tbar_p.  "te": the scalar model's s light only (schema v1 numbers).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .. import __version__
from ..inks import Ink, molecular_eps
from ..materials import MaterialData
from ..thinfilm import SlabResponse, slab, stack, to_mitsuba_convention
from .request import DEFAULT_POLARISATION, LAYER_SEPARATOR
from .schema import POLARISATIONS, SCHEMA_VERSION, InkTable

MIXING_RULE = "linear volume-weighted permittivity: eps = (1 - sum f_i) eps_binder + sum f_i eps_i"
#: appended where the material data give the pigments their local field (docs/polarisation.md)
LOCAL_FIELD_RULE = ", eps_i the pigment's local-field permittivity in the binder (materials.local_field_eps)"


def stack_label(layers: Sequence[tuple[Ink, float]]) -> str:
    """The stack's ink label, top layer first: "Y15/B15"."""
    return LAYER_SEPARATOR.join(ink.label for ink, _ in layers)


def build_thinfilm_table(ink: Ink, thickness_nm: float, wavelengths_nm, sigma_rad,
                         materials: MaterialData | None = None, *,
                         polarisation: str = DEFAULT_POLARISATION) -> InkTable:
    """Exact table of one homogeneous layer of the ink's molecular-mix permittivity."""
    if not thickness_nm > 0:
        raise ValueError(f"layer thickness must be > 0 nm, got {thickness_nm}")
    return build_stack_table([(ink, thickness_nm)], wavelengths_nm, sigma_rad, materials,
                             polarisation=polarisation)


def build_stack_table(layers: Sequence[tuple[Ink, float]], wavelengths_nm, sigma_rad,
                      materials: MaterialData | Sequence[MaterialData] | None = None, *,
                      polarisation: str = DEFAULT_POLARISATION) -> InkTable:
    """Exact table of homogeneous layers [(ink, thickness_nm), ...], top layer first, with air
    above and the air gap to the paper below (materials: None = the default data, or one
    MaterialData for every layer, or one per layer)."""
    layers = [(ink, float(d)) for ink, d in layers]
    if not layers:
        raise ValueError("a layer stack needs at least one (ink, thickness_nm) layer")
    for ink, d in layers:
        if not d > 0:
            raise ValueError(f"layer thickness must be > 0 nm, got {d} for {ink.label}")
    if polarisation not in POLARISATIONS:
        raise ValueError(f"polarisation must be one of {', '.join(map(repr, POLARISATIONS))}, "
                         f"got {polarisation!r}")
    wl = np.asarray(wavelengths_nm, dtype=float)
    sigma = np.asarray(sigma_rad, dtype=float)
    per_layer = materials if isinstance(materials, (list, tuple)) else [materials] * len(layers)
    if len(per_layer) != len(layers):
        raise ValueError(f"{len(per_layer)} material data for {len(layers)} layers")
    eps = [molecular_eps(ink, wl, data) for (ink, _), data in zip(layers, per_layer)]
    return film_table(eps, [d for _, d in layers], wl, sigma, polarisation,
                      _meta(layers, wl, sigma, polarisation,
                            any(d is not None and d.local_field is not None for d in per_layer)))


def film_table(eps_layers: Sequence[np.ndarray], thickness_nm: Sequence[float], wavelengths_nm, sigma_rad,
               polarisation: str, meta: dict) -> InkTable:
    """Exact table of homogeneous layers of the given permittivities ([nλ] each, top first)
    between air above and the air gap below."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    sigma = np.asarray(sigma_rad, dtype=float)
    eps = [np.asarray(e)[:, None] for e in eps_layers]
    thickness = [float(d) for d in thickness_nm]
    symmetric = len(eps) == 1                     # air on both sides of one layer

    def solve(pol: str, from_below: bool) -> SlabResponse:
        if symmetric:                                # Airy: the numbers of schema v1 tables
            return slab(eps[0], thickness[0], wl[:, None], sigma[None, :], polarisation=pol)
        return stack(eps, thickness, wl[:, None], sigma[None, :], polarisation=pol,
                     from_below=from_below)

    te = solve("te", False)
    te_below = te if symmetric else solve("te", True)
    if polarisation == "te":
        columns = {"R_spec": te.R, "T_coh": te.T, "Rbar_below": te_below.R}
        split = {}
    else:
        tm = solve("tm", False)
        tm_below = tm if symmetric else solve("tm", True)
        columns = {"R_spec": 0.5 * (te.R + tm.R), "T_coh": 0.5 * (te.T + tm.T),
                   "Rbar_below": 0.5 * (te_below.R + tm_below.R)}
        split = {"r_s": to_mitsuba_convention(te.r), "r_p": to_mitsuba_convention(tm.r),
                 "Rbar_s": te.R, "Rbar_p": tm.R, "Tbar_s": te.T, "Tbar_p": tm.T}
    if symmetric:
        columns["Rbar_below"] = columns["R_spec"].copy()
    return InkTable(wavelengths=wl, sigma=sigma, theta=np.array([0.0, np.pi / 2]),
                    dphi=np.array([0.0, np.pi]), R=np.zeros((wl.size, sigma.size, 2, 2)),
                    R_spec=columns["R_spec"], T_coh=columns["T_coh"], Rbar=columns["R_spec"].copy(),
                    Tbar=columns["T_coh"].copy(), Rbar_below=columns["Rbar_below"], meta=meta, **split)


def _meta(layers: list[tuple[Ink, float]], wl: np.ndarray, sigma: np.ndarray, polarisation: str,
          local_field: bool) -> dict:
    """The film's meta; a stack lists its pigments and thicknesses per layer, top first (as
    solver.table.meta.table_meta does)."""
    single = len(layers) == 1
    pigments = [[[c, f] for c, f in ink.components] for ink, _ in layers]
    return {
        "schema_version": SCHEMA_VERSION,
        "polarisation": polarisation,
        "ink": stack_label(layers),
        "pigments": pigments[0] if single else pigments,
        "particles": "molecular",
        "thickness_nm": layers[0][1] if single else [d for _, d in layers],
        "tier": "thin-film",
        "tier_reason": ("homogeneous layer: exact Airy (transfer-matrix) solution" if single else
                        "stack of homogeneous layers: exact transfer-matrix solution"),
        "mixing_rule": MIXING_RULE + (LOCAL_FIELD_RULE if local_field else ""),
        "generator": {"name": "inkbsdf.solver", "version": __version__},
        "settings": {"wavelengths_nm": [float(wl[0]), float(wl[-1]), int(wl.size)],
                     "sigma_count": int(sigma.size)},
        "seeds": [],
        "errors": {"model": 0.0, "energy_sum_tol": 1e-9},
    }


def request_film(request, wavelengths_nm=None, sigma_rad=None, polarisation: str | None = None) -> InkTable:
    """The exact film of a request's molecular (or mean-ε) layers, one or a stack, on the
    request's grids or on the given ones (the film tier, the effective-medium tier and the tier
    probe), for the request's polarisation unless one is given (the tier probe compares with
    the scalar wave solves: "te")."""
    return build_stack_table([(layer.ink, layer.thickness_nm) for layer in request.layers],
                             request.grids.wavelengths_nm if wavelengths_nm is None else wavelengths_nm,
                             request.grids.sigma_rad if sigma_rad is None else sigma_rad,
                             [request.layer_materials(i) for i in range(len(request.layers))],
                             polarisation=polarisation or request.polarisation)
