"""Perceptual gamut mapping: sRGB colours → printable colours, hue kept, compressed toward the
cusp of their hue (docs/printing.md, "Gamut mapping").

    boundary = GamutBoundary.build(model, tac=3.0)          # the print's gamut, per hue slice
    mapped = map_to_gamut(srgb_lab, boundary)                # CIELAB [N, 3] inside the gamut

**The print's gamut** (`GamutBoundary`): the printed colours of a dense sample of coverage
space (a grid, every 2-D face of the coverage cube finer, both with nodes at (i/n)² so that
the light tints near paper white are sampled finely; mixes over the total area coverage limit
scaled onto it) in CIELAB's L* and C* and Oklab's hue (the perceived hue: `to_lch`) under
the model's measurement (45:0, D50 by default).
Per hue slice (`HUE_BINS` slices, each gathering the samples within one slice width of its
hue) the boundary is the convex hull of the samples in the (C*, L*) half-plane, bounded by the
slice's exact section of the gamut's surface: the images of the coverage polytope's 2-D faces
(`face_grids`: the cube's, and those on the TAC limit) sampled on grids, cut into triangles
(`_face_triangles`), each triangle the slice's hue crosses giving a segment of the section
(`_section_chroma`). The section is concave where the gamut is: there the hull alone spans the
concave part (above the cusp of the process inks' yellow-greens by up to 8 C*, so that 16 % of
a 17³ table's mapped nodes were missed by up to ΔE76 2.3: benchmarks/bench_press.py, section 7).
The boundary is tabulated as the largest chroma C_max(h, L*) on `LIGHTNESS_NODES` lightness
levels, smoothed across hue (a Gaussian of `HUE_SMOOTHING_BINS` slices) and interpolated
bilinearly (periodic in hue). The mapping below takes a ray's first exit, continuous in the
colour while the slice is star-shaped about the focal point (the ramps of
tests/test_separation_press.py stay monotone and without a notch with the process inks);
`refined` checks the boundary against the print (targets on it separated, C_max scaled by the
chroma reached) and the report counts the mapped colours the separation still misses. The cusp
of a hue is the (L*, C*) of its largest chroma.

**The mapping** (`map_to_gamut`, vectorised):

1. Lightness (black-point compensation): L' = L_black + L*·(L_white − L_black)/100, where
   L_white is the print's white (100 relative to the paper) and L_black the darkest grey (step
   3) the print reaches, whatever its hue (with chromatic inks alone it has no neutral below the
   paper: the darkest neutral compressed the image into L* ≈ 100 and Y30 printed nothing); a*,
   b* unchanged.
2. Chroma toward the cusp: in the hue slice of the colour, along the ray from the focal point
   F = (C* 0, L_F) through the colour, L_F = L*_cusp(h) + w·(L' − L*_cusp(h)) between the
   cusp's lightness (w = 0: all rays to the cusp, the most chroma) and the colour's own
   (w → 1: constant lightness, the most faithful lightness; `lightness_weight`, default 0.7,
   measured in benchmarks/bench_press.py), with d the colour's distance from F, D the distance
   to the print's boundary (less `margin_de` of chroma) and S the distance to the sRGB gamut's
   boundary (after step 1): if S ≤ D nothing moves; else colours within `knee`·D keep their
   place and beyond it d ↦ kD + (D − kD)·s·t/(1 + (s − 1)·t), t = (d − kD)/(S − kD),
   s = (S − kD)/(D − kD) — slope 1 at the knee (no kink), the sRGB boundary lands on the
   print's boundary, monotone along the ray. The perceived hue (Oklab's) is untouched.

3. The print's greys (`GamutBoundary.spine_ab`, `greyed`): where the print has no neutral of
   the mapped lightness (chromatic inks alone; the darkest shadows of some sets), a*, b* are
   offset by those of its least chromatic colour of that L*, less `NEUTRAL_CHROMA` of chroma
   (continuous where neutrals begin), so that the lightness is printed with what the inks have.
   (One or two inks have no volume to map into: the separator prints a monotone, `monotone`,
   or maps onto the pair's surface of colours, `duotone`, instead.)
   Where the print has neutrals (the process inks above their darkest neutral) the offset is 0.

Every step is continuous in the colour, so smooth gradients stay smooth (no notch where
nearest-colour clipping would fold a ramp onto the boundary) and ramps that rise in L* stay
monotone (tests/test_separation_press.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations, product

import numpy as np

from solver.colour.hue import lab_from_lch, lab_hue, oklab_hue

from .colour_space import lab_to_linear_srgb

HUE_BINS = 180                  # hue slices (2° each)
LIGHTNESS_NODES = 201           # L* levels 0, 0.5, …, 100 of the boundary table
GRID_NODES = {1: 257, 2: 129, 3: 33, 4: 13}     # regular-grid samples per ink axis
FACE_NODES = 49                 # samples per axis on each 2-D face of the coverage cube
RAY_STEP_DE = 1.0               # marching step along a ray (CIELAB units) before bisection
RAY_MAX_DE = 200.0
BISECTIONS = 20
HUE_SMOOTHING_BINS = 0.75      # σ of the hue smoothing of C_max (slices); the cusp's L* twice that
REFINE_STEP_L = 3.0             # L* step of the boundary's check against the print (`refined`)
NEUTRAL_CHROMA = 3.0            # C* below which a sample counts as neutral (the print's black)
GREY_WINDOW_L = 0.1             # L* either side of a level where its least chromatic sample is sought
                                # (one ink's tints change by up to 13 C* per L*: Y30)
MAX_TRIANGLE_HUE_SPAN = 30.0    # degrees: a face's triangle spanning more straddles the neutral axis
SECTION_MIN_CHROMA = 0.5        # C* above which a face's hue counts as defined (its slice sections)


@dataclass(frozen=True)
class GamutSettings:
    """Knobs of the mapping (benchmarks/bench_separation.py measures them)."""

    knee: float = 0.8           # share of the print's boundary distance left untouched
    lightness_weight: float = 0.7   # focal point: 0 the hue's cusp L*, 1 the colour's own L*
    margin_de: float = 1.5      # mapped colours land this much chroma (CIELAB units) inside the boundary

    def __post_init__(self):
        if not 0.0 <= self.lightness_weight < 1.0:
            raise ValueError(f"lightness_weight must lie in [0, 1), got {self.lightness_weight}")
        if not 0.0 <= self.knee < 1.0:
            raise ValueError(f"knee must lie in [0, 1), got {self.knee}")
        if not self.margin_de >= 0.0:
            raise ValueError(f"margin_de must be ≥ 0, got {self.margin_de}")


def to_lch(lab) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(L*, C*, h in degrees [0, 360)) of CIELAB [..., 3] — h the perceived hue (Oklab's,
    `solver.colour.hue`): the mapping's hue slices are slices of constant perceived hue, so a
    colour compressed toward the neutral axis keeps the hue it is seen as (in CIELAB's own hue a
    saturated blue halved in chroma turns violet)."""
    lab = np.asarray(lab, dtype=np.float64)
    return lab[..., 0], np.hypot(lab[..., 1], lab[..., 2]), oklab_hue(lab)


