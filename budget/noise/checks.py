"""Data checks before ARMA modelling (seed 000 §3.1): stationarity (runs test, unit root) and normality.

* Stationarity — runs test (Wald & Wolfowitz 1940, the non-parametric test the paper names):
  the series is cut into ``segments`` equal pieces, each piece's mean is marked above/below the
  median of the means, and the number of runs R is compared with its distribution under
  randomness, E R = 2n₁n₂/n + 1, var R = 2n₁n₂(2n₁n₂ − n)/(n²(n − 1)) (normal approximation).
  Testing segment means (not samples) makes the test about a drifting level, not about the
  short-term correlation that the ARMA model is there to describe — provided a segment is longer
  than that correlation: segments are made at least the decorrelation lag long (fewer of them:
  with 40 segments shorter than it, stationary AR(1) series of 100 samples were flagged in 41 %
  (φ = 0.6) and 92 % (φ = 0.9) of simulations instead of 5 %). When fewer than 10 such segments
  fit, the test is made on 10 and flagged either way: a rejection means the level wanders at
  the scale of the record (a drift, or a correlation time beyond a tenth of it), no rejection
  that the record is too short for its correlation time to tell.
* Unit root — augmented Dickey–Fuller test (:func:`adf_test`, statsmodels' ``adfuller``
  regression and MacKinnon p-value): Δx_t on x_{t−1}, the terms the preprocessing removed (a
  constant; + a linear or quadratic trend for a detrend of order 1 or 2: ``ct``, ``ctt``, the
  same t-ratio as on the series before the detrend) and L = min(decorrelation lag,
  :data:`ADF_MAX_LAG`) lagged differences — fixed, not chosen by information criterion
  (``autolag`` fitted every lag to 200,000 samples: 15 s to minutes). A unit root not rejected
  at ``alpha`` is "not stationary": the runs test alone passed random walks, whose segment means
  wander slowly enough to look random over 10 segments (checks passed on 14/60 random walks of
  2,000 samples, a reviewer saw ~30 %). Measured over 60 seeds, after the pipeline's
  preprocessing (detrend 1, ``ct``): a unit root not rejected on 56/60 random walks of 2,000
  samples and 58/60 of 200,000 (checks passed 1/60 and 2/60); on stationary AR(1) φ = 0.9, 0/60
  at both lengths; φ = 0.99, 23/60 at 2,000 samples (n(1 − φ) = 20 correlation times: such a
  record cannot tell it from a random walk) and 0/60 at 200,000. 0.15–0.2 s on 200,000 samples.
* Normality — skewness and excess kurtosis with their large-sample standard errors √(6/n),
  √(24/n), and D'Agostino–Pearson's K² goodness-of-fit test (``scipy.stats.normaltest``). These
  assume independent samples, so they run on the series thinned to every L-th sample, L = the
  first lag where the sample autocorrelation falls below 0.05 (an ARMA series close to a unit
  root would otherwise fail any normality test). For long records every tiny deviation is
  "significant", so the effect sizes are reported next to the p-value; the flag follows the
  p-value.
Failing data are flagged; callers report the flag with the model, never drop it silently.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ..errors import InputError

#: Fewest segment means the runs test is made on (below: not testable, flagged).
MIN_SEGMENTS = 10
#: Largest lag of lagged differences in the ADF regression (module doc).
ADF_MAX_LAG = 12
#: Deterministic terms of the ADF regression for each detrend order of the preprocessing
#: (:data:`budget.noise.preprocess.DETREND_ORDERS`): constant, + linear, + quadratic trend.
ADF_REGRESSION = {0: "c", 1: "ct", 2: "ctt"}
#: Condition number of the ADF regression's normal matrix (unit-scaled columns) beyond which its
#: columns are taken as collinear (cond² of the columns: 1e12 leaves ~4 digits of the t-ratio).
ADF_MAX_CONDITION = 1e12


@dataclass(frozen=True)
class CheckReport:
    runs: int
    runs_expected: float
    runs_z: float
    runs_p: float
    segments: int
    skewness: float
    excess_kurtosis: float
    skewness_se: float
    kurtosis_se: float
    normal_p: float
    alpha: float
    thinning: int = 1
    runs_lag: int = 1  # decorrelation lag that set the segment length of the runs test
    runs_valid: bool = True  # segments ≥ runs_lag (else 10 shorter segments were tested)
    #: augmented Dickey–Fuller test (module doc): statistic, p-value (None: not made), lagged
    #: differences and deterministic terms of its regression
    adf_stat: float | None = None
    adf_p: float | None = None
    adf_lags: int = 0
    adf_regression: str = "c"

    @property
    def unit_root(self) -> bool:
        """True when the ADF test cannot reject a unit root at ``alpha`` (a random walk may
        describe the series; :func:`adf_test`); False when it was not made or not testable."""
        return self.adf_p is not None and math.isfinite(self.adf_p) and not self.adf_p < self.alpha

    @property
    def stationary(self) -> bool:
        return self.runs_valid and self.runs_p >= self.alpha and not self.unit_root

    @property
    def normal(self) -> bool:
        return self.normal_p >= self.alpha

    @property
    def passed(self) -> bool:
        return self.stationary and self.normal

    def flags(self) -> list[str]:
        out = []
        short = (f"segments at least as long as the decorrelation lag ({self.runs_lag} samples) "
                 f"would leave fewer than {MIN_SEGMENTS}")
        if self.runs_p < self.alpha:
            out.append(f"not stationary: runs test on {self.segments} segment means gives "
                       f"{self.runs} runs (expected {self.runs_expected:.1f}), p = {self.runs_p:.3g}"
                       + ("" if self.runs_valid else f" ({short}: the level wanders at the scale of "
                          "the record — a drift, or a correlation time beyond a tenth of it)"))
        elif not self.runs_valid:
            out.append(f"stationarity not testable: {short} — the record is short for its "
                       "correlation time")
        if self.adf_p is not None and not math.isfinite(self.adf_p):
            out.append("unit root not testable: the ADF regression is exact (the lagged differences "
                       "predict the series: a deterministic signal)")
        if self.unit_root:
            out.append(f"not stationary: ADF cannot reject a unit root (p = {self.adf_p:.3g}, statistic "
                       f"{self.adf_stat:.3g}, {self.adf_lags} lagged differences, regression "
                       f"'{self.adf_regression}'): the series may be a random walk, which no record length "
                       "makes stationary")
        if not self.normal:
            out.append(f"not normal: K² test p = {self.normal_p:.3g} (series thinned by "
                       f"{self.thinning}; skewness "
                       f"{self.skewness:.3g} ± {self.skewness_se:.2g}, excess kurtosis "
                       f"{self.excess_kurtosis:.3g} ± {self.kurtosis_se:.2g})")
        return out

    def to_dict(self) -> dict:
        return {"stationary": self.stationary, "normal": self.normal, "passed": self.passed,
                "runs": self.runs, "runs_expected": self.runs_expected, "runs_z": self.runs_z,
                "runs_p": self.runs_p, "runs_valid": self.runs_valid, "runs_lag": self.runs_lag,
                "segments": self.segments, "adf_stat": self.adf_stat, "adf_p": self.adf_p,
                "adf_lags": self.adf_lags, "adf_regression": self.adf_regression,
                "unit_root": self.unit_root, "skewness": self.skewness,
                "excess_kurtosis": self.excess_kurtosis, "normal_p": self.normal_p,
                "thinning": self.thinning, "alpha": self.alpha, "flags": self.flags()}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([self.to_dict()])

    def summary(self) -> str:
        return "checks passed" if self.passed else "; ".join(self.flags())


def runs_test(x: np.ndarray, segments: int = 40) -> tuple[int, float, float, float]:
    """(runs, expected, z, two-sided p) of the runs test on ``segments`` segment means."""
    x = np.asarray(x, float)
    if segments < 10 or x.size < 2 * segments:
        raise InputError(f"runs test needs ≥ 10 segments of ≥ 2 samples ({x.size} samples, "
                         f"{segments} segments)", field="segments")
    means = x[: x.size // segments * segments].reshape(segments, -1).mean(axis=1)
    above = means > np.median(means)
    n1, n2 = int(above.sum()), int((~above).sum())
    n = n1 + n2
    runs = int(1 + np.count_nonzero(above[1:] != above[:-1]))
    expected = 2.0 * n1 * n2 / n + 1.0
    var = 2.0 * n1 * n2 * (2.0 * n1 * n2 - n) / (n * n * (n - 1.0))
    z = (runs - expected) / math.sqrt(var) if var > 0 else 0.0
    return runs, expected, z, float(2 * stats.norm.sf(abs(z)))


def adf_test(x, lags: int, regression: str = "c") -> tuple[float, float]:
    """(statistic, p-value) of the augmented Dickey–Fuller test of a unit root in ``x``.

    The regression of statsmodels' ``adfuller(x, maxlag=lags, autolag=None,
    regression=regression)``: Δx_t on x_{t−1}, the deterministic terms (``c`` constant, ``ct`` +
    linear trend, ``ctt`` + quadratic trend) and Δx_{t−1} … Δx_{t−lags}, over the N − 1 − lags
    samples that have them all; the statistic is the t-ratio of x_{t−1}'s coefficient and the
    p-value MacKinnon's (1994, 2010) response surface, statsmodels' ``mackinnonp``. Solved by the
    normal equations of the unit-scaled columns: statsmodels' least squares (an SVD of the
    N × (lags + 4) matrix) took 1–2 s on 200,000 samples on a shared two-core machine, this
    0.15–0.2 s, with the same statistic to 1e-8 relative (adfuller on the series scaled to unit
    rms; on raw IMU magnitudes its unscaled t² column costs it 4e-7 with ``ctt``, where this agrees
    with a QR solve to 1e-14: ``tests/test_noise_review_fixes.py``).
    (nan, nan) when the regression is exact or singular — a deterministic series (an alternating
    sign: Δx_{t−1} = 2x_{t−1}) has no unit root to test, and the ARMA step refuses it by name."""
    from statsmodels.tsa.adfvalues import mackinnonp

    x = np.asarray(x, float)
    dx = np.diff(x)
    nobs = dx.size - lags
    trend = {"c": 0, "ct": 1, "ctt": 2}[regression]
    if lags < 0 or nobs < 2 * (lags + trend + 2):
        raise InputError(f"{x.size} samples are too few for an ADF regression with {lags} lags",
                         field="x", expected=f"at least {2 * (2 * lags + trend + 3)} samples")
    s = np.linspace(-1.0, 1.0, nobs)  # the trend in normalised time: same fit, well conditioned
    cols = [x[lags:-1], *(s ** k for k in range(trend + 1)), *(dx[lags - i:-i] for i in range(1, lags + 1))]
    X = np.column_stack(cols)
    y = dx[lags:]
    scale = np.linalg.norm(X, axis=0)
    scale[scale == 0] = 1.0
    Xs = X / scale
    G = Xs.T @ Xs
    if not np.linalg.cond(G) < ADF_MAX_CONDITION:  # collinear columns: a deterministic series
        return math.nan, math.nan
    b = np.linalg.solve(G, Xs.T @ y)
    resid = y - Xs @ b
    s2 = float(resid @ resid) / (nobs - X.shape[1])
    var0 = float(np.linalg.solve(G, np.eye(G.shape[0])[:, 0])[0]) * s2
    if not var0 > 0:  # the regression predicts every difference exactly
        return math.nan, math.nan
    stat = float(b[0] / np.sqrt(var0))
    return stat, float(mackinnonp(stat, regression=regression, N=1))


def check_series(x, *, segments: int = 40, alpha: float = 0.05, detrend_order: int = 0) -> CheckReport:
    """Runs (stationarity), unit-root (ADF) and normality checks of a preprocessed series.

    ``detrend_order``: the polynomial the preprocessing removed (0: the mean only), whose terms
    the ADF regression then carries (:data:`ADF_REGRESSION`)."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < max(20, 2 * segments):
        raise InputError(f"{x.size} samples are too few for the checks", field="x",
                         expected=f"at least {max(20, 2 * segments)} samples")
    if not np.all(np.isfinite(x)):  # NaN gave 'stationary' and a K² p-value of NaN
        raise InputError("series contains NaN or infinite values", field="x",
                         expected="finite values (repair the log first)")
    if np.ptp(x) == 0:
        raise InputError("series is constant (no noise to check)", field="x",
                         expected="a preprocessed series with noise")
    # segments no shorter than the decorrelation lag (module doc): adjacent means ~independent
    # (one lag beyond what 10 segments allow: not found within it means too short to test)
    runs_lag = decorrelation_lag(x, max_lag=x.size // MIN_SEGMENTS + 1)
    valid = x.size // runs_lag >= MIN_SEGMENTS
    segments = max(MIN_SEGMENTS, min(segments, x.size // runs_lag))
    runs, expected, z, p = runs_test(x, segments)
    lag = decorrelation_lag(x)
    if detrend_order not in ADF_REGRESSION:
        raise InputError("detrend order must be 0, 1 or 2", field="detrend_order", value=detrend_order,
                         expected="the order the preprocessing used")
    adf_lags = min(lag, ADF_MAX_LAG)
    adf_stat, adf_p = adf_test(x, adf_lags, ADF_REGRESSION[detrend_order])
    xs = x[::lag]
    n = xs.size
    skew = float(stats.skew(xs))
    kurt = float(stats.kurtosis(xs))
    normal_p = float(stats.normaltest(xs).pvalue) if n >= 20 else float("nan")
    return CheckReport(runs, expected, z, p, segments, skew, kurt, math.sqrt(6.0 / n),
                       math.sqrt(24.0 / n), normal_p, alpha, lag, runs_lag, valid, adf_stat, adf_p,
                       adf_lags, ADF_REGRESSION[detrend_order])


def decorrelation_lag(x: np.ndarray, threshold: float = 0.05, *, max_lag: int | None = None) -> int:
    """First lag whose sample autocorrelation is below ``threshold`` (≤ ``max_lag``, default
    n/50; ≥ 1)."""
    x = np.asarray(x, float) - np.mean(x)
    n = x.size
    cap = max(1, n // 50 if max_lag is None else int(max_lag))
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(x, nfft)
    acf = np.fft.irfft(f * np.conj(f), nfft)[: max(2, cap) + 1]
    if acf[0] <= 0:
        return 1
    below = np.flatnonzero(np.abs(acf / acf[0]) < threshold)
    return int(below[0]) if below.size else cap
