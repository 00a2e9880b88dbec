"""Separation of an image: sRGB colours → gamut mapping → black generation → coverages per
pixel, with a report.

    separator = Separator.build(model, black=3)            # the print's gamut, black rule, LUT init
    result = separate_image(separator, rgb8, progress=bar)
    result.coverages                 # float32 [rows, columns, k]
    result.report.lines()            # what to tell the user

Images repeat colours: only the distinct 8-bit colours are separated (`image.unique_colours`),
then scattered back to the pixels. An image with more distinct colours than the nodes of the
separation's 3-D lookup table (`lut_nodes`³, default 33³ = 35,937) is separated through the
table instead: its nodes (sRGB code values on a regular grid) are separated exactly and every
colour is interpolated tetrahedrally between the four nodes of its tetrahedron (`lut`), the
way an ICC B2A table is used; benchmarks/bench_separation.py measures the interpolation's
error against the direct separation.

One or two inks under the perceptual mapping have no volume of colours to map into (`few_inks`):
one ink prints a monotone (`monotone`): each colour's compensated L* as the coverage that prints
it, exact and cheap, so every distinct colour is separated directly whatever `lut_nodes` (the
table would only add its interpolation error); two inks map each colour onto their surface of
colours (`duotone`), also directly: a 33³ table's cells are coarse in their light yellows (ΔE76
up to 5.7 for Y30+B30, whose b* changes 13 per L*), and the direct mapping takes 1.5× the
table's time (970,693 distinct colours: 9.2 s against 6.3 s on 2 cores).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from .black import BlackGeneration, InkingObjective
from .colour_space import delta_e2000, srgb_to_lab
from .gamut import GamutBoundary, GamutSettings, map_to_gamut
from .duotone import DuotoneSurface
from .image import unique_colours
from .monotone import MonotoneRamp
from .printmodel import PrintColourModel
from .solve import CoverageGrid, SolverSettings, separate_lab

MAPPINGS = ("perceptual", "clip")
DEFAULT_MAPPING = "perceptual"
DEFAULT_LUT_NODES = 33
MAPPED_DE = 0.5                     # ΔE76 a colour must move to count as gamut-mapped
REFINE_ITERATIONS = 15             # LM steps (one start) of the boundary's check against the print
BLACK_MARGIN_L = 0.2                # L* above the darkest grey reached where the mapping puts black
BLACK_CHECKS = 4                    # separations of the black's grey while it prints lighter (`build`)
BLACK_GREY_TOLERANCE_L = 0.5        # L* the raised black's grey may print above it (one ink's grey lies
                                    # NEUTRAL_CHROMA inside its tints: Y30's prints 0.23 lighter)


@dataclass(frozen=True)
class Separator:
    """Everything that turns sRGB colours into coverages for one print."""

    model: PrintColourModel
    objective: InkingObjective
    boundary: GamutBoundary
    grid: CoverageGrid = field(repr=False)
    mapping: str = DEFAULT_MAPPING
    gamut: GamutSettings = GamutSettings()
    solver: SolverSettings = SolverSettings()
    lut_nodes: int = DEFAULT_LUT_NODES
    few_inks: MonotoneRamp | DuotoneSurface | None = None   # one or two inks, perceptual (`few_inks_map`)

    @classmethod
    def build(cls, model: PrintColourModel, black: int | None = None, rule: BlackGeneration = BlackGeneration(),
              mapping: str = DEFAULT_MAPPING, gamut: GamutSettings = GamutSettings(),
              solver: SolverSettings = SolverSettings(), lut_nodes: int = DEFAULT_LUT_NODES) -> "Separator":
        if mapping not in MAPPINGS:
            raise ValueError(f"gamut mapping must be one of {', '.join(MAPPINGS)}; got {mapping!r}")
        if lut_nodes != 0 and not 2 <= lut_nodes <= 129:
            raise ValueError(f"lut_nodes must be 0 (no table) or in [2, 129], got {lut_nodes}")
        hull = GamutBoundary.build(model, rule.tac)
        objective = InkingObjective.build(model, black, rule, hull)
        grid = CoverageGrid.build(objective, solver.nodes(model.n_inks))
        if model.n_inks <= 2 and mapping == "perceptual":        # a curve or a surface: no boundary
            return cls(model, objective, hull, grid, mapping, gamut, solver, lut_nodes,
                       few_inks_map(model, rule.tac))
        quick = replace(solver, starts=1, near_miss_starts=0, max_iterations=REFINE_ITERATIONS)
        printed_of = lambda lab: separate_lab(model, lab, quick, grid, objective=objective).printed_lab  # noqa: E731
        boundary = hull.refined(printed_of)
        # the black point is the darkest grey (`GamutBoundary.greyed`: the neutral, or the least
        # chromatic colour where the print has none) the separation reaches (under the TAC, with
        # the black rule's starts), a little above: greys below it would all print alike. The grey
        # of the raised black may print lighter still (the process inks' darkest colours are
        # chromatic, their darkest neutral lighter): raised until its own grey prints at it
        black_l, tolerance = boundary.black_l, 0.0
        for _ in range(BLACK_CHECKS):
            reached = float(printed_of(boundary.greyed([[black_l, 0.0, 0.0]]))[0, 0])
            if reached <= black_l + tolerance:
                break
            black_l, tolerance = reached + BLACK_MARGIN_L, BLACK_GREY_TOLERANCE_L
        boundary = boundary.with_black(black_l)
        objective = replace(objective, boundary=boundary)
        return cls(model, objective, boundary, grid, mapping, gamut, solver, lut_nodes)

    def with_rule(self, rule: BlackGeneration) -> "Separator":
        """The same print with another black rule (its gamut and start grid kept when the
        total area coverage limit is the same)."""
        if rule.tac != self.objective.rule.tac:
            return Separator.build(self.model, self.objective.black, rule, self.mapping, self.gamut, self.solver,
                                   self.lut_nodes)
        return replace(self, objective=replace(self.objective, rule=rule))

    @property
    def lightness_range(self) -> tuple[float, float] | None:
        """(black, white) L* of the black-point compensation (None: clip, none)."""
        if self.few_inks is not None:
            return self.few_inks.lightness_range
        return (self.boundary.black_l, self.boundary.white_l) if self.mapping == "perceptual" else None

    def lightness_mapped(self, source_lab) -> np.ndarray:
        """Source colours after the black-point compensation and the print's grey alone
        (perceptual), or as they are (clip): what a colour inside the gamut prints as (a
        monotone, a duotone: what the inks print for it)."""
        if self.few_inks is not None:
            return self.few_inks.mapped(source_lab, self.solver.chunk)
        lab = np.array(source_lab, dtype=np.float64).reshape(-1, 3)
        if self.mapping == "perceptual":
            lab[:, 0] = self.boundary.lightness_map(lab[:, 0])
            lab = self.boundary.greyed(lab)
        return lab

    def targets(self, source_lab) -> np.ndarray:
        """The colours to print of source colours (CIELAB of sRGB): gamut-mapped, the monotone's or
        duotone's, or as they are."""
        if self.few_inks is not None:
            return self.few_inks.mapped(source_lab, self.solver.chunk)
        if self.mapping == "clip":
            return np.asarray(source_lab, dtype=np.float64).reshape(-1, 3)
        return map_to_gamut(source_lab, self.boundary, self.gamut, self.model.measurement)

    def separate_srgb(self, encoded, progress=None):
        """(Separation of the mapped colours, source CIELAB) for encoded sRGB values [N, 3] in [0, 1]."""
        source = srgb_to_lab(np.asarray(encoded, dtype=np.float64).reshape(-1, 3), self.model.measurement)
        if self.few_inks is not None:
            sep = self.few_inks.separate(source, self.solver.gamut_de, self.solver.chunk)
            if progress is not None:
                progress(source.shape[0])
            return sep, source
        sep = separate_lab(self.model, self.targets(source), self.solver, self.grid, progress, self.objective)
        return sep, source


