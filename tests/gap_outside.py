"""Independent generators of static IMU logs with effects the gap vocabulary does not have.

Written from textbook definitions, without any code of ``budget.imu`` or ``budget.gap`` (nor of
``tests/gap_truth.py``, whose base-model magnitudes and model JSON only are read: tactical
grade, gyro ARW 0.5 deg/√h and ADEV floor 5 deg/h, accel VRW 0.05 m/s/√h and 50 µg, 100 Hz).
The base noise here is drawn by its own lines: white samples of σ = N·√rate plus flicker made by
shaping white noise to B²/(π f) over a record 8× the log (first N samples kept).

Effects (each outside the registry):

* ``telegraph`` — random telegraph (popcorn/burst) noise on gyro_y: a bias ±a that flips at
  the times of a Poisson process of rate λ (the first state drawn at random). Its
  autocovariance a²·e^(−2λ|t|) is that of a Gauss–Markov term of σ = a, τ_c = 1/(2λ), so its
  PSD is the same Lorentzian; its values are two: the slow part's excess kurtosis is −2 where a
  Gaussian's is 0.
* ``common`` — one band-limited vibration (a second-order resonator driven by white noise)
  added, the same series, to gyro_x and gyro_y: the two channels are coherent in its band
  (|γ|² ≈ (S_c/(S_c + S_own))² there), which a per-channel model, whose channels are
  independent, cannot give.
* ``quadratic_temperature`` — gyro_z bias c₂·(T − T_turn)² with a turnover temperature
  T_turn = 35 °C inside the 20 °C warm-up of the temperature column (curved in T: a linear
  sensitivity explains little of it).
* ``fractional`` — noise of one-sided PSD h·f^(−1/2) on accel_x (between white, f⁰, and
  flicker, f⁻¹): ADEV ∝ τ^(−1/4).

Every effect is scaled so that the channel's Allan deviation is ``RATIO`` × the base model's
(closed form √(N²/τ + floor²)) at the octave τ where the unit effect's own Allan deviation
stands out most (its expected one for the stochastic effects: closed form for the telegraph,
the mean over realizations otherwise).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.signal import lfilter

RATE = 100.0
DEG = math.pi / 180.0
G0 = 9.80665
CHANNELS = ("gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
RATIO = 3.0
#: base model: white density (unit/√Hz) and Allan-deviation floor (unit) per triad
GYRO_N, GYRO_FLOOR = 0.5 * DEG / 60.0, 5.0 * DEG / 3600.0
ACCEL_N, ACCEL_FLOOR = 0.05 / 60.0, 50e-6 * G0
#: flicker coefficient B from the ADEV floor: floor = B·√(2 ln 2/π)
FLOOR_PER_B = math.sqrt(2.0 * math.log(2.0) / math.pi)

#: telegraph: switching rate λ (1/s); correlation time 1/(2λ) = 10 s
TELEGRAPH_RATE = 0.05
#: common vibration: centre and −3 dB width (Hz)
COMMON_HZ, COMMON_WIDTH_HZ = 5.0, 1.0
COMMON_CHANNELS = ("gyro_x", "gyro_y")
#: quadratic temperature: turnover temperature (°C)
T_TURN = 35.0
#: fractional noise: exponent of f in its PSD
FRACTIONAL_SLOPE = -0.5

EFFECT_CHANNEL = {"telegraph": "gyro_y", "common": "gyro_x", "quadratic_temperature": "gyro_z",
                  "fractional": "accel_x"}
EFFECTS = tuple(EFFECT_CHANNEL)


def levels(channel: str) -> tuple[float, float]:
    return (GYRO_N, GYRO_FLOOR) if channel.startswith("gyro") else (ACCEL_N, ACCEL_FLOOR)


def octave_m(n: int) -> np.ndarray:
    return 2 ** np.arange(int(math.floor(math.log2(n // 4))) + 1)


def adev(x: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Overlapping Allan deviation through the phase (cumulative sum)."""
    phase = np.concatenate([[0.0], np.cumsum(x - x.mean())])
    return np.array([math.sqrt(np.mean((phase[2 * k:] - 2 * phase[k:-k] + phase[:-2 * k]) ** 2) / 2.0) / k
                     for k in m])


def base_adev(channel: str, tau: np.ndarray) -> np.ndarray:
    dens, floor = levels(channel)
    return np.sqrt(dens ** 2 / tau + floor ** 2)


def shaped(n: int, exponent: float, rng: np.random.Generator) -> np.ndarray:
    """Noise of one-sided PSD f^exponent (unit coefficient), by shaping white noise over 8n."""
    size = 8 * n
    f = np.fft.rfftfreq(size, 1.0 / RATE)
    gain = np.zeros_like(f)
    gain[1:] = np.sqrt(f[1:] ** exponent / (2.0 / RATE))  # unit white has one-sided PSD 2/rate
    return np.fft.irfft(np.fft.rfft(rng.standard_normal(size)) * gain, size)[:n]


def base(channel: str, n: int, rng: np.random.Generator) -> np.ndarray:
    dens, floor = levels(channel)
    b = floor / FLOOR_PER_B
    return dens * math.sqrt(RATE) * rng.standard_normal(n) + b / math.sqrt(math.pi) * shaped(n, -1.0, rng)