def from_lch(L, C, h_deg, exact: bool = True) -> np.ndarray:
    """CIELAB of lightness L*, chroma C* and perceived hue h (the inverse of `to_lch`; exact=False:
    the hue table alone, ≈ 0.05°, for searches along a ray)."""
    return lab_from_lch(L, C, lab_hue(L, C, h_deg, exact))


def compensate_lightness(L, black_l: float, white_l: float) -> np.ndarray:
    """Black-point compensation (step 1): L* 0…100 → black_l…white_l, linear."""
    return black_l + np.asarray(L, dtype=np.float64) * (white_l - black_l) / 100.0


def _smooth_hue(table: np.ndarray, sigma_bins: float) -> np.ndarray:
    """[H, …] smoothed along the (periodic) hue axis with a Gaussian of `sigma_bins` slices."""
    r = int(np.ceil(3 * sigma_bins))
    w = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma_bins) ** 2)
    w /= w.sum()
    return sum(wi * np.roll(table, shift, axis=0) for wi, shift in zip(w, range(-r, r + 1)))


def _dense_ends(n: int) -> np.ndarray:
    """n coverages in [0, 1], denser near 0 (light tints) and 1 (the darkest colours):
    (1 − cos(π i/(n−1)))/2."""
    return 0.5 - 0.5 * np.cos(np.pi * np.arange(n) / (n - 1))


def _onto_tac(c: np.ndarray, tac: float) -> np.ndarray:
    """Coverage mixes [..., k], those whose sum exceeds `tac` scaled onto the limit."""
    total = c.sum(axis=-1, keepdims=True)
    return np.where(total > tac, c * (tac / np.maximum(total, 1e-12)), c)


