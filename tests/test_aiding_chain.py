"""aided_position_error: the Monte Carlo entry point, with our truth and with the motion engine's."""

from __future__ import annotations

import numpy as np
import pytest

from budget import units as u
from budget.aiding import (FlexureConfig, ImuErrorModel, InitialUncertainty, NominalTrajectory,
                           aided_position_error, build_system, simulate_truth)
from budget.aiding_spec import parse_aiding
from budget.aiding.kalman import run_kalman
from budget.catalog.schema import PartSpec
from budget.errors import InputError

IMU = ImuErrorModel(gyro_bias_rad_s=u.deg_h_to_rad_s(1.0), gyro_arw_rad_s_rt_hz=u.deg_rt_h_to_rad_s_rt_hz(0.1),
                    accel_bias_m_s2=u.ug_to_m_s2(300.0), accel_vrw_m_s2_rt_hz=u.ug_rt_hz_to_m_s2_rt_hz(60.0))
INIT = InitialUncertainty(1.0, 0.05, 1e-3)
DT, N = 0.1, 1801


def _free_inertial(trials, seed):
    s = build_system(NominalTrajectory.straight_level(50.0, DT, N), IMU, [], INIT)
    x = simulate_truth(s, trials, np.random.default_rng(seed))
    return x[..., 0:3], x[..., 3:6], x[..., 6:9]


def test_gnss_aiding_bounds_the_error_at_its_predicted_level():
    pos, vel, att = _free_inertial(100, 0)
    gnss = [{"type": "gnss", "rate_hz": 1, "sigma_m": 0.5}]
    out = aided_position_error(pos, vel, att, IMU, gnss, DT, np.random.default_rng(1), initial=INIT)
    assert out.shape == pos.shape
    rms_aided = np.sqrt(np.mean(out[:, -1] ** 2, axis=0))
    rms_free = np.sqrt(np.mean(pos[:, -1] ** 2, axis=0))
    assert np.all(rms_aided < 0.1 * rms_free)
    # the truth follows the filter's model here, so the RMS matches the filter's σ (100 trials:
    # ±15 % covers the sampling error of an RMS)
    s = build_system(NominalTrajectory.straight_level(0.0, DT, N), IMU, parse_aiding(gnss), INIT)
    sig = np.sqrt(run_kalman(s, {"gnss0": np.zeros((1, len(s.epochs["gnss0"]), 3))}).p_diag[-1, :3])
    assert np.allclose(rms_aided, sig, rtol=0.15)


def test_smoother_beats_filter_between_fixes():
    pos, vel, att = _free_inertial(40, 2)
    gnss = [{"type": "gnss", "rate_hz": 0.5, "sigma_m": 0.3}]
    kf = aided_position_error(pos, vel, att, IMU, gnss, DT, np.random.default_rng(3), initial=INIT)
    rts = aided_position_error(pos, vel, att, IMU, gnss, DT, np.random.default_rng(3), initial=INIT,
                               smoother=True)
    mid = slice(N // 4, 3 * N // 4)
    assert np.sqrt(np.mean(rts[:, mid] ** 2)) < 0.8 * np.sqrt(np.mean(kf[:, mid] ** 2))


def test_no_aiding_returns_free_inertial_and_flexure_adds_its_variance():
    pos, vel, att = _free_inertial(4, 4)
    same = aided_position_error(pos, vel, att, IMU, [], DT, np.random.default_rng(0))
    assert np.array_equal(same, pos)
    flex = FlexureConfig(frequency_hz=0.5, damping_ratio=0.3, amplitude_m=(0.0, 0.0, 0.05))
    zero = np.zeros((30, N, 3))
    out = aided_position_error(zero, zero, zero, IMU, [], DT, np.random.default_rng(5),
                               antenna_flexure=flex)
    assert np.isclose(out[..., 2].std(), 0.05, rtol=0.1)
    assert np.allclose(out[..., :2], 0.0)


def test_works_on_the_motion_engine_errors():
    """Catalog part → budget.imu generator → budget.nav strapdown propagation → aiding."""
    gen = pytest.importorskip("budget.imu.generator")
    strap = pytest.importorskip("budget.nav.strapdown")
    part = PartSpec(part_id="T1", grade="tactical", gyro_bias_instability_deg_h=1.0,
                    gyro_bias_repeatability_deg_h=3.0, gyro_arw_deg_rt_h=0.1,
                    accel_bias_instability_ug=50.0, accel_bias_repeatability_ug=300.0,
                    accel_vrw_m_s_rt_h=0.03, source="test")
    rng = np.random.default_rng(6)
    n = 1201
    err = gen.generate_imu_errors(part, 8, n, 1 / DT, rng)
    nav = strap.propagate_errors(err.gyro_rad_s, err.accel_m_s2, DT, keep_states=True,
                                 phi0=rng.standard_normal((8, 3)) * 1e-3)
    out = aided_position_error(nav.position_m, nav.velocity_m_s, nav.attitude_rad, part.to_si(),
                               [{"type": "gnss", "rate_hz": 1, "sigma_m": 0.2}], DT, rng,
                               initial=InitialUncertainty(0.0 + 1e-3, 1e-3, 1e-3))
    assert np.all(np.isfinite(out))
    free = np.sqrt(np.mean(nav.position_m[:, -1] ** 2))
    assert np.sqrt(np.mean(out[:, -1] ** 2)) < 0.05 * free


def test_bad_inputs_are_clear():
    pos, vel, att = _free_inertial(2, 7)
    gnss = [{"type": "gnss", "rate_hz": 1, "sigma_m": 0.5}]
    rng = np.random.default_rng(0)
    with pytest.raises(InputError, match="above the IMU rate"):
        aided_position_error(pos, vel, att, IMU, [{"type": "gnss", "rate_hz": 20, "sigma_m": 1}], DT, rng)
    with pytest.raises(InputError, match="trials, samples, 3"):
        aided_position_error(pos[0], vel, att, IMU, gnss, DT, rng)
    with pytest.raises(InputError, match="ImuErrorsSI"):
        aided_position_error(pos, vel, att, "HG1700", gnss, DT, rng)
    bad = pos.copy()
    bad[0, 3, 1] = np.nan
    with pytest.raises(InputError, match="NaN"):
        aided_position_error(bad, vel, att, IMU, gnss, DT, rng)
