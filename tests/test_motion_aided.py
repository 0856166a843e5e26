"""The one motion path: free-inertial and aided trials from the same engine and error terms.

Checked: aiding switched off gives the free-inertial series exactly (same seed); an aided run
whose sensor carries no information reproduces the free-inertial error — lever arm, scale
factor and misalignment on a swaying platform included; frozen corrections remove the turn-on
biases (closed form: a bias gives a parabola); only the realtime mode steps at the fixes.
"""

from __future__ import annotations

import numpy as np
import pytest

from budget.aiding_spec import AidingPlan
from budget.errors import InputError
from budget.imu.noise_model import NoiseModel
from budget.motion import simulate_motion
from budget.nav.platform import Disturbance
from budget.nav.strapdown import InitialErrors
from budget.scenario import Scenario

# Tc ≈ 1 s at 200 Hz, X band: small and fast.
SCEN = Scenario(name="test_xband", carrier_frequency_hz=10e9, slant_range_m=1000.0, azimuth_resolution_m=0.3,
                range_resolution_m=0.3, platform_speed_m_s=50.0, depression_deg=25.0, squint_deg=5.0,
                lever_arm_m=(0.4, -0.1, 0.3), imu_rate_hz=200.0)
GNSS = {"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02}
SWAY = Disturbance.model_validate({"sinusoids": [
    {"axis": "sway", "frequency_hz": 0.7, "amplitude_m": 0.2},
    {"axis": "roll", "frequency_hz": 0.4, "amplitude_rad": 0.03, "phase_rad": 0.5}]})
NOISY = NoiseModel(gyro_arw_deg_rt_h=0.15, gyro_bias_instability_deg_h=0.5, gyro_bias_repeatability_deg_h=2.0,
                   accel_vrw_m_s_rt_h=0.05, accel_bias_instability_ug=50.0, accel_bias_repeatability_ug=500.0,
                   accel_scale_factor_ppm=500.0, accel_misalignment_mrad=0.5, gyro_misalignment_mrad=0.5,
                   gyro_scale_factor_ppm=300.0)
SERIES = ("position_error_m", "range_error_m", "quadratic_edge_rad", "residual_rms_deg", "peak_range_cells")


def aided(**upd) -> Scenario:
    return Scenario.model_validate(SCEN.model_dump() | {"aiding": [GNSS]} | upd)


def test_aiding_switched_off_gives_the_free_inertial_series_exactly():
    free = simulate_motion(SCEN, NOISY, 64, 7, disturbance=SWAY)
    off = simulate_motion(aided(), NOISY, 64, 7, disturbance=SWAY, aiding=None)
    empty = simulate_motion(aided(), NOISY, 64, 7, disturbance=SWAY,
                            aiding=AidingPlan(aiding=[], mode="frozen", warmup_s=30.0))
    for res in (off, empty):
        assert res.aiding == "none"
        for name in SERIES:
            np.testing.assert_array_equal(getattr(res, name), getattr(free, name), err_msg=name)


def test_an_uninformative_sensor_reproduces_the_free_inertial_error_with_every_term():
    """Warm-up 0, no initial error, GNSS with σ = 10 km: the filter's gain is ≈ σ_INS²/σ² ≈ 1e-12,
    so the aided error must equal the free-inertial one — including the lever arm, the scale
    factor and misalignment acting on the true rate and force of a swaying, rolling platform."""
    model = NoiseModel(accel_scale_factor_ppm=2000.0, gyro_scale_factor_ppm=2000.0,
                       accel_misalignment_mrad=1.0, gyro_misalignment_mrad=1.0)
    zero = InitialErrors()
    free = simulate_motion(SCEN, model, 64, 3, disturbance=SWAY, initial_errors=zero)
    useless = simulate_motion(aided(aiding=[GNSS | {"sigma_m": 1e4}], aiding_warmup_s=0.0), model, 64, 3,
                              disturbance=SWAY, initial_errors=zero)
    assert useless.aiding.startswith("gnss, frozen")
    scale = np.max(np.abs(free.position_error_m))
    assert scale > 1e-3  # the terms matter: millimetres of APC error in 1 s
    np.testing.assert_allclose(useless.position_error_m, free.position_error_m, rtol=0, atol=1e-9 * scale)


def test_frozen_corrections_remove_the_turn_on_biases():
    """An accel turn-on bias b (1σ per axis) gives the parabola b·t²/2; over t = T(u + 1)/2 its
    u² coefficient is b·T²/8, so the quadratic edge phase has rms (4π/λ)·σ_b·T²/8 along any unit
    LOS (64 trials: the rms is within ±27 % at 3σ). GNSS-calibrated and held across the
    aperture (frozen), the bias is gone."""
    sigma_ug = 1000.0
    model = NoiseModel(accel_bias_repeatability_ug=sigma_ug)
    free = simulate_motion(SCEN, model, 64, 5, keep_series=False)
    frozen = simulate_motion(aided(aiding_warmup_s=20.0), model, 64, 5, keep_series=False)
    span = free.time_s[-1]
    theory = 4 * np.pi / SCEN.wavelength_m * sigma_ug * 9.80665e-6 * span ** 2 / 8
    rms = lambda a: float(np.sqrt(np.mean(a ** 2)))  # noqa: E731
    assert rms(free.quadratic_edge_rad) == pytest.approx(theory, rel=0.27)
    assert rms(frozen.quadratic_edge_rad) < 0.02 * theory


@pytest.mark.parametrize("mode", ["realtime", "frozen", "feedforward", "smoothed"])
def test_only_the_realtime_mode_steps_at_the_fixes(mode):
    """Sample-to-sample change of the APC error at GNSS epochs vs elsewhere (white IMU noise
    makes both nonzero): realtime jumps at each fix, the other modes do not."""
    model = NoiseModel(gyro_arw_deg_rt_h=0.15, accel_vrw_m_s_rt_h=0.05, accel_bias_repeatability_ug=300.0)
    res = simulate_motion(aided(aiding_mode=mode, aiding_warmup_s=10.0), model, 64, 11)
    step = np.linalg.norm(np.diff(res.position_error_m, axis=1), axis=-1)   # (T, N−1)
    n_warm = int(round(10.0 * SCEN.imu_rate_hz))
    fix = np.zeros(step.shape[1], bool)
    k = np.arange(step.shape[1]) + 1 + n_warm            # sample index of the later point
    fix[(k % 20) == 0] = True                            # 10 Hz fixes at 200 Hz
    ratio = np.sqrt(np.mean(step[:, fix] ** 2) / np.mean(step[:, ~fix] ** 2))
    if mode == "realtime":
        assert ratio > 5.0
    else:
        assert ratio < 1.5


def test_bad_aiding_option_and_long_warmup():
    with pytest.raises(InputError, match="aiding"):
        simulate_motion(SCEN, NOISY, 2, 0, aiding="gnss")
    with pytest.raises(InputError, match="warm-up"):
        simulate_motion(aided(aiding_warmup_s=3600.0, imu_rate_hz=1000.0), NOISY, 2, 0)


def test_aided_trials_do_not_depend_on_chunking():
    s = aided(aiding_mode="smoothed", aiding_warmup_s=5.0)
    whole = simulate_motion(s, NOISY, 128, 9, keep_series=False)
    second = simulate_motion(s, NOISY, 64, 9, keep_series=False, first_trial=64)
    threads = simulate_motion(s, NOISY, 128, 9, keep_series=False, chunk_size=64, workers=2)
    np.testing.assert_array_equal(whole.quadratic_edge_rad[64:], second.quadratic_edge_rad)
    np.testing.assert_array_equal(whole.residual_rms_deg, threads.residual_rms_deg)
