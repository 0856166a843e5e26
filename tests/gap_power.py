"""The best any detector can do on the benchmark's logs: Neyman–Pearson power bounds.

For a hidden effect of known size on a channel whose base model is known exactly, the most
powerful test at false-positive rate α is the likelihood ratio of the two Gaussian hypotheses
(Neyman–Pearson lemma). Its power bounds what the model-gap workflow — which also fits the size,
tests several effects on six channels and so spends more than α — can reach on the same logs.

Built from the definitions of :mod:`gap_truth` only (no code of ``budget``):

* the log is cut into blocks of ``M`` samples and reduced to block sums; the effects judged here
  (rate random walk, rate ramp, temperature sensitivity) live below 1/(2·M·dt), where the base
  model's white noise is the same under both hypotheses, so the reduction loses almost nothing
  (checked by halving M);
* block-sum covariances in closed form: white noise σ²·M on the diagonal; the flicker of
  :func:`gap_truth.flicker` is a circular stationary process on a record 8× the log, whose
  autocovariance is exactly ``irfft(gain²)``, summed over block pairs with triangular weights;
  the random walk (a cumulative sum from t = 0) has Cov(S_i, S_j) = s²·(M³·min(i, j) + M²(M+1)/2)
  for i ≠ j and s²·(M³·i + M(M+1)(2M+1)/6) on the diagonal;
* the unknown bias is removed by projecting onto the contrasts of the block sums (orthogonal to
  a constant), as any detector must;
* random walk: a zero-mean covariance change, power by simulating the log-likelihood ratio under
  both hypotheses; ramp and temperature: a mean change d, power Φ(d − z₁₋α) (sign known) in closed
  form, with d² = Δμᵀ Σ₀⁻¹ Δμ; for the temperature also with a linear trend as a nuisance (a
  detector that must not read a ramp as a temperature effect projects the trend out, as the
  workflow's partial regression does).

The bounds are generous to the workflow: they know the magnitude and spend all of α on one test
of one channel.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.stats import norm

import gap_truth as gt


#: The effects whose bound is computed here (the others are seen 10/10 already).
BOUNDED = ("rate_random_walk", "rate_ramp", "temperature_sensitivity")


def flicker_autocovariance(n: int, b_coeff: float) -> np.ndarray:
    """Autocovariance c[0 … 8n−1] of :func:`gap_truth.flicker` (unit²): the generator shapes
    unit white noise by ``gain`` on a circular record of 8n samples, so c = irfft(gain²)."""
    size = 8 * n
    f = np.fft.rfftfreq(size, 1.0 / gt.RATE)
    gain2 = np.zeros_like(f)
    gain2[1:] = b_coeff ** 2 / (math.pi * f[1:]) / (2.0 / gt.RATE)
    return np.fft.irfft(gain2, size)


def stationary_block_cov(c: np.ndarray, n_blocks: int, m: int) -> np.ndarray:
    """Covariance (n_blocks, n_blocks) of sums over consecutive blocks of m samples of a
    stationary process with autocovariance c (circular, c[−d] = c[d])."""
    d = np.arange(-(m - 1), m)
    w = (m - np.abs(d)).astype(float)
    lag_cov = np.array([np.dot(w, c[(lag * m + d) % c.size]) for lag in range(n_blocks)])
    idx = np.abs(np.subtract.outer(np.arange(n_blocks), np.arange(n_blocks)))
    return lag_cov[idx]


def walk_block_cov(n_blocks: int, m: int, step_sigma: float) -> np.ndarray:
    """Covariance of block sums of W_t = step_sigma·Σ_{u ≤ t} e_u (e unit white, W_0 = e_0)."""
    i = np.arange(n_blocks, dtype=float)
    lo = np.minimum.outer(i, i)
    cov = m ** 3 * lo + m * m * (m + 1) / 2.0
    cov[np.diag_indices(n_blocks)] = m ** 3 * i + m * (m + 1) * (2 * m + 1) / 6.0
    return step_sigma ** 2 * cov


def contrasts(n_blocks: int, trend: bool = False) -> np.ndarray:
    """Orthonormal basis (n_blocks − 1, n_blocks) of the vectors orthogonal to a constant
    (``trend``: (n_blocks − 2, n_blocks), orthogonal to a linear trend too)."""
    i = np.arange(n_blocks, dtype=float)
    lead = [np.ones(n_blocks)] + ([i - i.mean()] if trend else [])
    q, _ = np.linalg.qr(np.column_stack(lead + [np.eye(n_blocks)[:, :n_blocks - len(lead)]]))
    return q[:, len(lead):].T


def base_block_cov(channel: str, n: int, m: int) -> np.ndarray:
    """Block-sum covariance of the base model's channel (white + flicker), unit²."""
    dens, floor = gt.base_levels(channel)
    nb = n // m
    cov = stationary_block_cov(flicker_autocovariance(n, floor / gt.FLOOR_PER_B), nb, m)
    cov[np.diag_indices(nb)] += (dens * math.sqrt(gt.RATE)) ** 2 * m
    return cov


