"""Expected signature increments of each vocabulary effect, in closed form (SI channel units).

Every effect of the shared vocabulary is an independent additive term (quantization only
approximately), so its *expected* contribution adds to the model's signatures:

* Allan variance at τ = m·dt (overlapping estimator, point-sampled rate data):

  - white noise N: N²/τ (IEEE Std 952 Annex C);
  - quantization Q of the integrated output (white angle/velocity noise of variance Q²):
    3Q²/τ²;
  - Gauss–Markov (σ, τc), φ = e^(−dt/τc), exact for the sampled process:
    σ²/m²·[m + (2φ(m(1−φ) − (1−φᵐ)) − φ(1−φᵐ)²)/(1−φ)²]  (from AVAR = Var(ȳ) − Cov(ȳ₁, ȳ₂)
    with the geometric sums of the AR(1) autocovariance σ²φ^|k|);
  - bias instability B: the same sum over the generator's Gauss–Markov bank
    (:func:`budget.imu.flicker.flicker_bank`), ≈ (2 ln2/π)·B² in the band;
  - rate random walk K (b_n = b_{n−1} + K√dt·w_n): K²·dt·(2m² + 1)/(6m) → K²τ/3;
  - rate ramp R: R²τ²/2;
  - sinusoid (A, f), random phase: A²·sin⁴(πfτ)/(m·sin(πf·dt))² → A² sin⁴(πfτ)/(πfτ)²;
  - outliers (rate p, magnitude M): white with per-sample variance pM²: pM²·dt/τ;
  - temperature sensitivity c: c²·AVAR(T) of the temperature series (deterministic).

* Welch PSD (one-sided, Hann window, 50 % overlap, segment mean removed; ``scipy.signal.welch``
  density scaling P = 2|X|²/(fs·Σw²)): white 2N²; quantization 8Q²·sin²(πf·dt)/dt; AR(1)
  2σ²(1−φ²)·dt/|1 − φe^(−2πif·dt)|²; random walk 2K²dt²/(4 sin²(πf·dt)); sinusoid
  (A²/2)(|Ŵ(f−f0)|² + |Ŵ(f+f0)|²)/(fs·Σw²) with Ŵ the window's transform; the ramp and the
  temperature series through the estimator itself (they are deterministic).

* First differences d_k = x_k − x_{k−1} (for the kurtosis and tail statistics): added variance
  and fourth cumulant — white 2N²/dt, 0; quantization 6Q²/dt², −0.6·var²; AR(1) 2σ²(1−φ), 0;
  random walk K²dt, 0; sinusoid 2A² sin²(πf·dt), −1.5·var²; outliers 2pM², 2pM⁴ − 6p²M⁴.

* Low-frequency coefficients (:mod:`budget.gap.lowfreq`, DCT of the detrended record below the
  first Welch band): a stationary term adds S(f_k)/(2·dt) to E c_k² (with the PSDs above,
  evaluated at f_k = k/(2N·dt)); the random walk exactly (tail sums in closed form); a tone
  exactly (its detrended cosine and sine); the ramp nothing (the line is removed); the
  temperature series its own c_k²·c²; the output filter S_model·(|H(f_k)|² − 1).

* Regression statistics (time slope, temperature coefficient): the variance a random walk,
  a Gauss–Markov term or the bias-instability bank adds (:mod:`budget.gap.regression_var`).

* ``lowpass`` (first-order output filter, |H(f)|² in :func:`budget.imu.effects.lowpass_gain2`)
  is not additive: it multiplies the model's PSD, ΔS = S_model·(|H|² − 1), and the Allan
  variance and difference variance follow from ΔS through their discrete-time kernels
  (:func:`avar_from_psd`, :func:`diff_var_from_psd`).

* ``vibration`` (resonator of rms σ): AVAR exact from its AR(2) autocorrelation, PSD σ² times
  the resonator's, difference variance 2σ²(1 − ρ(1)); ``heavy_tailed`` (Student t of density
  N): white-noise AVAR and PSD, difference variance 2N²/dt, fourth cumulant and tail counts of
  the differences from the t distribution (:func:`student_t_cum4`, :func:`student_t_tails`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import signal, special, stats

from ..imu.flicker import flicker_bank


@dataclass(frozen=True)
class Increment:
    """Expected change of a channel's signatures caused by one added effect.

    ``avar``: Δσ² at the grid's τ; ``psd``: ΔS at the Welch bins (``None`` without a PSD);
    ``diff_var``/``diff_cum4``: variance and fourth cumulant added to first differences;
    ``slope``/``temp``: shift of the time / temperature regression coefficients and
    ``slope_var``/``temp_var`` the variance they add (random walk only; 0 otherwise);
    ``outliers``: (rate, magnitude) for the tail-count prediction, else ``None``; ``low``:
    ΔE c_k² of the low-frequency coefficients (:mod:`budget.gap.lowfreq`; ``None``: no change);
    ``walk_cov``: covariance added to the record's slowest modes (:mod:`budget.gap.walk`;
    ``None``: not yet computed, :meth:`budget.gap.fitting.Candidate.full_increment` fills it);
    ``walk_mean``: mean added to those modes (a thermal lag's or a warm-up transient's response;
    ``None``: zero).
    """

    avar: np.ndarray
    psd: np.ndarray | None = None
    diff_var: float = 0.0
    diff_cum4: float = 0.0
    slope: float = 0.0
    temp: float = 0.0
    slope_var: float = 0.0
    temp_var: float = 0.0
    outliers: tuple[float, float] | None = None
    tails: tuple[float, float] | None = None   # predicted (tail count, tail2 count), if known
    low: np.ndarray | None = None
    walk_cov: np.ndarray | None = None
    walk_mean: np.ndarray | None = None


# --- Allan variance shapes (amplitude 1) --------------------------------------------------

def avar_gm(m: np.ndarray, dt_s: float, tau_c_s) -> np.ndarray:
    """Exact AVAR of point-sampled unit-variance Gauss–Markov processes, shape (len(tau_c), len(m)).

    Closed form in the module docstring; for m·dt/τc < 1e-5 the first-order series
    σ²·(dt/τc)·(2m² + 1)/(3m) replaces it (the closed form loses digits there).
    """
    m = np.asarray(m, dtype=float)[None, :]
    a = dt_s / np.atleast_1d(np.asarray(tau_c_s, dtype=float))[:, None]
    eps = -np.expm1(-a)                 # 1 − φ
    phi = 1.0 - eps
    e_m = -np.expm1(-a * m)             # 1 − φᵐ
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        closed = (m + (2.0 * phi * (m * eps - e_m) - phi * e_m ** 2) / eps ** 2) / m ** 2
    series = a * (2.0 * m ** 2 + 1.0) / (3.0 * m)
    out = np.where(a * m < 1e-5, series, closed)
    return np.clip(out, 0.0, None)


@lru_cache(maxsize=32)
def _flicker_shapes(m_key: tuple, dt_s: float, n_samples: int, nperseg: int | None):
    m = np.asarray(m_key, dtype=float)
    tau, var = flicker_bank(1.0, dt_s, dt_s * (n_samples - 1))
    avar = (var[:, None] * avar_gm(m, dt_s, tau)).sum(axis=0)
    psd = None
    if nperseg:
        f = np.fft.rfftfreq(nperseg, dt_s)
        psd = sum(v * psd_gm(f, dt_s, t) for t, v in zip(tau, var))
    return avar, psd


def avar_flicker(m, dt_s: float, n_samples: int) -> np.ndarray:
    """AVAR of the generator's bias-instability bank for B = 1 (≈ 2 ln2/π in the band)."""
    return _flicker_shapes(tuple(int(v) for v in m), dt_s, int(n_samples), None)[0]


