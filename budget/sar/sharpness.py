"""Focus measures of a complex image: how sharp it is, with no reference to compare against.

* sharpness S = Σ|g|⁴ / (Σ|g|²)² — the sum of squared normalised intensities (Muller &
  Buffington, JOSA 64(9), 1974, S₁; Fienup & Miller, JOSA A 20(4), 2003, the exponent-2 member
  of their family): 1/N for a uniform image of N pixels, 1 for a single bright pixel; higher is
  sharper. It is dominated by the brightest scatterers, the ones an autofocus works from;
* entropy H = −Σ p ln p of the normalised intensity p = |g|²/Σ|g|² (Fienup & Miller 2003,
  eq. 4): lower is sharper; it weights the weak pixels more;
* contrast std(|g|²)/mean(|g|²): 1 for fully developed speckle.
"""

from __future__ import annotations

import numpy as np


def image_sharpness(data) -> float:
    """Σ|g|⁴/(Σ|g|²)² (dimensionless, in [1/N, 1]; see module docstring); NaN for a zero image."""
    p = np.abs(np.asarray(data)) ** 2
    total = p.sum()
    return float(np.sum(p * p) / (total * total)) if total > 0 else float("nan")


def image_entropy(data) -> float:
    """Shannon entropy (nats) of the normalised intensity |g|²/Σ|g|² (see module docstring)."""
    p = np.abs(np.asarray(data)) ** 2
    total = p.sum()
    if not total > 0:
        return float("nan")
    p = p[p > 0] / total
    return float(-(p * np.log(p)).sum())


def image_contrast(data) -> float:
    """std(|g|²)/mean(|g|²) (dimensionless; 1 for fully developed speckle)."""
    p = np.abs(np.asarray(data)) ** 2
    m = p.mean()
    return float(p.std() / m) if m > 0 else float("nan")
