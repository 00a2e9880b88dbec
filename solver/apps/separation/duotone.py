"""Two inks: the image mapped onto the pair's surface of colours (docs/printing.md, "Two inks: a
surface").

With two inks the printable colours are a surface in CIELAB, the image of the coverage square
(under the total area coverage limit), not a volume: a hue slice has no boundary to compress
toward: the targets the perceptual mapping chose were off the surface (Y30+B30 on a 300×200
hue sweep: 32,913 of the 33³ table's nodes "missed" by up to ΔE76 3.1), and the closest
printable colour to each jumps where two parts of the surface are about as close, so smooth
gradients printed with ridges and a noisy band in a photograph's sky. The mapping here is one continuous rule instead, parameterised on the coverage square:

1. **Lightness first, exact.** Each colour's L* is black-point compensated onto the pair's L*
   range, L' = L_black + L*·(L_paper − L_black)/100 (`gamut.compensate_lightness`, L_black the
   darkest colour the pair prints), and printed exactly: the coverages lie on the pair's curve
   of lightness L'. The square is swept by rays from the paper corner, c = t·e(s) (s ∈ [0, 1]
   the second ink's share of the direction, e(s) the direction reaching the square's far edge
   or the limit at t = 1); along each ray the printed L* falls from the paper's (`DuotoneError`
   otherwise), so each ray meets the curve of L' once, and the rays that reach it (their far
   end at most L') form one interval of s, [s_lo(L'), s_hi(L')]: the curve, parameterised by
   u ∈ [0, 1] across that interval. At the paper it is a point, bare paper; at the black, the
   darkest colour.
2. **Then a*, b*: the nearest along the curve, blended where two are about as near.** Along
   the curve of L' (`CURVE_NODES` samples of u), d²(u) is the squared a*b* distance to the
   source colour; u is the nodes' mean weighted by exp(−(d² − d²_min)/(2σ²)), σ² = w·d_min + σ0²
   (`BLEND_DE` w, `BLEND_FLOOR_DE` σ0). Where one part of the curve is nearest, the weights
   are a narrow bump on it (the nearest point, to about σ0/|∂ab/∂u| for a colour on the
   surface); where two parts are about as near — a colour on the concave side of a bent curve,
   where the nearest point jumps — the weights pass from one to the other over about w/2 ΔE of
   the source colour, so u moves across instead of jumping. The price: a colour nearest an end
   of the curve (one ink alone) gets a little of the other ink, about w/(2|∂ab/∂u|) of the
   curve (sRGB (30, 60, 200), ΔE 78 from Y30+B30's blues: 5 % Y30 under its B30).

Every step is continuous in the source colour (d²_min is, the weights and the interval's ends
are), so neighbouring colours get neighbouring coverages. The mapped colour is the printed one
(the model's colour of the coverages): the separation is exact, no "miss".

    surface = DuotoneSurface.build(model, tac=3.0)    # a PrintColourModel of two inks
    sep = surface.separate(source_lab)                # solve.Separation: targets = printed colours

The curves are tabulated at `LEVELS` lightnesses × `CURVE_NODES` (their a*b*, for the weights);
a colour's coverage is found on its own curve (the ray of its s, the t of its L' by inverse
interpolation on `RAY_NODES` × `RAY_STEPS` rays and `NEWTON_STEPS` Newton steps on the model).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .gamut import compensate_lightness
from .monotone import ink_name
from .solve import Separation

RAY_NODES = 257          # rays s = 0, 1/256, …, 1 from the paper corner
RAY_STEPS = 257          # t = 0, 1/256, …, 1 along each ray
EDGE_NODES = 4097        # far ends of rays tabulated for the curve's interval of s
LEVELS = 257             # lightnesses L_black … L_paper at which the curves' a*b* are tabulated
CURVE_NODES = 65         # nodes u along each curve
NEWTON_STEPS = 2         # on the model, after the inverse interpolation (t of a given L*)
BLEND_DE = 3.0           # w, ΔE76: σ² = w·d_min + σ0², parts about as near blend over ~w/2 ΔE of source
BLEND_FLOOR_DE = 1.0     # σ0, ΔE76 in a*b*: the weights' width for a colour on the surface
FD_STEP = 1e-6           # ray parameter t: finite-difference step of dL*/dt


class DuotoneError(ValueError):
    """Two inks whose printed L* does not fall along a ray from the paper: a lightness would be
    printed twice on it (the message names the inks and where)."""


def ray_coverages(s, t, tac: float) -> np.ndarray:
    """Coverages [N, 2] at t ∈ [0, 1] along the rays s ∈ [0, 1] from the paper corner: direction
    (1 − s, s) scaled to the square's far edge, shortened to the total area coverage limit `tac`
    (a fraction, 3.0 = 300 %)."""
    s = np.asarray(s, dtype=np.float64).reshape(-1)
    t = np.asarray(t, dtype=np.float64).reshape(-1)
    big = np.maximum(1.0 - s, s)
    reach = np.minimum(1.0, tac * big) / big                  # the far end: c = reach·(1 − s, s)
    return (t * reach)[:, None] * np.stack([1.0 - s, s], -1)


@dataclass(frozen=True)
class DuotoneSurface:
    """The surface of colours of two inks, its curves of constant lightness, and the mapping."""

    model: object                 # PrintColourModel of two inks
    tac: float                    # total area coverage limit (fraction)
    inks: tuple                   # the inks' names, for the report
    paper_l: float                # L* at the paper corner: the image's white
    black_l: float                # the darkest L* printed: the image's black
    ray_t: np.ndarray             # [RAY_NODES, LEVELS] t printing each level on each ray (1: beyond)
    edge_s: np.ndarray            # [EDGE_NODES] s of the rays' far ends
    edge_l: np.ndarray            # [EDGE_NODES] their L*, made one-dipped (falls, then rises)
    curve_ab: np.ndarray          # [LEVELS, CURVE_NODES, 2] a*b* along each level's curve

    black_label = "two inks, no black generation"

    @classmethod
    def build(cls, model, tac: float = 3.0) -> "DuotoneSurface":
        if model.n_inks != 2:
            raise ValueError(f"a duotone surface is printed with two inks, the model has {model.n_inks}")
        inks = (ink_name(model, 0), ink_name(model, 1))
        s = np.linspace(0.0, 1.0, RAY_NODES)
        t = np.linspace(0.0, 1.0, RAY_STEPS)
        ray_l = model.lab(ray_coverages(np.repeat(s, t.size), np.tile(t, s.size), tac))[:, 0].reshape(s.size, t.size)
        rises = np.argwhere(np.diff(ray_l, axis=1) >= 0.0)
        if rises.size:
            i, j = rises[0]
            c0, c1 = (ray_coverages(s[i], t[j:j + 2], tac) * 100).round(1)
            raise DuotoneError(
                f"two inks ({' + '.join(inks)}): their printed L* does not fall steadily with coverage "
                f"(L* {ray_l[i, j]:.2f} at {c0[0]:g} % + {c0[1]:g} %, {ray_l[i, j + 1]:.2f} at {c1[0]:g} % + "
                f"{c1[1]:g} %), so their tones cannot carry the image's lightness: print with inks that darken "
                "the paper and each other")
        es = np.linspace(0.0, 1.0, EDGE_NODES)
        el = _one_dipped(model.lab(ray_coverages(es, np.ones_like(es), tac))[:, 0])
        paper_l, black_l = float(ray_l[0, 0]), float(el.min())
        levels = np.linspace(black_l, paper_l, LEVELS)
        ray_t = np.stack([np.interp(-levels, -row, t) for row in ray_l])      # clamped: 1 beyond the ray's end
        surface = cls(model, tac, inks, paper_l, black_l, ray_t, es, el, np.zeros((LEVELS, CURVE_NODES, 2)))
        u = np.linspace(0.0, 1.0, CURVE_NODES)
        level, node = np.repeat(levels, u.size), np.tile(u, levels.size)
        ab = model.lab(surface.coverages(level, node))[:, 1:]
        return cls(model, tac, inks, paper_l, black_l, ray_t, es, el, ab.reshape(LEVELS, CURVE_NODES, 2))

    # ---------------------------------------------------------------- the curves of constant L*
    def lightness_map(self, L) -> np.ndarray:
        """Black-point compensation: L* 0…100 → black_l…paper_l (linear)."""
        return compensate_lightness(L, self.black_l, self.paper_l)

    def interval(self, L) -> tuple[np.ndarray, np.ndarray]:
        """(s_lo, s_hi) [N]: the rays whose far end prints L* ≤ L, one interval of s (continuous in L)."""
        L = np.asarray(L, dtype=np.float64).reshape(-1)
        low = int(np.argmin(self.edge_l))
        left_s, left_l = self.edge_s[:low + 1], self.edge_l[:low + 1]      # falling
        right_s, right_l = self.edge_s[low:], self.edge_l[low:]            # rising
        return np.interp(-L, -left_l, left_s), np.interp(L, right_l, right_s)

    def coverages(self, L, u) -> np.ndarray:
        """Coverages [N, 2] printing L* L [N] at the position u [N] ∈ [0, 1] along its curve."""
        L = np.clip(np.asarray(L, dtype=np.float64).reshape(-1), self.black_l, self.paper_l)
        lo, hi = self.interval(L)
        s = lo + np.clip(np.asarray(u, dtype=np.float64).reshape(-1), 0.0, 1.0) * (hi - lo)
        t = _bilinear(self.ray_t, s * (RAY_NODES - 1), self._level_index(L))
        for _ in range(NEWTON_STEPS):                                       # on the model: L* exact
            here = self.model.lab(ray_coverages(s, t, self.tac))[:, 0]
            h = np.where(t > 1.0 - FD_STEP, -FD_STEP, FD_STEP)
            slope = (self.model.lab(ray_coverages(s, t + h, self.tac))[:, 0] - here) / h
            t = np.clip(t - (here - L) / np.minimum(slope, -1e-9), 0.0, 1.0)
        return ray_coverages(s, t, self.tac)

    def _level_index(self, L) -> np.ndarray:
        return (L - self.black_l) / max(self.paper_l - self.black_l, 1e-12) * (LEVELS - 1)

    # ---------------------------------------------------------------- the mapping
    def position(self, L, ab) -> np.ndarray:
        """u [N] along the curve of L* L [N] for source a*b* [N, 2] (module docstring, step 2)."""
        k = np.clip(self._level_index(np.asarray(L, dtype=np.float64).reshape(-1)), 0.0, LEVELS - 1)
        k0 = np.minimum(np.floor(k).astype(np.int64), LEVELS - 2)
        f = (k - k0)[:, None, None]
        curve = self.curve_ab[k0] * (1.0 - f) + self.curve_ab[k0 + 1] * f                 # [N, nodes, 2]
        d2 = np.sum((curve - np.asarray(ab, dtype=np.float64).reshape(-1, 1, 2)) ** 2, axis=-1)
        d2min = d2.min(axis=1, keepdims=True)
        w = np.exp(-(d2 - d2min) / (2.0 * (BLEND_DE * np.sqrt(d2min) + BLEND_FLOOR_DE ** 2)))
        return w @ np.linspace(0.0, 1.0, CURVE_NODES) / w.sum(axis=1)

    def separate(self, source_lab, gamut_de: float = 0.5, chunk: int | None = None) -> Separation:
        """Source colours CIELAB [N, 3] on the surface: coverages [N, 2], the mapped colours the
        printed ones (`gamut_de`: the Separation's out-of-gamut threshold, never exceeded; `chunk`:
        colours mapped together, memory ~ chunk·CURVE_NODES·40 B; None: all)."""
        source = np.asarray(source_lab, dtype=np.float64).reshape(-1, 3)
        L = self.lightness_map(source[:, 0])
        step = chunk or max(source.shape[0], 1)
        c = np.concatenate([self.coverages(L[i:i + step], self.position(L[i:i + step], source[i:i + step, 1:]))
                            for i in range(0, source.shape[0], step)] or [np.zeros((0, 2))])
        printed = self.model.lab(c)
        return Separation(c, printed.copy(), printed, np.zeros(c.shape[0], dtype=np.int64), gamut_de)

    def mapped(self, source_lab, chunk: int | None = None) -> np.ndarray:
        """The colours to print (CIELAB [N, 3]) of source colours: the pair's at their coverages."""
        return self.separate(source_lab, chunk=chunk).printed_lab

    @property
    def lightness_range(self) -> tuple[float, float]:
        """(black, white) L* of the black-point compensation."""
        return self.black_l, self.paper_l

    def report_line(self, mean_de2000: float, max_de2000: float) -> str:
        """What was printed instead of a gamut mapping, with the ΔE2000 image → print."""
        return (f"two inks: colours mapped onto the surface of colours {' + '.join(self.inks)} print (each "
                f"pixel's L* compensated onto theirs, {self.black_l:.1f} darkest – {self.paper_l:.1f} paper, and "
                "printed exactly; its a*b* the nearest along that lightness, blended where two parts are about as "
                f"near); ΔE2000 image → print mean {mean_de2000:.2f}, max {max_de2000:.2f}")


def _one_dipped(L: np.ndarray) -> np.ndarray:
    """L* along the rays' far ends made to fall to its minimum and rise after it (a running
    minimum from each end), so that the rays reaching a lightness form one interval."""
    low = int(np.argmin(L))
    out = L.copy()
    out[:low + 1] = np.minimum.accumulate(L[:low + 1])
    out[low:] = np.minimum.accumulate(L[low:][::-1])[::-1]
    return out


def _bilinear(table: np.ndarray, i, j) -> np.ndarray:
    """table [n, m] at fractional indices (i, j) [N], clamped to its edges."""
    i = np.clip(i, 0.0, table.shape[0] - 1)
    j = np.clip(j, 0.0, table.shape[1] - 1)
    i0 = np.minimum(np.floor(i).astype(np.int64), table.shape[0] - 2)
    j0 = np.minimum(np.floor(j).astype(np.int64), table.shape[1] - 2)
    fi, fj = i - i0, j - j0
    return ((table[i0, j0] * (1 - fj) + table[i0, j0 + 1] * fj) * (1 - fi)
            + (table[i0 + 1, j0] * (1 - fj) + table[i0 + 1, j0 + 1] * fj) * fi)
