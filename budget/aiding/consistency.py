"""Filter consistency: normalised estimation error squared (NEES) and innovation squared (NIS).

For a consistent filter the error e = x − x̂ is N(0, P), so ε = eᵀ P⁻¹ e ~ χ²(n). Over T
independent trials the average ε̄ at one epoch satisfies T ε̄ ~ χ²(T n); the two-sided
(1 − α) acceptance interval of ε̄ is [χ²_{α/2}(T n) / T, χ²_{1−α/2}(T n) / T]
(Bar-Shalom, Li & Kirubarajan 2001, §5.4.2). The same holds for the innovation ν with its
covariance S (NIS, m degrees of freedom). A consistent filter keeps ε̄ inside the interval at
about a fraction 1 − α of the epochs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.stats import chi2


def normalized_squares(err: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """eᵀ C⁻¹ e for err (T, K, d) and cov (K, d, d) → (T, K).

    Computed on the correlation matrix (C scaled by its diagonal), so states of very different
    units (metres and rad/s) do not make C look singular.
    """
    sd = np.sqrt(np.einsum("kii->ki", cov))
    sd = np.where(sd > 0, sd, 1.0)
    corr = cov / (sd[:, :, None] * sd[:, None, :])
    en = err / sd[None]
    inv = np.linalg.inv(corr)
    return np.einsum("tki,kij,tkj->tk", en, inv, en)


def average_bounds(dof: int, trials: int, alpha: float = 0.05) -> tuple[float, float]:
    """Two-sided acceptance interval of the trial-average of a χ²(dof) statistic."""
    return (chi2.ppf(alpha / 2, trials * dof) / trials, chi2.ppf(1 - alpha / 2, trials * dof) / trials)


@dataclass
class ConsistencyReport:
    """Average NEES/NIS per epoch with its χ² interval and the fraction of epochs inside it."""

    name: str
    dof: int
    trials: int
    alpha: float
    average: np.ndarray
    lower: float
    upper: float

    @property
    def fraction_inside(self) -> float:
        a = self.average
        return float(np.mean((a >= self.lower) & (a <= self.upper)))

    @property
    def overall_mean(self) -> float:
        """Mean over all epochs (≈ dof for a consistent filter)."""
        return float(np.mean(self.average))

    def to_dict(self) -> dict:
        """JSON-ready: statistic, degrees of freedom, trials, α, mean, χ² interval and fractions."""
        return {"name": self.name, "dof": self.dof, "trials": self.trials, "alpha": self.alpha,
                "mean": self.overall_mean, "interval": [self.lower, self.upper],
                "fraction_inside": self.fraction_inside, "expected_fraction": 1 - self.alpha}

    def summary(self) -> str:
        """One line: mean against the dof, and the fraction of epochs inside the χ² interval."""
        return (f"{self.name}: mean {self.overall_mean:.3g} (dof {self.dof}, {self.trials} trials); "
                f"{self.fraction_inside:.1%} of epochs inside [{self.lower:.3g}, {self.upper:.3g}] "
                f"(expected {1 - self.alpha:.0%})")

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"epoch": np.arange(self.average.size), "average": self.average,
                             "lower": self.lower, "upper": self.upper})


def nees_report(err: np.ndarray, cov: np.ndarray, *, alpha: float = 0.05,
                name: str = "NEES") -> ConsistencyReport:
    """NEES of errors (T, K, d) against covariances (K, d, d)."""
    eps = normalized_squares(err, cov)
    dof = err.shape[-1]
    lo, hi = average_bounds(dof, err.shape[0], alpha)
    return ConsistencyReport(name, dof, err.shape[0], alpha, eps.mean(axis=0), lo, hi)


def nis_report(innovations: tuple[np.ndarray, np.ndarray], *, alpha: float = 0.05,
               name: str = "NIS") -> ConsistencyReport:
    """NIS from a filter's (ν (T, E, m), S (E, m, m)) pair."""
    nu, S = innovations
    eps = normalized_squares(nu, S)
    lo, hi = average_bounds(nu.shape[-1], nu.shape[0], alpha)
    return ConsistencyReport(name, nu.shape[-1], nu.shape[0], alpha, eps.mean(axis=0), lo, hi)
