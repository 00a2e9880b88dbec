"""The colour of a recipe printed on paper, as an instrument measures it (solver.colour).

Molecular inks are exact thin films: each recipe is a table of the thin-film tier, made through
the same request as every other table (`table_request`; grids, polarisation and the pigments'
local field from its defaults) and not cached (a film costs milliseconds). Particle inks come
from the table cache (`get_or_build`: built once, read back after). Overprints are stacks of
layers in printing order, the last printed on top, measured as the Demichel print model's
primary at full coverage (solver.printing).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..colour.measurement import DEFAULT, Measurement
from ..paper import PAPER_ALBEDO, check_paper_albedo
from ..printing import PrintedInks, all_subsets, demichel_weights, stack_order
from ..table.builder import BuildOptions, get_or_build
from ..table.thinfilm_tier import request_film
from ..table.request import LAYER_SEPARATOR, ThinLayerWarning, table_request
from .recipe import Recipe


@dataclass
class FilmColour:
    """Measures recipes on a paper; counts the films it computed (`films`), and the particle
    tables it built (`wave_tables`) or read from the cache (`reads`)."""

    paper: float = PAPER_ALBEDO
    measurement: Measurement = DEFAULT
    cache: object = None                     # a TableCache for particle inks (None: the default)
    local_field: bool | None = None          # the pigments' local field (None: the tables' default)
    films: int = 0
    wave_tables: int = 0
    reads: int = 0
    _tables: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        check_paper_albedo(self.paper, what="--paper (the paper albedo)")

    def table(self, recipes: tuple[Recipe, ...]):
        """The table of recipes printed one over the other (top first); one recipe: the ink."""
        key = tuple((r.ink.base_composition(), round(r.thickness_nm, 9), r.particles) for r in recipes)
        if key in self._tables:
            return self._tables[key]
        label = LAYER_SEPARATOR.join(r.ink.label for r in recipes)
        particles = LAYER_SEPARATOR.join(r.particles for r in recipes)
        thickness = [r.thickness_nm for r in recipes]
        inks = recipes[0].ink if len(recipes) == 1 else label
        with warnings.catch_warnings():       # a thin range is told once, for --thickness-range (recipe.InkTemplate)
            warnings.simplefilter("ignore", ThinLayerWarning)
            request = table_request(inks, particles, thickness_nm=thickness if len(recipes) > 1 else thickness[0],
                                    local_field=self.local_field)
        if request.molecular:
            table = request_film(request)            # the thin-film tier's table of the request
            self.films += 1
        else:
            from ..table.cache import TableCache

            opts = BuildOptions(cache=self.cache or TableCache.default(), progress=False)
            table, _, built = get_or_build(request, opts)
            self.wave_tables += int(built)
            self.reads += int(not built)
        if len(self._tables) > 256:
            self._tables.clear()
        self._tables[key] = table
        return table

    @property
    def wavelengths_nm(self) -> np.ndarray:
        """The wavelengths (nm) of a molecular ink's table (the request's default grid)."""
        return np.asarray(table_request("Y10", local_field=self.local_field).grids.wavelengths_nm, dtype=float)

    def reflectance(self, table) -> np.ndarray:
        return self.measurement.reflectance(table, self.paper)

    def lab(self, recipe: Recipe) -> np.ndarray:
        """CIELAB of a solid of the recipe on the paper."""
        table = self.table((recipe,))
        return self.measurement.lab_of_spectra(table.wavelengths, self.reflectance(table))

    def print_lab(self, recipes: tuple[Recipe, ...]) -> np.ndarray:
        """CIELAB of inks printed solid one after another (recipes[0] first): the Demichel print
        model's weights at full coverage select one primary, the stack of all the inks, last
        printed on top (at full coverage Clapper–Yule and Murray–Davies agree)."""
        n = len(recipes)
        subsets = all_subsets(n)
        weights = demichel_weights(np.ones(n), subsets)
        (solid,) = [s for s, w in zip(subsets, weights) if w > 0.0]
        top_first = tuple(recipes[i] for i in stack_order(solid))
        printed = PrintedInks(tuple(self.table((r,)) for r in recipes),
                              {solid: self.table(top_first)} if n > 1 else {})
        table = printed.table(solid)
        return self.measurement.lab_of_spectra(table.wavelengths, self.reflectance(table))

    def paper_lab(self, wavelengths_nm) -> np.ndarray:
        """CIELAB of the bare paper (a Lambertian: its reflectance factor is its albedo)."""
        return self.measurement.lab_of_spectra(wavelengths_nm, check_paper_albedo(self.paper, wavelengths_nm))
