"""IMU error generator: 3 gyros + 3 accelerometers, vectorised over trials.

Sensor model per triad (seed 004 (3)–(4)): measured = (I + E)·true + b + n, with
E = diag(scale factors) + M (off-diagonal misalignment / non-orthogonality, 6 independent small
angles) and b + n the additive terms of every channel's effects. The generator returns
*errors* = measured − true, shape (trials, samples, 3), in rad/s and m/s².

Per trial, drawn once (1σ from the model, Gaussian): turn-on bias (catalog bias repeatability),
scale factor, misalignment. Per sample: every effect of :meth:`NoiseModelSI.channel_effects`
(catalog ARW/VRW → ``white_noise``, bias instability → flicker, gyro RRW → ``rate_random_walk``,
plus the explicit effects). Order of application: additive terms, the output low-pass filter
(``lowpass``) on them, then (I+E) on the true signals, turn-on bias, quantization of the
integrated output (which therefore sees the whole signal), and finally outliers (data glitches).
Draw order is fixed (gyro triad, then accel triad; within a triad: constants, stationary
Gaussian part (per axis with a coloured term), white noise of the other axes, random walk,
the registry's additive effects, quantization, outliers), so the same generator state gives the
same errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..units import ACCEL_CHANNELS, CHANNELS, G0, GYRO_CHANNELS
from . import effects as fx
from .flicker import coloured_eigenvalues, flicker_bank, stationary_gaussian
from .noise_model import NoiseModelSI, as_noise_model_si, check_rate
from .registry import REGISTRY

#: Hard limit on trials × samples × 6 channels held in memory at once (float64 elements).
MAX_ELEMENTS = 400_000_000


@dataclass
class ImuErrors:
    """Measured − true sensor outputs and the per-trial constants that produced them.

    ``gyro_rad_s``/``accel_m_s2``: (T, N, 3). ``*_turn_on_bias``: (T, 3). ``*_scale_factor``:
    (T, 3) (dimensionless). ``*_misalignment_rad``: (T, 3, 3) with zero diagonal; the error
    from scale factor and misalignment is (diag(s) + M)·true.
    """

    time_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    gyro_turn_on_bias_rad_s: np.ndarray
    accel_turn_on_bias_m_s2: np.ndarray
    gyro_scale_factor: np.ndarray
    accel_scale_factor: np.ndarray
    gyro_misalignment_rad: np.ndarray
    accel_misalignment_rad: np.ndarray


def _as_signal(name: str, arr, n_trials: int, n_samples: int) -> np.ndarray | None:
    if arr is None:
        return None
    a = np.asarray(arr, dtype=float)
    if a.shape not in ((n_samples, 3), (n_trials, n_samples, 3)):
        raise InputError(f"{name} has shape {a.shape}", field=name,
                         expected=f"({n_samples}, 3) or ({n_trials}, {n_samples}, 3)")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} contains NaN or infinite values", field=name, expected="finite numbers")
    return a


def _as_temperature(temp_c, n_trials: int, n_samples: int, time_s: np.ndarray) -> np.ndarray:
    if temp_c is None:
        return fx.default_temperature(time_s)
    t = np.asarray(temp_c, dtype=float)
    if t.shape not in ((n_samples,), (n_trials, n_samples)):
        raise InputError(f"temp_c has shape {t.shape}", field="temp_c",
                         expected=f"({n_samples},) or ({n_trials}, {n_samples}) in °C")
    if not np.all(np.isfinite(t)):
        raise InputError("temp_c contains NaN or infinite values", field="temp_c", expected="finite °C")
    return t


def _check_sizes(n_trials, n_samples, rate_hz) -> None:
    if not isinstance(n_trials, (int, np.integer)) or n_trials < 1:
        raise InputError("n_trials must be a positive integer", field="n_trials", value=n_trials)
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 2:
        raise InputError("n_samples must be an integer ≥ 2", field="n_samples", value=n_samples)
    if not (isinstance(rate_hz, (int, float, np.floating)) and math.isfinite(rate_hz) and rate_hz > 0):
        raise InputError("rate_hz must be a positive finite number", field="rate_hz", value=rate_hz,
                         expected="Hz > 0")
    if 6 * int(n_trials) * int(n_samples) > MAX_ELEMENTS:
        raise InputError(f"{n_trials} trials × {n_samples} samples is too large for one call",
                         field="n_trials", expected=f"trials × samples ≤ {MAX_ELEMENTS // 6:,} (use chunks)")


def _triad(si: NoiseModelSI, triad: str, n_trials: int, n_samples: int, dt_s: float,
           time_s: np.ndarray, rng: np.random.Generator, true: np.ndarray | None,
           temp: np.ndarray):
    channels = GYRO_CHANNELS if triad == "gyro" else ACCEL_CHANNELS
    per_axis = [si.channel_effects(ch) for ch in channels]
    shape = (n_trials, n_samples, 3)
    out = np.zeros(shape)

    # --- per-trial constants -----------------------------------------------------------
    sig_b, sig_s, sig_m = si.turn_on_bias(triad), si.scale_factor(triad), si.misalignment(triad)
    bias = rng.normal(0.0, sig_b, (n_trials, 3)) if sig_b > 0 else np.zeros((n_trials, 3))
    scale = rng.normal(0.0, sig_s, (n_trials, 3)) if sig_s > 0 else np.zeros((n_trials, 3))
    mis = np.zeros((n_trials, 3, 3))
    if sig_m > 0:
        mis[:] = rng.normal(0.0, sig_m, (n_trials, 3, 3))
        mis[:, [0, 1, 2], [0, 1, 2]] = 0.0

    # --- stationary Gaussian part: flicker bank + Gauss–Markov effects + white noise -------
    # A channel with a coloured term is drawn in one exact circulant-embedding pass that also
    # carries its white noise (one draw instead of two); white-only channels use plain normals.
    def summed(name: str, key: str) -> np.ndarray:
        return np.array([math.sqrt(sum(f.param(key) ** 2 for f in effs if f.name == name))
                         for effs in per_axis])

    density = summed("white_noise", "density")
    white_var = density**2 / dt_s  # per-sample variance N²/dt
    duration = dt_s * (n_samples - 1)
    white_axes = []
    for axis, effs in enumerate(per_axis):
        taus, variances = [], []
        for f in effs:
            if f.name == "bias_instability" and f.param("B") > 0:
                t, v = flicker_bank(f.param("B"), dt_s, duration)
                taus.extend(t.tolist())
                variances.extend(v.tolist())
            elif f.name == "gauss_markov" and f.param("sigma") > 0:
                taus.append(f.param("tau_s"))
                variances.append(f.param("sigma") ** 2)
        if taus:
            lam = coloured_eigenvalues(tuple(taus), tuple(variances), float(white_var[axis]),
                                       dt_s, n_samples)
            out[:, :, axis] += stationary_gaussian(lam, n_trials, n_samples, rng)
        elif white_var[axis] > 0:
            white_axes.append(axis)
    if len(white_axes) == 3:  # nothing added yet (no coloured term): draw straight into `out`
        rng.standard_normal(out=out)
        out *= np.sqrt(white_var)
    elif white_axes:
        fx.add_white(out, density[white_axes], dt_s, rng, axes=white_axes)
    k_rrw = summed("rate_random_walk", "K")
    if k_rrw.any():
        fx.add_random_walk(out, k_rrw, dt_s, rng)

    # --- additive terms, each drawn by its registry entry (channel order: fixed draw order)
    for axis, effs in enumerate(per_axis):
        for f in effs:
            spec = REGISTRY[f.name]
            if spec.stage == "additive":
                out[:, :, axis] += spec.simulate(f.params, n_trials, time_s, dt_s, rng, temp)

    # --- the sensor's output filter shapes its additive noise (not the true signal: its lag
    # of the motion is far below the bandwidths that matter here) ---------------------------
    for axis, effs in enumerate(per_axis):
        for f in effs:
            if f.name == "lowpass":
                out[:, :, axis] = fx.lowpass(out[:, :, axis], f.param("cutoff_hz"), dt_s)

    # --- scale factor and misalignment act on the true signal; then the turn-on bias -----
    const = bias.copy() if sig_b > 0 else None
    if true is not None and (sig_s > 0 or sig_m > 0):
        e_mat = mis.copy()
        e_mat[:, [0, 1, 2], [0, 1, 2]] = scale
        if true.ndim == 2 and np.all(true == true[0]):  # steady signal: one constant per trial
            shift = e_mat @ true[0]
            const = shift if const is None else const + shift
        else:
            out += np.matmul(true, e_mat.transpose(0, 2, 1))  # (N|T,N,3) @ (T,3,3) → (T,N,3)
    if const is not None:
        out += const[:, None, :]

    # --- quantization of the integrated output, then outliers ---------------------------
    for axis, effs in enumerate(per_axis):
        for f in effs:
            if f.name == "quantization" and f.param("Q") > 0:
                sig = out[:, :, axis] if true is None else out[:, :, axis] + true[..., axis]
                out[:, :, axis] += fx.quantization_error(sig, f.param("Q"), dt_s, rng)
            elif f.name == "rate_quantization" and f.param("step") > 0:
                sig = out[:, :, axis] if true is None else out[:, :, axis] + true[..., axis]
                out[:, :, axis] += fx.rate_quantization_error(sig, f.param("step"), rng)
    for axis, effs in enumerate(per_axis):
        for f in effs:
            if f.name == "outliers" and f.param("rate") > 0 and f.param("magnitude") > 0:
                out[:, :, axis] += fx.outlier_spikes((n_trials, n_samples), f.param("rate"),
                                                     f.param("magnitude"), rng)
    return out, bias, scale, mis


def generate_imu_errors(model, n_trials: int, n_samples: int, rate_hz: float,
                        rng: np.random.Generator, *, true_rate_rad_s=None, true_force_m_s2=None,
                        temp_c=None) -> ImuErrors:
    """Draw IMU errors (measured − true) for ``n_trials`` runs of ``n_samples`` at ``rate_hz``.

    ``model``: :class:`NoiseModel`, catalog :class:`PartSpec` or :class:`NoiseModelSI`.
    ``true_rate_rad_s`` / ``true_force_m_s2``: true body-frame angular rate and specific force,
    shape (N, 3) or (T, N, 3); ``None`` means zero (scale factor and misalignment then have no
    effect). ``temp_c``: temperature (N,) or (T, N) in °C, default
    :func:`~budget.imu.effects.default_temperature`. Sample k is at t = k/rate_hz.
    """
    _check_sizes(n_trials, n_samples, rate_hz)
    if not isinstance(rng, np.random.Generator):
        raise TypeError("rng must be a numpy.random.Generator")
    si = as_noise_model_si(model)
    try:
        check_rate(float(rate_hz), si.effects)
    except ValueError as err:
        raise InputError(str(err), field="rate_hz", value=rate_hz) from None
    n_trials, n_samples, dt = int(n_trials), int(n_samples), 1.0 / float(rate_hz)
    time_s = np.arange(n_samples) * dt
    w_true = _as_signal("true_rate_rad_s", true_rate_rad_s, n_trials, n_samples)
    f_true = _as_signal("true_force_m_s2", true_force_m_s2, n_trials, n_samples)
    temp = _as_temperature(temp_c, n_trials, n_samples, time_s)
    gyro, gb, gs, gm = _triad(si, "gyro", n_trials, n_samples, dt, time_s, rng, w_true, temp)
    accel, ab, as_, am = _triad(si, "accel", n_trials, n_samples, dt, time_s, rng, f_true, temp)
    return ImuErrors(time_s=time_s, gyro_rad_s=gyro, accel_m_s2=accel,
                     gyro_turn_on_bias_rad_s=gb, accel_turn_on_bias_m_s2=ab,
                     gyro_scale_factor=gs, accel_scale_factor=as_,
                     gyro_misalignment_rad=gm, accel_misalignment_rad=am)


def simulate_static_log(model, n_samples: int, rate_hz: float, rng: np.random.Generator,
                        temp_c=None, channels=None) -> dict[str, np.ndarray]:
    """A simulated static, level log: channel → output series (N,) in rad/s or m/s².

    The IMU sits still and level: true rate 0 (Earth rate neglected), true specific force
    (0, 0, +g) on the accelerometers, so accel_z reads ≈ 9.81 m/s² and misalignment / scale
    factor show up as constant offsets. ``channels`` selects a subset (default all six).
    """
    wanted = tuple(CHANNELS if channels is None else channels)
    bad = [c for c in wanted if c not in CHANNELS]
    if bad:
        raise InputError(f"unknown channel(s) {', '.join(bad)}", field="channels",
                         expected=", ".join(CHANNELS))
    force = np.zeros((int(n_samples), 3))
    force[:, 2] = G0
    errs = generate_imu_errors(model, 1, n_samples, rate_hz, rng, true_rate_rad_s=None,
                               true_force_m_s2=force, temp_c=temp_c)
    series = {ch: errs.gyro_rad_s[0, :, i] for i, ch in enumerate(GYRO_CHANNELS)}
    series.update({ch: errs.accel_m_s2[0, :, i] + force[:, i] for i, ch in enumerate(ACCEL_CHANNELS)})
    return {ch: np.ascontiguousarray(series[ch]) for ch in wanted}
