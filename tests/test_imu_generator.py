"""IMU error generator: every term against its closed-form Allan deviation / statistics.

Allan deviations are estimated with ``allantools.oadev`` (an independent implementation) and
averaged over trials as Allan *variances*. Tolerances are stated per test; they are ≥ 4 standard
errors of the estimate for the sample sizes used.
"""

from __future__ import annotations

import math

import allantools
import numpy as np
import pytest

from budget.errors import InputError
from budget.imu.flicker import avar_from_acov, flicker_bank, gm_acov
from budget.imu.generator import generate_imu_errors, simulate_static_log
from budget.imu.noise_model import NoiseModel
from budget.units import G0

RATE = 100.0
DT = 1.0 / RATE


def model(*effects, **fields) -> NoiseModel:
    m = NoiseModel(**fields)
    for e in effects:
        m = m.with_effect(e)
    return m


def fx(name, channel, **params):
    return {"name": name, "channel": channel, "params": params}


def mean_adev(series: np.ndarray, taus: np.ndarray) -> np.ndarray:
    """√(mean over trials of the overlapping Allan variance) at ``taus`` (s)."""
    avar = []
    for row in series:
        t, ad, _, _ = allantools.oadev(row, rate=RATE, data_type="freq", taus=taus)
        assert np.allclose(t, taus)
        avar.append(ad**2)
    return np.sqrt(np.mean(avar, axis=0))


def test_white_noise_adev():
    n = 1e-3  # rad/s/√Hz
    e = generate_imu_errors(model(fx("white_noise", "gyro_x", density=n)), 40, 20_000, RATE,
                            np.random.default_rng(1))
    taus = np.array([0.01, 0.1, 1.0])
    adev = mean_adev(e.gyro_rad_s[:, :, 0], taus)
    np.testing.assert_allclose(adev, n / np.sqrt(taus), rtol=0.04)  # SE ≤ 0.7 %
    assert not e.gyro_rad_s[:, :, 1:].any() and not e.accel_m_s2.any()


def test_catalog_vrw_is_white_noise_on_all_accels():
    part = NoiseModel(accel_vrw_m_s_rt_h=0.06)
    e = generate_imu_errors(part, 200, 2000, RATE, np.random.default_rng(2))
    sigma = e.accel_m_s2.std(axis=(0, 1))
    np.testing.assert_allclose(sigma, 0.06 / 60.0 * math.sqrt(RATE), rtol=0.01)  # SE 0.03 %


def test_rate_random_walk_adev():
    k = 2e-5
    e = generate_imu_errors(model(fx("rate_random_walk", "accel_y", K=k)), 60, 8000, RATE,
                            np.random.default_rng(3))
    taus = np.array([0.5, 2.0, 8.0])
    np.testing.assert_allclose(mean_adev(e.accel_m_s2[:, :, 1], taus), k * np.sqrt(taus / 3), rtol=0.08)


def test_rate_ramp_adev_is_exact():
    r = 3e-6
    e = generate_imu_errors(model(fx("rate_ramp", "gyro_z", R=r)), 1, 5000, RATE, np.random.default_rng(0))
    np.testing.assert_allclose(e.gyro_rad_s[0, :, 2], r * np.arange(5000) * DT)
    taus = np.array([0.1, 1.0, 10.0])
    np.testing.assert_allclose(mean_adev(e.gyro_rad_s[:, :, 2], taus), r * taus / math.sqrt(2), rtol=1e-9)


def test_exact_avar_from_autocovariance():
    """avar_from_acov against closed forms: white noise σ²/m; a GM process at τ ≫ dt."""
    m = np.array([1, 4, 50])
    white = avar_from_acov(lambda k: np.where(k == 0, 2.0, 0.0), m, DT)
    np.testing.assert_allclose(white, 2.0 / m, rtol=1e-12)
    sigma2, tau_c, tau = 1.0, 0.5, np.array([2.0, 10.0])
    gm = avar_from_acov(lambda k: gm_acov(k, DT, [tau_c], [sigma2]), (tau / DT).astype(int), DT)
    closed = 2 * sigma2 * tau_c / tau * (1 - tau_c / (2 * tau) * (3 - 4 * np.exp(-tau / tau_c)
                                                                   + np.exp(-2 * tau / tau_c)))
    np.testing.assert_allclose(gm, closed, rtol=0.01)  # sampled vs continuous averaging