def face_grids(n_inks: int, tac: float) -> np.ndarray:
    """Coverages [F, FACE_NODES, FACE_NODES, k] on the 2-D faces of the coverage polytope
    {c ∈ [0, 1]^k, Σc ≤ tac}, whose images bound the print's gamut: the cube's faces (two
    inks free, the others 0 or 1; nodes over `tac` scaled onto it) and the faces on the limit
    (two inks free, one taking the rest of the limit, the others 0 or 1; NaN where that ink
    would leave [0, 1])."""
    face = _dense_ends(FACE_NODES)
    fu, fv = np.meshgrid(face, face, indexing="ij")
    grids = []
    for i, j in combinations(range(n_inks), 2):
        others = [m for m in range(n_inks) if m not in (i, j)]
        for fixed in product((0.0, 1.0), repeat=len(others)):
            c = np.zeros(fu.shape + (n_inks,))
            c[..., i], c[..., j] = fu, fv
            c[..., others] = fixed
            grids.append(_onto_tac(c, tac))
        if tac >= n_inks:
            continue
        for m in others:
            rest = [x for x in others if x != m]
            for fixed in product((0.0, 1.0), repeat=len(rest)):
                c = np.zeros(fu.shape + (n_inks,))
                c[..., i], c[..., j] = fu, fv
                c[..., rest] = fixed
                c[..., m] = tac - fu - fv - sum(fixed)
                c[(c[..., m] < 0.0) | (c[..., m] > 1.0)] = np.nan
                if not np.isnan(c).all():
                    grids.append(c)
    return np.stack(grids) if grids else np.zeros((0, FACE_NODES, FACE_NODES, n_inks))


def coverage_samples(n_inks: int, tac: float) -> np.ndarray:
    """Coverage mixes [M, k] on a grid that samples the print's gamut (module docstring; mixes
    over `tac` scaled onto it); `face_grids` samples its boundary."""
    n = GRID_NODES.get(n_inks, 9)
    axis = _dense_ends(n)
    return _onto_tac(np.stack(np.meshgrid(*([axis] * n_inks), indexing="ij"), -1).reshape(-1, n_inks), tac)


def _face_triangles(L, C, h) -> np.ndarray:
    """The faces' grids [F, n, n] of (L*, C*, hue) cut into triangles: ([T, 3 vertices, (L, C, h)],
    the least hue [T], the hue span [T]), those with a defined hue (every vertex C* >
    `SECTION_MIN_CHROMA`) spanning < `MAX_TRIANGLE_HUE_SPAN` of hue, the hues unwrapped about the first vertex."""
    g = np.stack([L, C, h], -1)
    a, b, c, d = g[:, :-1, :-1], g[:, 1:, :-1], g[:, 1:, 1:], g[:, :-1, 1:]
    t = np.concatenate([np.stack([a, b, c], -2).reshape(-1, 3, 3), np.stack([a, c, d], -2).reshape(-1, 3, 3)])
    t = t[~np.isnan(t).any(axis=(1, 2)) & (t[:, :, 1].min(axis=1) > SECTION_MIN_CHROMA)]
    t[:, 1:, 2] = t[:, :1, 2] + (t[:, 1:, 2] - t[:, :1, 2] + 180.0) % 360.0 - 180.0
    h = np.ascontiguousarray(t[:, :, 2])
    span = h.max(axis=1) - h.min(axis=1)
    keep = (span < MAX_TRIANGLE_HUE_SPAN) & (span > 0.0)
    t, h_lo, span = t[keep], h.min(axis=1)[keep] % 360.0, span[keep]
    order = np.argsort(h_lo)                                    # by least hue: a slice's candidates
    return t[order], h_lo[order], span[order]                   # are one window (`_section_chroma`)