def psd_flicker(nperseg: int, dt_s: float, n_samples: int, m) -> np.ndarray:
    """One-sided PSD of the bias-instability bank for B = 1 at the Welch bins."""
    return _flicker_shapes(tuple(int(v) for v in m), dt_s, int(n_samples), int(nperseg))[1]


def avar_rrw(m, dt_s: float) -> np.ndarray:
    """AVAR of a discrete rate random walk with K = 1: dt·(2m² + 1)/(6m)."""
    m = np.asarray(m, dtype=float)
    return dt_s * (2.0 * m ** 2 + 1.0) / (6.0 * m)


def avar_sinusoid(m, dt_s: float, frequency_hz: float) -> np.ndarray:
    """AVAR of A·sin(2πft + φ), φ uniform, for A = 1: sin⁴(πfτ)/(m·sin(πf·dt))²."""
    m = np.asarray(m, dtype=float)
    x = math.pi * frequency_hz * dt_s
    return np.sin(x * m) ** 4 / (m * math.sin(x)) ** 2


# --- PSD shapes (one-sided, Welch density scaling) ------------------------------------------

def welch_freqs(nperseg: int, dt_s: float) -> np.ndarray:
    return np.fft.rfftfreq(nperseg, dt_s)


def psd_gm(freq_hz: np.ndarray, dt_s: float, tau_c_s: float) -> np.ndarray:
    """One-sided PSD of a unit-variance sampled AR(1) with φ = e^(−dt/τc)."""
    phi = math.exp(-dt_s / tau_c_s)
    w = 2.0 * math.pi * np.asarray(freq_hz) * dt_s
    den = 1.0 - 2.0 * phi * np.cos(w) + phi ** 2
    return 2.0 * (1.0 - phi ** 2) * dt_s / den


