"""Model adequacy of the ARMA result (budget/noise/adequacy.py) on independently generated series.

Generators here are numpy/scipy only (a white Gaussian sequence through the ARMA's own difference
equation, burn-in dropped), at gyro magnitudes (σ_w = 1e-4 rad/s per sample, 100 Hz).
References: statsmodels' ``acorr_ljungbox`` for Q and its p-value; ``scipy.linalg.solve_discrete_are``
for the steady covariances of an AR(1) + white model.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import signal, stats
from scipy.linalg import solve_discrete_are

from budget.cli.main import main
from budget.noise.adequacy import ALPHA, ljung_box, ljung_box_lags, model_adequacy, steady_error_variances
from budget.noise.arma import ArmaFit
from budget.noise.kalman import ArmaKalman
from budget.noise.pipeline import ArmaOptions, analyse_arma

FS = 100.0
SIG = 1e-4  # rad/s per sample: an ARW of about 0.2 deg/√h at 100 Hz
N = 20_000
BURN = 5_000


def _arma(rng, n, phi=(), theta=(), sigma=SIG):
    """x(k) = Σφᵢx(k−i) + w(k) + Σθⱼw(k−j), var w = σ²; the first BURN samples dropped."""
    w = sigma * rng.standard_normal(n + BURN)
    return signal.lfilter(np.r_[1.0, theta], np.r_[1.0, -np.asarray(phi, float)], w)[BURN:]


def _ljung_box_statsmodels(u, lags, model_df):
    from statsmodels.stats.diagnostic import acorr_ljungbox

    row = acorr_ljungbox(u, lags=[lags], model_df=model_df, return_df=True).iloc[0]
    return float(row["lb_stat"]), float(row["lb_pvalue"])


def test_lags_rule():
    # m = min(20, N/5), never fewer than p + q + 1
    assert ljung_box_lags(20_000, 2) == 20
    assert ljung_box_lags(100, 0) == 20
    assert ljung_box_lags(60, 1) == 12
    assert ljung_box_lags(10, 3) == 4


@pytest.mark.parametrize("name,phi,theta,orders", [("AR(1)", (0.9,), (), ((1, 0),)),
                                                    ("ARMA(1,1)", (0.9,), (-0.5,), ((1, 1),))])
def test_correct_model_gives_white_innovations(name, phi, theta, orders):
    """20 seeds of a correctly modelled series: p > 0.01 is expected with probability 0.99 each,
    0.2 failures in 20; P(≥ 3 failures | 0.01) = 1.0e-3, so ≥ 17 of 20 white is required. The
    normalised variance of N = 20,000 unit innovations has standard deviation √(2/N) = 0.010;
    required within 4 of them (0.04) of 1. Q and its p-value equal statsmodels' acorr_ljungbox on
    the same innovations (relative 1e-8), with its model_df = p + q."""
    white, worst = 0, 0.0
    for seed in range(20):
        x = _arma(np.random.default_rng(500 + seed), N, phi, theta)
        res = analyse_arma(x, FS, channel="gyro_x", options=ArmaOptions(orders=orders))
        ad = res.adequacy
        assert res.selection.selected.name == name and ad.model.lags == 20 and ad.model.dof == 20 - len(phi) - len(theta)
        white += ad.model.white
        worst = max(worst, abs(ad.model.normalised_variance - 1.0))
        if seed < 3:
            q_ref, p_ref = _ljung_box_statsmodels(ad.model_innovations, ad.model.lags, len(phi) + len(theta))
            assert ad.model.q == pytest.approx(q_ref, rel=1e-8)
            assert ad.model.p_value == pytest.approx(p_ref, rel=1e-8)
        if ad.model.white:
            assert not any("does not describe the series: the innovations" in n for n in res.notes)
    assert stats.binom(20, ALPHA).sf(2) < 2e-3  # the tolerance stated above
    assert white >= 17
    assert worst < 4 * np.sqrt(2.0 / N)


def test_ljung_box_matches_statsmodels_on_coloured_sequence():
    # an AR(1) sequence itself (strong correlation): Q large, same as statsmodels, with and without model_df
    u = _arma(np.random.default_rng(9), 3000, (0.3,))
    for fitted in (0, 2):
        q, dof, p = ljung_box(u, 15, fitted)
        q_ref, p_ref = _ljung_box_statsmodels(u, 15, fitted)
        assert dof == 15 - fitted and q == pytest.approx(q_ref, rel=1e-8) and p == pytest.approx(p_ref, rel=1e-8, abs=1e-300)


def test_model_innovations_are_the_exact_likelihood_innovations():
    """The selected model's innovations equal statsmodels' exact-likelihood one-step forecast errors
    of the same ARMA(1,1) (its Kalman filter from the stationary covariance), normalised by their
    variances, to 1e-6 relative rms."""
    from statsmodels.tsa.arima.model import ARIMA

    x = _arma(np.random.default_rng(77), 2000, (0.9,), (-0.5,))
    x = x - x.mean()
    fit = ArmaFit(1, 1, np.array([0.9]), np.array([-0.5]), SIG ** 2, x.size, "ls", float(np.var(x)), np.zeros(2))
    kf = ArmaKalman(fit, process_noise="model")
    ad = model_adequacy(fit, kf, x, kf.filter(x, center=False), unit="rad/s")
    mod = ARIMA(x / SIG, order=(1, 0, 1), trend="n")
    fr = mod.filter(np.array([0.9, -0.5, 1.0]))
    ref = fr.filter_results.forecasts_error[0] / np.sqrt(fr.filter_results.forecasts_error_cov[0, 0])
    u = ad.model_innovations
    assert np.sqrt(np.mean((u - ref) ** 2)) < 1e-6 * np.sqrt(np.mean(ref ** 2))


def test_model_that_cannot_describe_the_series_gets_the_note(tmp_path, capsys):
    """An AR(2) with complex poles 0.95·e^{±i2π·2 Hz/100 Hz} forced to AR(1): its innovations keep the
    oscillation, p < 0.01 on every one of 5 seeds, and the result says the model does not describe
    the series (summary, JSON notes, CLI stderr)."""
    phi = (2 * 0.95 * np.cos(2 * np.pi * 2.0 / FS), -0.95 ** 2)
    for seed in range(5):
        x = _arma(np.random.default_rng(900 + seed), N, phi)
        res = analyse_arma(x, FS, channel="gyro_x", options=ArmaOptions(orders=((1, 0),)))
        assert not res.adequacy.model.white and res.adequacy.model.p_value < ALPHA
        assert any(n.startswith("the model does not describe the series") for n in res.notes)
        assert "the model does not describe the series" in res.summary()
        assert any(n.startswith("the model does not describe the series") for n in res.to_dict()["notes"])
    log = tmp_path / "ar2.csv"
    log.write_text("time_s,gyro_x_rps\n" + "\n".join(f"{k / FS:.2f},{v:.9e}" for k, v in enumerate(x)) + "\n")
    assert main(["noise", "arma", str(log), "--channel", "gyro_x", "--orders", "1,0", "--json", "-", "--quiet"]) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert out["adequacy"]["model_innovations"]["white"] is False
    assert "the model does not describe the series" in captured.err
    # the same series with AR(2) among the candidates: selected, and white
    res = analyse_arma(x, FS, channel="gyro_x", options=ArmaOptions(orders=((1, 0), (2, 0))))
    assert res.selection.selected.name == "AR(2)" and res.adequacy.model.white


def test_steady_error_variances_against_dare_closed_form():
    """AR(1) + white (φ = 0.98, q = σ², r = 4σ²), the filter of the true model: predicted P⁻ from
    solve_discrete_are, filtered P = P⁻r/(P⁻ + r), smoother P_s = (P − C²P⁻)/(1 − C²), C = Pφ/P⁻;
    the library's to 1e-9 relative (the Riccati recursion stops at a gain change of 1e-13), P_s < P."""
    phi, q, r = 0.98, SIG ** 2, 4 * SIG ** 2
    fit = ArmaFit(1, 0, np.array([phi]), np.zeros(0), q, N, "ls", q / (1 - phi ** 2) + r, np.zeros(1))
    kf = ArmaKalman(fit, measurement_variance=r, process_noise="model")
    pf, ps = steady_error_variances(kf)
    Pp = solve_discrete_are(np.array([[phi]]), np.array([[1.0]]), np.array([[q]]), np.array([[r]]))[0, 0]
    P = Pp * r / (Pp + r)
    C = P * phi / Pp
    Ps = (P - C ** 2 * Pp) / (1 - C ** 2)
    assert pf == pytest.approx(P, rel=1e-9) and ps == pytest.approx(Ps, rel=1e-9) and ps < pf
    # and on a series of that model the filter's innovations pass (its model is the series')
    rng = np.random.default_rng(3)
    xs = _arma(rng, N, (phi,), sigma=np.sqrt(q))
    z = xs + np.sqrt(r) * rng.standard_normal(N)
    ad = model_adequacy(fit, kf, z, kf.filter(z, center=False), unit="rad/s")
    assert ad.filter.white and ad.filter.variance_consistent and ad.filter.dof == ad.filter.lags
    assert not any(n.startswith("the filter's model") for n in ad.notes)


