"""Synthetic rate noise with known IEEE-952 coefficients, and ARMA series (seed 000 (11)).

Used by the tests and the benchmarks to check that fits recover what was put in. Each term is
generated so that its overlapping Allan variance follows IEEE Std 952 Annex C:

* Q: white *angle* noise of standard deviation Q, differentiated → 3Q²/τ²
* N: white rate noise of standard deviation N·√fs → N²/τ
* B: flicker rate noise by Kasdin's fractional-integration filter (Kasdin 1995, α = 1,
  h₀ = 1, h_k = h_{k−1}(k − ½)/k) applied to white noise of standard deviation B, whose
  two-sided PSD ≈ B²/(2πf) → (2 ln2/π)B² (low-frequency approximation)
* K: random walk of the rate with steps of standard deviation K/√fs → K²τ/3
* R: deterministic ramp R·t → R²τ²/2
"""

from __future__ import annotations

import numpy as np
from scipy import signal


def flicker_noise(n: int, rng: np.random.Generator, sigma: float = 1.0) -> np.ndarray:
    """Kasdin flicker (1/f) noise of length ``n`` (IEEE B = ``sigma``)."""
    k = np.arange(1, n)
    h = np.concatenate(([1.0], np.cumprod((k - 0.5) / k)))
    w = rng.normal(0.0, sigma, n)
    return signal.fftconvolve(w, h)[:n]


def imu_noise(n: int, rate_hz: float, rng: np.random.Generator, *, Q: float = 0.0, N: float = 0.0,
              B: float = 0.0, K: float = 0.0, R: float = 0.0) -> np.ndarray:
    """Rate samples (unit of the coefficients) with the given IEEE-952 terms, zero mean start."""
    y = np.zeros(n)
    if Q:
        y += np.diff(rng.normal(0.0, Q, n + 1)) * rate_hz
    if N:
        y += rng.normal(0.0, N * np.sqrt(rate_hz), n)
    if B:
        y += flicker_noise(n, rng, B)
    if K:
        y += np.cumsum(rng.normal(0.0, K / np.sqrt(rate_hz), n))
    if R:
        y += R * np.arange(n) / rate_hz
    return y


def simulate_arma(phi, theta, sigma2: float, n: int, rng: np.random.Generator,
                  burn_in: int = 2000) -> np.ndarray:
    """x(k) = Σ φ_i x(k−i) + w(k) + Σ θ_j w(k−j), w ~ N(0, σ²) (seed 000 (11)); burn-in dropped."""
    w = rng.normal(0.0, np.sqrt(sigma2), n + burn_in)
    x = signal.lfilter(np.r_[1.0, np.asarray(theta, float)], np.r_[1.0, -np.asarray(phi, float)], w)
    return x[burn_in:]
