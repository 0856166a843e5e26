"""Preprocessing of static IMU data before time-series modelling (seed 000 §3.1, Fig. 3).

1. Outliers by the Pauta (3σ-type) criterion: a sample with |x − mean| > k·σ (mean and σ of the
   raw series, k = 3…5, paper and default 4) is an outlier. It is replaced by the mean of the
   remaining samples (``replace="mean"``) or by the nearest earlier non-outlier sample
   (``replace="neighbour"``) — the two rules the paper allows. One pass, as in the paper.
2. Polynomial detrend (order 1 or 2; 0 = none) by least-squares regression on time.
3. Zero mean (the mean left after detrending is removed and reported).
Nothing is changed silently: the result lists every step and the outlier indices.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError


@dataclass(frozen=True)
class Preprocessed:
    """The cleaned series and what was done to it."""

    x: np.ndarray
    outliers: np.ndarray          # indices replaced
    trend: np.ndarray             # polynomial coefficients (highest power first, t in samples/n)
    mean_removed: float
    steps: tuple[str, ...]

    def summary(self) -> str:
        return "; ".join(self.steps)

    def to_dict(self) -> dict:
        """JSON-ready: the steps done, outlier indices replaced, trend coefficients (highest power
        first, t in samples/n), mean removed and the number of samples."""
        return {"steps": list(self.steps), "samples": int(self.x.size), "outliers": self.outliers.tolist(),
                "trend": np.asarray(self.trend, float).tolist(), "mean_removed": float(self.mean_removed)}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"x": self.x})


def pauta_outliers(x: np.ndarray, k: float = 4.0, replace: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """(cleaned copy, outlier indices) by the Pauta criterion (module doc)."""
    if not 3.0 <= k <= 5.0:
        raise InputError("Pauta factor outside 3–5", field="pauta_k", value=k, expected="3 ≤ k ≤ 5")
    if replace not in ("mean", "neighbour"):
        raise InputError(f"unknown replacement {replace!r}", field="replace", expected="mean or neighbour")
    x = np.array(x, dtype=np.float64, copy=True)
    mu, sd = x.mean(), x.std()
    bad = np.flatnonzero(np.abs(x - mu) > k * sd)
    if bad.size == 0:
        return x, bad
    good = np.ones(x.size, bool)
    good[bad] = False
    if replace == "mean":
        x[bad] = x[good].mean()
    else:
        idx = np.where(good, np.arange(x.size), 0)
        prev = np.maximum.accumulate(idx)
        first_good = int(np.argmax(good))
        prev[:first_good] = first_good  # leading outliers take the first good sample
        x[bad] = x[prev[bad]]
    return x, bad


#: Degrees of the polynomial detrend (module doc: none, linear, quadratic).
DETREND_ORDERS = (0, 1, 2)


def check_detrend_order(order) -> int:
    """``order`` as an int if it is one of :data:`DETREND_ORDERS`, else :class:`InputError`
    (field ``detrend_order``; ``True`` and 1.0 are refused) — the one home of the limit
    (:func:`detrend` and :class:`~budget.noise.pipeline.ArmaOptions`)."""
    if isinstance(order, bool) or not isinstance(order, numbers.Integral) or order not in DETREND_ORDERS:
        allowed = ", ".join(map(str, DETREND_ORDERS[:-1])) + f" or {DETREND_ORDERS[-1]}"
        raise InputError(f"detrend order must be {allowed}", field="detrend_order", value=order,
                         expected="0 (none), 1 (linear) or 2 (quadratic), a whole number")
    return int(order)


def detrend(x: np.ndarray, order: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """(residual, coefficients) of a least-squares polynomial of ``order`` in normalised time."""
    order = check_detrend_order(order)
    if order == 0:
        return np.asarray(x, float).copy(), np.zeros(0)
    t = np.linspace(-1.0, 1.0, x.size)  # normalised: well-conditioned for any length
    coef = np.polynomial.polynomial.polyfit(t, x, order)[::-1]
    return x - np.polyval(coef, t), coef


def preprocess(x, *, pauta_k: float | None = 4.0, replace: str = "mean",
               detrend_order: int = 1, zero_mean: bool = True) -> Preprocessed:
    """Outliers → detrend → zero mean (each optional), as seed 000 §3.1."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < 3:
        raise InputError("expected a 1-D series of at least 3 samples", field="x")
    if not np.all(np.isfinite(x)):
        raise InputError("series contains NaN or infinite values", field="x",
                         expected="finite values (repair the log first)")
    steps = []
    outliers = np.zeros(0, np.int64)
    if pauta_k is not None:
        x, outliers = pauta_outliers(x, pauta_k, replace)
        steps.append(f"Pauta k={pauta_k:g}: {outliers.size} outlier(s) replaced by the "
                     f"{'mean of the other samples' if replace == 'mean' else 'previous good sample'}")
    x, coef = detrend(x, detrend_order)
    if detrend_order:
        steps.append(f"removed a degree-{detrend_order} polynomial trend")
    mean = float(x.mean()) if zero_mean else 0.0
    if zero_mean:
        x = x - mean
        steps.append(f"removed the mean {mean:.6g}")
    return Preprocessed(x, outliers, coef, mean, tuple(steps) or ("nothing done",))
