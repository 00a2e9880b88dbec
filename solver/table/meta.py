"""The table's `meta` record: one function writes it for every tier (what, how, from what)."""

from __future__ import annotations

from .. import __version__
from .request import TableRequest
from .schema import SCHEMA_VERSION


def table_meta(request: TableRequest, tier: str, reason: str, *, seeds=(), timings_s=None,
               extra: dict | None = None) -> dict:
    """Everything a reader needs to know where a table's numbers come from."""
    layers = request.layers
    meta = {
        "schema_version": SCHEMA_VERSION,
        "ink": request.ink_label,
        "pigments": [[c, f] for c, f in layers[0].ink.components] if len(layers) == 1
        else [[[c, f] for c, f in layer.ink.components] for layer in layers],
        "particles": request.particles_label,
        "thickness_nm": layers[0].thickness_nm if len(layers) == 1 else [l.thickness_nm for l in layers],
        "polarisation": request.polarisation,
        "local_field": request.local_field,
        "accuracy": request.accuracy,
        "tier": tier,
        "tier_reason": reason,
        "cache_key": request.key(),
        "materials": {"fingerprint": request.materials.fingerprint, "source": request.materials.source},
        "generator": {"name": "inkbsdf.solver", "version": __version__},
        "settings": request.numeric_fields(),
        "options": request.to_options(),                 # TableRequest.from_meta reads the request back
        "seeds": list(seeds),
        "timings_s": dict(timings_s or {}),
    }
    meta.update(extra or {})
    return meta
