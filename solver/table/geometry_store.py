"""One geometry, many inks: a realization's voxel fractions are shared by every table whose
grains are the same (docs/tables.md, "Shared geometry").

Realization r of a single-layer request is drawn from the grains' spec, the components' volume
fractions in order, the layer's thickness, the cell, the grid, the seed and r
(`solver.geometry.generate`, `voxelize`); the pigment codes only name the voxel fractions'
materials.  So R15, Y15, B15 and G15 on the same grains have the same voxel fractions, bit for
bit (four of the seven rows of each concentration block of Fig. 7, and any other ink with one
pigment at that load): the cache keeps a realization under `key` and `relabel` gives it the
request's pigment codes.  A stack's layers are merged by their codes (`stack_voxels`), so a
stack's key names them.  The key carries the fingerprint of the geometry code, so a change to
the generator never serves old voxels.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json

from .fingerprint import code_fingerprint
from .request import TableRequest


def _layer_fields(request: TableRequest) -> list[dict]:
    stack = len(request.layers) > 1
    fields = []
    for layer in request.layers:
        d = {"particles": layer.particles_label, "thickness_nm": float(layer.thickness_nm),
             "fractions": [round(float(f), 12) for _, f in layer.ink.components]}
        if stack:
            d["codes"] = [c for c, _ in layer.ink.components]
        fields.append(d)
    return fields


def key(request: TableRequest, realization: int) -> str:
    """The content address of a realization's voxel fractions (24 hex digits)."""
    w = request.wave
    fields = {"layers": _layer_fields(request), "cell_nm": float(w.cell_nm), "grid": [int(n) for n in w.grid],
              "seed": int(w.seed), "realization": int(realization), "code": code_fingerprint("geometry")}
    text = json.dumps(fields, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def relabel(voxels, request: TableRequest):
    """Stored voxel fractions with the request's pigment codes as their materials."""
    if len(request.layers) > 1:
        return voxels
    codes = tuple(c for c, _ in request.layers[0].ink.components)
    if len(voxels.materials) != 2 + len(codes):
        raise ValueError(f"stored geometry has materials {voxels.materials}, the request needs "
                         f"binder, air and {codes}: the store's key is wrong")
    return dataclasses.replace(voxels, materials=("binder", "air") + codes)
