"""Choosing the cheapest model that meets the tolerance, by measurement (the tier probe).

Candidates, cheapest first:
  effective-medium  the layer as a thin film of the volume-mean ε (the exact small-particle limit
                    of the scalar model); no diffuse scattering.  Cost: nothing.
  born              first-order distorted-wave Born approximation on the mean-ε film (one
                    operator application per solve instead of ~20–60).
  full              the converged wave solve.
A probe runs the full solve for the first realization (the first two where each solves one
polarisation: wave_tier.probe_realizations) at a few wavelengths (the most and least
absorbing and one between) and every solved σ, and the candidates at the same points; the
cheapest candidate whose largest deviation in Rbar, Tbar and the diffuse reflectance stays
within the tolerance is chosen.  The deviations are written into the table's meta.
"""

from __future__ import annotations

import numpy as np

from ..inks import molecular_eps
from .request import TableRequest
from .thinfilm_tier import request_film

CANDIDATES = ("effective-medium", "born", "full")


def probe_wavelength_indices(request: TableRequest) -> list[int]:
    """Most absorbing, least absorbing and a middle wavelength of the ink (by mean Im ε), among
    the wavelengths the table solves (so that the probe's full solves are table units)."""
    solved = np.asarray(request.solved_wavelength_indices)
    wl = np.asarray(request.grids.wavelengths_nm)[solved]
    loss = sum(molecular_eps(layer.ink, wl, request.layer_materials(i)).imag * layer.thickness_nm
               for i, layer in enumerate(request.layers))
    order = np.argsort(loss, kind="stable")
    return sorted({int(solved[order[-1]]), int(solved[order[0]]), int(solved[order[len(order) // 2]])})


def _summaries(units: list[dict]) -> dict:
    """Azimuth-averaged Rbar, Tbar and diffuse reflectance of probe units, stacked [λ, σ]."""
    stack = lambda key: np.stack([u[key] for u in units])
    rbar, tbar = stack("Rbar").mean(-1), stack("Tbar").mean(-1)
    diffuse = rbar - (np.abs(stack("alpha00")) ** 2).mean(-1)
    return {"Rbar": rbar, "Tbar": tbar, "diffuse": diffuse}


def effective_medium_summaries(request: TableRequest, lambda_indices, sigma) -> dict:
    wl = np.asarray(request.grids.wavelengths_nm)[lambda_indices]
    film = request_film(request, wl, np.concatenate([sigma, [np.pi / 2]]))
    return {"Rbar": film.Rbar[:, :-1], "Tbar": film.Tbar[:, :-1], "diffuse": np.zeros((wl.size, sigma.size))}


def deviation(candidate: dict, reference: dict) -> float:
    return float(max(np.max(np.abs(candidate[k] - reference[k])) for k in ("Rbar", "Tbar", "diffuse")))


def choose(request: TableRequest, full_units: list[dict], born_units: list[dict] | None,
           lambda_indices, sigma) -> tuple[str, dict]:
    """The tier to build and the measured deviations of each candidate from the full solve.
    lambda_indices: the wavelength index of each probe unit (in the units' order; a wavelength
    repeats where two realizations were probed)."""
    reference = _summaries(full_units)
    report = {"probe_wavelengths_nm": [request.grids.wavelengths_nm[i] for i in sorted(set(lambda_indices))],
              "tolerance": request.wave.tolerance,
              "deviation": {"effective-medium": deviation(
                  effective_medium_summaries(request, lambda_indices, sigma), reference)}}
    if born_units is not None:
        report["deviation"]["born"] = deviation(_summaries(born_units), reference)
    report["deviation"]["full"] = 0.0
    for tier in CANDIDATES:
        if tier in report["deviation"] and report["deviation"][tier] <= request.wave.tolerance:
            return tier, report
    return "full", report
