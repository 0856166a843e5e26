"""Variance that a slow stochastic term adds to the regression statistics of a channel.

The time slope and the temperature coefficient (:mod:`budget.gap.signatures`) are linear
statistics Σ_j w_j·x_j of the series with fixed regression weights w. A stochastic term with
autocovariance γ adds var = Σ_j Σ_l w_j w_l γ(j − l) to them; a candidate that adds such a term
must predict that variance (and pay its log-likelihood ln(var′/var),
:meth:`budget.gap.fitting.FitContext.sumsq`), or a slow Gauss–Markov term or a raised bias
instability would explain a long-τ excess for free while a rate random walk, which states its
slope variance (:func:`budget.gap.theory.random_walk_weight`), is charged for it.

* unit-variance sampled Gauss–Markov (AR(1), φ = e^(−dt/τc), γ(k) = φ^|k|):
  var = Σ w_j² + 2 Σ_j w_j·s_j with s_j = Σ_{l<j} φ^(j−l)·w_l (one first-order recursion);
* bias instability: the same sum over the generator's Gauss–Markov bank
  (:func:`budget.imu.flicker.flicker_bank`, B = 1);
* for a Gauss–Markov candidate whose τc moves during a fit, the value is interpolated in
  (ln τc, ln var) on a table of 8 points per decade (cubic; the curve is smooth).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import interpolate, signal

from ..imu.flicker import flicker_bank

#: Table points per decade of τc for :class:`GaussMarkovTable`.
POINTS_PER_DECADE = 8


def gauss_markov_weight_variance(weights: np.ndarray, dt_s: float, tau_c_s: float) -> float:
    """var(Σ w_j x_j) for a unit-variance sampled Gauss–Markov process of correlation time
    ``tau_c_s`` (module docstring)."""
    w = np.asarray(weights, float)
    phi = math.exp(-dt_s / tau_c_s)
    s = signal.lfilter([0.0, phi], [1.0, -phi], w)
    return float(np.dot(w, w) + 2.0 * np.dot(w, s))


def flicker_weight_variance(weights: np.ndarray, dt_s: float, n_samples: int) -> float:
    """var(Σ w_j x_j) of the bias-instability bank with B = 1."""
    tau, var = flicker_bank(1.0, dt_s, dt_s * (n_samples - 1))
    return float(sum(v * gauss_markov_weight_variance(weights, dt_s, t) for t, v in zip(tau, var)))


class GaussMarkovTable:
    """:func:`gauss_markov_weight_variance` over τc ∈ [lo, hi], interpolated (module docstring)."""

    def __init__(self, weights: np.ndarray, dt_s: float, lo_s: float, hi_s: float):
        n = max(int(math.ceil(math.log10(hi_s / lo_s) * POINTS_PER_DECADE)) + 1, 4)
        self.tau = np.geomspace(lo_s, hi_s, n)
        vals = np.array([gauss_markov_weight_variance(weights, dt_s, t) for t in self.tau])
        self._f = interpolate.CubicSpline(np.log(self.tau), np.log(np.clip(vals, 1e-300, None)))

    def __call__(self, tau_c_s: float) -> float:
        x = float(np.clip(math.log(tau_c_s), math.log(self.tau[0]), math.log(self.tau[-1])))
        return float(math.exp(self._f(x)))
