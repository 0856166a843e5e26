"""Aided (or smoothed) antenna motion error for the Monte Carlo chain (seeds 000–003 aid or
smooth the IMU; seed 004's bounds assume it is unaided).

For a block of trials: the IMU errors over ``aiding_warmup_s`` + Tc (:mod:`budget.imu`), the
free-inertial errors from flat-earth propagation with initial errors drawn from the filter's
initial uncertainty (:mod:`budget.nav.strapdown`), then the aided Kalman filter or RTS smoother
(:func:`budget.aiding.aided_position_error`); the aperture is the last Tc. The value at the
aperture start is removed: a constant position error only moves the image (geolocation), it
does not defocus it. The filter works on the IMU position: the lever-arm term of the aided
attitude error is not added (it is 1e-3 rad × lever arm at most after alignment).

Sign: returned as *true − measured* like :func:`budget.motion.simulate_motion`.
"""

from __future__ import annotations

import numpy as np

from ..aiding import InitialUncertainty, aided_position_error
from ..imu.generator import generate_imu_errors
from ..imu.noise_model import as_noise_model_si
from ..motion.engine import aperture_samples
from ..motion.geometry import los_unit_vector
from ..nav.strapdown import propagate_errors
from ..rng import trial_generator
from ..scenario import Scenario

AIDED_IMU_STREAM, AIDED_FILTER_STREAM = 31, 32
#: Trials per random-stream block of the aided path (chunk sizes are multiples of it).
AIDED_BLOCK = 64
INITIAL = InitialUncertainty(position_m=1.0, velocity_m_s=0.1, attitude_rad=1e-3)


def aided_motion(scenario: Scenario, model, seed: int, start: int, stop: int):
    """(time_s (N,), APC error true − measured (T, N, 3) over the aperture, peak LOS error in
    range cells (T,)) of trials ``start … stop−1`` with the scenario's aiding."""
    rate = scenario.imu_rate_hz
    dt = 1.0 / rate
    n_ap = aperture_samples(scenario)
    n_warm = int(round(scenario.aiding_warmup_s * rate))
    n = n_warm + n_ap
    si = as_noise_model_si(model)
    los = los_unit_vector(scenario.depression_deg, scenario.squint_deg)
    out = np.empty((stop - start, n_ap, 3))
    for b0 in range(start, stop, AIDED_BLOCK):
        m = min(AIDED_BLOCK, stop - b0)
        rng = trial_generator(seed, b0, AIDED_IMU_STREAM)
        err = generate_imu_errors(si, AIDED_BLOCK, n, rate, rng)
        init = {k: rng.standard_normal((AIDED_BLOCK, 3)) * s for k, s in
                (("dp0", INITIAL.position_m), ("dv0", INITIAL.velocity_m_s), ("phi0", INITIAL.attitude_rad))}
        nav = propagate_errors(err.gyro_rad_s, err.accel_m_s2, dt, keep_states=True, **init)
        del err
        est = aided_position_error(nav.position_m, nav.velocity_m_s, nav.attitude_rad, si.errors,
                                   [dict(a) for a in scenario.aiding], dt,
                                   trial_generator(seed, b0, AIDED_FILTER_STREAM),
                                   smoother=scenario.aiding_smoother == "rts", initial=INITIAL,
                                   imu_rate_hz=rate)
        ap = est[:, n_warm:] - est[:, n_warm:n_warm + 1]
        out[b0 - start:b0 - start + m] = -ap[:m]  # estimate − truth → true − measured
    peak = np.max(np.abs(out @ los), axis=1) / scenario.range_resolution_m
    return np.arange(n_ap) * dt, out, peak