def few_inks_map(model: PrintColourModel, tac: float) -> MonotoneRamp | DuotoneSurface:
    """The mapping of a print with too few inks for a volume of colours: one ink's monotone, two
    inks' surface (`tac`: the total area coverage limit, a fraction)."""
    if model.n_inks == 1:
        return MonotoneRamp.build(model)
    return DuotoneSurface.build(model, tac)


@dataclass(frozen=True)
class SeparationLUT:
    """Coverages at the nodes of a regular grid over encoded sRGB (`nodes` per axis)."""

    nodes: int
    coverages: np.ndarray            # [n, n, n, k]

    @classmethod
    def build(cls, separator: Separator, nodes: int, progress=None):
        """(the table, the Separation of its nodes)."""
        axis = np.linspace(0.0, 1.0, nodes)
        rgb = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
        sep, _ = separator.separate_srgb(rgb, progress)
        return cls(nodes, sep.coverages.reshape(nodes, nodes, nodes, -1)), sep

    def __call__(self, encoded) -> np.ndarray:
        """Coverages [N, k] of encoded sRGB [N, 3] in [0, 1], tetrahedral interpolation: the cube
        cell of the colour is cut into six tetrahedra along its main diagonal by the order of the
        fractional parts (the method of ICC colour management modules)."""
        x = np.clip(np.asarray(encoded, dtype=np.float64).reshape(-1, 3), 0.0, 1.0) * (self.nodes - 1)
        i = np.minimum(np.floor(x).astype(np.int64), self.nodes - 2)
        f = x - i
        order = np.argsort(-f, axis=1)                               # largest fraction first
        fs = np.take_along_axis(f, order, axis=1)
        table = self.coverages
        corner = i.copy()
        out = table[corner[:, 0], corner[:, 1], corner[:, 2]] * (1.0 - fs[:, 0:1])
        weights = (fs[:, 0] - fs[:, 1], fs[:, 1] - fs[:, 2], fs[:, 2])
        rows = np.arange(x.shape[0])
        for step, w in enumerate(weights):
            corner[rows, order[:, step]] += 1
            out += table[corner[:, 0], corner[:, 1], corner[:, 2]] * w[:, None]
        return out