def _section_chroma(tris, hue: float, levels: np.ndarray) -> np.ndarray:
    """C_max at each of `levels` (L*, ascending) of the faces' section by the slice of hue `hue`
    (degrees; `tris` from `_face_triangles`):
    each triangle the slice crosses contributes the segment where its linearly interpolated hue
    equals `hue` (the exact section of the piecewise-linear faces, concave where the gamut is);
    −1 where no segment reaches a level."""
    tris, h_lo, span = tris
    hue = hue % 360.0
    a, b = np.searchsorted(h_lo, [hue - MAX_TRIANGLE_HUE_SPAN, hue], side="right")
    cand = np.arange(a, b)
    if hue < MAX_TRIANGLE_HUE_SPAN:                                  # the window wraps around 0°
        cand = np.r_[cand, np.arange(np.searchsorted(h_lo, hue - MAX_TRIANGLE_HUE_SPAN + 360.0), h_lo.size)]
    t = tris[cand[(hue - h_lo[cand]) % 360.0 <= span[cand]]]
    hv = (t[:, :1, 2] - hue + 180.0) % 360.0 - 180.0 + (t[:, :, 2] - t[:, :1, 2])    # hue − slice, unwrapped
    out = np.full(levels.size, -1.0)
    if t.shape[0] == 0:
        return out
    ends = []
    for i, j in ((0, 1), (1, 2), (2, 0)):                     # where each edge crosses the hue
        hi, hj = hv[:, i], hv[:, j]
        cross = ((hi <= 0.0) & (hj >= 0.0) | (hi >= 0.0) & (hj <= 0.0)) & (hi != hj)
        w = np.where(cross, hi / np.where(hi != hj, hi - hj, 1.0), np.nan)
        ends.append(t[:, i, :2] + w[:, None] * (t[:, j, :2] - t[:, i, :2]))      # (L, C) or NaN
    ends = np.stack(ends, 1)                                      # [S, 3 edges, 2]
    ok = ~np.isnan(ends[:, :, 0])
    first = np.argmax(ok, axis=1)
    last = 2 - np.argmax(ok[:, ::-1], axis=1)
    p, q = ends[np.arange(len(ends)), first], ends[np.arange(len(ends)), last]
    lo, hi = np.minimum(p[:, 0], q[:, 0]), np.maximum(p[:, 0], q[:, 0])
    first_level = np.searchsorted(levels, lo, side="left")          # `levels` ascending
    count = np.searchsorted(levels, hi, side="right") - first_level
    seg = np.repeat(np.arange(lo.size), count)                       # each segment × its levels
    k = first_level[seg] + np.arange(seg.size) - np.repeat(np.cumsum(count) - count, count)
    dl = q[seg, 0] - p[seg, 0]
    u = np.where(dl != 0.0, (levels[k] - p[seg, 0]) / np.where(dl != 0.0, dl, 1.0), 0.0)
    c = np.where(dl != 0.0, p[seg, 1] + u * (q[seg, 1] - p[seg, 1]), np.maximum(p[seg, 1], q[seg, 1]))
    np.maximum.at(out, k, c)
    return out


def _hull_chroma(C, L, levels, black_l: float, white_l: float) -> np.ndarray:
    """C_max at each of `levels` (L*) of the convex hull of points (C, L) plus the neutral axis
    from the print's black to the paper's white (both printable); −1 outside the hull's
    lightness range."""
    from scipy.spatial import ConvexHull

    pts = np.concatenate([np.stack([C, L], -1), [[0.0, black_l], [0.0, white_l]]])
    try:
        poly = pts[ConvexHull(pts).vertices]
    except Exception:                                     # degenerate slice (collinear samples)
        poly = pts
    a, b = poly, np.roll(poly, -1, axis=0)
    lo, hi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
    lv = levels[:, None]
    cross = (lv >= lo) & (lv <= hi)
    t = np.where(hi > lo, (lv - a[:, 1]) / np.where(b[:, 1] != a[:, 1], b[:, 1] - a[:, 1], 1.0), 0.0)
    c = np.where(hi > lo, a[:, 0] + t * (b[:, 0] - a[:, 0]), np.maximum(a[:, 0], b[:, 0]))
    return np.max(np.where(cross, c, -1.0), axis=1)


def _grey_at(spine, L) -> np.ndarray:
    """(a*, b*) [N, 2] of the print's grey (`spine` [LIGHTNESS_NODES, 2], None: 0) at L* [N],
    linear between levels."""
    L = np.asarray(L, dtype=np.float64).reshape(-1)
    if spine is None:
        return np.zeros((L.size, 2))
    levels = np.linspace(0.0, 100.0, LIGHTNESS_NODES)
    return np.stack([np.interp(L, levels, spine[:, i]) for i in range(2)], -1)


