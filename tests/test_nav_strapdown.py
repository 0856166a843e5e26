"""Strapdown error propagation against the closed forms of DESIGN.md §2–3 (seed 004, seed 000).

Errors are computed − true here. Closed forms for a level IMU (f = (0, 0, g)) over t ∈ [0, T]:
accel bias b → b·t²/2; gyro bias → g·b·t³/6 (through the tilt); VRW N → σ(T) = N·√(T³/3);
ARW N → σ(T) = g·N·√(T⁵/20). Mean-square residual over [0, T] after removing the least-squares
line / quadratic, for position = N·∫W (VRW) and g·N·∬W (ARW), W a standard Wiener process:
1/420, 1/2520 (× N²T³) and 17/30240, 1/55440 (× g²N²T⁵) — from E∫(k(t,·) − Pk)² with kernels
(t − r) and (t − r)²/2 (computed symbolically for this test; ≈ 0.049, 0.020, 0.024, 0.0043 in rms).
Statistical tolerances: 4000 trials → standard error of a σ estimate 1.1 %; we allow 5 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.imu.generator import generate_imu_errors
from budget.imu.noise_model import NoiseModel
from budget.nav.earth import propagate_errors_earth
from budget.nav.strapdown import cross, propagate_errors
from budget.units import G0

RATE = 200.0
DT = 1.0 / RATE
T_AP = 2.0
N = int(T_AP * RATE) + 1
TIME = np.arange(N) * DT
LEVEL = np.tile([0.0, 0.0, G0], (N, 1))


def errors(model: NoiseModel, trials: int, seed: int):
    return generate_imu_errors(model, trials, N, RATE, np.random.default_rng(seed), true_force_m_s2=LEVEL)


def residual_rms(pos: np.ndarray, degree: int) -> float:
    """√(mean over trials of the mean-square residual after a least-squares polynomial fit)."""
    coef = np.polynomial.polynomial.polyfit(TIME, pos.T, degree)
    fit = np.polynomial.polynomial.polyval(TIME, coef)
    return float(np.sqrt(np.mean((pos - fit) ** 2)))


def test_accel_bias_gives_bt2_over_2():
    e = errors(NoiseModel(accel_bias_repeatability_ug=200.0), 4000, 1)
    pos = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT).apc_position_m
    b = e.accel_turn_on_bias_m_s2
    np.testing.assert_allclose(pos, b[:, None, :] * (TIME**2 / 2)[None, :, None], rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(pos[:, -1].std(axis=0), 200e-6 * G0 * T_AP**2 / 2, rtol=0.05)


def test_gyro_bias_gives_g_b_t3_over_6():
    e = errors(NoiseModel(gyro_bias_repeatability_deg_h=50.0), 4000, 2)
    nav = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT, keep_states=True)
    b = e.gyro_turn_on_bias_rad_s
    np.testing.assert_allclose(nav.attitude_rad, -b[:, None, :] * TIME[None, :, None], rtol=1e-9, atol=1e-18)
    closed = G0 * TIME**3 / 6
    # f × φ with φ = −b·t: x gets +g·b_y·t, y gets −g·b_x·t (t³/6 after two integrations); the
    # trapezoid position step adds at most g·b·t·dt²/12 (strapdown docstring).
    atol = G0 * np.abs(b).max() * T_AP * DT**2 / 12 * 1.001
    np.testing.assert_allclose(nav.position_m[:, :, 0], b[:, 1:2] * closed, rtol=0, atol=atol)
    np.testing.assert_allclose(nav.position_m[:, :, 1], -b[:, 0:1] * closed, rtol=0, atol=atol)
    assert not nav.position_m[:, :, 2].any()
    sigma_b = math.radians(50.0) / 3600
    np.testing.assert_allclose(nav.position_m[:, -1, :2].std(axis=0), sigma_b * closed[-1], rtol=0.05)


def test_vrw_endpoint_and_detrended_residual():
    n_vrw = 0.05 / 60.0  # m/s/√h → m/s²/√Hz
    e = errors(NoiseModel(accel_vrw_m_s_rt_h=0.05), 4000, 3)
    pos = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT).apc_position_m
    np.testing.assert_allclose(pos[:, -1].std(axis=0), n_vrw * math.sqrt(T_AP**3 / 3), rtol=0.05)
    x = pos[:, :, 0]
    assert residual_rms(x, 1) == pytest.approx(n_vrw * T_AP**1.5 / math.sqrt(420), rel=0.05)
    assert residual_rms(x, 2) == pytest.approx(n_vrw * T_AP**1.5 / math.sqrt(2520), rel=0.05)


def test_arw_endpoint_and_detrended_residual():
    n_arw = math.radians(0.5) / 60.0  # deg/√h → rad/s/√Hz
    e = errors(NoiseModel(gyro_arw_deg_rt_h=0.5), 4000, 4)
    pos = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT).apc_position_m
    np.testing.assert_allclose(pos[:, -1, :2].std(axis=0), G0 * n_arw * math.sqrt(T_AP**5 / 20), rtol=0.05)
    x = pos[:, :, 0]
    assert residual_rms(x, 1) == pytest.approx(G0 * n_arw * T_AP**2.5 * math.sqrt(17 / 30240), rel=0.05)
    assert residual_rms(x, 2) == pytest.approx(G0 * n_arw * T_AP**2.5 / math.sqrt(55440), rel=0.05)


def test_vertical_scale_factor_acts_like_bias_beta_g():
    e = errors(NoiseModel(accel_scale_factor_ppm=1000.0), 200, 5)
    pos = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT).apc_position_m
    beta = e.accel_scale_factor[:, 2]
    np.testing.assert_allclose(pos[:, :, 2], (beta * G0)[:, None] * TIME**2 / 2, rtol=1e-12)
    assert not pos[:, :, :2].any()  # horizontal axes see no specific force in level flight


def test_misalignment_couples_gravity():
    e = errors(NoiseModel(accel_misalignment_mrad=1.0), 200, 6)
    pos = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT).apc_position_m
    m = e.accel_misalignment_rad
    for axis in (0, 1):
        np.testing.assert_allclose(pos[:, :, axis], (m[:, axis, 2] * G0)[:, None] * TIME**2 / 2, rtol=1e-12)


def test_lever_arm_with_attitude_error():
    """APC 1 m above the IMU, initial pitch error φ_y: lever term d × φ = (−φ_y, 0, 0) plus the
    gravity coupling −g·φ_y·t²/2 along x."""
    trials = 50
    phi_y = np.random.default_rng(7).normal(0, 1e-3, trials)
    zeros = np.zeros((trials, N, 3))
    phi0 = np.zeros((trials, 3))
    phi0[:, 1] = phi_y
    nav = propagate_errors(zeros, zeros, DT, lever_arm_b_m=(0.0, 0.0, 1.0), phi0=phi0, keep_states=True)
    expected = -phi_y[:, None] * (1.0 + G0 * TIME**2 / 2)
    np.testing.assert_allclose(nav.apc_position_m[:, :, 0], expected, rtol=1e-12)
    # With gyro errors the lever term follows the attitude error at every sample.
    e = errors(NoiseModel(gyro_arw_deg_rt_h=1.0, gyro_bias_repeatability_deg_h=100.0), trials, 8)
    d = np.array([0.5, -0.2, 0.3])
    nav = propagate_errors(e.gyro_rad_s, e.accel_m_s2, DT, lever_arm_b_m=d, keep_states=True)
    np.testing.assert_allclose(nav.apc_position_m - nav.position_m, cross(d, nav.attitude_rad), atol=1e-15)


def test_initial_velocity_and_position_errors():
    zeros = np.zeros((3, N, 3))
    dv0 = np.array([[0.01, 0.0, -0.02]] * 3)
    dp0 = np.array([[1.0, 2.0, 3.0]] * 3)
    pos = propagate_errors(zeros, zeros, DT, dv0=dv0, dp0=dp0).apc_position_m
    np.testing.assert_allclose(pos, dp0[:, None, :] + dv0[:, None, :] * TIME[None, :, None])


def _random_inputs(trials, n, dt, seed):
    rng = np.random.default_rng(seed)
    gyro = rng.normal(0, 5e-6, (trials, 1, 3)) + rng.normal(0, 3e-5, (trials, n, 3)) / math.sqrt(dt) * 0.1
    accel = rng.normal(0, 1e-3, (trials, 1, 3)) + rng.normal(0, 5e-4, (trials, n, 3)) / math.sqrt(dt)
    phi0 = rng.normal(0, 1e-4, (trials, 3))
    return gyro, accel, phi0


def test_cumsum_discretisation_matches_exact_transition():
    """Flat-earth cumsum scheme = exact zero-order-hold transition of the same linear model."""
    gyro, accel, phi0 = _random_inputs(6, 801, DT, 9)
    d = (0.5, 0.0, 0.3)
    a = propagate_errors(gyro, accel, DT, phi0=phi0, lever_arm_b_m=d).apc_position_m
    b = propagate_errors_earth(gyro, accel, DT, speed_m_s=100.0, earth=False, phi0=phi0,
                               lever_arm_b_m=d).apc_position_m
    scale = np.linalg.norm(b, axis=2).max()
    assert np.abs(a - b).max() < 1e-5 * scale


@pytest.mark.parametrize("tc_s, rate, bound", [(60.0, 50.0, 0.02), (120.0, 50.0, 0.02)])
def test_flat_earth_adequate_up_to_minutes(tc_s, rate, bound):
    """Schuler, Earth-rate and transport-rate terms change the APC error by < 2 % for Tc ≤ 2 min
    (airborne, 200 m/s, 45° latitude, heading north-east)."""
    n, dt = int(tc_s * rate) + 1, 1.0 / rate
    gyro, accel, phi0 = _random_inputs(8, n, dt, 10)
    kw = dict(phi0=phi0, lever_arm_b_m=(0.5, 0.0, 0.3))
    flat = propagate_errors(gyro, accel, dt, **kw).apc_position_m
    full = propagate_errors_earth(gyro, accel, dt, speed_m_s=200.0, heading_rad=math.radians(45.0),
                                  **kw).apc_position_m
    rel = np.linalg.norm(full - flat, axis=2).max(axis=1) / np.linalg.norm(flat, axis=2).max(axis=1)
    assert rel.max() < bound


def test_flat_earth_breaks_down_at_half_an_hour():
    """At Tc = 30 min (a third of the Schuler period) the neglected terms are tens of percent."""
    tc_s, rate = 1800.0, 5.0
    n, dt = int(tc_s * rate) + 1, 1.0 / rate
    gyro, accel, phi0 = _random_inputs(4, n, dt, 11)
    flat = propagate_errors(gyro, accel, dt, phi0=phi0).apc_position_m
    full = propagate_errors_earth(gyro, accel, dt, speed_m_s=200.0, phi0=phi0).apc_position_m
    rel = np.linalg.norm(full - flat, axis=2).max(axis=1) / np.linalg.norm(flat, axis=2).max(axis=1)
    assert rel.min() > 0.15


def test_shape_errors():
    with pytest.raises(ValueError, match="shape"):
        propagate_errors(np.zeros((2, 10, 3)), np.zeros((2, 9, 3)), DT)
