"""Independent generators of static IMU logs for judging the model-gap workflow.

Written from the textbook definitions, without any code of ``budget.imu`` (the generator the
workflow simulates with) or ``budget.gap``, so a shared mistake cannot pass unseen:

* white noise of density N: i.i.d. normal samples of σ = N·√rate;
* flicker (bias instability B, IEEE Std 952, one-sided PSD B²/(π f)): white noise shaped in the
  frequency domain over a record 8× longer than the log (so the frequencies below 1/T that make
  a slow drift are present), first N samples kept;
* every hidden effect below is drawn by its own few lines (random walk by a cumulative sum,
  a turn-on transient by e^(−t/τ), a bias step by a comparison of the time with a drawn t₀, a Gauss–Markov bias by its AR(1)
  recursion, vibration by a second-order resonator, heavy tails by Student t, quantization by flooring
  the integrated output).

The base model is a tactical-grade row (gyro ARW 0.5 deg/√h, bias instability 5 deg/h as the
ADEV floor; accel VRW 0.05 m/s/√h, 50 µg) at 100 Hz; :func:`use` switches to another grade of
:data:`GRADES` or another rate, to check that the workflow holds beyond the logs it was built
on. Hidden effects are scaled so that the channel's
Allan deviation at the τ where the effect shows most is ``RATIO`` × the base model's (closed
form N²/τ + floor², independent of the package's theory), except the distribution effects
(outliers, heavy tails) whose size is stated per effect.
"""

from __future__ import annotations

import math

import numpy as np

