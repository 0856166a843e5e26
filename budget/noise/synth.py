"""Synthetic rate noise with known IEEE-952 coefficients, and ARMA series (seed 000 (11)).

Used by the tests, the benchmarks and the Noise lab's example log to check that fits recover
what was put in. The rate terms N, B, K, R are drawn by the one IMU generator of the package
(:func:`budget.imu.generate_imu_errors`, one channel; bias instability by its documented
Gauss–Markov bank, :mod:`budget.imu.flicker`), so the Noise lab, the Monte Carlo and the model
gap share one synthesiser and one flicker model. Allan variances (IEEE Std 952 Annex C):

* Q: white *angle* noise of standard deviation Q, differentiated → 3Q²/τ² (the idealised
  quantization term of the standard, not the generator's quantizer of the integrated output)
* N: white rate noise of density N → N²/τ
* B: flicker rate noise of one-sided PSD B²/(π f) → (2 ln2/π)B² in the band
* K: random walk of the rate → K²τ/3
* R: deterministic ramp R·t → R²τ²/2
"""

from __future__ import annotations

import numpy as np
from scipy import signal


def imu_noise(n: int, rate_hz: float, rng: np.random.Generator, *, Q: float = 0.0, N: float = 0.0,
              B: float = 0.0, K: float = 0.0, R: float = 0.0) -> np.ndarray:
    """Rate samples (unit of the coefficients) with the given IEEE-952 terms, zero mean start."""
    from ..imu import NoiseModel, generate_imu_errors  # the one generator (imu sits below noise)
    effects = [{"name": name, "channel": "gyro_x", "params": {key: val}}
               for name, key, val in (("white_noise", "density", N), ("bias_instability", "B", B),
                                      ("rate_random_walk", "K", K), ("rate_ramp", "R", R))
               if val]
    y = np.zeros(n)
    if effects:
        model = NoiseModel(rate_hz=float(rate_hz), effects=tuple(effects))
        y += generate_imu_errors(model, 1, n, float(rate_hz), rng).gyro_rad_s[0, :, 0]
    if Q:
        y += np.diff(rng.normal(0.0, Q, n + 1)) * rate_hz
    return y


def simulate_arma(phi, theta, sigma2: float, n: int, rng: np.random.Generator,
                  burn_in: int = 2000) -> np.ndarray:
    """x(k) = Σ φ_i x(k−i) + w(k) + Σ θ_j w(k−j), w ~ N(0, σ²) (seed 000 (11)); burn-in dropped."""
    w = rng.normal(0.0, np.sqrt(sigma2), n + burn_in)
    x = signal.lfilter(np.r_[1.0, np.asarray(theta, float)], np.r_[1.0, -np.asarray(phi, float)], w)
    return x[burn_in:]