@dataclass(frozen=True)
class SeparationReport:
    """Pixel statistics of a separation: how far the gamut mapping moved the colours, and how
    closely the print matches the mapped colours."""

    pixels: int
    unique_colours: int
    mapped_pixels: int                   # moved by the chroma compression by more than MAPPED_DE
    mapping: str
    mapped_mean_de2000: float            # source → print, over the mapped pixels (0 when none)
    mapped_max_de2000: float
    mean_de2000: float                   # source → print, all pixels
    residual_max_de76: float             # mapped colour → print (the solver's miss)
    residual_pixels: int                 # pixels (table nodes with a LUT) whose miss exceeds gamut_de
    gamut_de: float
    lut_nodes: int                       # 0: every colour separated directly
    lightness_range: tuple | None        # (black, white) L* of the black-point compensation
    black: str
    seconds: float
    few_inks_line: str | None = None     # one or two inks: what was printed instead of a gamut mapping

    def lines(self) -> list[str]:
        how = (f"through a {self.lut_nodes}³ table" if self.lut_nodes else "directly")
        out = [f"separated {self.pixels:,} pixels ({self.unique_colours:,} distinct colours) {how} in "
               f"{self.seconds:.1f} s; {self.black}; mean ΔE2000 image → print {self.mean_de2000:.2f}"]
        if self.few_inks_line is not None:             # no gamut to map into: one line says what it is
            out.append(self.few_inks_line)
        else:
            out.extend(self._gamut_lines())
        if self.residual_pixels:
            what = "table nodes" if self.lut_nodes else "pixels"
            out.append(f"{self.residual_pixels:,} {what} miss their mapped colour by more than ΔE76 "
                       f"{self.gamut_de:g} (max {self.residual_max_de76:.2f}): the separation found no closer "
                       "colour (its starts miss them, or the gamut's boundary is overestimated there)")
        return out

    def _gamut_lines(self) -> list[str]:
        """The black-point compensation and what the gamut mapping moved (two inks or more)."""
        out = []
        if self.lightness_range is not None:
            out.append(f"lightness compressed to the print's L* {self.lightness_range[0]:.1f}–"
                       f"{self.lightness_range[1]:.1f} (black-point compensation)")
        if self.mapped_pixels:
            verb = ("chroma compressed toward the cusp (perceptual)" if self.mapping == "perceptual"
                    else "clipped to the closest printable colour")
            share = self.mapped_pixels / max(self.pixels, 1)
            out.append(f"out of gamut, {verb}: {self.mapped_pixels:,} pixels ({share:.1%}); ΔE2000 mean "
                       f"{self.mapped_mean_de2000:.2f}, max {self.mapped_max_de2000:.2f}")
        else:
            out.append("every pixel in gamut")
        return out


