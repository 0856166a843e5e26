"""Model adequacy of the ARMA pipeline: are the innovations white, is their variance the model's?

A navigation engineer validates a filter's model by its innovations ν_k = z_k − ẑ_{k|k−1}: when
the model describes the series they are white with the variance S_k = H P⁻_k Hᵀ + R the model
predicts, so the normalised innovations ν_k/√S_k are white with unit variance. Two sequences are
tested (same samples, same lags):

* **the selected ARMA model** — its exact one-step prediction errors through the state-augmented
  form of :mod:`.kalman` with no measurement noise (Q = σ² G Gᵀ, R = 0, started from the
  stationary covariance: the innovations of the exact Gaussian likelihood; in steady state the
  ARMA's own w(k), S = σ²). These are the residuals the p + q parameters were fitted to, so the
  Ljung–Box statistic has m − p − q degrees of freedom. Not white at α = 1 %: a note says the
  model does not describe the series, and nothing computed from it (the filter, its variance
  reduction, its error variances) is to be trusted.
* **the pipeline's Kalman filter as run** (its Q and R; the paper's R = δ₂ is the series'
  whole variance on top of an ARMA fitted to that same series). Its innovations are not the
  residuals any parameter was fitted to: m degrees of freedom. A note says when they are not
  white at 1 % or their normalised variance lies outside its 99 % band 1 ± 2.576·√(2/N): then the
  filter's steady error variances below are what it believes, not its errors.

Ljung–Box (Ljung & Box, Biometrika 65(2), 1978, eq. 2.1):
Q = N(N + 2) Σ_{k=1..m} r̂_k²/(N − k), r̂_k the lag-k autocorrelation of the demeaned sequence
(denominator Σ(u − ū)²), referred to χ² with m − p − q degrees of freedom for the residuals of a
fitted ARMA(p, q). Lags: m = min(20, N/5), at least p + q + 1. Why: the χ² reference holds when m
is large enough that the model's ψ-weights have died out by lag m (20 covers the correlation of
the pipeline's candidates at the sampling scale; Ljung & Box use 20–30 for series of 100–200),
while each r̂_k rests on N − k pairs and the test loses power as m grows — the Box–Jenkins rule
keeps m ≤ N/4; N/5 leaves 20 lags from 100 samples (:data:`~.arma.MIN_SAMPLES`) on.

Steady-state error variances: the filter's P (its [0, 0] entry: the error of x̂_k) from the
Riccati recursion of :class:`~.kalman.ArmaKalman`, the RTS smoother's from the discrete Lyapunov
equation P_s − C P_s Cᵀ = P − C P⁻ Cᵀ (C = P Fᵀ P⁻⁻¹, the smoother's steady gain), so P_s ≤ P.
Both are the filter model's own: they are the estimates' error variances only when the filter's
innovations pass. Units: the channel's SI unit squared.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import linalg, stats

from ..errors import InputError
from .arguments import float_series
from .arma import ArmaFit
from .kalman import ArmaKalman, KalmanResult

#: Significance level of the whiteness test and of the normalised-variance band.
ALPHA = 0.01
#: Largest number of Ljung–Box lags (module doc).
MAX_LAGS = 20


def ljung_box_lags(n: int, fitted: int = 0) -> int:
    """m = min(20, N // 5), at least ``fitted`` + 1 (p + q of the model: ≥ 1 degree of freedom)."""
    return max(min(MAX_LAGS, n // 5), fitted + 1)


def ljung_box(u, lags: int, fitted: int = 0) -> tuple[float, int, float]:
    """(Q, degrees of freedom, p-value) of Ljung & Box (1978) eq. 2.1 over ``lags`` lags, the
    degrees of freedom reduced by ``fitted`` (= p + q for the residuals of a fitted ARMA)."""
    u = float_series(u, "innovations", "a 1-D array of innovations")
    n = u.size
    if u.ndim != 1 or not (0 <= fitted < lags < n):
        raise InputError("Ljung–Box needs 0 ≤ fitted < lags < N", field="lags", value=(fitted, lags, n),
                         expected="a 1-D sequence longer than its number of lags")
    d = u - u.mean()
    c0 = float(d @ d)
    if not c0 > 0:
        raise InputError("the sequence is constant: no autocorrelation to test", field="innovations")
    k = np.arange(1, lags + 1)
    r = np.array([d[:n - j] @ d[j:] for j in k]) / c0
    q = float(n * (n + 2) * np.sum(r ** 2 / (n - k)))
    dof = lags - fitted
    return q, dof, float(stats.chi2(dof).sf(q))


@dataclass(frozen=True)
class InnovationTest:
    """Whiteness and scale of one normalised innovation sequence ν_k/√S_k."""

    what: str
    samples: int
    lags: int
    dof: int
    q: float
    p_value: float
    normalised_variance: float

    @property
    def white(self) -> bool:
        return self.p_value > ALPHA

    @property
    def variance_band(self) -> float:
        """Half-width of the 99 % band of the normalised variance of N white unit innovations."""
        return float(stats.norm.ppf(1 - ALPHA / 2) * math.sqrt(2.0 / self.samples))

    @property
    def variance_consistent(self) -> bool:
        return abs(self.normalised_variance - 1.0) <= self.variance_band

    def summary(self) -> str:
        return (f"{self.what} innovations: Ljung–Box Q = {self.q:.4g} over {self.lags} lags ({self.dof} dof), "
                f"p = {self.p_value:.3g} ({'white' if self.white else 'NOT white'} at α = {ALPHA:g}); "
                f"normalised variance {self.normalised_variance:.4g} (1 ± {self.variance_band:.2g} at 99 %)")

    def to_frame(self) -> pd.DataFrame:
        """One row (index: which innovations), the columns of :meth:`to_dict`."""
        return pd.DataFrame([self.to_dict()], index=pd.Index([self.what], name="innovations"))

    def to_dict(self) -> dict:
        return {"samples": self.samples, "lags": self.lags, "dof": self.dof, "ljung_box_q": self.q,
                "p_value": self.p_value, "white": bool(self.white), "alpha": ALPHA,
                "normalised_variance": self.normalised_variance,
                "normalised_variance_band_99": self.variance_band}


def _test(what: str, nu: np.ndarray, s: np.ndarray, fitted: int) -> tuple[InnovationTest, np.ndarray]:
    u = nu / np.sqrt(s)
    lags = ljung_box_lags(u.size, fitted)
    q, dof, p = ljung_box(u, lags, fitted)
    return InnovationTest(what, int(u.size), lags, dof, q, p, float(np.mean(u ** 2))), u


def model_innovations(fit: ArmaFit, x) -> tuple[np.ndarray, np.ndarray]:
    """(ν, S): exact one-step prediction errors of the ARMA ``fit`` on the zero-mean series ``x``
    and their variances (:meth:`ArmaKalman.exact_predictor`: Q = σ² G Gᵀ, R = 0, from the
    stationary covariance)."""
    z = float_series(x, "x", "a 1-D zero-mean series in the model's unit")
    kf = ArmaKalman.exact_predictor(fit)
    return filter_innovations(kf, z, kf.filter(z, center=False))


def filter_innovations(kf: ArmaKalman, x, filtered: KalmanResult) -> tuple[np.ndarray, np.ndarray]:
    """(ν, S) of the Kalman filter ``kf`` as it ran on ``x`` (``filtered`` = ``kf.filter(x)``)."""
    z = float_series(x, "x", "the series the filter ran on") - filtered.mean_removed
    X = filtered.states
    pred = np.zeros(z.size)
    pred[1:] = X[:-1] @ kf.F[0, :]
    s_ss = float(kf.Pp_ss[0, 0]) + kf.R
    S = np.full(z.size, s_ss)
    T = min(kf.T, z.size)
    if T:
        S[:T] = kf._Pp[:T, 0, 0] + kf.R
    return z - pred, S


def steady_error_variances(kf: ArmaKalman) -> tuple[float, float]:
    """(filter, RTS smoother) steady-state error variance of x̂ as the filter's model states it."""
    P, Pp, C = kf.P_ss, kf.Pp_ss, kf.C_ss  # C: the smoother's steady gain P Fᵀ Pp⁻¹, kept by the filter
    Ps = linalg.solve_discrete_lyapunov(C, P - C @ Pp @ C.T)
    return float(P[0, 0]), float(Ps[0, 0])


@dataclass(frozen=True)
class ModelAdequacy:
    """Innovation tests of the selected model and of the filter, and the steady error variances."""

    model_name: str
    unit: str
    model: InnovationTest
    filter: InnovationTest
    filter_error_variance: float
    smoother_error_variance: float
    measurement_variance: float
    model_innovations: np.ndarray
    filter_innovations: np.ndarray

    @property
    def variance_unit(self) -> str:
        return f"({self.unit})^2"

    @property
    def notes(self) -> tuple[str, ...]:
        out = []
        m = self.model
        if not m.white:
            out.append(f"the model does not describe the series: the innovations of {self.model_name} are not "
                       f"white (Ljung–Box Q = {m.q:.4g} over {m.lags} lags, {m.dof} dof, p = {m.p_value:.2g} < "
                       f"{ALPHA:g}); the filter built from it, its variance reduction and error variances rest "
                       "on a wrong model — try other orders")
        f = self.filter
        if not (f.white and f.variance_consistent):
            why = []
            if not f.white:
                why.append(f"not white (Ljung–Box Q = {f.q:.4g} over {f.lags} lags, p = {f.p_value:.2g})")
            if not f.variance_consistent:
                why.append(f"normalised variance {f.normalised_variance:.3g}, not 1 ± {f.variance_band:.2g}")
            out.append(f"the filter's model ({self.model_name} plus white measurement noise of R = "
                       f"{self.measurement_variance:.4g} {self.variance_unit}) does not describe the series: its "
                       f"innovations are {' and '.join(why)}; its error variances are what it believes, not "
                       "its errors, and its variance reduction is not noise removed")
        return tuple(out)

    def fields(self) -> dict:
        """Flat, unit-named values (the pipeline's frame columns and the JSON's scalars)."""
        vu = self.variance_unit
        return {"innovations_ljung_box_q": self.model.q, "innovations_ljung_box_lags": self.model.lags,
                "innovations_ljung_box_dof": self.model.dof, "innovations_ljung_box_p": self.model.p_value,
                "innovations_normalised_variance": self.model.normalised_variance,
                "filter_innovations_ljung_box_p": self.filter.p_value,
                "filter_innovations_normalised_variance": self.filter.normalised_variance,
                f"filter_error_variance_{vu}": self.filter_error_variance,
                f"smoother_error_variance_{vu}": self.smoother_error_variance}

    def to_dict(self) -> dict:
        vu = self.variance_unit
        return {"model": self.model_name, "model_innovations": self.model.to_dict(),
                "filter_innovations": self.filter.to_dict(),
                f"filter_error_variance_{vu}": self.filter_error_variance,
                f"smoother_error_variance_{vu}": self.smoother_error_variance,
                "error_variances": "steady state, of the estimate of x, as the filter's model states them",
                "notes": list(self.notes)}

    def to_frame(self) -> pd.DataFrame:
        """Two rows, the model's and the filter's innovation tests (:meth:`InnovationTest.to_dict`)."""
        return pd.concat([self.model.to_frame(), self.filter.to_frame()])

    def summary(self) -> str:
        lines = [f"model adequacy ({self.model_name}): " + self.model.summary(),
                 "filter adequacy: " + self.filter.summary(),
                 f"steady error variance (filter's model): filter {self.filter_error_variance:.4g}, RTS smoother "
                 f"{self.smoother_error_variance:.4g} {self.variance_unit}"]
        return "\n".join(lines + [f"note: {n}" for n in self.notes])


def model_adequacy(fit: ArmaFit, kf: ArmaKalman, x, filtered: KalmanResult, *, unit: str) -> ModelAdequacy:
    """Innovation tests of ``fit`` and of ``kf`` (as it ran: ``filtered``) on the zero-mean ``x``."""
    mt, mu = _test("model", *model_innovations(fit, x), fit.k)
    ft, fu = _test("filter", *filter_innovations(kf, x, filtered), 0)
    pf, ps = steady_error_variances(kf)
    return ModelAdequacy(fit.name, unit, mt, ft, pf, ps, float(kf.R), mu, fu)
