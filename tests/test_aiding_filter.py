"""Kalman filter and RTS smoother against closed forms and independent implementations."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from budget.aiding_spec import (DvlAiding, FlexureConfig, GnssAiding, MasterInsAiding,
                                  StarTrackerAiding)
from budget.aiding.consistency import average_bounds, nees_report, nis_report
from budget.aiding.ins_error_model import ImuErrorModel, NominalTrajectory
from budget.aiding.kalman import joseph_update, run_kalman
from budget.aiding.rts import run_rts
from budget.aiding.system import (InitialUncertainty, build_system, simulate_measurements,
                                  simulate_truth)

NOISY_IMU = ImuErrorModel(gyro_arw_rad_s_rt_hz=1e-4, accel_vrw_m_s2_rt_hz=5e-3)


def test_random_constant_position_is_the_weighted_mean():
    """No process noise: after n fixes P = 1/(1/P0 + n/σ²) and x̂ = Σz/σ² · P (closed form)."""
    traj = NominalTrajectory.straight_level(10.0, 0.1, 51)
    s = build_system(traj, ImuErrorModel(), [GnssAiding(rate_hz=2, sigma_m=1.5)],
                     InitialUncertainty(3.0, 0.0, 0.0))
    rng = np.random.default_rng(0)
    truth = simulate_truth(s, 7, rng)
    z = simulate_measurements(s, truth, rng)
    f = run_kalman(s, z)
    ep = s.epochs["gnss0"]
    n = np.arange(1, ep.size + 1)
    P = 1.0 / (1 / 9.0 + n / 1.5 ** 2)
    assert np.allclose(f.p_diag[ep, 0], P, rtol=1e-10)
    xhat = np.cumsum(z["gnss0"][:, :, 0], axis=1) / 1.5 ** 2 * P
    assert np.allclose(f.estimate[:, ep, 0], xhat, rtol=1e-9, atol=1e-12)


def test_joseph_form_equals_standard_form_for_optimal_gain():
    rng = np.random.default_rng(1)
    A = rng.standard_normal((6, 6))
    P = A @ A.T + np.eye(6)
    H = rng.standard_normal((2, 6))
    R = np.diag([0.5, 2.0])
    K, S, Pj = joseph_update(P, H, R)
    assert np.allclose(Pj, (np.eye(6) - K @ H) @ P, atol=1e-10)
    assert np.allclose(S, H @ P @ H.T + R)


def test_steady_state_matches_discrete_riccati():
    """Long run with GNSS + star tracker → prior covariance at an epoch = DARE solution."""
    dt, m = 0.1, 5   # updates every 5 steps
    traj = NominalTrajectory.straight_level(50.0, dt, 2001)
    aid = [GnssAiding(rate_hz=2, sigma_m=0.5), StarTrackerAiding(rate_hz=2, sigma_arcsec=20)]
    s = build_system(traj, NOISY_IMU, aid, InitialUncertainty(5.0, 1.0, 1e-2))
    f = run_kalman(s, {k: np.zeros((1, len(v), 3)) for k, v in s.epochs.items()})
    phi, qd = s.transitions("filter", 0, 1)
    Pm, Qm = np.eye(9), np.zeros((9, 9))
    for _ in range(m):
        Qm = phi[0] @ Qm @ phi[0].T + qd[0]
        Pm = phi[0] @ Pm
    H = np.vstack([s.H("filter", mm, 0) for mm in s.measurements])
    R = np.diag([0.25] * 3 + [(20 * np.pi / 180 / 3600) ** 2] * 3)
    X = solve_discrete_are(Pm.T, H.T, Qm, R)
    assert np.allclose(f.p_prior[-2], X, rtol=1e-6, atol=1e-14)


def _batch_smoother(s, z):
    """Independent fixed-interval MAP estimate: one sparse least-squares problem over all states."""
    N, n = s.n_samples, s.layout["filter"].n
    phi, qd = s.transitions("filter", 0, 1)
    Qi = np.linalg.inv(qd[0])
    J = np.zeros((N * n, N * n))
    blk = lambda k: slice(k * n, (k + 1) * n)
    J[blk(0), blk(0)] += np.linalg.inv(s.P0("filter"))
    for k in range(N - 1):
        A = np.hstack([-phi[0], np.eye(n)])
        idx = np.r_[blk(k), blk(k + 1)]
        J[np.ix_(idx, idx)] += A.T @ Qi @ A
    T = next(iter(z.values())).shape[0]
    b = np.zeros((T, N * n))
    for m in s.measurements:
        H = s.H("filter", m, 0)
        Ri = np.linalg.inv(m.R_white(s.trajectory, 0))
        for j, k in enumerate(s.epochs[m.name]):
            J[blk(k), blk(k)] += H.T @ Ri @ H
            b[:, blk(k)] += z[m.name][:, j] @ (Ri @ H)
    x = np.linalg.solve(J, b.T).T.reshape(T, N, n)
    cov = np.linalg.inv(J)
    var = np.array([np.diag(cov[blk(k), blk(k)]) for k in range(N)])
    return x, var


def test_rts_equals_batch_least_squares():
    traj = NominalTrajectory.straight_level(50.0, 0.1, 41)
    aid = [GnssAiding(rate_hz=2, sigma_m=0.3), StarTrackerAiding(rate_hz=1, sigma_arcsec=30)]
    s = build_system(traj, NOISY_IMU, aid, InitialUncertainty(1.0, 0.2, 1e-3))
    rng = np.random.default_rng(2)
    truth = simulate_truth(s, 3, rng)
    z = simulate_measurements(s, truth, rng)
    sm = run_rts(s, run_kalman(s, z))
    xb, varb = _batch_smoother(s, z)
    assert np.allclose(sm.estimate, xb, rtol=1e-6, atol=1e-9)
    assert np.allclose(sm.p_diag, varb, rtol=1e-6, atol=1e-15)


def test_rts_without_measurements_is_the_prediction():
    traj = NominalTrajectory.straight_level(50.0, 0.5, 4500)   # > MAX_INTERVAL: several checkpoints
    s = build_system(traj, NOISY_IMU, [], InitialUncertainty(1.0, 0.2, 1e-3))
    x0 = np.random.default_rng(3).standard_normal((2, 9))
    f = run_kalman(s, {}, x0=x0)
    sm = run_rts(s, f)
    assert len(f.checkpoints) >= 3
    assert np.allclose(sm.estimate, f.estimate, rtol=1e-9, atol=1e-9)


def test_latency_output_uses_only_arrived_measurements():
    dt, lat = 0.1, 0.5
    traj = NominalTrajectory.straight_level(50.0, dt, 201)
    s = build_system(traj, NOISY_IMU, [GnssAiding(rate_hz=1, sigma_m=0.5, latency_s=lat)],
                     InitialUncertainty(2.0, 0.3, 1e-3))
    rng = np.random.default_rng(4)
    truth = simulate_truth(s, 4, rng)
    f = run_kalman(s, simulate_measurements(s, truth, rng))
    phi = s.transitions("filter", 0, 1)[0][0]
    ck, L = list(f.checkpoints), int(round(lat / dt))
    for i in (14, 15, 16, 19, 57, 103):
        last = max(k for k in ck if k + L <= i)   # latest checkpoint whose data has arrived
        expect = f.x_post[:, ck.index(last)] @ np.linalg.matrix_power(phi, i - last).T
        assert np.allclose(f.realtime[:, i], expect[:, :9], rtol=1e-9, atol=1e-12)
    # at validity time the estimate already holds the measurement
    assert not np.allclose(f.realtime[:, 10], f.estimate[:, 10])


def _consistent_system(n=3001, dt=0.1):
    imu = ImuErrorModel(gyro_bias_rad_s=5e-6, gyro_gm_sigma_rad_s=3e-6, gyro_gm_tau_s=60.0,
                        gyro_arw_rad_s_rt_hz=2e-5, accel_bias_m_s2=2e-3, accel_vrw_m_s2_rt_hz=2e-3)
    traj = NominalTrajectory.straight_level(100.0, dt, n)
    flex = FlexureConfig(frequency_hz=1.0, damping_ratio=0.2, amplitude_m=(0.01, 0.01, 0.02))
    aid = [MasterInsAiding(rate_hz=1, sigma_position_m=0.5, sigma_velocity_m_s=0.02,
                           lever_arm_m=(1.0, 2.0, 0.0), flexure=flex)]
    return imu, traj, aid


def test_filter_and_smoother_are_consistent_nees_nis():
    imu, traj, aid = _consistent_system()
    s = build_system(traj, imu, aid, InitialUncertainty(3.0, 0.1, 2e-3))
    assert s.consistent()
    rng = np.random.default_rng(5)
    truth = simulate_truth(s, 200, rng)
    z = simulate_measurements(s, truth, rng)
    f = run_kalman(s, z)
    ck = f.checkpoints
    kf = nees_report(truth[:, ck] - f.x_post, f.p_post)
    sm = run_rts(s, f)
    rts = nees_report(truth[:, ck] - sm.x_smooth, sm.p_smooth)
    nis = nis_report(f.innovations["master0"])
    for rep in (kf, rts, nis):
        # 95 % two-sided interval per epoch; epochs are correlated, so ask for ≥ 85 % inside
        assert rep.fraction_inside >= 0.85, rep.summary()
        assert abs(rep.overall_mean / rep.dof - 1) < 0.05, rep.summary()


def test_consistent_on_a_turning_trajectory_with_gnss_and_dvl():
    """Time-varying F and H (S-turns), GNSS lever arm and Gauss–Markov error, DVL GM bias."""
    from budget.seeds.transfer_alignment import TransferParams, s_turn_trajectory
    traj = s_turn_trajectory(TransferParams(rate_hz=5, duration_s=200, imaging_s=40, turn_period_s=40))
    imu = ImuErrorModel(gyro_bias_rad_s=2e-5, gyro_arw_rad_s_rt_hz=1e-4, accel_bias_m_s2=3e-3,
                        accel_vrw_m_s2_rt_hz=3e-3)
    aid = [GnssAiding(rate_hz=1, sigma_m=0.3, lever_arm_m=(0.5, -1.0, 0.8), correlated_sigma_m=0.5,
                      correlation_time_s=100.0),
           DvlAiding(rate_hz=5, sigma_m_s=0.02, bias_sigma_m_s=0.01, bias_correlation_time_s=50.0)]
    s = build_system(traj, imu, aid, InitialUncertainty(2.0, 0.2, 5e-3))
    assert not s.trajectory.constant and s.layout["filter"].has("dvl0_bias")
    rng = np.random.default_rng(9)
    truth = simulate_truth(s, 150, rng)
    f = run_kalman(s, simulate_measurements(s, truth, rng))
    for rep in (nees_report(truth[:, f.checkpoints] - f.x_post, f.p_post),
                nis_report(f.innovations["gnss0"]), nis_report(f.innovations["dvl0"])):
        assert rep.fraction_inside >= 0.85, rep.summary()
        assert abs(rep.overall_mean / rep.dof - 1) < 0.05, rep.summary()


def test_nees_flags_an_overconfident_filter():
    imu, traj, aid = _consistent_system(n=1001)
    optimistic = ImuErrorModel(gyro_bias_rad_s=5e-7, gyro_gm_sigma_rad_s=3e-7, gyro_gm_tau_s=60.0,
                               gyro_arw_rad_s_rt_hz=2e-6, accel_bias_m_s2=2e-4,
                               accel_vrw_m_s2_rt_hz=2e-4)
    s = build_system(traj, imu, aid, InitialUncertainty(3.0, 0.1, 2e-3), filter_imu=optimistic)
    assert not s.consistent()
    rng = np.random.default_rng(6)
    truth = simulate_truth(s, 100, rng)
    f = run_kalman(s, simulate_measurements(s, truth, rng))
    rep = nees_report(truth[:, f.checkpoints] - f.x_post, f.p_post)
    assert rep.overall_mean > average_bounds(rep.dof, 100)[1]
    assert rep.fraction_inside < 0.5


def test_unmodelled_flexure_inflates_r():
    imu, traj, aid = _consistent_system(n=11)
    aid_off = [aid[0].model_copy(update={"estimate_flexure": False})]
    s_on, s_off = build_system(traj, imu, aid), build_system(traj, imu, aid_off)
    assert s_off.layout["filter"].n == s_on.layout["filter"].n - 6
    m = s_off.measurements[0]
    R = s_off.R_filter(m, 0)
    w = 2 * np.pi
    assert np.allclose(np.diag(R), [0.25 + 1e-4, 0.25 + 1e-4, 0.25 + 4e-4,
                                    4e-4 + w * w * 1e-4, 4e-4 + w * w * 1e-4, 4e-4 + w * w * 4e-4])


@pytest.mark.parametrize("T", [1, 5])
def test_results_do_not_depend_on_batch_composition(T):
    """Trial i's estimate is the same whether it runs alone or in a batch (shared P and K)."""
    imu, traj, aid = _consistent_system(n=301)
    s = build_system(traj, imu, aid)
    rng = np.random.default_rng(8)
    truth = simulate_truth(s, T, rng)
    z = simulate_measurements(s, truth, rng)
    f = run_kalman(s, z)
    f0 = run_kalman(s, {k: v[:1] for k, v in z.items()})
    assert np.allclose(f.estimate[:1], f0.estimate, rtol=1e-12, atol=1e-15)


