"""The particle shapes, by the word that names them in spec strings (docs/geometry.md, "Shapes").

Each shape is one module implementing the `Shape` protocol (`base.py`); adding one is that
module, its tests, and its entry in SHAPES below — every stage, the tables, the figures' columns,
the CLI and the scenes take it from here.
"""

from __future__ import annotations

from ..grammar import ParticleSpecError
from .base import Shape
from .cylinder import Cylinder
from .sphere import Sphere
from .spheroid import Spheroid

#: every particle shape, by its grammar word
SHAPES: dict[str, type[Shape]] = {shape.name: shape for shape in (Sphere, Cylinder, Spheroid)}


def shape_class(name: str, spec: str | None = None) -> type[Shape]:
    """The shape a spec's first word names (case-insensitive), or one clear ParticleSpecError."""
    try:
        return SHAPES[name.strip().lower()]
    except KeyError:
        where = f" in {spec!r}" if spec is not None else ""
        raise ParticleSpecError(f"unknown particle shape {name!r}{where}: expected "
                                + ", ".join(tuple(SHAPES) + ("molecular",))) from None


def oriented_plurals() -> str:
    """'cylinders and spheroids': the shapes that take an orientation, for messages."""
    names = [shape.plural for shape in SHAPES.values() if shape.oriented]
    return " and ".join(filter(None, [", ".join(names[:-1]), names[-1]]))


__all__ = ["SHAPES", "Shape", "oriented_plurals", "shape_class"]
