"""Colour separation and halftoning of images for printing with the project's inks (pure
NumPy; Pillow for image files): docs/printing.md.

    from solver.apps.separation import PrintSettings, parse_dots, parse_ink_list, print_image, printed_inks, read_image
    settings = PrintSettings(inks=parse_ink_list("process"), dots=parse_dots("AM:150"))   # K, C, M, Y
    result = print_image(read_image("photo.png").rgb8, settings, printed_inks(settings.inks))
    result.separation.report.lines(); result.textures          # uint8 per ink, 255 = full ink

Stages, one per module: `printset` (ink lists → tables of inks and overprints, through the
cache), `printmodel` (coverages → CIELAB under the press's measurement, 45:0 D50, with
`solver.printing`), `gamut` (the print's gamut, perceptual gamut mapping), `monotone` (one
ink: the image's lightness in it), `duotone` (two inks: the image on their surface of colours),
`black` (black generation, TAC), `solve` (start grid + projected Levenberg–Marquardt), `separate`
(an image's distinct colours or a 3-D table over sRGB, report), `characterisation` (a CGATS chart),
`screens` (AM and FM thresholds), `halftone` (texel grid, dots), `image` (files), `job` (one
print's settings).
"""

from .black import BLACK_MODES, BlackGeneration, BlackGenerationError, InkingObjective, black_index
from .colour_space import INTENTS, delta_e76, delta_e2000, lab_to_srgb8, srgb8_to_lab
from .halftone import Dots, DotsError, TexelGrid, halftone_ink, parse_dots, texture_mean
from .image import ImageError, ImageWarning, LoadedImage, read_image, read_srgb8, unique_colours, write_grey_png, write_rgb_png
from .job import AUTO_MODEL, PrintedImage, PrintSettings, print_image, resolve_coverage_model, write_textures
from .printmodel import PrintColourModel
from .printset import InkListError, parse_ink_list, printed_inks
from .screens import am_threshold, blue_noise_mask, fm_threshold, screen_angles
from .gamut import GamutBoundary, GamutSettings, map_to_gamut
from .duotone import DuotoneError, DuotoneSurface
from .monotone import MonotoneError, MonotoneRamp
from .separate import MAPPINGS, ImageSeparation, SeparationLUT, SeparationReport, Separator, separate_image
from .solve import CoverageGrid, Separation, SolverSettings, separate_lab

__all__ = ["AUTO_MODEL", "BLACK_MODES", "BlackGeneration", "BlackGenerationError", "DuotoneError", "DuotoneSurface",
           "GamutBoundary", "GamutSettings", "InkingObjective",
           "MAPPINGS", "MonotoneError", "MonotoneRamp", "SeparationLUT", "Separator", "black_index", "map_to_gamut", "INTENTS", "CoverageGrid", "Dots", "DotsError", "ImageError", "ImageSeparation",
           "ImageWarning", "InkListError", "LoadedImage", "read_image", "PrintColourModel", "PrintSettings", "PrintedImage", "Separation",
           "SeparationReport", "SolverSettings", "TexelGrid", "am_threshold", "blue_noise_mask",
           "delta_e76", "delta_e2000", "fm_threshold", "halftone_ink", "lab_to_srgb8", "parse_dots",
           "parse_ink_list", "print_image", "printed_inks", "read_srgb8", "resolve_coverage_model",
           "screen_angles", "separate_image", "separate_lab", "srgb8_to_lab", "texture_mean",
           "unique_colours", "write_grey_png", "write_rgb_png", "write_textures"]
