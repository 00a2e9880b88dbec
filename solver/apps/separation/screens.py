"""Halftone threshold arrays: a texel is inked where its threshold t ∈ [0, 1) is below the
ink's coverage there. Thresholds uniform over the area keep the mean coverage.

**AM** (amplitude modulation, `am_threshold`): a screen of `lpi` cells per inch at an angle;
the dot grows from each cell's centre with the cosine spot function
s(u, v) = (cos 2πu + cos 2πv)/2 (u, v ∈ [−½, ½) within the cell): round dots in the light tones,
a checkerboard at 50 %, round holes in the shadows. The threshold of a point is the fraction of
the cell whose spot value exceeds its own, t = P(S > s) (`spot_area`), so a constant coverage c
inks exactly a fraction c of each cell (up to the texel sampling).

**FM** (frequency modulation, `blue_noise_mask`): a tile of ranks from Ulichney's
void-and-cluster method (1993): single-texel dots spread as evenly as possible at every level
(blue noise), t = (rank + ½)/N². Each ink gets its own tile (its own seed): dots of different
inks are placed independently, as the Demichel weights assume.

Screen angles (`screen_angles`): the classic set — the lightest ink at 0° (the most visible
direction), the darkest of four at 45° (the least visible), the others at 15° and 75°.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

#: screen angles (degrees) for k inks, listed from the lightest ink to the darkest
ANGLES_BY_COUNT = {1: (45.0,), 2: (75.0, 45.0), 3: (0.0, 75.0, 15.0), 4: (0.0, 75.0, 15.0, 45.0)}
SPOT_TABLE_SIZE = 2049          # nodes of the tabulated spot-area function
FM_TILE = 64                    # blue-noise tile (texels per side)
FM_SIGMA = 1.5                  # void-and-cluster Gaussian filter (texels)


def screen_angles(lightness) -> tuple[float, ...]:
    """Screen angle (degrees) of each ink from its full-coverage lightness L* (printing order)."""
    light = np.asarray(lightness, dtype=np.float64)
    order = np.argsort(-light, kind="stable")                   # lightest first
    angles = np.empty(light.size)
    angles[order] = ANGLES_BY_COUNT[light.size]
    return tuple(float(a) for a in angles)


@lru_cache(maxsize=1)
def _spot_area_table() -> tuple[np.ndarray, np.ndarray]:
    """s nodes and P(S > s) for S = (cos 2πU + cos 2πV)/2, U, V uniform on [0, 1):

    P(S ≤ s) = ∫₀¹ P(cos 2πV ≤ 2s − cos 2πu) du,  P(cos 2πV ≤ y) = 1 − arccos(y)/π (y clipped),
    by the midpoint rule on 4096 u nodes."""
    s = np.linspace(-1.0, 1.0, SPOT_TABLE_SIZE)
    u = (np.arange(4096) + 0.5) / 4096
    y = np.clip(2.0 * s[:, None] - np.cos(2.0 * np.pi * u)[None, :], -1.0, 1.0)
    below = np.mean(1.0 - np.arccos(y) / np.pi, axis=1)
    return s, 1.0 - below


def spot_area(spot) -> np.ndarray:
    """Fraction of a cell whose spot value exceeds `spot` (the AM threshold of that value)."""
    s, area = _spot_area_table()
    return np.interp(spot, s, area)


def aligned_cell(n: int) -> np.ndarray:
    """Thresholds of one n × n-texel cell of a screen aligned with the texel grid: the texels
    ranked by spot value, (rank + ½)/n², so that k of the n² texels are inked at coverages in
    (k − ½, k + ½]/n². Texels of equal spot value (the spot's symmetries) are ranked by angle
    around the centre, then by distance from the top-left corner."""
    f = (np.arange(n) + 0.5) / n - 0.5
    fu, fv = np.meshgrid(f, f, indexing="xy")
    spot = 0.5 * (np.cos(2.0 * np.pi * fu) + np.cos(2.0 * np.pi * fv))
    order = np.lexsort((((fu + 0.5) ** 2 + (fv + 0.5) ** 2).ravel(),
                        np.arctan2(fv, fu).round(9).ravel(), -spot.round(12).ravel()))
    rank = np.empty(n * n, dtype=np.int64)
    rank[order] = np.arange(n * n)
    return ((rank + 0.5) / (n * n)).reshape(n, n)


def am_threshold(rows: slice, width: int, texel_in: float, lpi: float, angle_deg: float) -> np.ndarray:
    """AM thresholds of texel rows `rows` (a slice) × `width` columns, texels of `texel_in`
    inches, a screen of `lpi` lines per inch at `angle_deg`; float32 [len(rows), width].

    A screen at a multiple of 90° whose cell is a whole number of texels samples the same few
    points of every cell, so its thresholds are the cell's ranks (`aligned_cell`) rather than
    the spot areas (which repeat between symmetric texels and would ink them together)."""
    cell = 1.0 / (texel_in * lpi)
    if abs(angle_deg / 90.0 - round(angle_deg / 90.0)) < 1e-12 and abs(cell - round(cell)) < 1e-9 * cell:
        n = int(round(cell))
        block = aligned_cell(n)
        i = np.arange(rows.start, rows.stop) % n
        return block[i[:, None], (np.arange(width) % n)[None, :]].astype(np.float32)
    i = np.arange(rows.start, rows.stop, dtype=np.float64)
    j = np.arange(width, dtype=np.float64)
    y = ((i + 0.5) * texel_in)[:, None]
    x = ((j + 0.5) * texel_in)[None, :]
    a = np.radians(angle_deg)
    u = (x * np.cos(a) + y * np.sin(a)) * lpi
    v = (-x * np.sin(a) + y * np.cos(a)) * lpi
    fu, fv = u - np.floor(u) - 0.5, v - np.floor(v) - 0.5
    spot = 0.5 * (np.cos(2.0 * np.pi * fu) + np.cos(2.0 * np.pi * fv))
    return spot_area(spot).astype(np.float32)


def _gaussian_kernel(size: int, sigma: float) -> np.ndarray:
    """Toroidal Gaussian centred on texel (0, 0) of a size × size tile."""
    d = np.minimum(np.arange(size), size - np.arange(size)).astype(np.float64)
    g = np.exp(-0.5 * (d / sigma) ** 2)
    return g[:, None] * g[None, :]


@lru_cache(maxsize=8)
def blue_noise_mask(size: int = FM_TILE, seed: int = 0, sigma: float = FM_SIGMA) -> np.ndarray:
    """Void-and-cluster threshold tile [size, size]: (rank + ½)/size², float64.

    1. Random initial pattern (10 % of texels), relaxed: the tightest cluster (the set texel of
       highest filtered density) moves to the largest void (the empty texel of lowest) until
       they coincide.
    2. Ranks: removing tightest clusters from that pattern ranks its texels downward; adding
       into largest voids ranks the rest upward (the density filter a toroidal Gaussian).
    """
    n = size * size
    kernel = _gaussian_kernel(size, sigma)

    def splat(i: int, sign: float, energy: np.ndarray) -> None:
        r, c = divmod(i, size)
        energy += sign * np.roll(np.roll(kernel, r, axis=0), c, axis=1)

    rng = np.random.default_rng(seed)
    ones = np.zeros(n, dtype=bool)
    ones[rng.choice(n, size=max(1, n // 10), replace=False)] = True
    energy = np.zeros((size, size))
    for i in np.flatnonzero(ones):
        splat(i, 1.0, energy)
    flat = energy.ravel()                                   # a view: splat updates it
    for _ in range(10 * n):
        cluster = int(np.argmax(np.where(ones, flat, -np.inf)))
        ones[cluster] = False
        splat(cluster, -1.0, energy)
        void = int(np.argmin(np.where(ones, np.inf, flat)))
        ones[void] = True
        splat(void, 1.0, energy)
        if void == cluster:
            break
    rank = np.empty(n, dtype=np.int64)
    prototype, proto_energy = ones.copy(), energy.copy()
    count = int(ones.sum())
    for r in range(count - 1, -1, -1):                      # phase 1: remove clusters
        cluster = int(np.argmax(np.where(ones, flat, -np.inf)))
        ones[cluster] = False
        splat(cluster, -1.0, energy)
        rank[cluster] = r
    ones, energy = prototype, proto_energy
    flat = energy.ravel()
    for r in range(count, n):                               # phases 2–3: fill voids
        void = int(np.argmin(np.where(ones, np.inf, flat)))
        ones[void] = True
        splat(void, 1.0, energy)
        rank[void] = r
    return ((rank + 0.5) / n).reshape(size, size)


def fm_threshold(rows: slice, width: int, seed: int, tile: int = FM_TILE) -> np.ndarray:
    """FM thresholds of texel rows `rows` × `width` columns: the ink's blue-noise tile repeated;
    float32."""
    mask = blue_noise_mask(tile, seed)
    i = np.arange(rows.start, rows.stop) % tile
    j = np.arange(width) % tile
    return mask[i[:, None], j[None, :]].astype(np.float32)