def block_sums(x: np.ndarray, m: int) -> np.ndarray:
    nb = x.size // m
    return x[:nb * m].reshape(nb, m).sum(axis=1)


def mean_change_power(channel: str, profile: np.ndarray, m: int, alpha: float,
                      trend: bool = False) -> float:
    """Power of the most powerful test at level α for a known mean change ``profile`` (per
    sample, unit) added to the base channel, bias unknown (``trend``: a linear trend unknown
    too, as for a detector that must not take a ramp for the effect), sign known: Φ(d − z₁₋α)."""
    n = profile.size
    a = contrasts(n // m, trend)
    s0 = a @ base_block_cov(channel, n, m) @ a.T
    dmu = a @ block_sums(profile, m)
    d = math.sqrt(float(dmu @ np.linalg.solve(s0, dmu)))
    return float(norm.cdf(d - norm.ppf(1.0 - alpha)))


def walk_power(channel: str, n: int, step_sigma: float, m: int, alpha: float,
               rng: np.random.Generator, draws: int = 20000) -> float:
    """Power of the most powerful test at level α for a rate random walk of per-sample step
    ``step_sigma`` (unit) added to the base channel, bias unknown: the Gaussian log-likelihood
    ratio of the block-sum contrasts, its threshold and power from ``draws`` simulations each."""
    nb = n // m
    a = contrasts(nb)
    s0 = a @ base_block_cov(channel, n, m) @ a.T
    s1 = s0 + a @ walk_block_cov(nb, m, step_sigma) @ a.T
    l0, l1 = np.linalg.cholesky(s0), np.linalg.cholesky(s1)
    q = np.linalg.inv(s0) - np.linalg.inv(s1)   # LLR = ½ yᵀ q y + const

    def stat(chol):
        y = chol @ rng.standard_normal((chol.shape[0], draws))
        return np.einsum("ij,ij->j", y, q @ y)

    threshold = np.quantile(stat(l0), 1.0 - alpha)
    return float(np.mean(stat(l1) > threshold))


def effect_profile(name: str, n: int, ratio: float) -> tuple[str, np.ndarray | float]:
    """(channel, size) of a hidden effect sized to ``ratio`` as :func:`gap_truth.make` sizes it:
    the per-sample mean profile for ramp and temperature, the walk's step σ for the walk."""
    old = gt.RATIO
    gt.RATIO = ratio
    try:
        scale = gt.calibrate(name, n)
    finally:
        gt.RATIO = old
    channel, gen = gt.EFFECTS[name]
    if name == "rate_random_walk":
        return channel, scale / math.sqrt(gt.RATE)
    # the profiles of ramp and temperature are deterministic (the thermometer's own noise aside)
    y, _ = gen(n, np.random.default_rng(0), gt.temperature(n))
    return channel, scale * y


def power_bound(name: str, ratio: float, *, n: int = gt.ONE_HOUR, m: int = 1000, alpha: float = 0.02,
                rng: np.random.Generator | None = None, trend: bool = False) -> float:
    """Neyman–Pearson power at level α for ``name`` sized to ``ratio`` on an n-sample log
    (``trend``: with a linear trend as a nuisance, for the temperature sensitivity)."""
    channel, size = effect_profile(name, n, ratio)
    if name == "rate_random_walk":
        return walk_power(channel, n, float(size), m, alpha, rng or np.random.default_rng(0))
    return mean_change_power(channel, size, m, alpha, trend)
