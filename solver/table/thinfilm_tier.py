"""The exact tier: a homogeneous (molecular or clear) ink layer is a thin film.

No particles, so no diffuse scattering: R ≡ 0, Rbar = R_spec, Tbar = T_coh, and the layer is
up-down symmetric (air above, air gap below), so Rbar_below = Rbar.  Exact at every λ and σ.
"""

from __future__ import annotations

import numpy as np

from .. import __version__
from ..inks import Ink, molecular_eps
from ..materials import MaterialData
from ..thinfilm import slab
from .schema import SCHEMA_VERSION, InkTable

MIXING_RULE = "linear volume-weighted permittivity: eps = (1 - sum f_i) eps_binder + sum f_i eps_i"


def build_thinfilm_table(ink: Ink, thickness_nm: float, wavelengths_nm, sigma_rad,
                         materials: MaterialData | None = None) -> InkTable:
    """Exact table of a homogeneous layer of the ink's molecular-mix permittivity."""
    if not thickness_nm > 0:
        raise ValueError(f"layer thickness must be > 0 nm, got {thickness_nm}")
    wl = np.asarray(wavelengths_nm, dtype=float)
    sigma = np.asarray(sigma_rad, dtype=float)
    eps = molecular_eps(ink, wl, materials)[:, None]
    film = slab(eps, thickness_nm, wl[:, None], sigma[None, :])
    R_spec, T_coh = film.R, film.T
    theta = np.array([0.0, np.pi / 2])
    dphi = np.array([0.0, np.pi])
    meta = {
        "schema_version": SCHEMA_VERSION,
        "ink": ink.label,
        "pigments": [[c, f] for c, f in ink.components],
        "particles": "molecular",
        "thickness_nm": float(thickness_nm),
        "tier": "thin-film",
        "tier_reason": "homogeneous layer: exact Airy (transfer-matrix) solution",
        "mixing_rule": MIXING_RULE,
        "generator": {"name": "inkbsdf.solver", "version": __version__},
        "settings": {"wavelengths_nm": [float(wl[0]), float(wl[-1]), int(wl.size)],
                     "sigma_count": int(sigma.size)},
        "seeds": [],
        "errors": {"model": 0.0, "energy_sum_tol": 1e-9},
    }
    return InkTable(wavelengths=wl, sigma=sigma, theta=theta, dphi=dphi,
                    R=np.zeros((wl.size, sigma.size, 2, 2)),
                    R_spec=R_spec, T_coh=T_coh, Rbar=R_spec.copy(), Tbar=T_coh.copy(),
                    Rbar_below=R_spec.copy(), meta=meta)


def request_film(request, wavelengths_nm=None, sigma_rad=None) -> InkTable:
    """The exact film of a request's (single, molecular or mean-ε) layer on the request's grids
    or on the given ones (the film tier, the effective-medium tier and the tier probe)."""
    layer = request.layer
    return build_thinfilm_table(layer.ink, layer.thickness_nm,
                                request.grids.wavelengths_nm if wavelengths_nm is None else wavelengths_nm,
                                request.grids.sigma_rad if sigma_rad is None else sigma_rad,
                                request.materials)