def test_flicker_bank_floor_is_0664_b():
    """The documented GM sum has the IEEE flicker Allan floor B·√(2 ln2/π) (exact AVAR)."""
    b = 1.0
    tau, var = flicker_bank(b, DT, 600.0)
    m = np.unique(np.geomspace(3, 30_000, 25).astype(int))  # 0.03 s … 300 s = record/2
    adev = np.sqrt(avar_from_acov(lambda k: gm_acov(k, DT, tau, var), m, DT))
    np.testing.assert_allclose(adev, 0.6643 * b, rtol=0.01)


@pytest.mark.slow
def test_bias_instability_adev_by_simulation():
    b = 1e-5
    e = generate_imu_errors(model(fx("bias_instability", "gyro_y", B=b)), 24, 30_000, RATE,
                            np.random.default_rng(4))
    taus = np.array([0.05, 0.5, 5.0, 20.0])
    adev = mean_adev(e.gyro_rad_s[:, :, 1], taus)
    # 24 records of 300 s: SE of the Allan variance ≈ 5 % at 20 s (edf ≈ 24·13); 12 % on ADEV.
    np.testing.assert_allclose(adev, 0.6643 * b, rtol=0.12)
    np.testing.assert_allclose(adev[:3], 0.6643 * b, rtol=0.05)


def test_gauss_markov_autocovariance_and_adev():
    sigma, tau_c = 2e-4, 0.5
    e = generate_imu_errors(model(fx("gauss_markov", "accel_x", tau_s=tau_c, sigma=sigma)), 100, 4000,
                            RATE, np.random.default_rng(5))
    x = e.accel_m_s2[:, :, 0]
    # Stationary from the first sample (exact synthesis): variance σ² at t = 0 and at the end.
    assert x[:, 0].std() == pytest.approx(sigma, rel=0.3)  # 100 samples: SE 7 %
    assert x.var() == pytest.approx(sigma**2, rel=0.06)
    lag = int(tau_c / DT)
    acf = np.mean(x[:, :-lag] * x[:, lag:])
    assert acf == pytest.approx(sigma**2 * math.exp(-1.0), rel=0.08)
    taus = np.array([0.1, 0.5, 2.0, 5.0])
    q2 = 2 * sigma**2 / tau_c  # continuous GM: AVAR = q²T²/τ·[1 − T/(2τ)(3 − 4e^{−τ/T} + e^{−2τ/T})]
    closed = q2 * tau_c**2 / taus * (1 - tau_c / (2 * taus) * (3 - 4 * np.exp(-taus / tau_c)
                                                              + np.exp(-2 * taus / tau_c)))
    np.testing.assert_allclose(mean_adev(x, taus), np.sqrt(closed), rtol=0.08)


def test_lowpass_shapes_white_noise_as_a_first_order_filter():
    """White σ² through y_k = (1 − a)y_{k−1} + a·x_k: variance σ²·a/(2 − a), lag-k correlation
    (1 − a)^k (AR(1)), Allan deviation from the filtered spectrum (closed-form kernel)."""
    from budget.gap.theory import avar_from_psd
    from budget.imu.effects import lowpass_coefficient, lowpass_gain2

    dens, fc = 1e-3, 12.0
    e = generate_imu_errors(model(fx("white_noise", "gyro_y", density=dens), fx("lowpass", "gyro_y", cutoff_hz=fc)),
                            40, 20_000, RATE, np.random.default_rng(21))
    x = e.gyro_rad_s[:, 100:, 1]  # past the ≈ 1/a-sample start-up transient
    a, s2 = lowpass_coefficient(fc, DT), dens**2 * RATE
    # 800k samples: SE of the variance ≈ 0.3 %, of the lag-k correlation ≈ 0.2 %
    assert x.var() == pytest.approx(s2 * a / (2.0 - a), rel=0.02)
    for lag in (1, 3):
        r = np.mean(x[:, :-lag] * x[:, lag:]) / x.var()
        assert r == pytest.approx((1.0 - a) ** lag, abs=0.01)
    taus = np.array([0.01, 0.02, 0.05, 0.2, 1.0])
    freq = np.fft.rfftfreq(1 << 14, DT)
    closed = avar_from_psd(2.0 * s2 * DT * lowpass_gain2(freq, fc, DT), freq, np.rint(taus * RATE), DT)
    np.testing.assert_allclose(mean_adev(x, taus), np.sqrt(closed), rtol=0.03)
    assert not e.gyro_rad_s[:, :, [0, 2]].any()


