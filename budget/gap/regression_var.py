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
  (ln τc, ln var) on a table of 8 points per decade (cubic; the curve is smooth);
* the whole channel model's mean and variance of the statistic, every registered effect in
  closed form (:func:`model_weight_mean`, :func:`model_weight_variance`): what the slope and
  temperature z are judged against, so that they are normal scores rather than t scores with
  the realizations' 11 degrees of freedom.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from functools import lru_cache

import numpy as np
from scipy import interpolate, signal

from ..imu import Effect
from ..imu import effects as fx
from ..imu.flicker import flicker_bank
from ..imu.registry import DETERMINISTIC_EFFECTS, REGISTRY

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


def slope_weights(n_samples: int, rate_hz: float) -> np.ndarray:
    """Weights w of the time-slope statistic, slope = w·x (1/s per sample; the signature grid's
    ``time_w`` with no temperature column): the centred time over its sum of squares."""
    tc = np.arange(n_samples) / rate_hz
    tc = tc - tc.mean()
    return tc / np.dot(tc, tc)


@lru_cache(maxsize=4)
def flicker_slope_variance(n_samples: int, rate_hz: float) -> float:
    """Variance of the time slope from the bias-instability bank with B = 1 ((1/s)², per unit B²)."""
    return flicker_weight_variance(slope_weights(n_samples, rate_hz), 1.0 / rate_hz, n_samples)


@lru_cache(maxsize=4)
def gauss_markov_slope_table(n_samples: int, rate_hz: float) -> GaussMarkovTable:
    """Variance of the time slope from a unit Gauss–Markov term, tabulated over τc from 2·dt to
    half the record (the range a Gauss–Markov candidate searches)."""
    dt = 1.0 / rate_hz
    return GaussMarkovTable(slope_weights(n_samples, rate_hz), dt, 2.0 * dt, 0.5 * n_samples * dt)


def _lowpass_adjoint(w: np.ndarray, cutoff_hz: float, dt_s: float) -> np.ndarray:
    """v with v·x = w·lowpass(x) (:func:`budget.imu.effects.lowpass`, y_0 = x_0,
    y_k = r·y_{k−1} + a·x_k, r = 1 − a): v_j = a·Σ_{k≥j} r^(k−j)·w_k for j ≥ 1, v_0 = Σ_k r^k·w_k."""
    a = fx.lowpass_coefficient(cutoff_hz, dt_s)
    u = signal.lfilter([1.0], [1.0, a - 1.0], w[::-1])[::-1]
    v = a * u
    v[0] = u[0]
    return v


def _autocorrelation(w: np.ndarray) -> np.ndarray:
    """R(k) = Σ_j w_j·w_{j+k}, k = 0 … N−1 (by FFT)."""
    n = w.size
    spec = np.fft.rfft(w, 2 * n)
    return np.fft.irfft(spec.real ** 2 + spec.imag ** 2, 2 * n)[:n]