def psd_quantization(freq_hz: np.ndarray, dt_s: float) -> np.ndarray:
    """One-sided PSD of the rate error of white angle quantization with Q = 1."""
    return 8.0 * np.sin(math.pi * np.asarray(freq_hz) * dt_s) ** 2 / dt_s


def psd_rrw(freq_hz: np.ndarray, dt_s: float) -> np.ndarray:
    """One-sided PSD of a discrete random walk with K = 1 (0 at f = 0)."""
    s = np.sin(math.pi * np.asarray(freq_hz) * dt_s) ** 2
    with np.errstate(divide="ignore"):
        out = np.where(s > 0, 2.0 * dt_s ** 2 / (4.0 * s), 0.0)
    return out


@lru_cache(maxsize=8)
def _hann(nperseg: int) -> np.ndarray:
    w = signal.get_window("hann", nperseg)
    w.setflags(write=False)
    return w


def _window_transform(nu_hz: np.ndarray, nperseg: int, dt_s: float) -> np.ndarray:
    """|Ŵ(ν)|² of the periodic Hann window of length L (closed form via geometric sums)."""
    L = nperseg
    w0 = 2.0 * math.pi * np.asarray(nu_hz) * dt_s

    def dirichlet(w):
        num = -np.expm1(-1j * w * L)
        den = -np.expm1(-1j * w)
        small = np.abs(den) < 1e-12
        return np.where(small, L + 0j, num / np.where(small, 1.0, den))

    step = 2.0 * math.pi / L
    win = 0.5 * dirichlet(w0) - 0.25 * dirichlet(w0 - step) - 0.25 * dirichlet(w0 + step)
    return np.abs(win) ** 2


def psd_sinusoid(freq_hz: np.ndarray, nperseg: int, dt_s: float, f0_hz: float) -> np.ndarray:
    """Expected Welch PSD of a random-phase sinusoid of amplitude 1 at ``f0_hz``."""
    w = _hann(nperseg)
    norm = (1.0 / dt_s) * float(np.sum(w ** 2))
    k = (_window_transform(freq_hz - f0_hz, nperseg, dt_s)
         + _window_transform(freq_hz + f0_hz, nperseg, dt_s))
    out = 2.0 * 0.25 * k / norm
    out[0] *= 0.5  # scipy does not double the DC bin
    if nperseg % 2 == 0:
        out[-1] *= 0.5  # nor the Nyquist bin
    return out


def psd_of_series(y: np.ndarray, dt_s: float, nperseg: int) -> np.ndarray:
    """Welch PSD of a deterministic series through the same estimator as the signatures."""
    return signal.welch(np.asarray(y, float), fs=1.0 / dt_s, nperseg=nperseg, detrend="constant")[1]


