"""One print: an sRGB image → coverage images → coverage textures, with every choice in one
typed object.

    settings = PrintSettings(inks=parse_ink_list("process"), dots=parse_dots("AM:150"))
    result = print_image(rgb8, settings, printed_inks(settings.inks))
    paths = write_textures(result, folder, stem="page")

The coverage model `auto` is what a render of the textures shows: with binary dots (AM, FM)
each texel is bare paper or full overprint, and the BSDF, which has no light spreading sideways
under neighbouring dots, shows their area-weighted mean — Murray–Davies of the dot areas; with
continuous coverages the BSDF applies its coverage model per texel — Clapper–Yule, its default.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from solver.paper import check_paper_albedo
from solver.printing import COVERAGE_MODELS, PrintedInks
from .black import BlackGeneration, black_index
from .colour_space import DEFAULT_INTENT, check_intent
from .gamut import GamutSettings
from .printset import default_paper
from .halftone import Dots, TexelGrid, halftone_ink, print_size
from .image import write_grey_png
from .printmodel import PrintColourModel
from .screens import screen_angles
from .separate import DEFAULT_LUT_NODES, DEFAULT_MAPPING, MAPPINGS, ImageSeparation, Separator, separate_image
from .solve import SolverSettings

AUTO_MODEL = "auto"
DEFAULT_WIDTH_CM = 12.0


def resolve_coverage_model(name: str, dots: Dots) -> str:
    """`auto` → murray-davies for binary dots, clapper-yule for continuous coverages."""
    if name == AUTO_MODEL:
        return "murray-davies" if dots.binary else "clapper-yule"
    if name not in COVERAGE_MODELS:
        raise ValueError(f"coverage model must be {AUTO_MODEL}, {' or '.join(COVERAGE_MODELS)}; got {name!r}")
    return name


@dataclass(frozen=True)
class PrintSettings:
    """Everything a print is made from (each default lives here or in the module it names)."""

    inks: tuple[str, ...]                         # ink specs in printing order (printset)
    dots: Dots = Dots("none")
    coverage_model: str = AUTO_MODEL
    paper: float | None = None                    # paper albedo; None: printset.default_paper(inks)
    size_cm: tuple = (DEFAULT_WIDTH_CM, None)     # (width, height or None: the image's aspect)
    dpi: float | None = None                      # texture resolution (None: halftone.default_dpi)
    intent: str = DEFAULT_INTENT
    black: BlackGeneration = BlackGeneration()   # black generation and the TAC limit
    black_ink: str | None = None                  # None: the K ink, else the darkest neutral one
    mapping: str = DEFAULT_MAPPING                # perceptual gamut mapping, or clip (closest colour)
    gamut: GamutSettings = GamutSettings()
    lut_nodes: int = DEFAULT_LUT_NODES            # separation table nodes per sRGB axis (0: none)
    solver: SolverSettings = field(default_factory=SolverSettings)

    def __post_init__(self):
        resolve_coverage_model(self.coverage_model, self.dots)
        check_intent(self.intent)
        if self.mapping not in MAPPINGS:
            raise ValueError(f"gamut mapping must be one of {', '.join(MAPPINGS)}; got {self.mapping!r}")
        if self.paper is None:
            object.__setattr__(self, "paper", default_paper(self.inks))
        check_paper_albedo(self.paper)
        if self.dpi is not None and not self.dpi > 0:
            raise ValueError(f"dpi must be positive, got {self.dpi}")

    @property
    def model(self) -> str:
        return resolve_coverage_model(self.coverage_model, self.dots)

    def grid(self, image_shape) -> TexelGrid:
        """The texture grid for an image of `image_shape` (rows, columns); DotsError when the
        textures would be too large."""
        return TexelGrid.for_print(print_size(self.size_cm, image_shape), image_shape, self.dots, self.dpi)


@dataclass(frozen=True)
class PrintedImage:
    settings: PrintSettings
    separation: ImageSeparation
    grid: TexelGrid
    angles_deg: tuple[float, ...]                 # AM screen angle per ink
    textures: tuple[np.ndarray, ...]              # uint8 [rows, columns] per ink, 255 = full ink


def print_image(rgb8: np.ndarray, settings: PrintSettings, printed: PrintedInks, progress=None,
                grid: TexelGrid | None = None) -> PrintedImage:
    """Separate and halftone an 8-bit sRGB image; `progress(n)` as in `separate_image`."""
    grid = grid or settings.grid(rgb8.shape[:2])
    separator = build_separator(settings, printed)
    model = separator.model
    separation = separate_image(separator, rgb8, progress=progress)
    angles = screen_angles(model.full_ink_lightness())
    textures = tuple(halftone_ink(separation.coverages[:, :, i], grid, settings.dots, angles[i], seed=i + 1)
                     for i in range(model.n_inks))
    return PrintedImage(settings, separation, grid, angles, textures)


def print_model(settings: PrintSettings, printed: PrintedInks) -> tuple[PrintColourModel, int | None]:
    """(the print's colour model, the index of its black ink or None)."""
    model = PrintColourModel.build(printed, settings.paper, settings.model, settings.intent)
    return model, black_index(model, settings.inks, settings.black_ink)


def build_separator(settings: PrintSettings, printed: PrintedInks) -> Separator:
    """The print's model, gamut, black rule and solver from its settings."""
    model, black = print_model(settings, printed)
    return Separator.build(model, black, settings.black, settings.mapping, settings.gamut, settings.solver,
                           settings.lut_nodes)


def texture_name(stem: str, index: int, ink: str) -> str:
    """File name of ink `index` (0-based) of a print: '<stem>_<n>_<ink>.png'."""
    return f"{stem}_{index + 1}_{ink.replace('+', '_').replace('.', 'p').replace('@', '_')}.png"


def write_textures(result: PrintedImage, folder, stem: str) -> list[Path]:
    """Write each ink's texture as an 8-bit grey PNG into `folder`; the paths, ink order."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return [write_grey_png(folder / texture_name(stem, i, ink), tex)
            for i, (ink, tex) in enumerate(zip(result.settings.inks, result.textures))]
