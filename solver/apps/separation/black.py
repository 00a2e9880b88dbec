"""Black generation and the total area coverage limit (docs/printing.md, "Black generation").

    rule = BlackGeneration("gcr", strength=0.7, start=0.2, tac=3.0)
    objective = InkingObjective.build(model, black=0, rule=rule, boundary=boundary)
    separate_lab(model, lab, objective=objective)         # the black aim, then the colour

With a black ink, a colour has a one-parameter family of separations (three equations, four
unknowns). The rule picks one by an *aim* for the black coverage K of each target colour:

    K_n(L*)   the black alone that prints lightness L* (its ramp inverted; 0 above the paper)
    g         greyness: 1 − C*/C*_max(h, L*) against the print's gamut (1 on the neutral axis,
              0 on the gamut's boundary)
    curve     0 for K_n ≤ start, then linear to 1 at K_n = 1, its corner rounded (a parabola over
              `START_WIDTH`): no black in the light tones, entering without a kink
    gcr       K_aim = strength · g · curve(K_n)    (grey component replacement: black takes the
              grey part of every colour)
    ucr       K_aim = strength · g⁴ · curve(K_n)   (under-colour removal: black in the
              near-neutral shadows only)

and the separation minimises |Lab(c) − t|² + (w_K·(c_K − K_aim))² + (w_TAC·max(0, Σc − TAC))²
with w_K = `K_WEIGHT` ΔE per unit coverage (the aim chooses the black), then, for the colours
that pass leaves unmatched, from there with w_K = `K_POLISH_WEIGHT` (the colour is matched: in
the deep shadows the colour hardly depends on the inks, and the first pass would trade half a
ΔE for the aim). The solver projects its steps onto Σc ≤ TAC (`tac_limit`, `solve.project`);
the stiff penalty makes its Jacobian see the limit, and `enforce_tac` (scaling the chromatic
inks) guarantees it at the end. Defaults: `BlackGeneration()` — GCR, strength 0.7, start 0.2, TAC 300 %.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

BLACK_MODES = ("gcr", "ucr")
DEFAULT_TAC = 3.0                # 300 %
K_WEIGHT = 3.0                   # ΔE per unit coverage of the black aim's residual
K_POLISH_WEIGHT = 0.03           # … in the polishing pass that matches the colour
TAC_WEIGHT = 300.0               # ΔE per unit coverage above the limit
_UCR_POWER = 4
START_WIDTH = 0.1                # K_n over which the black curve rounds its start


@dataclass(frozen=True)
class Bounds:
    """The values a field accepts: [low, high], or [low, high) with `high_open`."""

    low: float
    high: float
    high_open: bool = False

    def __contains__(self, x) -> bool:
        return self.low <= x and (x < self.high if self.high_open else x <= self.high)

    def text(self, scale: float = 1.0) -> str:
        """'[0, 1)' — in units of `scale` (100: a fraction shown in percent)."""
        return f"[{scale * self.low:g}, {scale * self.high:g}{')' if self.high_open else ']'}"


# the one home of BlackGeneration's ranges (the print command's options report them)
STRENGTH_BOUNDS = Bounds(0.0, 1.0)                  # share of the grey component
START_BOUNDS = Bounds(0.0, 1.0, high_open=True)     # share of the black's range
TAC_BOUNDS = Bounds(1.0, 4.0)                       # fraction: 100–400 %


class BlackGenerationError(ValueError):
    """A field of `BlackGeneration` out of its range: `field` names it ('mode', 'strength',
    'start', 'tac'), `value` is what it got, `allowed` its `Bounds` (or, for 'mode', the modes),
    so that a command can name its own option."""

    def __init__(self, field: str, value, allowed):
        self.field, self.value, self.allowed = field, value, allowed
        if isinstance(allowed, Bounds):
            told = f"must lie in {allowed.text()}, got {value:g}"
        else:
            told = f"must be one of {', '.join(allowed)}, got {value!r}"
        super().__init__(f"black generation: {field} {told}")


@dataclass(frozen=True)
class BlackGeneration:
    """How much black a colour gets (module docstring); `tac` is a fraction (3.0 = 300 %).
    Out-of-range fields raise `BlackGenerationError` naming the field."""

    mode: str = "gcr"
    strength: float = 0.7
    start: float = 0.2
    tac: float = DEFAULT_TAC

    def __post_init__(self):
        if self.mode not in BLACK_MODES:
            raise BlackGenerationError("mode", self.mode, BLACK_MODES)
        for field, bounds in (("strength", STRENGTH_BOUNDS), ("start", START_BOUNDS), ("tac", TAC_BOUNDS)):
            if getattr(self, field) not in bounds:
                raise BlackGenerationError(field, getattr(self, field), bounds)

    def label(self) -> str:
        return f"{self.mode.upper()} strength {self.strength:g}, start {self.start:g}, TAC {100 * self.tac:g} %"

    def aim(self, k_neutral, greyness) -> np.ndarray:
        """K_aim from the neutral black K_n and the greyness g (module docstring)."""
        g = np.clip(greyness, 0.0, 1.0)
        return self.strength * (g if self.mode == "gcr" else g ** _UCR_POWER) * self.curve(k_neutral)

    def curve(self, k_neutral) -> np.ndarray:
        """The black curve of a neutral: 0 up to the start, then linear to 1 at K_n = 1, the
        corner rounded over `START_WIDTH` (a parabola: no kink, so no visible step in a
        gradient where the black starts)."""
        x = np.clip(np.asarray(k_neutral, dtype=np.float64), 0.0, 1.0) - self.start
        w = min(START_WIDTH, 1.0 - self.start)
        r = np.where(x <= 0.0, 0.0, np.where(x < w, x * x / (2 * w), x - w / 2))
        return r / (1.0 - self.start - w / 2)


def find_black(model) -> int | None:
    """Index of the ink that is the black: the darkest solid whose chroma is below a quarter of
    its distance from white in L* — None when no ink is that dark and neutral."""
    lab = model.lab(np.eye(model.n_inks))
    chroma = np.hypot(lab[:, 1], lab[:, 2])
    neutral = (lab[:, 0] < 40.0) & (chroma < 0.25 * (100.0 - lab[:, 0]))
    if not neutral.any():
        return None
    return int(np.flatnonzero(neutral)[np.argmin(lab[neutral, 0])])


def black_index(model, inks, black_spec: str | None) -> int | None:
    """The black ink's index: `black_spec` (an ink of `inks`, or 'none'), else the ink whose
    main pigment is K, else `find_black`."""
    from .printset import dominant_pigment, split_ink

    specs = [split_ink(x)[0] for x in inks]
    if black_spec is not None:
        if black_spec == "none":
            return None
        spec = split_ink(black_spec)[0]
        if spec not in specs:
            raise ValueError(f"black ink {black_spec!r} is not one of the inks ({', '.join(inks)})")
        return specs.index(spec)
    for i, spec in enumerate(specs):
        if dominant_pigment(spec) == "K":
            return i
    return find_black(model)


@dataclass(frozen=True)
class InkingObjective:
    """The separation's residuals: colour (3), the black aim (1, with a black), the TAC (1)."""

    model: object                  # PrintColourModel
    black: int | None
    rule: BlackGeneration
    k_lightness: np.ndarray        # L* of the black alone at K_NODES coverages (decreasing)
    boundary: object               # GamutBoundary (greyness), or None
    k_weight: float = K_WEIGHT

    K_NODES = 65

    @classmethod
    def build(cls, model, black: int | None, rule: BlackGeneration = BlackGeneration(), boundary=None):
        k = np.zeros((cls.K_NODES, model.n_inks))
        if black is not None:
            k[:, black] = np.linspace(0.0, 1.0, cls.K_NODES)
        return cls(model, black, rule, model.lab(k)[:, 0], boundary)

    @property
    def n_inks(self) -> int:
        return self.model.n_inks

    @property
    def tac_limit(self) -> float:
        """The solver projects its steps onto Σc ≤ this (the penalty then only shapes its Jacobian)."""
        return self.rule.tac

    @property
    def extras(self) -> int:
        return 2 if self.black is not None else 1

    def polished(self) -> "InkingObjective":
        """The objective of the polishing pass (module docstring)."""
        from dataclasses import replace

        return replace(self, k_weight=K_POLISH_WEIGHT)

    def k_neutral(self, L) -> np.ndarray:
        """K_n(L*): the black alone that prints lightness L* (0 above paper, 1 below the solid)."""
        lk = self.k_lightness
        return np.interp(-np.asarray(L, dtype=np.float64), -lk, np.linspace(0.0, 1.0, lk.size))

    def k_aim(self, lab) -> np.ndarray:
        from .gamut import to_lch

        L, C, h = to_lch(lab)
        if self.boundary is None:
            greyness = np.ones_like(L)
        else:
            cmax = self.boundary.chroma_max(h, L)
            greyness = 1.0 - C / np.maximum(cmax, 1e-6)
            greyness = np.where(cmax > 0, greyness, 1.0)
        return self.rule.aim(self.k_neutral(L), greyness)

    def targets(self, lab) -> np.ndarray:
        """Targets [N, 3 + extras] of the colours `lab` [N, 3]."""
        lab = np.asarray(lab, dtype=np.float64).reshape(-1, 3)
        cols = [lab]
        if self.black is not None:
            cols.append(self.k_weight * self.k_aim(lab)[:, None])
        cols.append(np.zeros((lab.shape[0], 1)))
        return np.concatenate(cols, axis=1)

    def lab(self, coverages) -> np.ndarray:
        """The residual vector's model side [..., 3 + extras] (named `lab` for the solver)."""
        c = np.asarray(coverages, dtype=np.float64)
        cols = [self.model.lab(c)]
        if self.black is not None:
            cols.append(self.k_weight * c[..., self.black:self.black + 1])
        cols.append(TAC_WEIGHT * np.maximum(c.sum(axis=-1, keepdims=True) - self.rule.tac, 0.0))
        return np.concatenate(cols, axis=-1)

    def enforce_tac(self, coverages) -> np.ndarray:
        """Coverages with Σc ≤ TAC: the chromatic inks scaled down where the sum is over it."""
        c = np.array(coverages, dtype=np.float64)
        over = c.sum(axis=-1) - self.rule.tac
        bad = over > 0
        if not bad.any():
            return c
        chromatic = np.ones(c.shape[-1], dtype=bool)
        if self.black is not None:
            chromatic[self.black] = False
        cs = c[bad][:, chromatic]
        scale = np.clip(1.0 - over[bad] / np.maximum(cs.sum(axis=-1), 1e-12), 0.0, 1.0)
        c_bad = c[bad]
        c_bad[:, chromatic] = cs * scale[:, None]
        c[bad] = c_bad
        return c
