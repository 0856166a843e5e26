"""The record's lowest frequencies: detrended cosine coefficients, in octave bands.

The Welch PSD of :mod:`budget.gap.signatures` starts at bin 4 of its segments (≈ 0.024 Hz for a
one-hour log at 100 Hz) and the Allan variance stops at τ ≈ N·dt/4 with 2–5 degrees of freedom
at its last octave. What lies between (periods from ≈ 40 s to the record length) is where a rate
random walk (PSD ∝ f⁻²) stands out from bias instability (∝ f⁻¹), and both estimators see it
poorly. This module reads it off the whole record at once:

* the series (rad/s or m/s², N samples, step dt) minus its least-squares line a + b·t (the
  line belongs to the time-slope statistic, so a rate ramp leaves these coefficients alone);
* its orthonormal DCT-II coefficients c_k = Σ_j a_k(j)·x_j, a_k the DCT-II basis vector
  √(2/N)·cos(πk(j + ½)/N) made orthogonal to 1 and t, for k = 2 … k_max: frequencies
  f_k = k/(2N·dt) below the first Welch band (k = 1 is dropped: the line removes 99.6 % of
  it). The DCT is the Karhunen–Loève basis of a random walk with free ends (Ahmed, Natarajan
  & Rao 1974, IEEE Trans. Comput. C-23, 90–93; Strang 1999, SIAM Rev. 41, 135–147), so for
  red and white spectra alike the c_k are nearly independent zero-mean Gaussians;
* for a stationary term of one-sided PSD S(f), E c_k² ≈ S(f_k)/(2·dt) (white noise of
  variance σ²: E c_k² = σ²) — within 10 % at k = 2 and 2 % from k = 9 for the bias-instability
  bank, checked against the exact quadratic form; the random walk is done exactly
  (:func:`random_walk_low`);
* octave bands k ∈ [2, 4), [4, 8), … ; a band's statistic is the mean c̄² of its n coefficients.

**Score.** With the model's expectation ĉ² taken from S realizations, c̄²_meas/ĉ² is the ratio
of a χ²_ν/ν to an independent χ²_{Sν}/(Sν) (independent Gaussian coefficients of nearly equal
variance within an octave: ν = n, an upper bound that the spread of E c_k² over one octave
lowers by ≤ 4 % for a flicker spectrum), i.e. F(ν, S·ν), and the band's z is the normal score
of that F probability (exact in the tails, unlike a log-normal approximation of a χ² with 2–8
degrees of freedom). When an effect's expected increment Δ is added to the S-realization mean m,
the denominator is m + Δ with only m random: its degrees of freedom become S·ν·((m + Δ)/m)²
(Satterthwaite 1946, Biometrics Bull. 2, 110–114).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import scipy.fft as sfft
from scipy import special

#: Lowest DCT index used (k = 1 is nearly the removed line itself).
FIRST_K = 2


def low_k_max(n_samples: int, first_welch_hz: float, dt_s: float) -> int:
    """Largest k with f_k = k/(2N·dt) below ``first_welch_hz`` (the first Welch band)."""
    return int(math.ceil(2.0 * n_samples * dt_s * first_welch_hz)) - 1


def band_starts(k_max: int) -> np.ndarray:
    """Indices (into k = FIRST_K … k_max) where each octave band starts; a last band shorter
    than half the one before it joins that one."""
    starts, k = [], FIRST_K
    while k <= k_max:
        starts.append(k)
        k *= 2
    if len(starts) > 1 and (k_max + 1 - starts[-1]) < 0.5 * (starts[-1] - starts[-2]):
        starts.pop()
    return np.array(starts, dtype=np.int64) - FIRST_K


def detrended(x: np.ndarray) -> np.ndarray:
    """``x`` minus its least-squares line in the sample index."""
    x = np.asarray(x, float)
    n = x.size
    t = np.arange(n) - 0.5 * (n - 1)
    y = x - x.mean()
    return y - (np.dot(t, y) / np.dot(t, t)) * t


def coefficients_sq(x: np.ndarray, k_max: int) -> np.ndarray:
    """c_k² for k = FIRST_K … k_max (unit², see module docstring)."""
    c = sfft.dct(detrended(x), type=2, norm="ortho")
    return c[FIRST_K:k_max + 1] ** 2


def frequencies(n_samples: int, dt_s: float, k_max: int) -> np.ndarray:
    """f_k = k/(2N·dt) in Hz for k = FIRST_K … k_max."""
    return np.arange(FIRST_K, k_max + 1) / (2.0 * n_samples * dt_s)


def from_psd(psd: np.ndarray, dt_s: float) -> np.ndarray:
    """E c_k² of a stationary term from its one-sided PSD at f_k: S(f_k)/(2·dt)."""
    return np.asarray(psd, float) / (2.0 * dt_s)


def band_means(values: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Mean over each band of per-coefficient values (works on (..., K) arrays)."""
    sums = np.add.reduceat(values, starts, axis=-1)
    counts = np.diff(np.append(starts, values.shape[-1]))
    return sums / counts