def test_pipeline_reports_error_variances_with_units():
    """Every pipeline result: smoother ≤ filter steady error variance, in the channel's SI unit squared
    in the field names (frame and JSON), and the summary states them."""
    x = _arma(np.random.default_rng(11), N, (0.9,), (-0.5,))
    for channel, unit in (("gyro_z", "(rad/s)^2"), ("accel_x", "(m/s²)^2")):
        res = analyse_arma(x, FS, channel=channel)
        ad = res.adequacy
        assert 0 < ad.smoother_error_variance <= ad.filter_error_variance
        d = res.to_dict()["adequacy"]
        assert d[f"filter_error_variance_{unit}"] == ad.filter_error_variance
        assert d[f"smoother_error_variance_{unit}"] == ad.smoother_error_variance
        frame = res.to_frame()
        sel = frame[frame["selected"]].iloc[0]
        assert sel[f"smoother_error_variance_{unit}"] == ad.smoother_error_variance
        assert sel["innovations_ljung_box_p"] == ad.model.p_value
        assert frame.loc[~frame["selected"], "innovations_ljung_box_p"].isna().all()
        assert f"RTS smoother {ad.smoother_error_variance:.4g} {unit}" in res.summary()
    json.dumps(res.to_dict())  # JSON-safe


def test_paper_filter_is_flagged_as_not_describing_the_series():
    """With the paper's settings (R = δ₂, the series' whole variance, on top of an ARMA fitted to
    that same series) the filter's model predicts innovations of about twice the series' one-step
    error: the normalised variance is far below 1 and the innovations correlated — a note says so,
    while the ARMA itself passes."""
    x = _arma(np.random.default_rng(12), N, (0.9,), (-0.5,))
    res = analyse_arma(x, FS, channel="gyro_z", options=ArmaOptions(orders=((1, 1),)))
    ad = res.adequacy
    assert ad.model.white
    assert ad.filter.normalised_variance < 0.5 and not ad.filter.white
    assert any(n.startswith("the filter's model (ARMA(1,1) plus white measurement noise") for n in res.notes)


@pytest.mark.parametrize("seed", range(5))
def test_exact_likelihood_fit_gives_white_innovations(seed):
    """method="mle" (statsmodels' exact likelihood): ARMA(1,1) φ = 0.9, θ = −0.5 at IMU magnitude,
    orders forced to the true ones, seeded draws 900–904; the model's exact innovations are white
    at α = 1 % (each draw passes with probability 0.99 when the model is right) and their
    normalised variance is 1 within 4·√(2/N)."""
    x = _arma(np.random.default_rng(900 + seed), N, (0.9,), (-0.5,))
    res = analyse_arma(x, FS, channel="gyro_x",
                       options=ArmaOptions(orders=((1, 1),), method="mle", pauta_k=None, detrend_order=0))
    m = res.adequacy.model
    assert res.selection.selected.method == "mle"
    assert m.dof == m.lags - 2 and m.p_value > ALPHA
    assert m.normalised_variance == pytest.approx(1.0, abs=4 * np.sqrt(2.0 / m.samples))