def temperature(n: int, rng: np.random.Generator | None = None) -> np.ndarray:
    """25 °C warming by 20 °C with a 15-min time constant, ±0.5 °C cycles of 12 min, 0.02 °C
    thermometer noise (when ``rng`` is given)."""
    t = np.arange(n) / RATE
    temp = 25.0 + 20.0 * (1.0 - np.exp(-t / 900.0)) + 0.5 * np.sin(2 * math.pi * t / 720.0)
    return temp if rng is None else temp + 0.02 * rng.standard_normal(n)


def telegraph(n: int, rng: np.random.Generator, rate: float = TELEGRAPH_RATE) -> np.ndarray:
    """±1 flipping at Poisson times of ``rate`` per second."""
    t_end = n / RATE
    flips = np.cumsum(rng.exponential(1.0 / rate, int(3 * rate * t_end) + 50))
    flips = flips[flips < t_end]
    count = np.searchsorted(flips, np.arange(n) / RATE, side="right")
    return rng.choice([-1.0, 1.0]) * np.where(count % 2 == 0, 1.0, -1.0)


def resonator(n: int, rng: np.random.Generator, f0: float = COMMON_HZ, width: float = COMMON_WIDTH_HZ) -> np.ndarray:
    """White noise through y_k = 2r cos ω₀ y_{k−1} − r² y_{k−2} + w_k, r = e^(−π·width/rate), at
    unit variance (its stationary variance in closed form, so every draw has the same scale)."""
    r, w0 = math.exp(-math.pi * width / RATE), 2 * math.pi * f0 / RATE
    a1, a2 = 2 * r * math.cos(w0), -r * r
    # AR(2) stationary variance: (1 − a2) / ((1 + a2)((1 − a2)² − a1²))
    var = (1 - a2) / ((1 + a2) * ((1 - a2) ** 2 - a1 * a1))
    y = lfilter([1.0], [1.0, -a1, -a2], rng.standard_normal(n + 4000))[4000:]
    return y / math.sqrt(var)


def _unit(name: str, n: int, rng: np.random.Generator, temp: np.ndarray) -> np.ndarray:
    if name == "telegraph":
        return telegraph(n, rng)
    if name == "common":
        return resonator(n, rng)
    if name == "quadratic_temperature":
        return (temp - T_TURN) ** 2
    if name == "fractional":
        return shaped(n, FRACTIONAL_SLOPE, rng)
    raise ValueError(f"no generator for {name!r}")


def _telegraph_adev(tau: np.ndarray) -> np.ndarray:
    """Expected Allan deviation of the unit telegraph: that of an exponentially correlated
    process of σ = 1, τ_c = 1/(2λ): σ²·(τ_c/τ)·[2 − (τ_c/τ)(3 − 4e^(−τ/τ_c) + e^(−2τ/τ_c))]."""
    tc = 1.0 / (2.0 * TELEGRAPH_RATE)
    x = tau / tc
    return np.sqrt((2.0 - (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)) / x) / x)


def scale(name: str, n: int) -> float:
    """Magnitude that makes the channel's ADEV ``RATIO`` × the base's where the unit effect
    stands out most (effect ADEV = √(RATIO² − 1) × base ADEV there)."""
    channel = EFFECT_CHANNEL[name]
    m = octave_m(n)
    tau = m / RATE
    if name == "telegraph":
        unit = _telegraph_adev(tau)
    elif name == "quadratic_temperature":
        unit = adev(_unit(name, n, np.random.default_rng(0), temperature(n)), m)
    else:  # mean Allan variance over realizations
        rng = np.random.default_rng(2024)
        unit = np.sqrt(np.mean([adev(_unit(name, n, rng, None), m) ** 2 for _ in range(8)], axis=0))
    return math.sqrt(RATIO ** 2 - 1.0) / float(np.max(unit / base_adev(channel, tau)))


def make(name: str | None, n: int, seed: int) -> tuple[dict, np.ndarray | None, dict]:
    """(channel → series in SI, temp_c or None, truth) of a static log with the effect ``name``
    (``None``: the base model only). ``truth``: name, channels, params in SI."""
    rng = np.random.default_rng(seed)
    logs = {ch: base(ch, n, rng) for ch in CHANNELS}
    temp = temperature(n, rng) if name == "quadratic_temperature" else None
    truth = {"name": name, "channels": (), "params": {}}
    if name is not None:
        k = scale(name, n)
        y = k * _unit(name, n, rng, temperature(n))  # the element's temperature, no thermometer noise
        chans = COMMON_CHANNELS if name == "common" else (EFFECT_CHANNEL[name],)
        for ch in chans:
            logs[ch] = logs[ch] + y
        params = {"telegraph": {"amplitude": k, "switch_rate_hz": TELEGRAPH_RATE,
                                "tau_c_s": 1.0 / (2.0 * TELEGRAPH_RATE)},
                  "common": {"sigma": k, "center_hz": COMMON_HZ, "width_hz": COMMON_WIDTH_HZ},
                  "quadratic_temperature": {"c2_per_degc2": k, "t_turn_c": T_TURN},
                  "fractional": {"h": k ** 2, "slope": FRACTIONAL_SLOPE}}[name]
        truth = {"name": name, "channels": chans, "params": params}
    logs["accel_z"] = logs["accel_z"] - G0
    return logs, temp, truth


def base_model_dict() -> dict:
    """The base model as the package's noise-model JSON (bias instability as the ADEV floor)."""
    return {"rate_hz": RATE, "gyro_arw_deg_rt_h": 0.5, "gyro_bias_instability_deg_h": 5.0,
            "accel_vrw_m_s_rt_h": 0.05, "accel_bias_instability_ug": 50.0,
            "bias_instability_convention": "adev_min"}
