"""State-augmented Kalman filter and RTS smoother (seed 000 (14)–(16)): exactness of the fast
path, the state-space model, the variance reduction and what the filter does to motion.

The paper's "variance ÷10" is NOT reproduced on data simulated from its own model with its own
settings (R = δ₂ = variance of the static series, Q = δ₁·I): the filter gives ÷1.6, which is also
what the spectral integral of the filter response predicts. ÷10 needs R ≈ 12–30 × var(z)
(the test below pins where): the paper's figure reflects its tuning (or unit mix: its δ₁ =
0.007778 cannot be in (deg/s)² when the static variance is 1.2e-5 (deg/s)²), not the method.
"""

import numpy as np
import pytest
from scipy import integrate, optimize

from budget.errors import InputError
from budget.noise import ArmaKalman, fit_arma, frequency_response, motion_distortion
from budget.noise.arma import ArmaFit
from budget.noise.kalman import state_space
from budget.noise.recurrence import linear_recurrence
from budget.noise.synth import simulate_arma

PHI, THETA, S2 = np.array([0.8397, 0.1288]), np.array([0.9596]), 0.007778


def _paper_fit(data_variance):
    return ArmaFit(2, 1, PHI, THETA, S2, 10 ** 5, "paper", data_variance, np.zeros(3))


def _gamma0():
    """Variance of the paper's ARMA(2,1) from its spectrum, σ²/2π ∫ |θ(e^{−iω})|²/|φ(e^{−iω})|² dω."""
    def s(w):
        e = np.exp(-1j * w)
        return S2 * abs(1 + THETA[0] * e) ** 2 / abs(1 - PHI[0] * e - PHI[1] * e * e) ** 2
    return integrate.quad(s, -np.pi, np.pi, limit=400)[0] / (2 * np.pi)


def _reference(kf, z):
    """Plain textbook loop (Joseph form) and RTS smoother, independent of the fast path."""
    F, H, Q, R = kf.F, kf.H, kf.Q, kf.R
    n = F.shape[0]
    x, P = np.zeros(n), np.eye(n)
    xs, Ps, Pps = [], [], []
    for zk in z:
        xp, Pp = F @ x, F @ P @ F.T + Q
        K = Pp @ H / (H @ Pp @ H + R)
        x = xp + K * (zk - xp[0])
        IKH = np.eye(n) - np.outer(K, H)
        P = IKH @ Pp @ IKH.T + R * np.outer(K, K)
        xs.append(x), Ps.append(P), Pps.append(Pp)
    xs = np.array(xs)
    sm = xs.copy()
    for k in range(len(z) - 2, -1, -1):
        C = Ps[k] @ F.T @ np.linalg.inv(Pps[k + 1])
        sm[k] = xs[k] + C @ (sm[k + 1] - F @ xs[k])
    return xs[:, 0], sm[:, 0]


@pytest.mark.parametrize("order, mode", [((2, 1), "paper"), ((3, 0), "model"), ((1, 1), "paper"),
                                         ((2, 2), "model"), ((0, 2), "paper")])
def test_fast_path_equals_textbook_loop(order, mode):
    rng = np.random.default_rng(sum(order))
    x = simulate_arma([0.6, 0.2, -0.1][:order[0]], [0.5, 0.2][:order[1]], 1.0, 6000, rng)
    kf = ArmaKalman(fit_arma(x - x.mean(), *order), process_noise=mode)
    ref_f, ref_s = _reference(kf, x - x.mean())
    np.testing.assert_allclose(kf.filter(x).signal - x.mean(), ref_f, rtol=0, atol=1e-10 * np.std(x))
    np.testing.assert_allclose(kf.smooth(x).signal - x.mean(), ref_s, rtol=0, atol=1e-10 * np.std(x))
    short = x[:5]  # shorter than the gain transient: pure loop path
    np.testing.assert_allclose(kf.smooth(short, center=False).signal, _reference(kf, short)[1], atol=1e-12)


def test_state_space_reproduces_the_arma_recursion():
    """Driving F, G with w gives exactly lfilter's ARMA output (seed 000 (11) ⇔ (15))."""
    fit = ArmaFit(3, 2, np.array([0.5, -0.2, 0.1]), np.array([0.4, 0.3]), 1.0, 100, "t", 1.0, np.zeros(5))
    F, G, H = state_space(fit)
    w = np.random.default_rng(0).normal(size=300)
    X = linear_recurrence(F, np.outer(w, G))
    ref = simulate_arma(fit.phi, fit.theta, 1.0, 300, np.random.default_rng(0), burn_in=0)
    np.testing.assert_allclose(X @ H, ref, atol=1e-12)


