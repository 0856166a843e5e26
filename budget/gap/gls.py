"""Regression weights of the temperature statistic: generalised least squares under the model's
own noise spectrum.

The temperature coefficient of a channel is a linear statistic c = w·x of its series
(:mod:`budget.gap.signatures`). Ordinary least squares (w ∝ the temperature with mean and trend
removed) weights every frequency alike, so a slow warm-up — most of a temperature record's
variance — is judged against the bias instability and rate random walk, which are largest at
those same low frequencies: a coefficient a regression sees at > 10σ reads as z ≈ 4–5, and a
random walk explains it as well as the temperature does. GLS weights each frequency by the
inverse of the noise spectrum S(f) the model predicts there, so the faster temperature changes
(a cycle of minutes, the warm-up's curvature) carry the statistic where the noise is low.

Noise is taken as diagonal in the orthonormal DCT-II basis with variance ∝ S(f_k),
f_k = k·rate/(2N) (exact for white noise; the DCT is close to the Karhunen–Loève basis of a
random walk and of slow Gauss–Markov terms, Jain, *Fundamentals of Digital Image Processing*,
1989, §5.6). With the regressor matrix A = [T, t] in that basis, k ≥ 1 (k = 0 is the intercept,
which the mean removal takes), the GLS coefficient of T is

    c = e₁ᵀ (Aᵀ S⁻¹ A)⁻¹ Aᵀ S⁻¹ X,

so w = IDCT(S⁻¹ A (Aᵀ S⁻¹ A)⁻¹ e₁): w·T = 1, w·t = 0, Σ w = 0 (a rate ramp stays the slope
statistic's). The weights are fixed once per channel; the statistic's null spread still comes
from the model's simulated realizations (:mod:`budget.gap.metric`), so a spectrum that is only
approximately right costs power, never validity.

The model spectrum (two-sided, IEEE Std 952-1997 annex C): white N², bias instability
B²/(2πf), rate random walk K²/(2πf)², quantization (2πf)²Q²·dt, Gauss–Markov 2σ²τ/(1+(2πfτ)²).
Other effects (lines, filters, spikes, temperature) do not enter the weighting.
"""

from __future__ import annotations

import math
from typing import Callable, Iterable

import numpy as np
from scipy import fft as sfft

from ..imu import Effect

#: Spectrum floor, relative to its largest value (a model without white noise stays invertible).
FLOOR = 1e-12


def model_spectrum(effects: Iterable[Effect], dt_s: float) -> Callable[[np.ndarray], np.ndarray]:
    """Two-sided PSD S(f) (unit²/Hz) of a channel's stochastic terms (module docstring);
    ``effects`` in SI (:meth:`budget.imu.NoiseModelSI.channel_effects`)."""
    terms = [(f.name, dict(f.params)) for f in effects]

    def psd(freq_hz: np.ndarray) -> np.ndarray:
        f = np.asarray(freq_hz, float)
        w = 2.0 * math.pi * f
        s = np.zeros_like(f)
        for name, p in terms:
            if name == "white_noise":
                s += p["density"] ** 2
            elif name == "bias_instability":
                s += p["B"] ** 2 / w
            elif name == "rate_random_walk":
                s += p["K"] ** 2 / w ** 2
            elif name == "quantization":
                s += w ** 2 * p["Q"] ** 2 * dt_s
            elif name == "gauss_markov":
                s += 2.0 * p["sigma"] ** 2 * p["tau_s"] / (1.0 + (w * p["tau_s"]) ** 2)
        return s
    return psd


def regression_weights(regressor: np.ndarray, rate_hz: float,
                       psd: Callable[[np.ndarray], np.ndarray]) -> np.ndarray | None:
    """w (N,) with w·x the GLS coefficient of x on ``regressor`` given an intercept and a linear
    time trend, noise spectrum ``psd`` (module docstring); None when the regressor is (close to)
    a constant plus a trend."""
    T = np.asarray(regressor, float)
    n = T.size
    t = np.arange(n) / rate_hz
    A = sfft.dct(np.column_stack([T - T.mean(), t - t.mean()]), type=2, norm="ortho", axis=0)[1:]
    s = np.asarray(psd(np.arange(1, n) * rate_hz / (2.0 * n)), float)
    peak = float(np.max(s)) if s.size else 0.0
    if not np.isfinite(peak) or peak <= 0.0:
        s = np.ones(n - 1)
    else:
        s = np.maximum(s, FLOOR * peak)
    a_s = A / s[:, None]
    m = A.T @ a_s
    # T indistinguishable from intercept + trend: its part beyond the trend carries no weight
    resid = m[0, 0] - m[0, 1] ** 2 / m[1, 1]
    if not resid > 1e-12 * m[0, 0]:
        return None
    row = np.linalg.solve(m, np.array([1.0, 0.0]))
    wk = a_s @ row
    return sfft.idct(np.concatenate([[0.0], wk]), type=2, norm="ortho")
