"""Reference model of printed colour (pure NumPy, no Mitsuba): halftones of several inks on
paper, Clapper–Yule or Murray–Davies over Demichel primaries (docs/plugin.md, "Printing").

    from solver.printing import PrintedInks, ReflectancePredictor, directional_albedo
    printed = PrintedInks((R30, Y30, B30), stacks={(0, 2): b30_over_r30, ...})
    directional_albedo(printed, [0.5, 0.2, 0.0], paper=0.9, polar_rad=0.0)     # [nλ]
    ReflectancePredictor.build(printed, paper=0.9, view_rad=0.0)(coverages)    # [..., nλ]

The `ink` BSDF evaluates the same formulas per lane; its tests compare against this package.
"""

from .demichel import all_subsets, demichel_weights, stack_order
from .inkset import PrintedInks
from .measured import MeasuredPredictor
from .model import (COVERAGE_MODELS, DEFAULT_COVERAGE_MODEL, brdf_smooth, check_coverage_model,
                    directional_albedo, specular_reflectance)
from .overlap import TexelMask, possible_primaries
from .predict import ReflectancePredictor, reflectance

__all__ = ["COVERAGE_MODELS", "DEFAULT_COVERAGE_MODEL", "MeasuredPredictor", "PrintedInks", "ReflectancePredictor",
           "TexelMask", "all_subsets", "brdf_smooth", "check_coverage_model", "demichel_weights",
           "directional_albedo", "possible_primaries", "reflectance", "specular_reflectance",
           "stack_order"]
