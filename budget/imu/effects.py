"""Sample generators for the individual error effects (vectorised over trials, SI channel units).

Each function draws only from the ``numpy.random.Generator`` it is given. Conventions (IEEE Std
952, two-sided PSDs; ``dt`` = 1/rate):

* white noise of density N: independent samples of σ = N/√dt → ADEV N/√τ;
* rate random walk K: b_n = b_{n−1} + K·√dt·w_n, b_{−1} = 0 → ADEV K·√(τ/3);
* rate ramp R: R·t → ADEV R·τ/√2;
* sinusoid: A·sin(2πft + φ), φ uniform per trial → ADEV A·sin²(πfτ)/(πfτ);
* quantization Q: the *integrated* output (angle / velocity) is truncated to a quantum
  q = √12·Q, so the integrated error stays within one quantum and the ADEV is √3·Q/τ once the
  signal moves by more than q per sample;
* temperature sensitivity c: c·(T(t) − T(0)) (the offset at switch-on belongs to the turn-on bias);
* thermal lag τ_th: the same with the sensing element's temperature, which follows the logged
  temperature through a first-order lag (:func:`thermal_lag`);
* bias step A at t₀: A·H(t − t₀), the bias jumping once by A at t₀ s after the first sample
  (:func:`step_response`);
* outliers: each sample is hit with probability ``rate`` by a spike of ±``magnitude``
  (random sign).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import signal

#: Default temperature series when none is given: 25 °C at switch-on, warming 0.5 °C/min.
DEFAULT_TEMP_START_C = 25.0
DEFAULT_TEMP_RAMP_C_PER_S = 0.5 / 60.0


def default_temperature(time_s: np.ndarray) -> np.ndarray:
    """Linear warm-up T(t) = 25 °C + 0.5 °C/min · t (documented default), shape (N,)."""
    return DEFAULT_TEMP_START_C + DEFAULT_TEMP_RAMP_C_PER_S * time_s


def thermal_lag(temp_c: np.ndarray, tau_s: float, dt_s: float) -> np.ndarray:
    """T_e − T(0) of a sensing element whose temperature follows the logged one through a first-
    order lag: T_e,k = T_e,k−1 + a·(T_k − T_e,k−1), a = 1 − exp(−dt/τ), T_e,0 = T_0 (the log starts
    in thermal equilibrium; the exact discretisation for T held over each step, as
    ``lowpass``). ``temp_c`` (N,) or (T, N) in °C, along the last axis; °C."""
    temp = np.asarray(temp_c, float)
    a = -math.expm1(-dt_s / tau_s)
    return signal.lfilter([a], [1.0, a - 1.0], temp - temp[..., :1], axis=-1)


def warmup_response(tau_s: float, n_samples: int, dt_s: float) -> np.ndarray:
    """e^(−t/τ) of a turn-on transient at t = k·dt, k = 0 … n−1 from the record's (or the
    simulation's) first sample, shape (n,)."""
    return np.exp(-(np.arange(n_samples) * dt_s) / tau_s)


def step_response(time_s: float, n_samples: int, dt_s: float) -> np.ndarray:
    """H(t − t₀) of a bias step at t₀ = ``time_s`` after the first sample: 0 before, 1 from the
    first sample at or after t₀, at t = k·dt, k = 0 … n−1, shape (n,)."""
    return (np.arange(n_samples) * dt_s >= time_s).astype(float)


def mean_series(name: str, params: dict, n_samples: int, dt_s: float,
                temp_c: np.ndarray | None) -> np.ndarray | None:
    """The series (n,) a deterministic effect (``registry.DETERMINISTIC_EFFECTS``) adds to its
    channel, SI: R·t, A·e^(−t/τ), A·H(t − t₀), or c times the temperature response; ``None`` for
    a temperature effect without a temperature column (``temp_c`` (N,) or (T, N)). The one home
    of these series: the generator draws them (:mod:`budget.imu.registry`) and the model gap's
    statistics read their means from them (:mod:`budget.gap.regression_var`,
    :mod:`budget.gap.walk`)."""
    t = np.arange(n_samples) * dt_s
    if name == "rate_ramp":
        return params["R"] * t
    if name == "warmup_transient":
        return params["amplitude"] * warmup_response(params["tau_s"], n_samples, dt_s)
    if name == "bias_step":
        return params["amplitude"] * step_response(params["time_s"], n_samples, dt_s)
    if name in ("temperature_sensitivity", "temperature_lag"):
        if temp_c is None:
            return None
        return params["coefficient"] * temperature_response(name, params, temp_c, dt_s)
    raise ValueError(f"{name!r} is not a deterministic effect")