def test_variance_reduction_paper_settings_matches_spectral_prediction():
    g0 = _gamma0()
    x = simulate_arma(PHI, THETA, S2, 200_000, np.random.default_rng(10))
    kf = ArmaKalman(_paper_fit(float(np.var(x))))
    res = kf.filter(x)
    ratio = res.variance_before / res.variance_after
    fr = frequency_response(kf, 1.0, np.linspace(0, 0.5, 4001))
    w = 2 * np.pi * fr.freq_hz
    e = np.exp(-1j * w)
    spec = S2 * np.abs(1 + THETA[0] * e) ** 2 / np.abs(1 - PHI[0] * e - PHI[1] * e * e) ** 2
    predicted = g0 / (integrate.simpson(fr.magnitude ** 2 * spec, x=w) / np.pi)
    assert ratio == pytest.approx(predicted, rel=0.05)
    assert 1.4 < ratio < 1.8  # not the paper's 10: see module docstring
    sm = kf.smooth(x)
    assert 1.1 < sm.variance_before / sm.variance_after < ratio


def test_measurement_variance_needed_for_a_factor_of_ten():
    x = simulate_arma(PHI, THETA, S2, 40_000, np.random.default_rng(11))
    v = float(np.var(x))

    def log_ratio(mult):
        r = ArmaKalman(_paper_fit(v), measurement_variance=mult * v).filter(x)
        return np.log(r.variance_before / r.variance_after) - np.log(10.0)

    mult = optimize.brentq(log_ratio, 1.0, 200.0, xtol=0.1)
    # the README's R ≈ 21× the data variance; over seeds 11–18 of this 40,000-sample record it
    # came out 20.2–22.5, so 15 % covers the record's sampling spread
    assert mult == pytest.approx(21.0, rel=0.15)


def test_frequency_response_matches_sinusoid_through_filter():
    kf = ArmaKalman(_paper_fit(0.42))
    rate = 100.0
    t = np.arange(30_000) / rate
    for smoother in (False, True):
        for f0 in (0.3, 4.0, 20.0):
            m = np.sin(2 * np.pi * f0 * t)
            out = (kf.smooth if smoother else kf.filter)(m, center=False).signal[5000:-5000]
            # amplitude by projection on sin/cos (whole number of periods is not needed at this length)
            s, c = np.sin(2 * np.pi * f0 * t[5000:-5000]), np.cos(2 * np.pi * f0 * t[5000:-5000])
            amp = np.hypot(out @ s, out @ c) / (s @ s)
            h = frequency_response(kf, rate, [f0], smoother=smoother).magnitude[0]
            assert amp == pytest.approx(h, rel=2e-3)


def test_motion_is_attenuated_and_reported():
    """On a moving platform the filter also removes real motion: DC gain < 1, −3 dB at a few Hz."""
    kf = ArmaKalman(_paper_fit(0.42))
    fr = frequency_response(kf, 100.0)
    assert fr.dc_gain < 0.9 and 1.0 < fr.bandwidth_hz < 10.0
    t = np.arange(20_000) / 100.0
    d = motion_distortion(kf, 0.5 * np.sin(2 * np.pi * 5.0 * t))
    assert d["amplitude_ratio"] == pytest.approx(frequency_response(kf, 100.0, [5.0]).magnitude[0], rel=0.01)
    assert d["relative_error"] > 0.5
    assert "−3 dB" in fr.summary()


def test_bad_inputs():
    fit = _paper_fit(0.42)
    with pytest.raises(InputError, match="process_noise"):
        ArmaKalman(fit, process_noise="magic")
    with pytest.raises(InputError, match="positive"):
        ArmaKalman(fit, measurement_variance=-1.0)
    with pytest.raises(InputError, match="non-finite"):
        ArmaKalman(fit).filter(np.array([1.0, np.nan, 2.0]))


def test_recurrence_clustered_poles():
    """Triple pole at 0.999 (worst case for direct-form IIR): sections keep 1e-9 accuracy."""
    M = np.diag([0.999, 0.999, 0.998]) + np.diag([1e-3, 1e-3], 1)
    u = np.random.default_rng(0).normal(size=(50_000, 3))
    s, x = np.empty_like(u), np.ones(3)
    for k in range(u.shape[0]):
        x = M @ x + u[k]
        s[k] = x
    np.testing.assert_allclose(linear_recurrence(M, u, np.ones(3)), s, atol=1e-9 * np.abs(s).max())


@pytest.mark.shared_data
def test_real_static_gyro_pipeline(shared_data):
    """ADIS16405 gyro z (first 50 000 samples): the checks flag the 0.05 deg/s quantized data as
    non-normal; the filter reduces the variance but also scales a constant rate by its DC gain."""
    from budget.noise import check_series, preprocess, read_log, select_arma
    log = read_log(shared_data / "logs" / "adis16405_static_1.csv.gz", channels=["gyro_z"],
                   max_rows=50_000)
    pre = preprocess(log.channels["gyro_z"])
    assert not check_series(pre.x).normal
    sel = select_arma(pre.x)
    kf = ArmaKalman(sel.selected)
    res = kf.filter(pre.x)
    assert res.variance_before / res.variance_after > 1.5
    fr = frequency_response(kf, log.rate_hz, [0.0])
    assert fr.dc_gain < 0.9
