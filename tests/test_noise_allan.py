"""Overlapping Allan deviation against allantools and closed forms; EDF and intervals; PSD."""

import allantools
import numpy as np
import pytest
from scipy import stats

from budget.errors import InputError
from budget.noise import allan_deviation, welch_psd
from budget.noise.allan import averaging_factors, edf_simple, noise_type_from_slope
from budget.noise.synth import imu_noise


@pytest.mark.parametrize("taus", ["octave", "decade", "dense", "explicit"])
def test_matches_allantools_oadev(taus):
    rng = np.random.default_rng(11)
    y = 3.0 + imu_noise(60_001, 200.0, rng, N=2e-3, B=3e-4, K=1e-5)  # odd length, offset
    t_in = np.array([0.005, 0.0125, 0.3, 7.7, 140.0]) if taus == "explicit" else taus
    r = allan_deviation(y, 200.0, t_in)
    tau, ad, _, ns = allantools.oadev(y, rate=200.0, data_type="freq", taus=r.tau_s)
    np.testing.assert_array_equal(tau, r.tau_s)
    np.testing.assert_array_equal(ns, r.n)
    np.testing.assert_allclose(r.adev, ad, rtol=1e-9)


def test_octave_list_is_allantools_default():
    y = np.random.default_rng(1).normal(size=5000)
    r = allan_deviation(y, 10.0)
    tau, *_ = allantools.oadev(y, rate=10.0, data_type="freq")
    np.testing.assert_allclose(r.tau_s, tau)


def test_white_noise_closed_form_within_interval():
    """White rate noise of variance s²: E σ²(τ = m τ0) = s²/m exactly (SP 1065)."""
    rng = np.random.default_rng(5)
    s = 0.7
    r = allan_deviation(rng.normal(0, s, 200_000), 100.0)
    expected = s / np.sqrt(r.m)
    inside = (r.lo <= expected) & (expected <= r.hi)
    assert np.all(r.alpha[:10] == 0)  # identified as white FM at short τ
    assert inside.mean() >= 0.6  # 68 % intervals
    # and every point within 4 standard errors, σ(σ̂)/σ ≈ 1/√(2 edf)
    assert np.all(np.abs(r.adev / expected - 1) <= 4 / np.sqrt(2 * r.edf))


def test_interval_coverage_white_noise():
    """Over 200 records, the 68 % interval at m = 16 covers the true σ about 68 % of the time."""
    rng = np.random.default_rng(8)
    hits = 0
    for _ in range(200):
        r = allan_deviation(rng.normal(size=4096), 1.0, [16.0])
        hits += r.lo[0] <= 0.25 <= r.hi[0]
    assert 0.58 <= hits / 200 <= 0.78


@pytest.mark.parametrize("alpha", [2, 1, 0, -2])
def test_edf_matches_allantools_edf_simple(alpha):
    N = 10_001
    m = np.array([1, 2, 8, 64, 1000])
    ref = [allantools.edf_simple(N, mi, alpha) for mi in m]
    np.testing.assert_allclose(edf_simple(N, m, np.full(m.size, alpha)), ref, rtol=1e-12)


def test_edf_flicker_fm():
    """Flicker FM: m ≥ 2 as allantools; m = 1 is SP 1065 Table 5's 2(N−2)²/(2.3N−4.9) ≈ 0.87 N
    (allantools omits the square, giving < 1 degree of freedom)."""
    N = 10_001
    m = np.array([2, 16, 512])
    np.testing.assert_allclose(edf_simple(N, m, np.full(3, -1)),
                               [allantools.edf_simple(N, mi, -1) for mi in m], rtol=1e-12)
    assert edf_simple(N, np.array([1]), np.array([-1]))[0] == pytest.approx(2 * (N - 2) ** 2 / (2.3 * N - 4.9))


def test_interval_is_chi_square():
    r = allan_deviation(np.random.default_rng(2).normal(size=3000), 1.0, ci=0.9)
    nu = r.edf
    np.testing.assert_allclose(r.lo, r.adev * np.sqrt(nu / stats.chi2.ppf(0.95, nu)))
    np.testing.assert_allclose(r.hi, r.adev * np.sqrt(nu / stats.chi2.ppf(0.05, nu)))


def test_noise_type_from_slope_is_monotone():
    tau = np.logspace(-2, 3, 30)
    ad = np.sqrt(3e-6 / tau ** 2 + 1e-4 / tau + 1e-7 + 1e-9 * tau)
    ad[-3] *= 0.2  # a noisy low point must not be read as white phase noise
    alpha = noise_type_from_slope(tau, ad)
    assert alpha[0] == 2 and np.all(np.diff(alpha) <= 0) and alpha[-1] <= -1


def test_bad_inputs():
    with pytest.raises(InputError, match="non-finite"):
        allan_deviation(np.array([1.0, np.nan, 2.0, 3.0]), 1.0)
    with pytest.raises(InputError, match="too few"):
        allan_deviation(np.ones(2), 1.0)
    with pytest.raises(InputError, match="no τ inside"):
        allan_deviation(np.random.default_rng(0).normal(size=100), 1.0, [1000.0])
    with pytest.raises(InputError, match="unknown τ list"):
        averaging_factors(100, 1.0, "weekly")
    with pytest.raises(InputError, match="positive"):
        allan_deviation(np.ones(10), 0.0)


def test_psd_white_level_recovers_n():
    """One-sided PSD of white rate noise N is 2N²: √(S/2) returns N."""
    rng = np.random.default_rng(3)
    N = 2e-3
    p = welch_psd(imu_noise(2 ** 17, 100.0, rng, N=N), 100.0)
    assert p.white_level() == pytest.approx(N, rel=0.03)
    with pytest.raises(InputError):
        welch_psd(np.ones(5), 100.0)


def test_figures_have_data_fit_and_response():
    from budget.noise import ArmaKalman, fit_arma, fit_noise_terms, frequency_response
    from budget.plots.noise import allan_figure, filter_figure, psd_figure, response_figure
    from budget.noise.synth import simulate_arma
    y = imu_noise(20_000, 100.0, np.random.default_rng(0), N=1e-3, B=1e-4)
    r = allan_deviation(y, 100.0, channel="gyro_x", unit="rad/s")
    fig = allan_figure({"gyro_x": r}, {"gyro_x": fit_noise_terms(r)}, show_terms=True)
    assert [t.name for t in fig.data][:2] == ["gyro_x", "gyro_x IEEE-952 fit"]
    np.testing.assert_allclose(fig.data[0].y, r.adev)
    assert len(psd_figure(welch_psd(y, 100.0, channel="gyro_x")).data) == 1
    x = simulate_arma([0.5], [], 1.0, 2000, np.random.default_rng(1))
    kf = ArmaKalman(fit_arma(x, 1, 0))
    assert len(filter_figure(x, kf.filter(x), 100.0).data) == 2
    resp = response_figure(frequency_response(kf, 100.0), frequency_response(kf, 100.0, smoother=True))
    assert [t.name for t in resp.data] == ["Kalman filter", "RTS smoother"]