def temperature_response(name: str, params: dict, temp_c: np.ndarray, dt_s: float) -> np.ndarray:
    """The series a temperature effect's ``coefficient`` multiplies (°C): T − T(0) for
    ``temperature_sensitivity``, the lagged T_e − T(0) (:func:`thermal_lag`) for
    ``temperature_lag``; ``temp_c`` (N,) or (T, N), along the last axis."""
    if name == "temperature_lag":
        return thermal_lag(temp_c, params["tau_s"], dt_s)
    temp = np.asarray(temp_c, float)
    return temp - temp[..., :1]


def add_white(out: np.ndarray, density: np.ndarray, dt_s: float, rng: np.random.Generator,
              axes: list[int] | None = None) -> None:
    """Add white noise of per-axis density (unit/√Hz, one per entry of ``axes``, default all
    three) to ``out`` (T, N, 3)."""
    axes = [0, 1, 2] if axes is None else list(axes)
    buf = rng.standard_normal((*out.shape[:2], len(axes)))
    buf *= np.asarray(density) / math.sqrt(dt_s)
    if len(axes) == out.shape[2]:
        out += buf
    else:
        out[:, :, axes] += buf


def add_random_walk(out: np.ndarray, k_coeff: np.ndarray, dt_s: float, rng: np.random.Generator) -> None:
    """Add a rate random walk of per-axis coefficient K (shape (3,), unit/√s) to ``out`` (T, N, 3)."""
    buf = rng.standard_normal(out.shape)
    buf *= k_coeff * math.sqrt(dt_s)
    np.cumsum(buf, axis=1, out=buf)
    out += buf


def sinusoid(n_trials: int, time_s: np.ndarray, frequency_hz: float, amplitude: float,
             rng: np.random.Generator) -> np.ndarray:
    """A·sin(2πft + φ) with φ ~ U[0, 2π) per trial, shape (T, N)."""
    phase = rng.uniform(0.0, 2.0 * math.pi, n_trials)
    arg = 2.0 * math.pi * frequency_hz * time_s
    # sin(a + φ) = sin a·cos φ + cos a·sin φ: two outer products instead of T·N sines.
    return amplitude * (np.outer(np.cos(phase), np.sin(arg)) + np.outer(np.sin(phase), np.cos(arg)))


def quantization_error(measured: np.ndarray, q_coeff: float, dt_s: float,
                       rng: np.random.Generator) -> np.ndarray:
    """Error added by quantizing the integrated output of ``measured`` (T, N) rates.

    The accumulator starts at an unknown fraction U·q of a quantum (U ~ U[0, 1) per trial);
    output increment k = q·⌊S_k/q⌋ − q·⌊S_{k−1}/q⌋ with S_k = U·q + dt·Σ_{j≤k} measured_j.
    Returns (increment/dt − measured), shape (T, N).
    """
    quantum = math.sqrt(12.0) * q_coeff
    offset = rng.random((measured.shape[0], 1)) * quantum
    integ = np.cumsum(measured, axis=1)
    integ *= dt_s
    integ += offset
    counts = np.floor(integ / quantum)
    inc = np.diff(counts, axis=1, prepend=np.zeros((measured.shape[0], 1)))  # ⌊offset/q⌋ = 0
    return inc * (quantum / dt_s) - measured


def rate_quantization_error(measured: np.ndarray, step: float, rng: np.random.Generator) -> np.ndarray:
    """Error added by rounding the output *rate* ``measured`` (T, N) to a lattice of step δ
    (a sensor that outputs its rate in LSBs without an accumulator). The lattice's offset from
    the true static level is unknown: U·δ, U ~ U[0, 1) per trial. Returns (rounded − measured)."""
    offset = rng.random((measured.shape[0], 1)) * step
    return step * np.round((measured + offset) / step) - offset - measured


def outlier_spikes(shape: tuple[int, int], rate: float, magnitude: float,
                   rng: np.random.Generator) -> np.ndarray:
    """Spikes of ±magnitude on a random fraction ``rate`` of the samples, shape (T, N)."""
    hit = rng.random(shape) < rate
    spikes = np.zeros(shape)
    n_hit = int(hit.sum())
    spikes[hit] = magnitude * (2.0 * rng.integers(0, 2, n_hit) - 1.0)
    return spikes


def lowpass_coefficient(cutoff_hz: float, dt_s: float) -> float:
    """Smoothing factor a = 1 − exp(−2π·f_c·dt) of the first-order output filter."""
    return -math.expm1(-2.0 * math.pi * cutoff_hz * dt_s)


