"""Preprocessing of static IMU data before time-series modelling (seed 000 §3.1, Fig. 3).

1. Outliers by the Pauta (3σ-type) criterion: a sample with |x − mean| > k·σ (mean and σ of the
   raw series, k = 3…5, paper and default 4) is an outlier — if its neighbours do not predict it:
   its one-step prediction error, forward or backward, by an AR(:data:`PREDICTION_ORDER`) fitted
   to the series (Yule–Walker), is also beyond k times that error's standard deviation. On white
   data (the paper's) the two tests are one; on a coloured series a level beyond 4σ is an ordinary
   excursion (2 in 30,000 Gaussian samples), and replacing it by the mean made up an innovation of
   4σ of the series: on an oscillating AR(2) (poles 0.95·e^{±i2π·0.02}) that one replaced sample
   moved φ by 16 standard errors and σ² by +55 %, and AIC chose ARMA(2,1). Such samples are
   kept and counted in the step's text. An outlier is replaced by the mean of the remaining
   samples (``replace="mean"``) or by the nearest earlier non-outlier sample
   (``replace="neighbour"``) — the two rules the paper allows. One pass, as in the paper.
2. Polynomial detrend (order 1 or 2; 0 = none) by least-squares regression on time.
3. Zero mean (the mean left after detrending — round-off, the fit has a constant term — is removed).
The offset reported is the constant actually taken out of the series by steps 2–3, in its unit:
the series' mean (a least-squares polynomial with a constant leaves residuals of zero mean), not
the round-off mean step 3 finds after a detrend (reported as "removed the mean -2.57e-20" for a
gyro whose offset was 0.05 deg/s).
Nothing is changed silently: the result lists every step and the outlier indices.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import linalg, signal

from ..errors import InputError

#: Order of the AR model whose one-step prediction errors confirm a Pauta outlier (module doc).
PREDICTION_ORDER = 10


@dataclass(frozen=True)
class Preprocessed:
    """The cleaned series and what was done to it."""

    x: np.ndarray
    outliers: np.ndarray          # indices replaced
    trend: np.ndarray             # polynomial coefficients (highest power first, t from −1 at the first sample to +1 at the last)
    mean_removed: float           # the mean left after the detrend, removed by step 3 (unit of x)
    steps: tuple[str, ...]
    #: the constant the preprocessing took out (steps 2–3): the mean of the series after the outlier
    #: step less that of ``x`` (unit of x; module doc)
    offset_removed: float = 0.0
    #: the series' unit, as the steps name it ('' unknown)
    unit: str = ""

    def summary(self) -> str:
        return "; ".join(self.steps)

    def to_dict(self) -> dict:
        """JSON-ready: the steps done, outlier indices replaced, trend coefficients (highest power
        first, t from −1 at the first sample to +1 at the last, as :func:`detrend` fits them), mean
        removed and the number of samples."""
        return {"steps": list(self.steps), "samples": int(self.x.size), "outliers": self.outliers.tolist(),
                "trend": np.asarray(self.trend, float).tolist(), "mean_removed": float(self.mean_removed),
                "offset_removed": float(self.offset_removed), "unit": self.unit}

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
    if bad.size:
        bad = bad[_unpredicted(x - mu, bad, k)]
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


def pauta_excursions(x: np.ndarray, k: float = 4.0) -> int:
    """How many samples beyond k·σ the Pauta step keeps because their neighbours predict them."""
    x = np.asarray(x, dtype=np.float64)
    mu, sd = x.mean(), x.std()
    beyond = np.flatnonzero(np.abs(x - mu) > k * sd)
    return int(beyond.size - (np.count_nonzero(_unpredicted(x - mu, beyond, k)) if beyond.size else 0))


def _unpredicted(xc: np.ndarray, idx: np.ndarray, k: float) -> np.ndarray:
    """Mask over ``idx``: the sample's forward or backward one-step prediction error (AR by
    Yule–Walker on the zero-mean ``xc``) is beyond k times the errors' standard deviation."""
    n = xc.size
    m = min(PREDICTION_ORDER, n // 10)
    if m < 1:
        return np.ones(idx.size, bool)
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    spec = np.fft.rfft(xc, nfft)
    acov = np.fft.irfft((spec * np.conj(spec)).real, nfft)[:m + 1] / n
    if not acov[0] > 0:
        return np.ones(idx.size, bool)
    try:
        a = linalg.solve_toeplitz(acov[:m], acov[1:m + 1])
    except (linalg.LinAlgError, ValueError):
        return np.ones(idx.size, bool)
    if not np.all(np.isfinite(a)):
        return np.ones(idx.size, bool)
    kern = np.r_[1.0, -a]
    fwd = signal.lfilter(kern, [1.0], xc)           # x(j) − Σ aᵢ x(j−i)
    bwd = signal.lfilter(kern, [1.0], xc[::-1])[::-1]  # x(j) − Σ aᵢ x(j+i) (stationary: same a)
    s = float(np.std(fwd[m:]))
    if not s > 0:
        return np.ones(idx.size, bool)
    return (np.abs(fwd[idx]) > k * s) | (np.abs(bwd[idx]) > k * s)


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
               detrend_order: int = 1, zero_mean: bool = True, unit: str = "") -> Preprocessed:
    """Outliers → detrend → zero mean (each optional), as seed 000 §3.1. ``unit``: the series'
    unit (rad/s, m/s² for IMU channels), named with the offset and trend removed."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < 3:
        raise InputError("expected a 1-D series of at least 3 samples", field="x")
    if not np.all(np.isfinite(x)):
        raise InputError("series contains NaN or infinite values", field="x",
                         expected="finite values (repair the log first)")
    steps = []
    outliers = np.zeros(0, np.int64)
    if pauta_k is not None:
        kept = pauta_excursions(x, pauta_k) if 3.0 <= pauta_k <= 5.0 else 0
        x, outliers = pauta_outliers(x, pauta_k, replace)
        steps.append(f"Pauta k={pauta_k:g}: {outliers.size} outlier(s) replaced by the "
                     f"{'mean of the other samples' if replace == 'mean' else 'previous good sample'}"
                     + (f" ({kept} sample(s) beyond {pauta_k:g}σ kept: their neighbours predict them, "
                        "an excursion of a correlated series, not a spike)" if kept else ""))
    level = float(x.mean())  # after the outlier step: what the offset is measured against
    unit_text = f" {unit}" if unit else ""
    x, coef = detrend(x, detrend_order)
    mean = float(x.mean()) if zero_mean else 0.0
    if zero_mean:
        x = x - mean
    offset = level - float(x.mean())
    if detrend_order:
        change = float(np.polyval(coef, 1.0) - np.polyval(coef, -1.0))
        steps.append(f"removed a degree-{detrend_order} polynomial trend: offset {offset:.6g}{unit_text} (the "
                     f"series' mean), change {change:.3g}{unit_text} from the first sample to the last")
    elif zero_mean:
        steps.append(f"removed the offset {offset:.6g}{unit_text} (the series' mean)")
    return Preprocessed(x, outliers, coef, mean, tuple(steps) or ("nothing done",), offset, unit)