def _surrounds_neutral(ab) -> bool:
    """Whether the neutral (a* = b* = 0) lies in the convex hull of points (a*, b*) [M, 2]: no
    gap of half a turn or more between their hues."""
    hue = np.sort(np.arctan2(ab[:, 1], ab[:, 0]))
    if hue.size < 3:
        return False
    gaps = np.diff(np.r_[hue, hue[0] + 2 * np.pi])
    return bool(gaps.max() < np.pi)


def _grey_spine(lab, levels, white_l: float) -> np.ndarray:
    """(a*, b*) [NL, 2] of the print's grey at each of `levels`, from printed samples CIELAB
    [M, 3]: 0 where the samples within two level spacings of that L* surround the neutral (the
    print has one), else the least chromatic sample within GREY_WINDOW_L of it, its chroma less
    `NEUTRAL_CHROMA` (continuous where neutrals begin); linear across levels no sample reaches;
    0 beyond the print's black…white."""
    L, C, ab = lab[:, 0], np.hypot(lab[:, 1], lab[:, 2]), lab[:, 1:]
    black_l = float(np.min(L))
    order = np.argsort(L)
    Ls, Cs, abs_ = L[order], C[order], ab[order]
    half = levels[1] - levels[0]
    lo = np.searchsorted(Ls, levels - GREY_WINDOW_L, side="left")
    hi = np.searchsorted(Ls, levels + GREY_WINDOW_L, side="right")
    out = np.zeros((levels.size, 2))
    known = np.zeros(levels.size, dtype=bool)
    wide_lo = np.searchsorted(Ls, levels - 2 * half, side="left")
    wide_hi = np.searchsorted(Ls, levels + 2 * half, side="right")
    for j in np.flatnonzero((hi > lo) & (levels >= black_l - half) & (levels <= white_l + half)):
        known[j] = True
        if _surrounds_neutral(abs_[wide_lo[j]:wide_hi[j]]):
            continue
        i = lo[j] + int(np.argmin(Cs[lo[j]:hi[j]]))
        c = Cs[i]
        out[j] = abs_[i] * (max(c - NEUTRAL_CHROMA, 0.0) / c if c > 0.0 else 0.0)
    inside = (levels >= black_l - half) & (levels <= white_l + half)
    if known.any():
        for i in range(2):
            out[inside & ~known, i] = np.interp(levels[inside & ~known], levels[known], out[known, i])
    out[~inside] = 0.0
    return out