@dataclass(frozen=True)
class ImageSeparation:
    coverages: np.ndarray                # float32 [rows, columns, k]
    printed_lab: np.ndarray              # float32 [rows, columns, 3]: the model's colour
    report: SeparationReport


def separate_image(separator, rgb8: np.ndarray, settings: SolverSettings | None = None,
                   progress=None) -> ImageSeparation:
    """Separate an 8-bit sRGB image [rows, columns, 3] (a `Separator`, or a PrintColourModel for
    the defaults with no black); `progress(done, total)` is called with the number of colours
    (distinct colours, or LUT nodes) separated so far and their total."""
    t0 = time.perf_counter()
    if isinstance(separator, PrintColourModel):
        separator = Separator.build(separator, solver=settings or SolverSettings())
    model = separator.model
    rows, cols = rgb8.shape[:2]
    colours, index = unique_colours(rgb8)
    encoded = colours / 255.0
    few = separator.few_inks
    # one or two inks are separated directly whatever lut_nodes (module docstring)
    use_lut = few is None and separator.lut_nodes and colours.shape[0] > separator.lut_nodes ** 3
    total = separator.lut_nodes ** 3 if use_lut else colours.shape[0]
    done = [0]

    def chunk_done(n: int) -> None:
        done[0] += n
        progress(done[0], total)

    if progress is not None:
        progress(0, total)
    bar = chunk_done if progress is not None else None
    source = srgb_to_lab(encoded, model.measurement)
    counts = np.bincount(index, minlength=colours.shape[0])
    if use_lut:
        lut, sep = SeparationLUT.build(separator, separator.lut_nodes, bar)
        coverages = lut(encoded)
        printed = model.lab(coverages)
        reached = printed                          # moved by the mapping, or missed
        miss = sep.delta_e76                                               # at the table's nodes
        missed_count = int(np.sum(miss > separator.solver.gamut_de))
    else:
        sep, _ = separator.separate_srgb(encoded, bar)
        coverages, printed = sep.coverages, sep.printed_lab
        reached = sep.target_lab
        miss = sep.delta_e76
        missed_count = int(counts[miss > separator.solver.gamut_de].sum())
    if separator.mapping == "clip":                  # the solver's miss is the clipping
        moved = np.linalg.norm(printed - source, axis=-1) > separator.solver.gamut_de
        missed_count = 0
    elif few is not None:                            # one or two inks: no gamut mapping moved them
        moved = np.zeros(colours.shape[0], dtype=bool)
    else:
        moved = np.linalg.norm(reached - separator.lightness_mapped(source), axis=-1) > MAPPED_DE
    de00 = delta_e2000(printed, source)
    mean_de00 = float(np.average(de00, weights=counts))
    w = counts[moved]
    report = SeparationReport(
        rows * cols, colours.shape[0], int(w.sum()), separator.mapping,
        float(np.average(de00[moved], weights=w)) if w.sum() else 0.0, float(de00[moved].max(initial=0.0)),
        mean_de00, float(miss.max(initial=0.0)), missed_count,
        separator.solver.gamut_de, separator.lut_nodes if use_lut else 0, separator.lightness_range,
        few.black_label if few is not None
        else ("black: " + separator.objective.rule.label()) if separator.objective.black is not None
        else f"no black ink, TAC {100 * separator.objective.rule.tac:g} %",
        time.perf_counter() - t0,
        few.report_line(mean_de00, float(de00.max(initial=0.0))) if few is not None else None)
    k = model.n_inks
    return ImageSeparation(coverages.astype(np.float32)[index].reshape(rows, cols, k),
                           printed.astype(np.float32)[index].reshape(rows, cols, 3), report)
