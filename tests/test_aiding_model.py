"""Error-state model, discretisation, measurement Jacobians and flexure against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from budget import units as u
from budget.aiding_spec import DvlAiding, FlexureConfig, GnssAiding
from budget.aiding.flexure import (antenna_flexure_error, flexure_autocorrelation, flexure_blocks,
                                   simulate_flexure)
from budget.aiding.ins_error_model import (ImuErrorModel, NominalTrajectory, StateLayout,
                                           expm_batched, skew, van_loan)
from budget.aiding.measurements import DvlVelocity, GnssPosition
from budget.aiding.system import InitialUncertainty, build_system, simulate_truth


def test_skew_is_cross_product():
    rng = np.random.default_rng(0)
    a, b = rng.standard_normal((2, 5, 3))
    assert np.allclose(skew(a) @ b[..., None], np.cross(a, b)[..., None])


def test_van_loan_matches_white_acceleration_closed_form():
    # ẋ = [[0,1],[0,0]] x + [0, w]: Qd = q [[dt³/3, dt²/2], [dt²/2, dt]]
    F = np.array([[0.0, 1.0], [0.0, 0.0]])
    q, dt = 0.7, 0.3
    phi, qd = van_loan(F, np.diag([0.0, q]), dt)
    assert np.allclose(phi, [[1, dt], [0, 1]])
    assert np.allclose(qd, q * np.array([[dt ** 3 / 3, dt ** 2 / 2], [dt ** 2 / 2, dt]]), rtol=1e-12)


def test_batched_expm_matches_scipy():
    rng = np.random.default_rng(1)
    M = rng.standard_normal((7, 12, 12)) * np.array([0.05, 0.5, 3.0, 0.01, 1, 2, 0.1])[:, None, None]
    E = expm_batched(M)
    ref = np.stack([expm(m) for m in M])
    assert np.allclose(E, ref, rtol=1e-11, atol=1e-12)


def _bias_only_truth(gyro_bias=0.0, accel_bias=0.0, n=401, dt=0.05):
    """One noiseless trial whose only error is a known bias on the x axis."""
    imu = ImuErrorModel(gyro_bias_rad_s=1e-6, accel_bias_m_s2=1e-6)
    traj = NominalTrajectory.straight_level(50.0, dt, n)
    sys_ = build_system(traj, imu, [], InitialUncertainty(0.0, 0.0, 0.0))
    lay = sys_.layout["truth"]
    phi, _ = sys_.transitions("truth", 0, 1)
    x = np.zeros(lay.n)
    x[lay.slice("gyro_bias").start] = gyro_bias
    x[lay.slice("accel_bias").start] = accel_bias
    out = [x]
    for _ in range(n - 1):
        out.append(phi[0] @ out[-1])
    return traj.time_s, np.array(out), lay


def test_gyro_bias_gives_g_b_t3_over_6_with_stated_sign():
    b = u.deg_h_to_rad_s(10.0)
    t, x, lay = _bias_only_truth(gyro_bias=b)
    # φ_x = −b t; δv_y = −g b t²/2; δp_y = −g b t³/6 (module docstring, DESIGN.md §2)
    assert np.allclose(x[:, lay.slice("att")][:, 0], -b * t, rtol=1e-10, atol=1e-18)
    assert np.allclose(x[:, lay.slice("vel")][:, 1], -u.G0 * b * t ** 2 / 2, rtol=1e-9, atol=1e-15)
    assert np.allclose(x[:, lay.slice("pos")][:, 1], -u.G0 * b * t ** 3 / 6, rtol=1e-9, atol=1e-15)


def test_accel_bias_gives_b_t2_over_2():
    b = u.ug_to_m_s2(300.0)
    t, x, lay = _bias_only_truth(accel_bias=b)
    assert np.allclose(x[:, lay.slice("pos")][:, 0], b * t ** 2 / 2, rtol=1e-10, atol=1e-15)


def test_free_inertial_matches_motion_engine():
    """Independent implementation: budget.nav.strapdown integrates the same equations by sums."""
    strapdown = pytest.importorskip("budget.nav.strapdown")
    bg, ba, dt, n = u.deg_h_to_rad_s(np.array([3.0, -2.0, 1.0])), np.array([1e-3, -2e-3, 5e-4]), 0.01, 1001
    nav = strapdown.propagate_errors(np.broadcast_to(bg, (1, n, 3)), np.broadcast_to(ba, (1, n, 3)),
                                     dt, keep_states=True)
    imu = ImuErrorModel(gyro_bias_rad_s=1e-6, accel_bias_m_s2=1e-6)
    traj = NominalTrajectory.straight_level(100.0, dt, n)
    s = build_system(traj, imu, [], InitialUncertainty(0.0, 0.0, 0.0))
    lay = s.layout["truth"]
    phi, _ = s.transitions("truth", 0, 1)
    x = np.zeros(lay.n)
    x[lay.slice("gyro_bias")], x[lay.slice("accel_bias")] = bg, ba
    pos = []
    for _ in range(n):
        pos.append(x[lay.slice("pos")])
        x = phi[0] @ x
    scale = np.abs(nav.position_m[0, -1]).max()
    assert np.allclose(np.array(pos), nav.position_m[0], atol=1e-6 * scale)


@pytest.mark.parametrize("seed", [0, 1])
def test_gnss_lever_arm_jacobian_matches_rotation(seed):
    """H_att = [(C l)×] is the derivative of (Ĉ − C) l with Ĉ = (I − [φ×]) C = exp(−[φ×]) C."""
    rng = np.random.default_rng(seed)
    C = Rotation.random(random_state=seed).as_matrix()
    lever = rng.standard_normal(3)
    traj = NominalTrajectory.from_arrays(0.1, np.tile([0, 0, u.G0], (2, 1)), np.stack([C, C]),
                                         np.zeros((2, 3)))
    m = GnssPosition(GnssAiding(rate_hz=1, sigma_m=1, lever_arm_m=tuple(lever)))
    lay = StateLayout((("pos", 3), ("vel", 3), ("att", 3)))
    H = m.H(lay, traj, 0)[:, lay.slice("att")]
    phi = 1e-6 * rng.standard_normal(3)
    nonlinear = Rotation.from_rotvec(-phi).as_matrix() @ C @ lever - C @ lever
    assert np.allclose(H @ phi, nonlinear, rtol=1e-5, atol=1e-15)


def test_dvl_jacobian_matches_rotation():
    """z = v̂ − Ĉ v_b: the attitude part is −[v_n×] φ and the bias part −C b."""
    rng = np.random.default_rng(3)
    C = Rotation.random(random_state=3).as_matrix()
    v_n = np.array([1.5, 0.2, -0.1])
    traj = NominalTrajectory.from_arrays(0.1, np.tile([0, 0, u.G0], (2, 1)), np.stack([C, C]),
                                         np.stack([v_n, v_n]))
    m = DvlVelocity(DvlAiding(rate_hz=1, sigma_m_s=0.01, bias_sigma_m_s=0.01))
    lay = StateLayout((("pos", 3), ("vel", 3), ("att", 3), ("dvl0_bias", 3)))
    H = m.H(lay, traj, 0)
    phi, bias = 1e-6 * rng.standard_normal(3), 1e-3 * rng.standard_normal(3)
    v_b = C.T @ v_n
    nonlinear = v_n - Rotation.from_rotvec(-phi).as_matrix() @ C @ (v_b + bias)
    assert np.allclose(H[:, lay.slice("att")] @ phi + H[:, lay.slice("dvl0_bias")] @ bias,
                       nonlinear, rtol=1e-5, atol=1e-15)


def test_measurement_epochs_follow_rate():
    m = GnssPosition(GnssAiding(rate_hz=10, sigma_m=1))
    assert np.array_equal(m.epochs(101, 0.01), np.arange(10, 101, 10))
    m3 = GnssPosition(GnssAiding(rate_hz=3, sigma_m=1))
    ep = m3.epochs(1001, 0.01)
    assert np.all(np.abs(np.diff(ep) - 100 / 3) <= 1) and ep[0] == 33


def test_flexure_stationary_moments_closed_form():
    mode = FlexureConfig(frequency_hz=2.0, damping_ratio=0.1, amplitude_m=(0.01, 0.0, 0.03))
    F, Qc, P = flexure_blocks(mode)
    # stationary covariance solves F P + P Fᵀ + Qc = 0
    assert np.allclose(F @ P + P @ F.T + Qc, 0.0, atol=1e-12)
    w = 2 * math.pi * 2.0
    assert np.isclose(P[3, 3], w * w * 1e-4) and np.isclose(P[5, 5], w * w * 9e-4)


def test_flexure_autocorrelation_of_simulation(seed=5):
    mode = FlexureConfig(frequency_hz=1.0, damping_ratio=0.2, amplitude_m=(0.0, 0.0, 0.02))
    dt = 0.02
    h = simulate_flexure(mode, dt, 3000, 40, np.random.default_rng(seed))
    d = h.displacement_m[..., 2]
    lags = np.array([0, 10, 25, 50])
    emp = np.array([np.mean(d[:, : d.shape[1] - k] * d[:, k:]) for k in lags])
    ref = flexure_autocorrelation(mode, lags * dt)[:, 2]
    # 40 trials × 60 s ≈ 1000 correlation times: ≈ 5 % sampling error; allow 15 % of σ²
    assert np.allclose(emp, ref, atol=0.15 * 0.02 ** 2)
    assert np.allclose(h.displacement_m[..., :2], 0.0)


def test_antenna_flexure_error_rotates_to_nav():
    d = np.zeros((1, 2, 3))
    d[..., 0] = 0.01
    C = Rotation.from_euler("z", 90, degrees=True).as_matrix()
    out = antenna_flexure_error(d, C)
    assert np.allclose(out[0, :, 1], 0.01) and np.allclose(out[0, :, 0], 0.0, atol=1e-15)


def test_truth_simulation_reproduces_initial_covariance():
    imu = ImuErrorModel(gyro_bias_rad_s=1e-5, accel_bias_m_s2=1e-3)
    traj = NominalTrajectory.straight_level(50.0, 0.1, 3)
    s = build_system(traj, imu, [], InitialUncertainty(2.0, 0.5, 1e-3))
    x = simulate_truth(s, 20000, np.random.default_rng(7))
    sd = x[:, 0].std(axis=0)
    expect = np.sqrt(np.diag(s.P0("truth")))
    assert np.allclose(sd, expect, rtol=0.03)
