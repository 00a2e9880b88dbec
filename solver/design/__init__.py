"""The inverse problem: the ink recipe whose printed colour is closest to an aim (ΔE2000).

    from solver.design import InkTemplate, FilmColour, design_ink, design_process_set
    result = design_ink(aim, InkTemplate.of("C"), FilmColour.default(paper=0.88))

`recipe` holds the free parameters and their bounds (the one home of the design defaults),
`colour` measures a recipe's colour on paper (molecular inks through exact films, particle inks
through the table cache), `optimise` minimises ΔE2000, `process_set` designs a whole set of
process inks against ISO 12647-2's solids and overprints (docs/printing.md).
"""

from .colour import FilmColour
from .optimise import DesignResult, design_ink, design_paper
from .process_set import design_process_set
from .recipe import InkTemplate, Recipe

__all__ = ["DesignResult", "FilmColour", "InkTemplate", "Recipe", "design_ink", "design_paper",
           "design_process_set"]
