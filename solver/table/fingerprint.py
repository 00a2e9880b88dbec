"""A fingerprint of the code that produces a table's numbers (part of the cache key).

Instead of a hand-bumped version number, the key includes a hash of the syntax trees of the
modules of the stages that compute the numbers, with docstrings dropped: editing a comment or a
docstring keeps every cached table; editing code that could change a number gives new keys, so
the cache can never serve a table computed by other code.

    film: the materials, the ink mixing rule, the thin-film optics and the film tier
    wave: the film's modules plus geometry, the wave solver and the wave tier's stages
"""

from __future__ import annotations

import ast
import hashlib
import importlib
from functools import lru_cache
from pathlib import Path

FILM_MODULES = ("solver.materials", "solver.inks", "solver.thinfilm", "solver.table.thinfilm_tier",
                "solver.table.integrals")
WAVE_MODULES = FILM_MODULES + ("solver.geometry", "solver.wave", "solver.table.wave_tier",
                               "solver.table.wave_ensemble", "solver.table.orders_to_brdf", "solver.table.tier_choice",
                               "solver.table.retry", "solver.table.spectral")
#: modules of a package that draw pictures, print reports or hold the tests' independent
#: reference solutions (solver/wave/oracles.py, validation.py): no table imports them, so they
#: never change a table's number
_NOT_NUMERIC = {"render.py", "report.py", "oracles.py", "validation.py"}
#: the code that turns a layer's grains into voxel fractions (the shared geometry's key, geometry_store.py)
GEOMETRY_MODULES = ("solver.geometry",)
KINDS = {"film": FILM_MODULES, "wave": WAVE_MODULES, "geometry": GEOMETRY_MODULES}


def _strip_docstrings(tree: ast.AST) -> ast.AST:
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) \
                and isinstance(getattr(body[0], "value", None), ast.Constant) \
                and isinstance(body[0].value.value, str):
            node.body = body[1:] or [ast.Pass()]
    return tree


def _package_dir(module_name: str) -> Path:
    return Path(importlib.import_module(module_name).__file__).parent


def _source_files(module_name: str) -> list[Path]:
    module = importlib.import_module(module_name)
    path = Path(module.__file__)
    if path.name == "__init__.py":      # a package: every module in it and its sub-packages
        return sorted(p for p in path.parent.rglob("*.py") if p.name not in _NOT_NUMERIC)
    return [path]


@lru_cache(maxsize=None)
def file_digest(path: str, mtime_ns: int) -> str:
    tree = _strip_docstrings(ast.parse(Path(path).read_text(encoding="utf-8")))
    return hashlib.sha256(ast.dump(tree, annotate_fields=False).encode()).hexdigest()


def code_fingerprint(kind: str) -> str:
    """Hash of the numeric code of a pipeline kind ('film', 'wave' or 'geometry'), 16 hex digits."""
    h = hashlib.sha256(kind.encode())
    for name in KINDS[kind]:
        top = _package_dir(name)
        for path in _source_files(name):
            h.update(f"{name}:{path.relative_to(top)}".encode() + file_digest(str(path), path.stat().st_mtime_ns).encode())
    return h.hexdigest()[:16]
