"""Distribution of a weighted sum of independent χ²₁ variables, Q = Σ λ_i χ²_1,i.

The gap's null (:class:`budget.gap.metric.NullModel`) and the slow-mode statistic
(:mod:`budget.gap.walk`) are both such sums; their tail probabilities and quantiles come from
the four-cumulant noncentral-χ² match of Liu, Tang & Zhang (2009), Comput. Stat. Data Anal.
53, 853–856, exact for equal λ (checked against simulation in ``tests/test_gap_walk.py``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats


def _liu_parameters(eigenvalues: np.ndarray) -> tuple[float, float, float, float, float]:
    """(a, δ, ν, c1, c2) of the Liu, Tang & Zhang (2009) match of Q = Σ λ_i χ²_1,i: a noncentral
    χ²(ν, δ) with the first four cumulants of Q (Comput. Stat. Data Anal. 53, 853–856)."""
    lam = np.asarray(eigenvalues, float)
    lam = lam[lam > 1e-12 * lam.max()]
    c1, c2, c3, c4 = (float(np.sum(lam ** k)) for k in (1, 2, 3, 4))
    s1, s2 = c3 / c2 ** 1.5, c4 / c2 ** 2
    if s1 * s1 > s2:
        a = 1.0 / (s1 - math.sqrt(s1 * s1 - s2))
        delta = s1 * a ** 3 - a * a
        dof = a * a - 2.0 * delta
    else:
        a, delta, dof = 1.0 / s1, 0.0, c2 ** 3 / c3 ** 2
    return a, delta, dof, c1, c2


def quadratic_form_quantile(eigenvalues: np.ndarray, alpha: float) -> float:
    """Upper-α quantile of Q = Σ λ_i χ²_1,i (independent) by the Liu, Tang & Zhang (2009)
    approximation (:func:`_liu_parameters`), exact for equal λ."""
    a, delta, dof, c1, c2 = _liu_parameters(eigenvalues)
    q = stats.ncx2.isf(alpha, dof, delta) if delta > 0 else stats.chi2.isf(alpha, dof)
    return float((q - (dof + delta)) / (math.sqrt(2.0) * a) * math.sqrt(2.0 * c2) + c1)


def quadratic_form_sf(eigenvalues: np.ndarray, t: float) -> float:
    """P(Q > t) for Q = Σ λ_i χ²_1,i, the inverse of :func:`quadratic_form_quantile`."""
    a, delta, dof, c1, c2 = _liu_parameters(eigenvalues)
    q = (t - c1) / math.sqrt(2.0 * c2) * (math.sqrt(2.0) * a) + dof + delta
    return float(stats.ncx2.sf(q, dof, delta) if delta > 0 else stats.chi2.sf(q, dof))