def test_white_plus_gauss_markov_on_one_channel():
    """White noise and a coloured term on the same channel are drawn together (one circulant
    pass): variance σ_w² + σ_gm², lag-k autocovariance σ_gm²·e^{−k·dt/τ} (white adds nothing)."""
    dens, sigma, tau_c = 5e-5, 5e-4, 0.2  # per-sample white σ = GM σ
    m = model(fx("white_noise", "gyro_z", density=dens), fx("gauss_markov", "gyro_z", tau_s=tau_c, sigma=sigma),
              fx("white_noise", "gyro_x", density=dens))
    e = generate_imu_errors(m, 200, 2000, RATE, np.random.default_rng(14))
    x = e.gyro_rad_s[:, :, 2]
    # 400k samples, ≈ 10k independent GM correlation times: SE ≈ 1.5 % (variance), 2–3 % (acov)
    assert x.var() == pytest.approx(dens**2 * RATE + sigma**2, rel=0.06)
    for lag in (1, 20):
        acov = np.mean(x[:, :-lag] * x[:, lag:])
        assert acov == pytest.approx(sigma**2 * math.exp(-lag * DT / tau_c), rel=0.12)
    assert e.gyro_rad_s[:, :, 0].std() == pytest.approx(dens * math.sqrt(RATE), rel=0.01)
    assert not e.gyro_rad_s[:, :, 1].any()


def test_sinusoid_adev_and_amplitude():
    a, f = 1e-3, 2.0
    e = generate_imu_errors(model(fx("sinusoid", "gyro_x", frequency_hz=f, amplitude=a)), 20, 4000, RATE,
                            np.random.default_rng(6))
    x = e.gyro_rad_s[:, :, 0]
    np.testing.assert_allclose(np.abs(x).max(axis=1), a, rtol=2e-3)
    taus = np.array([0.05, 0.2, 0.35])
    closed = a * np.sin(np.pi * f * taus) ** 2 / (np.pi * f * taus)
    np.testing.assert_allclose(mean_adev(x, taus), closed, rtol=0.03)


def test_quantization_adev_and_bounded_integral():
    q_coeff = 2e-6
    base = model(fx("white_noise", "gyro_z", density=1e-4))  # moves by ≫ one quantum per sample
    quant = base.with_effect(fx("quantization", "gyro_z", Q=q_coeff))
    e0 = generate_imu_errors(base, 20, 5000, RATE, np.random.default_rng(7))
    e1 = generate_imu_errors(quant, 20, 5000, RATE, np.random.default_rng(7))
    dq = e1.gyro_rad_s[:, :, 2] - e0.gyro_rad_s[:, :, 2]
    quantum = math.sqrt(12) * q_coeff
    assert np.abs(np.cumsum(dq, axis=1) * DT).max() <= quantum * (1 + 1e-9)
    taus = np.array([0.01, 0.1, 1.0])
    np.testing.assert_allclose(mean_adev(dq, taus), math.sqrt(3) * q_coeff / taus, rtol=0.05)


def test_temperature_sensitivity_default_and_given():
    c = 1e-4
    mdl = model(fx("temperature_sensitivity", "accel_z", coefficient=c))
    t = np.arange(3000) * DT
    e = generate_imu_errors(mdl, 2, 3000, RATE, np.random.default_rng(0))
    np.testing.assert_allclose(e.accel_m_s2[0, :, 2], c * 0.5 / 60.0 * t, atol=1e-15)
    temp = 20 + 3 * np.sin(t)
    e = generate_imu_errors(mdl, 2, 3000, RATE, np.random.default_rng(0), temp_c=temp)
    np.testing.assert_allclose(e.accel_m_s2[1, :, 2], c * (temp - 20), atol=1e-15)


def test_outliers_fraction_and_size():
    e = generate_imu_errors(model(fx("outliers", "gyro_y", rate=0.01, magnitude=0.5)), 50, 4000, RATE,
                            np.random.default_rng(8))
    x = e.gyro_rad_s[:, :, 1]
    hits = x != 0
    assert set(np.unique(x[hits])) == {-0.5, 0.5}
    n = x.size
    assert abs(hits.sum() - 0.01 * n) < 5 * math.sqrt(0.01 * 0.99 * n)


def test_turn_on_bias_is_constant_per_trial():
    e = generate_imu_errors(NoiseModel(accel_bias_repeatability_ug=100.0), 4000, 50, RATE,
                            np.random.default_rng(9))
    x = e.accel_m_s2
    assert np.all(x == x[:, :1])
    np.testing.assert_allclose(x[:, 0].std(axis=0), 100e-6 * G0, rtol=0.05)  # SE 1.1 %
    np.testing.assert_array_equal(x[:, 0], e.accel_turn_on_bias_m_s2)