def psd_ramp(nperseg: int, dt_s: float, n_samples: int) -> np.ndarray:
    """Welch PSD of a unit ramp t (every segment holds the same mean-removed ramp)."""
    n_seg = 1 + (n_samples - nperseg) // (nperseg // 2)
    y = np.arange(nperseg // 2 * (n_seg - 1) + nperseg) * dt_s
    return psd_of_series(y, dt_s, nperseg)


def random_walk_weight(weights: np.ndarray, dt_s: float) -> float:
    """var(Σ w_k b_k) of a random walk with K = 1: dt·Σ_k (Σ_{j≥k} w_j)² (regression weights w)."""
    tail = np.cumsum(weights[::-1])[::-1]
    return float(dt_s * np.einsum("i,i->", tail, tail))


def _sum_weights(freq_hz: np.ndarray, dt_s: float) -> float:
    return 1.0 / (dt_s * 2.0 * (freq_hz.size - 1))  # bin width of a one-sided rfft grid


def avar_from_psd(psd: np.ndarray, freq_hz: np.ndarray, m, dt_s: float) -> np.ndarray:
    """Allan variance at τ = m·dt of a sampled series with one-sided PSD ``psd`` on the rfft
    grid ``freq_hz``: Σ S(f)·2 sin⁴(πfm·dt)/(m² sin²(πf·dt))·Δf (the transfer function of the
    difference of two adjacent m-sample means; white S = 2σ²dt gives σ²/m)."""
    f = np.asarray(freq_hz, float)[1:]
    m = np.asarray(m, float)[:, None]
    x = math.pi * f * dt_s
    kern = 2.0 * np.sin(m * x) ** 4 / (m * m * np.sin(x) ** 2)
    return kern @ np.asarray(psd, float)[1:] * _sum_weights(np.asarray(freq_hz), dt_s)


def diff_var_from_psd(psd: np.ndarray, freq_hz: np.ndarray, dt_s: float) -> float:
    """Variance of the first differences: Σ S(f)·4 sin²(πf·dt)·Δf."""
    f = np.asarray(freq_hz, float)
    return float(np.sum(np.asarray(psd) * 4.0 * np.sin(math.pi * f * dt_s) ** 2)
                 * _sum_weights(f, dt_s))


# --- band-limited vibration and heavy-tailed white noise -----------------------------------

def avar_vibration(m, dt_s: float, center_hz: float, width_hz: float) -> np.ndarray:
    """AVAR of the unit-variance resonator (:func:`budget.imu.effects.vibration`), exact: its
    autocorrelation is ρ(k) = Re(C·z^|k|) with z = r·e^(iω0), C = −i·e^(iψ)/sin ψ
    (:func:`budget.imu.effects.vibration_acov`), and AVAR is linear in ρ, so it is Re(C·A(z))
    with A the Gauss–Markov closed form of :func:`avar_gm` evaluated at the complex φ = z."""
    m = np.asarray(m, dtype=float)
    r = math.exp(-math.pi * width_hz * dt_s)
    w0 = 2.0 * math.pi * center_hz * dt_s
    psi = math.atan2((1.0 + r * r) * math.sin(w0), (1.0 - r * r) * math.cos(w0))
    z = r * complex(math.cos(w0), math.sin(w0))
    c = -1j * complex(math.cos(psi), math.sin(psi)) / math.sin(psi)
    zm = z ** m
    a = (m + (2.0 * z * (m * (1.0 - z) - (1.0 - zm)) - z * (1.0 - zm) ** 2) / (1.0 - z) ** 2) / m ** 2
    return np.clip((c * a).real, 0.0, None)


@lru_cache(maxsize=64)
def _t_grid(nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Quadrature nodes v and weights pdf(v)·Δv of Student t(ν) on a sinh-spaced grid reaching
    ±10⁶ (the tails matter: they are what is measured)."""
    u = np.linspace(-16.0, 16.0, 4001)
    v = np.sinh(u)
    w = stats.t.pdf(v, nu) * np.cosh(u) * (u[1] - u[0])
    v.setflags(write=False)
    w.setflags(write=False)
    return v, w


def student_t_tails(nu: float, scale: float, base_var: float, limit: float) -> float:
    """P(|d| > limit) for first differences d = g + s·(t₁ − t₂) of Student-t(ν) white noise of
    scale s on Gaussian differences g of variance ``base_var``. A large difference comes from
    one large t (sub-exponential tails), so P ≈ 2·P(|s·t₁ + y| > L) − P(|y′| > L): y ~ N(0, v₀)
    stands for g − s·t₂ with the variance of its core, v₀ = base_var + (c_ν·s)² (c_ν: the
    robust scale of t in σ units), and y′ ~ N(0, v₀ + (c_ν·s)²) is the case with no large t,
    counted twice by the first term. The expectation over t₁ by quadrature (:func:`_t_grid`)."""
    c_nu = float(stats.t.ppf(0.75, nu) / stats.norm.ppf(0.75))
    core = (c_nu * scale) ** 2
    sy = math.sqrt(base_var + core)
    v, w = _t_grid(float(nu))
    x = scale * v
    one = float(np.dot(w, special.ndtr((x - limit) / sy) + special.ndtr((-limit - x) / sy)))
    both = 2.0 * stats.norm.sf(limit / math.sqrt(base_var + 2.0 * core))
    return float(min(max(2.0 * one - both, 0.0), 1.0))


def student_t_cum4(nu: float, n_samples: int) -> float:
    """Fourth cumulant of a unit-scale Student-t(ν) sample as a record of N samples sees it:
    the fourth moment truncated at the expected largest |t| (t_ν quantile 1 − 1/(2N)), so ν ≤ 4
    (infinite population kurtosis) still gives the finite value a record shows."""
    top = float(stats.t.isf(0.5 / n_samples, nu))
    v, w = _t_grid(float(nu))
    m4 = float(np.dot(w, np.where(np.abs(v) <= top, v ** 4, 0.0)))
    var = nu / (nu - 2.0)
    return m4 - 3.0 * var * var