def test_blended_output_feeds_each_update_in_with_its_time_constant():
    """Random-constant position (Φ = I on position, no process noise): two critically damped
    stages leave of an update Δ_j, m = k − k_j ≥ 0 steps later, the pending part
    Δ_j·a^{m−1}·(a + m(1 − a)), a = e^{−1/τ} (closed form); the output has no step at fixes."""
    traj = NominalTrajectory.straight_level(10.0, 0.1, 81)
    s = build_system(traj, ImuErrorModel(), [GnssAiding(rate_hz=2, sigma_m=1.5)],
                     InitialUncertainty(3.0, 0.0, 0.0))
    rng = np.random.default_rng(2)
    truth = simulate_truth(s, 5, rng)
    z = simulate_measurements(s, truth, rng)
    tau_steps = 12.0
    f = run_kalman(s, z, blend_steps=tau_steps)
    ep = s.epochs["gnss0"]
    x = f.estimate[..., 0]
    delta = x[:, ep] - x[:, ep - 1]                          # the update at each epoch
    k = np.arange(x.shape[1])
    lag = k[None, :] - ep[:, None]                           # (E, N)
    a = np.exp(-1.0 / tau_steps)
    m = np.clip(lag, 0, None)
    weight = np.where(lag >= 0, a ** (m - 1.0) * (a + m * (1 - a)), 0.0)
    expect = x - delta @ weight
    np.testing.assert_allclose(f.blended[..., 0], expect, rtol=0, atol=1e-12)
    # at a fix the output changes by a small fraction of what is pending, not by Δ
    jump_rt = np.abs(np.diff(f.estimate[..., 0], axis=1)[:, ep - 1]).mean()
    jump_ff = np.abs(np.diff(f.blended[..., 0], axis=1)[:, ep - 1]).mean()
    assert jump_ff < 0.1 * jump_rt
    assert run_kalman(s, z).blended is None
