"""A Gauss–Markov term named on a slow part that is two-valued: a random telegraph signal.

A bias that flips between ±a at Poisson times of rate λ (random telegraph, popcorn or burst
noise) has the autocovariance a²·e^(−2λ|t|) of a Gauss–Markov term of σ = a, τ_c = 1/(2λ): the
same Lorentzian spectrum, so every spectral statistic of the workflow (Allan deviation, PSD)
names it ``gauss_markov`` — and the registry has no telegraph effect. What tells the two apart
is the distribution of the slow part: a Gaussian's excess kurtosis is 0, a two-valued signal's
−2 (with white noise of variance s² on top, −2·a⁴/(a² + s²)²).

After the run, for every ``gauss_markov`` step this module forms the record's slow part on that
channel — block means over τ_c/2 of the linearly detrended record — and its excess kurtosis,
and compares it with the same statistic on realizations of the *updated* model (which holds
the Gauss–Markov term, so the sampling scatter of a correlated slow part with few
correlation times in the record is the model's own). When the record's value lies below every
realization and more than :data:`Z_LIMIT` standard deviations below their mean, the report
says so in a note: the spectrum is explained, the shape is not — when the kurtosis is also at or
below :data:`KURTOSIS_LIMIT` (an effect size, not only a significance) and the blocks hold at
least :data:`MIN_BLOCK_SAMPLES` samples.
"""

from __future__ import annotations

import numpy as np
from scipy import signal, stats

from ..imu import NoiseModel
from .simulate import model_statistic

#: Realizations of the updated model behind the null of the slow part's kurtosis.
REALIZATIONS = 32
#: How far (in the realizations' standard deviations) below their mean the record must lie.
Z_LIMIT = 3.0
#: Fewest blocks for the statistic to be formed.
MIN_BLOCKS = 32
#: Fewest samples per block: below it the "slow part" is the samples themselves, whose
#: distribution carries the white noise and the output's lattice (quantization), not the
#: Gauss–Markov term (on the real ADIS16405 gyro_z a τ_c = 0.021 s term — the output's
#: decimation filter — gave one-sample blocks and a kurtosis of −0.29 from the lattice).
MIN_BLOCK_SAMPLES = 8
#: Largest excess kurtosis called two-valued, an effect size beside the significance (on 10⁶
#: samples a kurtosis of −0.05 is already many standard deviations from 0): a bias switching
#: between ±a under a Gaussian slow part of variance s² gives −2a⁴/(a² + s²)², so −0.5 means the
#: two-valued part holds at least half the slow part's variance (a² ≥ s²).
KURTOSIS_LIMIT = -0.5


def slow_kurtosis(x: np.ndarray, block: int) -> float:
    """Excess kurtosis of the block means (``block`` samples) of the linearly detrended ``x``."""
    x = signal.detrend(np.asarray(x, float), type="linear")
    nb = x.size // block
    means = x[:nb * block].reshape(nb, block).mean(axis=1)
    return float(stats.kurtosis(means, fisher=True, bias=True))


def check(model: NoiseModel, channel: str, x: np.ndarray, rate_hz: float, tau_s: float, seed: int,
          true_value: float = 0.0, temp_c=None) -> dict | None:
    """The slow part's kurtosis on ``channel`` against ``model``'s (the updated model, holding the
    Gauss–Markov term of ``tau_s``): a dict (measured, model mean and sd, z, block seconds,
    realizations, two_valued) or None when the record has fewer than :data:`MIN_BLOCKS` blocks
    or a block fewer than :data:`MIN_BLOCK_SAMPLES` samples (τ_c too short for a slow part)."""
    block = max(1, int(round(0.5 * tau_s * rate_hz)))
    n = np.asarray(x).size
    if n // block < MIN_BLOCKS or block < MIN_BLOCK_SAMPLES:
        return None
    meas = slow_kurtosis(x, block)
    sims, mean, sd = model_statistic(model, channel, lambda s: slow_kurtosis(s, block), n, rate_hz, seed,
                                     "gap_two_valued", REALIZATIONS, true_value=true_value, temp_c=temp_c)
    z = (meas - mean) / sd if sd > 0 else 0.0
    return {"channel": channel, "tau_s": float(tau_s), "block_s": block / rate_hz,
            "kurtosis": meas, "model_mean": mean, "model_sd": sd, "z": float(z),
            "realizations": REALIZATIONS,
            "two_valued": bool(z < -Z_LIMIT and meas < float(sims.min()) and meas <= KURTOSIS_LIMIT)}


def note(found: dict) -> str:
    return (f"{found['channel']}: the Gauss–Markov term (τ_c = {found['tau_s']:.3g} s) fits the spectrum, "
            f"but the slow part is two-valued: excess kurtosis {found['kurtosis']:.2f} of its "
            f"{found['block_s']:.3g}-s means where the updated model gives {found['model_mean']:.2f} ± "
            f"{found['model_sd']:.2f} ({found['realizations']} realizations, z = {found['z']:.1f}; a "
            "Gaussian slow part has 0, a bias switching between two levels −2) — a random telegraph "
            "(popcorn, burst) signal has this spectrum; the registry has no such effect, so the "
            "Gauss–Markov term is the nearest it has, right in its spectrum and wrong in its distribution")
