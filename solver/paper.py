"""The paper under the ink (docs/design.md §1): a Lambertian reflector of albedo r.

The one home of its default — 0.9, the paper's — and of its check: an albedo is a number or a
spectrum (one value per wavelength) in [0, 1]. Every consumer (tables' evaluation, colour
measurement, printing, figures, the CLI, the plugin's scene check) asks here.
"""

from __future__ import annotations

import numpy as np

#: the paper's paper (Voloboy et al., §3): a white Lambertian of albedo 0.9
PAPER_ALBEDO = 0.9


class PaperError(ValueError):
    """A paper albedo that is not a number or spectrum in [0, 1]."""


def albedo_problem(low: float, high: float) -> str | None:
    """Why values spanning [low, high] are not an albedo (None when they are)."""
    if not (np.isfinite(low) and np.isfinite(high)):
        return "got a value that is not a finite number"
    if low >= 0.0 and high <= 1.0:
        return None
    if low == high:
        return f"got {low:g}"
    return f"got a spectrum reaching {high:.3g}" if high > 1.0 else f"got a spectrum down to {low:.3g}"


def check_paper_albedo(paper, wavelengths_nm=None, what: str = "paper albedo") -> np.ndarray:
    """The albedo as an array (broadcast to the wavelengths when given), checked in [0, 1];
    PaperError naming `what` otherwise."""
    try:
        r = np.asarray(paper, dtype=np.float64)
    except (TypeError, ValueError):
        raise PaperError(f"{what} must be a number in [0, 1], got {paper!r}") from None
    if wavelengths_nm is not None:
        try:
            r = np.broadcast_to(r, np.shape(wavelengths_nm)).astype(np.float64)
        except ValueError:
            raise PaperError(f"{what}: a number or {np.size(wavelengths_nm)} values (one per wavelength), "
                             f"got shape {np.shape(paper)}") from None
    problem = albedo_problem(float(np.min(r)), float(np.max(r))) if r.size else "got no value"
    if problem:
        raise PaperError(f"{what} must lie in [0, 1], {problem}")
    return r