@dataclass(frozen=True)
class GamutBoundary:
    """The print's gamut as C_max(h, L*) per hue slice (module docstring)."""

    hue_deg: np.ndarray            # [H] slice centres
    lightness: np.ndarray          # [NL] levels
    cmax: np.ndarray               # [H, NL]; −1 where the slice has no colour of that L*
    white_l: float                 # L* of the print's white (bare paper)
    black_l: float                 # L* of the darkest grey (`spine_ab`), whatever its hue
    cusp_l: np.ndarray             # [H]
    cusp_c: np.ndarray             # [H]
    spine_ab: np.ndarray | None = None  # [NL, 2] (a*, b*) of the print's grey per L* (`greyed`); None: 0

    @classmethod
    def build(cls, model, tac: float = float("inf")) -> "GamutBoundary":
        """The gamut of `model` (PrintColourModel) under the total area coverage limit `tac`
        (fraction: 3.0 = 300 %)."""
        faces = face_grids(model.n_inks, tac)
        ok = ~np.isnan(faces[..., 0])
        lab = np.full(faces.shape[:-1] + (3,), np.nan)
        lab[ok] = model.lab(faces[ok])
        samples = np.r_[model.lab(coverage_samples(model.n_inks, tac)), lab[ok]]
        white_l = float(model.lab(np.zeros(model.n_inks))[0])
        spine = _grey_spine(samples, np.linspace(0.0, 100.0, LIGHTNESS_NODES), white_l)
        # the slices are taken about the print's greys (step 3): a*, b* less the grey's of their L*
        ungreyed = GamutBoundary.ungreyed_by(spine)
        Lf, Cf, hf = (np.full(ok.shape, np.nan) for _ in range(3))
        Lf[ok], Cf[ok], hf[ok] = to_lch(ungreyed(lab[ok]))
        L, C, h = to_lch(ungreyed(samples))
        # the print's black: its darkest grey — a sample within NEUTRAL_CHROMA of the least
        # chromatic colour of its L* (the neutral where the print has one; where it has none, the
        # grey is that colour less NEUTRAL_CHROMA of chroma: `_grey_spine`)
        chromatic = np.hypot(*_grey_at(spine, L).T) > 0.0
        grey = C <= NEUTRAL_CHROMA * np.where(chromatic, 2.0, 1.0)
        black_l = float(np.min(L[grey])) if grey.any() else float(np.min(L))
        return cls.from_samples(L, C, h, white_l, faces=(Lf, Cf, hf), spine=spine, black_l=black_l)

    @staticmethod
    def ungreyed_by(spine):
        """CIELAB [N, 3] → the same less the grey (`spine_ab` [NL, 2], None: 0) of their L*."""
        def ungreyed(lab):
            lab = np.array(lab, dtype=np.float64).reshape(-1, 3)
            lab[:, 1:] -= _grey_at(spine, lab[:, 0])
            return lab
        return ungreyed

    @classmethod
    def from_samples(cls, L, C, h, white_l: float, faces=None, spine=None, black_l=None) -> "GamutBoundary":
        """The boundary of samples (L*, C*, hue) of the gamut; `faces`: (L*, C*, hue) [F, n, n] on
        the grids of `face_grids`, whose sections by each slice bound its hull where the gamut is
        concave (module docstring); `spine`: the print's greys (`spine_ab`), the samples taken
        about them (None: the print has a neutral of every L* it reaches); `black_l`: the print's
        black (None: its darkest near-neutral sample, else its darkest)."""
        width = 360.0 / HUE_BINS
        centres = (np.arange(HUE_BINS) + 0.5) * width
        levels = np.linspace(0.0, 100.0, LIGHTNESS_NODES)
        cmax = np.empty((HUE_BINS, LIGHTNESS_NODES))
        if black_l is None:
            neutral = C <= NEUTRAL_CHROMA
            black_l = float(np.min(L[neutral])) if neutral.any() else float(np.min(L))
        black_l = min(float(black_l), float(white_l))
        order = np.argsort(h)
        hs, Ls, Cs = h[order], L[order], C[order]
        hs3 = np.concatenate([hs - 360.0, hs, hs + 360.0])          # windows that wrap around 0°
        tris = _face_triangles(*faces) if faces is not None else None
        inside = (levels >= black_l) & (levels <= white_l)
        for j, hc in enumerate(centres):
            lo, hi = np.searchsorted(hs3, [hc - width, hc + width], side="left")
            sel = np.arange(lo, hi) % hs.size
            if sel.size < 3:
                cmax[j] = -1.0
                continue
            dh = np.abs((hs[sel] - hc + 180.0) % 360.0 - 180.0)
            proj = Cs[sel] * np.cos(np.radians(dh))             # the samples' chroma along the slice
            cmax[j] = _hull_chroma(proj, Ls[sel], levels, black_l, white_l)
            if tris is not None:              # the faces' section: concave where the gamut is
                section = _section_chroma(tris, hc, levels[inside])
                known = section >= 0.0    # levels no face reaches with a defined hue: toward the
                if known.any():           # neutral axis's ends (the print's black and white)
                    section = np.interp(levels[inside], np.r_[black_l, levels[inside][known], white_l],
                                        np.r_[0.0, section[known], 0.0])
                    cmax[j, inside] = np.minimum(cmax[j, inside], section)
        # smooth across hue (a circular Gaussian of HUE_SMOOTHING_BINS): the slices' hulls follow
        # the samples' scatter
        cmax[:, inside] = _smooth_hue(np.maximum(cmax[:, inside], 0.0), HUE_SMOOTHING_BINS)
        cmax[:, levels < black_l] = np.minimum(cmax[:, levels < black_l], -1.0)
        cmax[:, (levels >= black_l) & (levels <= white_l)] = np.maximum(
            cmax[:, (levels >= black_l) & (levels <= white_l)], 0.0)
        best = np.argmax(cmax, axis=1)
        return cls(centres, levels, cmax, float(white_l), black_l,
                   _smooth_hue(levels[best][:, None], 2 * HUE_SMOOTHING_BINS)[:, 0],
                   cmax[np.arange(HUE_BINS), best], spine)

    def refined(self, printed_of) -> "GamutBoundary":
        """The boundary checked against the print: targets on it (every slice, every
        `REFINE_STEP_L` of L*) are separated by `printed_of` (CIELAB [N, 3] → the closest printed
        CIELAB [N, 3]); where the print falls short — the hull spans a concave part of the
        gamut — C_max is scaled by the chroma reached (projected on the slice) over the chroma
        asked, the ratios smoothed across hue and interpolated in L*."""
        Ls = np.arange(self.black_l + REFINE_STEP_L / 2, self.white_l - REFINE_STEP_L / 4, REFINE_STEP_L)
        if Ls.size < 2:
            return self
        hh, LL = np.meshgrid(self.hue_deg, Ls, indexing="ij")
        C = self.chroma_max(hh, LL)
        asked = C > 1.0
        ratio = np.ones_like(C)
        if asked.any():
            ungreyed = GamutBoundary.ungreyed_by(self.spine_ab)
            Lp, Cp, hp = to_lch(ungreyed(printed_of(self.greyed(from_lch(LL[asked], C[asked], hh[asked])))))
            reached = Cp * np.cos(np.radians(hp - hh[asked]))
            ratio[asked] = np.clip(reached / C[asked], 0.0, 1.0)
        ratio = _smooth_hue(ratio, HUE_SMOOTHING_BINS)
        scale = np.stack([np.interp(self.lightness, Ls, r) for r in ratio])
        cmax = np.where(self.cmax >= 0.0, self.cmax * scale, self.cmax)
        best = np.argmax(cmax, axis=1)
        return GamutBoundary(self.hue_deg, self.lightness, cmax, self.white_l, self.black_l,
                             _smooth_hue(self.lightness[best][:, None], 2 * HUE_SMOOTHING_BINS)[:, 0],
                             cmax[np.arange(HUE_BINS), best], self.spine_ab)

    def with_black(self, black_l: float) -> "GamutBoundary":
        """The boundary with its black raised to `black_l` (what the separation reaches): the
        slices' profiles stretched in L* from black…white onto the new black…white (a cut
        would leave a flat floor with a corner)."""
        if black_l <= self.black_l or black_l >= self.white_l:
            return self
        from dataclasses import replace

        old = self.black_l + (self.lightness - black_l) * (self.white_l - self.black_l) / (self.white_l - black_l)
        cmax = np.stack([np.interp(old, self.lightness, row) for row in self.cmax])
        cmax[:, self.lightness < black_l] = np.minimum(cmax[:, self.lightness < black_l], -1.0)
        best = np.argmax(cmax, axis=1)
        return replace(self, cmax=cmax, black_l=float(black_l),
                       cusp_l=_smooth_hue(self.lightness[best][:, None], 2 * HUE_SMOOTHING_BINS)[:, 0],
                       cusp_c=cmax[np.arange(HUE_BINS), best])

    def _hue_weights(self, h_deg):
        width = 360.0 / HUE_BINS
        x = (np.asarray(h_deg, dtype=np.float64) / width - 0.5) % HUE_BINS
        i0 = np.floor(x).astype(np.int64) % HUE_BINS
        return i0, (i0 + 1) % HUE_BINS, x - np.floor(x)

    def cusp(self, h_deg) -> tuple[np.ndarray, np.ndarray]:
        """(L*, C*) of the cusp at hues `h_deg` (linear between slices)."""
        i0, i1, t = self._hue_weights(h_deg)
        return (self.cusp_l[i0] * (1 - t) + self.cusp_l[i1] * t,
                self.cusp_c[i0] * (1 - t) + self.cusp_c[i1] * t)

    def chroma_max(self, h_deg, L) -> np.ndarray:
        """C_max at (h, L*) (bilinear; −1 outside the print's lightness range)."""
        i0, i1, t = self._hue_weights(h_deg)
        x = np.clip(np.asarray(L, dtype=np.float64), 0.0, 100.0) / 100.0 * (LIGHTNESS_NODES - 1)
        j0 = np.minimum(np.floor(x).astype(np.int64), LIGHTNESS_NODES - 2)
        u = x - j0
        row = lambda i: self.cmax[i, j0] * (1 - u) + self.cmax[i, j0 + 1] * u      # noqa: E731
        out = row(i0) * (1 - t) + row(i1) * t
        # the neutral axis from black to white is printable (a level on either side may not be)
        return np.where((np.asarray(L) < self.black_l) | (np.asarray(L) > self.white_l), -1.0, np.maximum(out, 0.0))

    def contains(self, lab) -> np.ndarray:
        """Whether CIELAB colours [N, 3] (as printed: with the print's grey) lie in the gamut."""
        L, C, h = to_lch(GamutBoundary.ungreyed_by(self.spine_ab)(lab))
        return C <= self.chroma_max(h, L) + 1e-9

    def lightness_map(self, L) -> np.ndarray:
        """Black-point compensation: L* 0…100 → black_l…white_l (linear)."""
        return compensate_lightness(L, self.black_l, self.white_l)

    def grey_ab(self, L) -> np.ndarray:
        """(a*, b*) [N, 2] of the print's grey at lightnesses L* (module docstring, step 3; linear
        between levels, 0 where the print has a neutral)."""
        return _grey_at(self.spine_ab, L)

    def greyed(self, lab) -> np.ndarray:
        """CIELAB [N, 3] with a*, b* offset by the print's grey of their L* (step 3)."""
        lab = np.array(lab, dtype=np.float64).reshape(-1, 3)
        lab[:, 1:] += self.grey_ab(lab[:, 0])
        return lab

    def lightness_unmap(self, L) -> np.ndarray:
        return (np.asarray(L, dtype=np.float64) - self.black_l) * 100.0 / max(self.white_l - self.black_l, 1e-9)