DEG = math.pi / 180.0
G0 = 9.80665
FLOOR_PER_B = math.sqrt(2.0 * math.log(2.0) / math.pi)  # ADEV floor = 0.664·B
CHANNELS = ("gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
#: Allan-deviation ratio (log / base model) at the effect's most telling τ.
RATIO = 3.0
ONE_HOUR = 360_000
#: Base-model grades the generators can draw (datasheet units: gyro ARW deg/√h, gyro ADEV floor
#: deg/h, accel VRW m/s/√h, accel ADEV floor µg): the benchmark's tactical row, a high-end
#: tactical (FOG-class) row and a consumer MEMS row (MPU-6050 class: 0.005 °/s/√Hz, 400 µg/√Hz).
GRADES = {"tactical": (0.5, 5.0, 0.05, 50.0),
          "high_tactical": (0.15, 1.0, 0.03, 20.0),
          "consumer": (0.3, 20.0, 0.24, 100.0)}
GRADE = "tactical"
#: The base flicker's generator: "spectral" (:func:`flicker`: stationary, with the frequencies
#: below 1/T that make a slow drift) or "kasdin" (:func:`kasdin_flicker`: a fractional
#: integrator started at the first sample, flicker with no history before the log). A second,
#: differently built flicker, to check the workflow on logs no generator of it was tuned on.
FLICKER = "spectral"


def use(grade: str = "tactical", rate_hz: float = 100.0) -> None:
    """Draw the base model of ``grade`` (:data:`GRADES`) at ``rate_hz``: sets the module's levels
    and rate, which every generator reads when it runs (worker processes fork after the call)."""
    global RATE, GYRO_N, GYRO_FLOOR, ACCEL_N, ACCEL_FLOOR, GRADE
    if grade not in GRADES:
        raise ValueError(f"no grade {grade!r}; one of {', '.join(GRADES)}")
    if not rate_hz > 0:
        raise ValueError("rate_hz must be positive")
    arw, bi, vrw, abi = GRADES[grade]
    GRADE, RATE = grade, float(rate_hz)
    # base model in SI: white density (unit/√Hz) and ADEV floor (unit) per triad
    GYRO_N, GYRO_FLOOR = arw * DEG / 60.0, bi * DEG / 3600.0
    ACCEL_N, ACCEL_FLOOR = vrw / 60.0, abi * 1e-6 * G0


use()


def base_levels(channel: str) -> tuple[float, float]:
    return (GYRO_N, GYRO_FLOOR) if channel.startswith("gyro") else (ACCEL_N, ACCEL_FLOOR)


def octave_m(n: int) -> np.ndarray:
    return 2 ** np.arange(int(math.floor(math.log2(n // 4))) + 1)


def adev(x: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Overlapping Allan deviation from the phase (cumulative sum), own few lines."""
    phase = np.concatenate([[0.0], np.cumsum(x - x.mean())])
    out = []
    for k in m:
        d = phase[2 * k:] - 2.0 * phase[k:-k] + phase[:-2 * k]
        out.append(math.sqrt(np.mean(d * d) / 2.0) / k)
    return np.array(out)


def base_adev(channel: str, tau: np.ndarray) -> np.ndarray:
    n, floor = base_levels(channel)
    return np.sqrt(n * n / tau + floor * floor)


def flicker(n: int, b_coeff: float, rng: np.random.Generator) -> np.ndarray:
    size = 8 * n
    f = np.fft.rfftfreq(size, 1.0 / RATE)
    w = rng.standard_normal(size)
    spec = np.fft.rfft(w)
    gain = np.zeros_like(f)
    # white of unit variance has one-sided PSD 2/rate; scale it to B²/(π f)
    gain[1:] = np.sqrt(b_coeff ** 2 / (math.pi * f[1:]) / (2.0 / RATE))
    return np.fft.irfft(spec * gain, size)[:n]


def kasdin_flicker(n: int, b_coeff: float, rng: np.random.Generator) -> np.ndarray:
    """Flicker by the fractional integrator (1 − z⁻¹)^(−1/2) of white noise (Kasdin & Walter,
    IEEE FCS 1992): impulse response h₀ = 1, h_k = h_{k−1}·(k − ½)/k, applied as a linear
    convolution (FFT over ≥ 2n samples) from the first sample on. With white samples of σ its
    two-sided PSD is σ²·dt/|2 sin(π f dt)| → σ²/(2π f) at low f, IEEE Std 952's B²/(2π f) for
    σ = B (independent of the rate)."""
    k = np.arange(1, n, dtype=float)
    h = np.concatenate([[1.0], np.cumprod((k - 0.5) / k)])
    w = b_coeff * rng.standard_normal(n)
    size = 1 << int(math.ceil(math.log2(2 * n)))
    return np.fft.irfft(np.fft.rfft(w, size) * np.fft.rfft(h, size), size)[:n]


def base_channel(channel: str, n: int, rng: np.random.Generator) -> np.ndarray:
    dens, floor = base_levels(channel)
    make_flicker = {"spectral": flicker, "kasdin": kasdin_flicker}[FLICKER]
    return dens * math.sqrt(RATE) * rng.standard_normal(n) + make_flicker(n, floor / FLOOR_PER_B, rng)


def temperature(n: int) -> np.ndarray:
    """Warm-up by 20 °C with a 15-min time constant plus ±0.5 °C of air-conditioning cycles
    (12-min period), °C."""
    t = np.arange(n) / RATE
    return 25.0 + 20.0 * (1.0 - np.exp(-t / 900.0)) + 0.5 * np.sin(2 * math.pi * t / 720.0)


# --- hidden effects at unit size: (series, params at unit size) ----------------------------

def _rrw(n, rng, temp):
    return np.cumsum(rng.standard_normal(n)) / math.sqrt(RATE), {"K": 1.0}


def _ramp(n, rng, temp):
    return np.arange(n) / RATE, {"R": 1.0}


def _temp(n, rng, temp):
    return temp - temp[0], {"coefficient": 1.0}


#: Time constant of the hidden thermal lag, s (a sensing element a few minutes behind its case).
LAG_TAU_S = 300.0


def lagged_temperature(n: int, tau_s: float) -> np.ndarray:
    """T_e − T_e(0) of an element that follows :func:`temperature` (without the thermometer's
    noise) through dT_e/dt = (T − T_e)/τ from equilibrium, in closed form: the warm-up
    20(1 − e^(−t/a)), a = 900 s, becomes 20[1 − (a·e^(−t/a) − τ·e^(−t/τ))/(a − τ)]; the cycle
    0.5 sin ωt becomes 0.5[sin ωt − ωτ cos ωt + ωτ e^(−t/τ)]/(1 + ω²τ²), °C."""
    t = np.arange(n) / RATE
    a, w = 900.0, 2 * math.pi / 720.0
    warm = 20.0 * (1.0 - (a * np.exp(-t / a) - tau_s * np.exp(-t / tau_s)) / (a - tau_s))
    wt = w * tau_s
    cycle = 0.5 * (np.sin(w * t) - wt * np.cos(w * t) + wt * np.exp(-t / tau_s)) / (1.0 + wt * wt)
    return warm + cycle


def _temp_lag(n, rng, temp):
    return lagged_temperature(n, LAG_TAU_S), {"coefficient": 1.0, "tau_s": LAG_TAU_S}


#: Time constant of the hidden turn-on transient, s.
WARMUP_TAU_S = 600.0
#: Correlation time of the Gauss–Markov bias (s): a correlated bias of a minute or two, whose Allan
#: deviation peaks at τ ≈ 1.9·τ_c, well inside a one-hour log.
GM_TAU_S = 100.0


def _warmup(n, rng, temp):
    """A bias settling after power-up: e^(−t/τ) from the first sample (no temperature column)."""
    return np.exp(-np.arange(n) / RATE / WARMUP_TAU_S), {"amplitude": 1.0, "tau_s": WARMUP_TAU_S}


def _bias_step(n, rng, temp):
    """The bias jumps once, at a time drawn uniformly over the middle 80 % of the log."""
    t0 = rng.uniform(0.1, 0.9) * n / RATE
    return (np.arange(n) / RATE >= t0).astype(float), {"amplitude": 1.0, "time_s": t0}


def _sinusoid(n, rng, temp, f0=7.3):
    t = np.arange(n) / RATE
    return np.sin(2 * math.pi * f0 * t + rng.uniform(0, 2 * math.pi)), {"frequency_hz": f0, "amplitude": 1.0}


def _vibration(n, rng, temp, f0=12.0, width=1.5):
    """Band-limited random vibration: white noise through the resonator
    y_k = 2r cos(ω0) y_{k−1} − r² y_{k−2} + w_k (pole radius r = e^(−π·width/rate), so the
    −3 dB width of the peak is ≈ ``width`` Hz), scaled to unit rms."""
    from scipy.signal import lfilter
    r = math.exp(-math.pi * width / RATE)
    w0 = 2 * math.pi * f0 / RATE
    y = lfilter([1.0], [1.0, -2 * r * math.cos(w0), r * r], rng.standard_normal(n + 2000))[2000:]
    return y / y.std(), {"center_hz": f0, "width_hz": width, "sigma": 1.0}


def _gauss_markov(n, rng, temp, tau_s=GM_TAU_S):
    """A first-order Gauss–Markov (exponentially correlated) bias of correlation time ``tau_s``:
    the AR(1) recursion x_k = φ·x_{k−1} + √(1 − φ²)·w_k, φ = e^(−dt/τ), started from its
    stationary distribution (unit variance)."""
    from scipy.signal import lfilter
    phi = math.exp(-1.0 / (RATE * tau_s))
    w = rng.standard_normal(n) * math.sqrt(1.0 - phi * phi)
    w[0] = rng.standard_normal()
    return lfilter([1.0], [1.0, -phi], w), {"tau_s": tau_s, "sigma": 1.0}


EFFECTS = {
    # name: (channel, unit generator, τ-selection) — the magnitude is set by calibrate()
    "rate_random_walk": ("gyro_x", _rrw),
    "rate_ramp": ("gyro_y", _ramp),
    "temperature_sensitivity": ("gyro_z", _temp),
    "temperature_lag": ("gyro_z", _temp_lag),
    "warmup_transient": ("accel_z", _warmup),
    "bias_step": ("accel_x", _bias_step),
    "sinusoid": ("accel_x", _sinusoid),
    "vibration": ("accel_y", _vibration),
    "gauss_markov": ("gyro_y", _gauss_markov),
}


def calibrate(name: str, n: int = ONE_HOUR) -> float:
    """Magnitude that makes the channel's ADEV ``RATIO`` × the base model's at the τ where the
    unit effect stands out most: effect ADEV = √(RATIO² − 1) × base ADEV there."""
    channel, gen = EFFECTS[name]
    m = octave_m(n)
    tau = m / RATE
    rng = np.random.default_rng(12345)
    x, _ = gen(n, rng, temperature(n))
    if name == "temperature_lag":
        # sized by what sets a lag apart: its part beyond an instantaneous sensitivity, a
        # constant and a trend (least squares on 1, t, T − T0); sized like every other effect
        # on its whole series, a 300-s lag is 1/8 of this and at the detection limit
        temp = temperature(n)
        basis = np.column_stack([np.ones(n), np.arange(n) / RATE, temp - temp[0]])
        x = x - basis @ np.linalg.lstsq(basis, x, rcond=None)[0]
    rho = adev(x, m) / base_adev(channel, tau)
    if name == "rate_random_walk":
        rho = np.sqrt(tau / 3.0) / base_adev(channel, tau)  # expected, not one realization
    return math.sqrt(RATIO ** 2 - 1.0) / float(rho.max())


def quantized(x: np.ndarray, q_coeff: float, true_rate: float, rng: np.random.Generator) -> np.ndarray:
    """Output of a sensor whose integrated output (angle) is floored to a quantum √12·Q; the
    true static rate ``true_rate`` is in the integral. Returns the output rate minus the truth."""
    quantum = math.sqrt(12.0) * q_coeff
    angle = rng.random() * quantum + np.cumsum(x + true_rate) / RATE
    counts = np.floor(angle / quantum)
    return np.diff(counts, prepend=0.0) * quantum * RATE - true_rate


def base_model_dict() -> dict:
    """The base model as the package's noise-model JSON (datasheet units, bias instability as
    the ADEV floor: the catalog's ``adev_min`` convention)."""
    arw, bi, vrw, abi = GRADES[GRADE]
    return {"rate_hz": RATE, "gyro_arw_deg_rt_h": arw, "gyro_bias_instability_deg_h": bi,
            "accel_vrw_m_s_rt_h": vrw, "accel_bias_instability_ug": abi,
            "bias_instability_convention": "adev_min"}


def make(name: str | None, n: int, seed: int) -> tuple[dict, np.ndarray | None, dict]:
    """(channel → series in SI, temp_c or None, truth {'name', 'channel', 'params'}) of a static
    log with one hidden effect (``None``: the base model only)."""
    rng = np.random.default_rng(seed)
    logs = {ch: base_channel(ch, n, rng) for ch in CHANNELS}
    temp = temperature(n) + 0.02 * rng.standard_normal(n)  # sensor noise of the thermometer
    truth = {"name": name, "channel": None, "params": {}}
    if name in EFFECTS:
        channel, gen = EFFECTS[name]
        scale = calibrate(name, n)
        y, unit = gen(n, rng, temp)
        logs[channel] = logs[channel] + scale * y
        params = {k: (v * scale if k in ("K", "R", "coefficient", "amplitude", "sigma") else v)
                  for k, v in unit.items()}
        truth = {"name": name, "channel": channel, "params": params}
    elif name == "quantization":
        # ADEV of white angle quantization √3·Q/τ: RATIO × the base white ADEV at τ = dt
        channel = "gyro_x"
        dens, _ = base_levels(channel)
        q = math.sqrt(RATIO ** 2 - 1.0) * dens / math.sqrt(RATE) / math.sqrt(3.0) * 1.0
        logs[channel] = quantized(logs[channel], q, 7.3e-5, rng)  # Earth rate as the truth
        truth = {"name": name, "channel": channel, "params": {"Q": q}}
    elif name == "heavy_tailed":
        # Student t (ν = 4) replaces the white noise of gyro_y at twice its variance: the ADEV
        # at τ = dt is √3 × the base's, the differences have a large excess kurtosis
        channel, nu = "gyro_y", 4.0
        dens, _ = base_levels(channel)
        sigma = math.sqrt(2.0) * dens * math.sqrt(RATE)
        t = rng.standard_t(nu, n) * sigma / math.sqrt(nu / (nu - 2.0))
        logs[channel] = logs[channel] + t
        # in the package's terms: density N = σ·√dt of the t samples, and ν
        truth = {"name": name, "channel": channel,
                 "params": {"density": sigma / math.sqrt(RATE), "dof": nu}}
    elif name == "outliers":
        # sparse spikes: 1 sample in 2000 hit by ±10 white σ
        channel = "gyro_z"
        dens, _ = base_levels(channel)
        mag = 10.0 * dens * math.sqrt(RATE)
        hit = rng.random(n) < 5e-4
        logs[channel] = logs[channel] + hit * mag * rng.choice([-1.0, 1.0], n)
        truth = {"name": name, "channel": channel, "params": {"rate": 5e-4, "magnitude": mag}}
    elif name is not None:
        raise ValueError(f"no generator for {name!r}")
    logs["accel_z"] = logs["accel_z"] - G0  # gravity on z (z up: reads −g), removed by the mean
    return logs, (temp if name in ("temperature_sensitivity", "temperature_lag") else None), truth


#: Every hidden effect the benchmark draws, in the order it prints them.
ALL = ("rate_random_walk", "rate_ramp", "temperature_sensitivity", "temperature_lag", "warmup_transient", "bias_step",
       "quantization", "sinusoid", "vibration", "heavy_tailed", "outliers", "gauss_markov")
