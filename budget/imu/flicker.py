"""Bias instability as a documented bank of Gauss–Markov terms, and exact stationary synthesis.

Flicker (1/f) bias instability
------------------------------
IEEE Std 952 defines bias instability by the two-sided rate PSD S(f) = B²/(2π f) (one-sided
B²/(π f); the same convention in which white noise of density N has S = N²), whose Allan
deviation is flat at B·√(2 ln 2/π) ≈ 0.664·B. We approximate the 1/f PSD by a sum of
first-order Gauss–Markov (GM) terms with correlation times τ_k on a geometric grid of ratio r
(``BRANCHES_PER_DECADE`` per decade) from ``τ_lo = dt/2`` to ``τ_hi = max(10·record, 10·dt)``.
Each GM term of variance σ² has one-sided PSD 4σ²τ/(1 + (2πfτ)²); summed over a log-grid of τ
it gives ≈ σ²/(f·ln r), so equal variances σ² = B²·ln r/π reproduce B²/(πf) inside the
band. The Allan deviation is then 0.664·B within ±1 % for averaging times from 3·dt to
≈τ_hi/20 = record/2 (2 % high at 2·dt, 9 % at dt; checked with :func:`avar_from_acov` in the
tests). Below f ≈ 1/(2π τ_hi) the PSD flattens: the slowest terms act as a random constant
plus a slow drift over the record.

Exact synthesis
---------------
A sum of decaying exponentials is a convex, decreasing, non-negative autocovariance, for which
the circulant embedding of Davies & Harte (1987) is non-negative definite (Craigmile 2003), so
any stationary Gaussian process with such a covariance (flicker bank + ``gauss_markov`` effects)
is drawn *exactly* — stationary from the first sample — with one FFT per pair of trials.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import scipy.fft as sfft

#: GM terms per decade of correlation time (3 → Allan-deviation ripple below 0.1 %).
BRANCHES_PER_DECADE = 3
#: τ_hi = FLICKER_SPAN_RECORDS × record duration (at least 10·dt).
FLICKER_SPAN_RECORDS = 10.0


def flicker_bank(b_coeff: float, dt_s: float, duration_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Correlation times (s) and variances of the GM bank that models IEEE bias instability B.

    Returns ``(tau_s, variance)``, each of shape (K,); variance in (channel unit)².
    """
    tau_lo = 0.5 * dt_s
    tau_hi = max(FLICKER_SPAN_RECORDS * duration_s, 10.0 * dt_s)
    n = int(math.ceil(math.log10(tau_hi / tau_lo) * BRANCHES_PER_DECADE)) + 1
    tau = np.geomspace(tau_lo, tau_hi, n)
    ratio = (tau_hi / tau_lo) ** (1.0 / (n - 1))
    var = np.full(n, b_coeff**2 * math.log(ratio) / math.pi)
    return tau, var


def gm_acov(lags: np.ndarray, dt_s: float, tau_s, variance) -> np.ndarray:
    """Autocovariance Σ σ_k²·exp(−|lag|·dt/τ_k) of a sum of point-sampled GM processes."""
    lags = np.abs(np.asarray(lags, dtype=float))
    tau = np.atleast_1d(np.asarray(tau_s, dtype=float))
    var = np.atleast_1d(np.asarray(variance, dtype=float))
    out = np.zeros(lags.shape)
    for t, v in zip(tau, var):
        out += v * np.exp(-lags * dt_s / t)
    return out


def _even_fast_len(n: int) -> int:
    m = sfft.next_fast_len(n)
    while m % 2:
        m = sfft.next_fast_len(m + 1)
    return m


def circulant_eigenvalues(acov_fn, n_samples: int) -> np.ndarray:
    """Eigenvalues (length L, even, L ≥ 2(n−1)) of the circulant embedding of ``acov_fn(lags)``.

    Raises ``ValueError`` if the embedding is not non-negative definite (cannot happen for sums
    of decaying exponentials, beyond round-off which is clipped).
    """
    size = _even_fast_len(max(2 * (n_samples - 1), 2))
    c = np.asarray(acov_fn(np.arange(size // 2 + 1)), dtype=float)
    row = np.concatenate([c, c[-2:0:-1]])
    lam = sfft.rfft(row).real
    lam = np.concatenate([lam, lam[-2:0:-1]])
    floor = -1e-9 * max(float(lam.max()), 1e-300)
    if lam.min() < floor:
        raise ValueError("circulant embedding is not non-negative definite for this covariance")
    return np.clip(lam, 0.0, None)


def stationary_gaussian(eigenvalues: np.ndarray, n_trials: int, n_samples: int,
                        rng: np.random.Generator) -> np.ndarray:
    """Draw ``n_trials`` independent stationary Gaussian series of length ``n_samples``.

    Davies–Harte: X = FFT(√(λ/L)·(Z₁ + iZ₂)); Re X and Im X are two independent exact draws,
    so trials are generated in pairs (trial 2i ← real part, 2i+1 ← imaginary part of row i).
    Returns shape (n_trials, n_samples).
    """
    size = eigenvalues.shape[0]
    pairs = (n_trials + 1) // 2
    z = rng.standard_normal((pairs, size, 2)).view(np.complex128)[..., 0]
    z *= np.sqrt(eigenvalues / size)
    x = sfft.fft(z, axis=-1, overwrite_x=True)
    out = np.empty((2 * pairs, n_samples))
    out[0::2] = x.real[:, :n_samples]
    out[1::2] = x.imag[:, :n_samples]
    return out[:n_trials]


@lru_cache(maxsize=64)
def coloured_eigenvalues(tau_s: tuple, variance: tuple, white_variance: float, dt_s: float,
                         n_samples: int) -> np.ndarray:
    """Cached circulant eigenvalues of a GM sum plus white noise of per-sample variance
    ``white_variance`` (adding δ_k keeps the covariance convex, so the embedding stays valid)."""
    def acov(k):
        return gm_acov(k, dt_s, tau_s, variance) + np.where(np.asarray(k) == 0, white_variance, 0.0)
    lam = circulant_eigenvalues(acov, n_samples)
    lam.setflags(write=False)
    return lam


def avar_from_acov(acov_fn, m: np.ndarray, dt_s: float) -> np.ndarray:
    """Exact Allan variance of a sampled stationary process at τ = m·dt from its autocovariance.

    AVAR(m) = Var(ȳ) − Cov(ȳ₁, ȳ₂) for adjacent means of m samples:
    (1/m²)·Σ_{|k|<m} (m−|k|)·[c(k) − c(k+m)].
    """
    m = np.atleast_1d(np.asarray(m, dtype=int))
    out = np.empty(m.shape, dtype=float)
    for i, mi in enumerate(m):
        k = np.arange(-(mi - 1), mi)
        w = mi - np.abs(k)
        out[i] = np.sum(w * (acov_fn(k) - acov_fn(k + mi))) / mi**2
    del dt_s  # the lag grid already carries the sampling interval
    return out