@lru_cache(maxsize=8)
def _random_walk_low(n_samples: int, dt_s: float, k_max: int) -> np.ndarray:
    n = int(n_samples)
    k = np.arange(FIRST_K, k_max + 1, dtype=float)
    half = np.sin(0.5 * math.pi * k / n)
    # R_u(i) = Σ_{j≥i} u_k(j) = −√(2/N)·sin(πki/N)/(2 sin(πk/2N)); Σ_i R_u² = 1/(4 sin²(πk/2N))
    ru2 = 0.25 / half ** 2
    i = np.arange(1, n, dtype=float)
    rt = 0.5 * (n - i) * i                       # Σ_{j≥i} (j − (N−1)/2)
    # Σ_i sin(πki/N)·R_t(i) for every k at once (DST-I: y_{k−1} = 2 Σ_i x_i sin(πki/N))
    s_rt = 0.5 * sfft.dst(rt, type=1)[FIRST_K - 1:k_max]
    ru_rt = -math.sqrt(2.0 / n) / (2.0 * half) * s_rt
    tc = np.arange(n) - 0.5 * (n - 1)
    beta = sfft.dct(tc, type=2, norm="ortho")[FIRST_K:k_max + 1] / (n * (n * n - 1.0) / 12.0)
    rt2 = float(np.dot(rt, rt))
    a2 = ru2 - 2.0 * beta * ru_rt + beta ** 2 * rt2
    out = dt_s * np.clip(a2, 0.0, None)
    out.setflags(write=False)
    return out


def random_walk_low(n_samples: int, dt_s: float, k_max: int) -> np.ndarray:
    """Exact E c_k² of a discrete rate random walk b_j = b_{j−1} + K·√dt·w_j with K = 1.

    c_k = Σ_j a_k(j)·b_j = K√dt·Σ_i w_i·A_k(i) with A_k(i) = Σ_{j≥i} a_k(j), so
    E c_k² = K²·dt·Σ_i A_k(i)² — the tail-sum form of
    :func:`budget.gap.theory.random_walk_weight` — evaluated in closed form for the DCT vector
    and the line it is made orthogonal to (one DST-I and one DCT, O(N log N))."""
    return _random_walk_low(int(n_samples), float(dt_s), int(k_max))


def sinusoid_low(n_samples: int, dt_s: float, k_max: int, frequency_hz: float) -> np.ndarray:
    """Exact E c_k² of A·sin(2πft + φ), φ uniform, A = 1: ½(C_k² + S_k²), C and S the
    coefficients of the detrended cosine and sine."""
    t = np.arange(n_samples) * dt_s
    w = 2.0 * math.pi * frequency_hz * t
    return 0.5 * (coefficients_sq(np.cos(w), k_max) + coefficients_sq(np.sin(w), k_max))


def band_z(meas: np.ndarray, model: np.ndarray, base: np.ndarray, counts: np.ndarray,
           n_real: int) -> np.ndarray:
    """Normal scores of the band ratios meas/model under F(ν, S·ν·(model/base)²), ν = n.

    ``meas``/``model``: band means of c² (measured; the model's S-realization mean plus any
    predicted increment); ``base``: the S-realization part of ``model``."""
    nu1 = counts.astype(float)
    frac = np.clip(np.asarray(model, float) / np.clip(base, 1e-300, None), 1.0, 1e6)
    nu2 = n_real * nu1 * frac ** 2
    ratio = np.clip(np.asarray(meas, float) / np.clip(model, 1e-300, None), 1e-300, 1e300)
    lower = special.fdtr(nu1, nu2, ratio)
    upper = special.fdtrc(nu1, nu2, ratio)
    with np.errstate(divide="ignore"):
        # beyond double range the tails fall as r^(−ν₂/2) (upper) and rise as r^(ν₁/2) (lower)
        log_up = np.where(upper > 0, np.log(upper), -0.5 * nu2 * np.log(ratio))
        log_lo = np.where(lower > 0, np.log(lower), 0.5 * nu1 * np.log(ratio))
    return np.where(lower < 0.5, special.ndtri_exp(np.minimum(log_lo, 0.0)),
                    -special.ndtri_exp(np.minimum(log_up, 0.0)))