def _ray_exit(inside, n: int) -> np.ndarray:
    """Distance along each of n rays to the first point where `inside(s)` ([n] distances →
    [n] bool) turns false: marching by RAY_STEP_DE, then bisection. Rays never leaving within
    RAY_MAX_DE give RAY_MAX_DE."""
    lo = np.zeros(n)
    hi = np.full(n, RAY_MAX_DE)
    found = np.zeros(n, dtype=bool)
    for s in np.arange(RAY_STEP_DE, RAY_MAX_DE + RAY_STEP_DE / 2, RAY_STEP_DE):
        todo = ~found
        if not todo.any():
            break
        out = ~inside(np.full(n, s))
        newly = todo & out
        hi[newly] = s
        found |= newly
        lo[todo & ~out] = s
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        ok = inside(mid)
        lo = np.where(ok, mid, lo)
        hi = np.where(ok, hi, mid)
    return np.where(found, lo, RAY_MAX_DE)


def map_to_gamut(lab, boundary: GamutBoundary, settings: GamutSettings = GamutSettings(),
                 measurement=None) -> np.ndarray:
    """sRGB colours in CIELAB [N, 3] (relative to the measurement white, from `srgb8_to_lab`)
    → CIELAB [N, 3] inside the print's gamut (module docstring)."""
    from .colour_space import DEFAULT_MEASUREMENT

    measurement = measurement or DEFAULT_MEASUREMENT
    lab = np.asarray(lab, dtype=np.float64).reshape(-1, 3)
    L, C, h = to_lch(lab)
    L1 = boundary.lightness_map(L)
    cusp_l, _ = boundary.cusp(h)
    F = cusp_l + settings.lightness_weight * (L1 - cusp_l)
    vc, vl = C, L1 - F
    d = np.hypot(vc, vl)
    moving = d > 1e-9
    uc = np.where(moving, vc / np.where(moving, d, 1.0), 0.0)
    ul = np.where(moving, vl / np.where(moving, d, 1.0), 1.0)

    def in_print(s):
        return C_at(s) <= boundary.chroma_max(h, F + s * ul) + 1e-9      # round-off chroma of a neutral

    def C_at(s):
        return s * uc

    def in_srgb(s):
        lab_s = from_lch(boundary.lightness_unmap(F + s * ul), C_at(s), h, exact=False)
        rgb = lab_to_linear_srgb(lab_s, measurement)
        return np.all((rgb >= -1e-6) & (rgb <= 1.0 + 1e-6), axis=-1)

    n = lab.shape[0]
    # the margin is taken in chroma (a neutral at the print's black or white stays there)
    D = np.maximum(_ray_exit(in_print, n) - settings.margin_de * np.abs(uc), 0.0)
    S = np.maximum(_ray_exit(in_srgb, n), d)                  # an sRGB colour lies inside its gamut
    k = settings.knee * D
    squeeze = moving & (S > D) & (d > k)
    s_ratio = (S - k) / np.maximum(D - k, 1e-12)
    t = (d - k) / np.maximum(S - k, 1e-12)
    mapped = np.minimum(k + (D - k) * s_ratio * t / (1.0 + (s_ratio - 1.0) * t), D)
    d_new = np.where(squeeze, mapped, d)
    return boundary.greyed(from_lch(F + d_new * ul, d_new * uc, h))