def model_weight_variance(effects: Iterable[Effect], weights: np.ndarray, dt_s: float) -> float | None:
    """var(Σ w_j x_j) of a channel whose error x is drawn from ``effects`` (SI) by the
    package's generator (:mod:`budget.imu.generator`), for weights with Σ w = 0 (a constant
    bias drops out); ``None`` when an effect has no entry below.

    Stationary terms add γ(0)·R(0) + 2·Σ_{k≥1} γ(k)·R(k), R the weights' autocorrelation:
    white (and Student-t) noise γ(0) = N²/dt; each Gauss–Markov term of the flicker bank and
    every ``gauss_markov`` σ²·φ^k; vibration σ²·ρ(k) (:func:`budget.imu.effects.vibration_acov`);
    spikes rate·m²; rounding of the output rate δ²/12; quantization of the integrated output
    (Δε)/dt with ε uniform of variance Q² (independent from sample to sample: an approximation
    when the noise spans less than a quantum). A random-phase sinusoid adds
    (A²/2)·|Σ w_j·e^(iωt_j)|², the rate random walk K²·dt·Σ_k(Σ_{j≥k} w_j)²; ramp and
    temperature terms are the same in every realization and add nothing. The output filter
    acts on the Gaussian and additive terms: their weights are its adjoint applied to w."""
    w = np.asarray(weights, float)
    effects = list(effects)
    upstream = w
    for f in reversed([f for f in effects if f.name == "lowpass"]):
        upstream = _lowpass_adjoint(upstream, f.param("cutoff_hz"), dt_s)
    r_up, r_out = _autocorrelation(upstream), None
    k = np.arange(w.size)

    def stationary(r: np.ndarray, gamma: np.ndarray) -> float:
        return float(gamma[0] * r[0] + 2.0 * np.dot(gamma[1:], r[1:gamma.size]))

    total = 0.0
    for f in effects:
        name, p = f.name, dict(f.params)
        if name in ("white_noise", "heavy_tailed"):
            total += p["density"] ** 2 / dt_s * r_up[0]
        elif name == "bias_instability":
            tau, var = flicker_bank(p["B"], dt_s, dt_s * (w.size - 1))
            total += sum(v * stationary(r_up, np.exp(-k * dt_s / t)) for t, v in zip(tau, var))
        elif name == "gauss_markov":
            total += p["sigma"] ** 2 * stationary(r_up, np.exp(-k * dt_s / p["tau_s"]))
        elif name == "vibration":
            gamma = fx.vibration_acov(k, p["center_hz"], p["width_hz"], dt_s)
            total += p["sigma"] ** 2 * stationary(r_up, gamma)
        elif name == "sinusoid":
            arg = 2.0 * math.pi * p["frequency_hz"] * dt_s * k
            total += 0.5 * p["amplitude"] ** 2 * (np.dot(upstream, np.cos(arg)) ** 2
                                                  + np.dot(upstream, np.sin(arg)) ** 2)
        elif name == "rate_random_walk":
            tail = np.cumsum(upstream[::-1])[::-1]
            total += p["K"] ** 2 * dt_s * float(np.dot(tail, tail))
        elif name == "lowpass" or name in DETERMINISTIC_EFFECTS:
            continue
        elif name in ("quantization", "rate_quantization", "outliers"):
            if r_out is None:
                r_out = _autocorrelation(w)
            if name == "quantization":
                q2 = p["Q"] ** 2 / dt_s ** 2
                total += q2 * (2.0 * r_out[0] - 2.0 * r_out[1])
            elif name == "rate_quantization":
                total += p["step"] ** 2 / 12.0 * r_out[0]
            else:
                total += p["rate"] * p["magnitude"] ** 2 * r_out[0]
        else:
            return None
    return total


def model_weight_mean(effects: Iterable[Effect], weights: np.ndarray, rate_hz: float,
                      temp_c: np.ndarray | None) -> float | None:
    """E(Σ w_j x_j) under ``effects`` (SI) for weights with Σ w = 0: a ramp adds R·Σ w_j t_j, a
    warm-up transient A·Σ w_j e^(−t_j/τ), a bias step A·Σ_{t_j ≥ t₀} w_j, a
    temperature sensitivity c·Σ w_j (T_j − T_0) with T the log's temperature (a thermal lag:
    the lagged T_e, :func:`budget.imu.effects.temperature_response`; what the
    generator is driven by); every other registered effect has zero mean (random phase,
    symmetric spikes, lattice offsets drawn per record). ``None`` for an unknown effect, or a
    temperature effect without a temperature column."""
    w = np.asarray(weights, float)
    total = 0.0
    for f in effects:
        if f.name in DETERMINISTIC_EFFECTS:
            series = fx.mean_series(f.name, dict(f.params), w.size, 1.0 / rate_hz, temp_c)
            if series is None:
                return None
            total += float(np.dot(w, series))
        elif f.name not in REGISTRY:
            return None
    return total