def test_scale_factor_and_misalignment_act_on_true_signals():
    rng = np.random.default_rng(10)
    w_true = rng.normal(0, 0.2, (300, 3))
    f_true = np.tile([0.0, 0.0, G0], (300, 1)) + rng.normal(0, 1, (300, 3))
    m = NoiseModel(gyro_scale_factor_ppm=500, gyro_misalignment_mrad=1.0,
                   accel_scale_factor_ppm=300, accel_misalignment_mrad=0.5)
    e = generate_imu_errors(m, 500, 300, RATE, rng, true_rate_rad_s=w_true, true_force_m_s2=f_true)
    for err, s, mis, true in ((e.gyro_rad_s, e.gyro_scale_factor, e.gyro_misalignment_rad, w_true),
                              (e.accel_m_s2, e.accel_scale_factor, e.accel_misalignment_rad, f_true)):
        mat = mis + np.einsum("ti,ij->tij", s, np.eye(3))
        np.testing.assert_allclose(err, np.einsum("tij,nj->tni", mat, true), rtol=1e-12, atol=1e-18)
        assert np.all(np.diagonal(mis, axis1=1, axis2=2) == 0)
    np.testing.assert_allclose(e.accel_scale_factor.std(), 300e-6, rtol=0.06)
    off = e.gyro_misalignment_rad[:, [0, 0, 1, 1, 2, 2], [1, 2, 0, 2, 0, 1]]
    np.testing.assert_allclose(off.std(), 1e-3, rtol=0.06)
    # Level static IMU: scale factor on z reads β_z·g, misalignment couples gravity into x, y.
    e = generate_imu_errors(m, 10, 5, RATE, rng, true_force_m_s2=np.tile([0.0, 0.0, G0], (5, 1)))
    np.testing.assert_allclose(e.accel_m_s2[:, 0, 2], e.accel_scale_factor[:, 2] * G0)
    np.testing.assert_allclose(e.accel_m_s2[:, 0, 0], e.accel_misalignment_rad[:, 0, 2] * G0)


def test_same_generator_state_same_errors_and_no_global_state():
    m = NoiseModel(gyro_arw_deg_rt_h=0.1, gyro_bias_instability_deg_h=1.0, accel_vrw_m_s_rt_h=0.05,
                   accel_bias_repeatability_ug=50)
    a = generate_imu_errors(m, 6, 500, RATE, np.random.default_rng(11))
    np.random.seed(0)
    b = generate_imu_errors(m, 6, 500, RATE, np.random.default_rng(11))
    c = generate_imu_errors(m, 6, 500, RATE, np.random.default_rng(12))
    np.testing.assert_array_equal(a.gyro_rad_s, b.gyro_rad_s)
    np.testing.assert_array_equal(a.accel_m_s2, b.accel_m_s2)
    assert not np.array_equal(a.gyro_rad_s, c.gyro_rad_s)


def test_generator_input_errors():
    m = model(fx("sinusoid", "gyro_x", frequency_hz=30.0, amplitude=1e-3))
    rng = np.random.default_rng(0)
    with pytest.raises(InputError, match="below twice the 30 Hz sinusoid"):
        generate_imu_errors(m, 2, 100, 50.0, rng)
    with pytest.raises(InputError, match="true_force_m_s2 has shape"):
        generate_imu_errors(NoiseModel(), 2, 100, RATE, rng, true_force_m_s2=np.zeros((99, 3)))
    with pytest.raises(InputError, match="NaN"):
        generate_imu_errors(NoiseModel(), 2, 3, RATE, rng, true_rate_rad_s=np.full((3, 3), np.nan))
    with pytest.raises(InputError, match="n_samples"):
        generate_imu_errors(NoiseModel(), 2, 1, RATE, rng)
    with pytest.raises(InputError, match="rate_hz"):
        generate_imu_errors(NoiseModel(), 2, 10, -1.0, rng)
    with pytest.raises(InputError, match="temp_c"):
        generate_imu_errors(NoiseModel(), 2, 10, RATE, rng, temp_c=np.zeros(3))


def test_static_log_channels():
    m = NoiseModel(gyro_arw_deg_rt_h=0.2, accel_vrw_m_s_rt_h=0.05)
    log = simulate_static_log(m, 2000, RATE, np.random.default_rng(13))
    assert set(log) == {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"}
    assert log["accel_z"].mean() == pytest.approx(G0, abs=1e-3)
    assert abs(log["accel_x"].mean()) < 1e-3 and log["gyro_z"].shape == (2000,)
    one = simulate_static_log(m, 100, RATE, np.random.default_rng(13), channels=["gyro_z"])
    assert list(one) == ["gyro_z"]
    with pytest.raises(InputError, match="unknown channel"):
        simulate_static_log(m, 100, RATE, np.random.default_rng(13), channels=["mag_x"])