def lowpass_gain2(freq_hz: np.ndarray, cutoff_hz: float, dt_s: float) -> np.ndarray:
    """|H(f)|² of y_k = (1 − a)·y_{k−1} + a·x_k (unit DC gain):
    a² / (1 − 2(1 − a)·cos 2πf·dt + (1 − a)²)."""
    a = lowpass_coefficient(cutoff_hz, dt_s)
    r = 1.0 - a
    return a * a / (1.0 - 2.0 * r * np.cos(2.0 * math.pi * np.asarray(freq_hz) * dt_s) + r * r)


def lowpass(x: np.ndarray, cutoff_hz: float, dt_s: float) -> np.ndarray:
    """First-order low-pass of ``x`` (T, N) along time, y_k = (1 − a)·y_{k−1} + a·x_k, started
    at y_0 = x_0 (the transient lasts ≈ 1/a samples). Models a sensor's internal output filter
    (e.g. the averaging/decimation stage of a MEMS IMU) acting on its additive noise."""
    a = lowpass_coefficient(cutoff_hz, dt_s)
    return signal.lfilter([a], [1.0, a - 1.0], x, axis=-1, zi=(1.0 - a) * x[:, :1])[0]


def resonator_coefficients(center_hz: float, width_hz: float, dt_s: float) -> tuple[float, float, float]:
    """AR(2) resonator y_k = a1·y_{k−1} + a2·y_{k−2} + e_k with poles r·e^(±iω0),
    r = e^(−π·w·dt), ω0 = 2π·f0·dt (−3 dB full width ≈ w for w ≪ f0). Returns (a1, a2, v) with
    v = Var(y)/Var(e) = (1 − a2)/((1 + a2)((1 − a2)² − a1²)) (Box & Jenkins, AR(2) variance)."""
    r = math.exp(-math.pi * width_hz * dt_s)
    a1, a2 = 2.0 * r * math.cos(2.0 * math.pi * center_hz * dt_s), -r * r
    return a1, a2, (1.0 - a2) / ((1.0 + a2) * ((1.0 - a2) ** 2 - a1 * a1))


def vibration_acov(lags: np.ndarray, center_hz: float, width_hz: float, dt_s: float) -> np.ndarray:
    """Autocorrelation of the unit-variance resonator at integer lags k:
    ρ(k) = r^|k|·sin(ω0|k| + ψ)/sin ψ, tan ψ = (1 + r²)/(1 − r²)·tan ω0 (AR(2), complex poles)."""
    k = np.abs(np.asarray(lags, dtype=float))
    r = math.exp(-math.pi * width_hz * dt_s)
    w0 = 2.0 * math.pi * center_hz * dt_s
    psi = math.atan2((1.0 + r * r) * math.sin(w0), (1.0 - r * r) * math.cos(w0))
    return r ** k * np.sin(w0 * k + psi) / math.sin(psi)


def vibration_psd(freq_hz: np.ndarray, center_hz: float, width_hz: float, dt_s: float) -> np.ndarray:
    """One-sided PSD of the unit-variance resonator: 2·dt/(v·|1 − a1·z⁻¹ − a2·z⁻²|²)."""
    a1, a2, v = resonator_coefficients(center_hz, width_hz, dt_s)
    z = np.exp(-2j * math.pi * np.asarray(freq_hz) * dt_s)
    return 2.0 * dt_s / (v * np.abs(1.0 - a1 * z - a2 * z * z) ** 2)


def vibration(n_trials: int, n_samples: int, center_hz: float, width_hz: float, sigma: float,
              dt_s: float, rng: np.random.Generator) -> np.ndarray:
    """Band-limited random vibration of rms ``sigma``: the resonator driven by white noise,
    started from its stationary state (a burn-in of 10 time constants is discarded), (T, N)."""
    a1, a2, v = resonator_coefficients(center_hz, width_hz, dt_s)
    r = math.sqrt(-a2)
    burn = int(math.ceil(10.0 / max(1.0 - r, 1e-6)))
    e = rng.standard_normal((n_trials, n_samples + burn)) * (sigma / math.sqrt(v))
    return signal.lfilter([1.0], [1.0, -a1, -a2], e, axis=-1)[:, burn:]


def student_t_noise(n_trials: int, n_samples: int, density: float, dof: float, dt_s: float,
                    rng: np.random.Generator) -> np.ndarray:
    """White noise of density N (per-sample σ = N/√dt) with Student-t(ν) samples: the same
    ADEV and PSD as Gaussian white noise of density N, heavier tails (excess kurtosis
    6/(ν − 4) for ν > 4), (T, N)."""
    scale = density / math.sqrt(dt_s) / math.sqrt(dof / (dof - 2.0))
    return rng.standard_t(dof, (n_trials, n_samples)) * scale
