"""Preprocessing, checks and ARMA selection (seed 000 §3.1) on data simulated with the paper's model.

Paper (seed 000 (17), STIM300 gyro Z): x(k) = 0.8397 x(k−1) + 0.1288 x(k−2) + w(k) + 0.9596 w(k−1),
var w = 0.007778. Tolerances: |Δφ| ≤ 0.03, |Δθ| ≤ 0.01, σ² within 3 %, and each estimate within
4 of its own asymptotic standard errors (n = 50 000).
"""

import warnings

import numpy as np
import pytest

from budget.errors import InputError
from budget.noise import check_series, fit_arma, preprocess, select_arma
from budget.noise.preprocess import detrend, pauta_outliers
from budget.noise.synth import simulate_arma

PHI, THETA, S2 = [0.8397, 0.1288], [0.9596], 0.007778


@pytest.fixture(scope="module")
def paper_series():
    return simulate_arma(PHI, THETA, S2, 50_000, np.random.default_rng(2016))


def test_paper_model_stationary_and_invertible_but_close():
    """φ₁ + φ₂ = 0.9685 < 1 and |θ| = 0.9596 < 1: both inside, the MA root 0.04 from the circle."""
    fit = fit_arma(simulate_arma(PHI, THETA, S2, 5000, np.random.default_rng(0)), 2, 1)
    roots_ar = np.abs(np.roots([1, -PHI[0], -PHI[1]]))
    assert roots_ar.max() == pytest.approx(0.9722, abs=1e-4) and fit.stationary and fit.invertible


def test_selection_picks_arma21_with_tolerances(paper_series):
    sel = select_arma(paper_series)
    assert [c.name for c in sel.candidates] == ["white", "AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)"]
    assert sel.selected.name == "ARMA(2,1)" and sel.by_fpe.name == "ARMA(2,1)"
    f = sel.selected
    est = np.r_[f.phi, f.theta]
    true = np.r_[PHI, THETA]
    assert np.all(np.abs(est - true) <= np.r_[0.03, 0.03, 0.01])
    assert np.all(np.abs(est - true) <= 4 * f.stderr)
    assert f.sigma2 == pytest.approx(S2, rel=0.03)
    assert f.stationary and f.invertible
    aics = [c.aic for c in sel.candidates]
    assert aics[-1] == min(aics)


def test_criteria_definitions(paper_series):
    f = fit_arma(paper_series - paper_series.mean(), 2, 1)
    assert f.aic == pytest.approx(np.log(f.sigma2) + 2 * 3 / f.n)
    assert f.fpe == pytest.approx(f.sigma2 * (f.n + 3) / (f.n - 3))
    assert f.n == paper_series.size - 2


def test_ls_equals_ols_for_ar():
    x = simulate_arma([0.5, -0.3], [], 1.0, 5000, np.random.default_rng(1))
    f = fit_arma(x, 2, 0)
    X = np.column_stack([x[1:-1], x[:-2]])
    beta = np.linalg.lstsq(X, x[2:], rcond=None)[0]
    np.testing.assert_allclose(f.phi, beta, rtol=1e-10)


def test_ls_agrees_with_statsmodels_mle():
    """Least squares vs exact ML (independent implementation): parameters within 2 %."""
    from statsmodels.tsa.arima.model import ARIMA
    x = simulate_arma(PHI, THETA, S2, 10_000, np.random.default_rng(5))
    f = fit_arma(x, 2, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = ARIMA(x, order=(2, 0, 1), trend="n").fit().params
    np.testing.assert_allclose(np.r_[f.phi, f.theta, f.sigma2], ref, rtol=0.02)


def test_mle_method():
    x = simulate_arma([0.6], [0.3], 1.0, 3000, np.random.default_rng(6))
    f = fit_arma(x, 1, 1, method="mle")
    assert f.method == "mle" and abs(f.phi[0] - 0.6) < 0.06 and abs(f.theta[0] - 0.3) < 0.08


def test_non_stationary_candidate_flagged_not_selected():
    """A random walk: AR(1) fits φ ≈ 1; models at or past the unit circle are flagged."""
    x = np.cumsum(np.random.default_rng(3).normal(size=4000))
    sel = select_arma(x, orders=[(1, 0), (2, 0)])
    assert all(c.ar_root_max > 0.99 for c in sel.candidates)
    assert "stationary" in sel.summary()


def test_ma_only_and_order_checks():
    x = simulate_arma([], [0.5], 1.0, 5000, np.random.default_rng(8))
    f = fit_arma(x, 0, 1)
    assert f.name == "MA(1)" and abs(f.theta[0] - 0.5) < 0.05
    with pytest.raises(InputError, match="p, q ≤ 3"):
        select_arma(x, orders=[(4, 0)])
    with pytest.raises(InputError, match="at least 100"):
        select_arma(x[:50])
    with pytest.raises(InputError, match="constant"):
        select_arma(np.ones(500))
    with pytest.raises(InputError, match="non-finite"):
        select_arma(np.r_[x[:200], np.nan])


def test_pauta_outliers_rules():
    x = np.random.default_rng(4).normal(size=2000)
    x[[10, 500]] = [40.0, -35.0]
    clean, idx = pauta_outliers(x, 4.0, "mean")
    assert list(idx) == [10, 500]
    good = np.delete(x, idx)
    assert clean[10] == pytest.approx(good.mean()) and clean[500] == pytest.approx(good.mean())
    clean, _ = pauta_outliers(x, 4.0, "neighbour")
    assert clean[10] == x[9] and clean[500] == x[499]
    with pytest.raises(InputError, match="3–5"):
        pauta_outliers(x, 2.0)


def test_detrend_removes_exact_polynomial():
    t = np.linspace(-1, 1, 1000)
    noise = np.random.default_rng(0).normal(size=1000)
    noise -= np.polyval(np.polyfit(t, noise, 2), t)  # orthogonal to the quadratic
    x = 3 + 2 * t - 5 * t ** 2 + noise
    res, coef = detrend(x, 2)
    np.testing.assert_allclose(coef, [-5, 2, 3], atol=1e-10)
    np.testing.assert_allclose(res, noise, atol=1e-10)


def test_preprocess_reports_steps():
    x = 5 + 0.001 * np.arange(3000) + np.random.default_rng(1).normal(size=3000)
    x[7] = 100
    pre = preprocess(x)
    assert list(pre.outliers) == [7] and abs(pre.x.mean()) < 1e-12
    assert "Pauta k=4" in pre.summary() and "degree-1" in pre.summary()


def test_checks_pass_on_gaussian_arma_and_flag_drift(paper_series):
    ok = check_series(paper_series)
    assert ok.passed, ok.flags()
    drift = paper_series + np.linspace(0, 5, paper_series.size)
    bad = check_series(drift)
    assert not bad.stationary and "not stationary" in bad.summary()
    skewed = np.random.default_rng(2).exponential(size=5000)
    assert not check_series(skewed).normal


def test_runs_test_closed_form_expectation():
    """Alternating segment means give the maximum number of runs (= segments)."""
    seg = np.repeat(np.tile([1.0, -1.0], 20), 10)
    rep = check_series(seg, segments=40)
    assert rep.runs == 40 and rep.runs_expected == pytest.approx(21.0)
