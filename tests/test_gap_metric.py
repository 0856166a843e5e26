"""The gap metric: null calibration, quadratic-form quantiles, predictions, localisation."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from budget.gap import theory as th
from budget.gap.metric import ModelSummary, NullModel, gap_terms, loo_z
from budget.quadform import quadratic_form_quantile
from budget.gap.report import localize
from budget.gap.signatures import SignatureGrid, series_signature
from budget.gap.simulate import simulate_signatures
from budget.imu import NoiseModel

RATE = 100.0
MODEL = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=0.5, gyro_bias_instability_deg_h=5.0,
                   accel_vrw_m_s_rt_h=0.05, accel_bias_instability_ug=50.0)


def test_quadratic_form_quantile_exact_for_equal_weights():
    for k in (1, 5, 30):
        assert quadratic_form_quantile(np.full(k, 2.0), 0.01) == pytest.approx(2.0 * stats.chi2.isf(0.01, k), rel=1e-9)


def test_quadratic_form_quantile_against_monte_carlo():
    lam = np.array([6.0, 2.0, 1.0, 1.0, 0.5, 0.5, 0.2, 0.1])
    draws = np.random.default_rng(0).chisquare(1, (400_000, lam.size)) @ lam
    for alpha in (0.05, 0.01):
        mc = np.quantile(draws, 1 - alpha)
        # Liu–Tang–Zhang is an approximation: within 3 % here (MC error ≈ 0.5 %)
        assert quadratic_form_quantile(lam, alpha) == pytest.approx(mc, rel=0.03)


def test_null_model_from_correlated_z_vectors():
    rng = np.random.default_rng(1)
    k, m = 10, 4000
    cov = 0.6 ** np.abs(np.subtract.outer(np.arange(k), np.arange(k)))
    z = rng.multivariate_normal(np.zeros(k), cov, size=m)
    null = NullModel.fit({"gyro_x": (z, ("a",))}, alpha=0.01)
    gaps = np.mean(rng.multivariate_normal(np.zeros(k), cov, size=200_000) ** 2, axis=1)
    assert null.channel_threshold("gyro_x") == pytest.approx(np.quantile(gaps, 0.99), rel=0.05)
    assert null.mean("gyro_x") == pytest.approx(1.0, rel=0.05)
    assert null.inflation("gyro_x") == pytest.approx(np.sum(np.linalg.eigvalsh(cov) ** 2) / k, rel=0.1)


def _grid_and_sims(channel: str, n: int, reps: int, seed: int):
    grid = SignatureGrid.for_log(n, RATE)
    return grid, simulate_signatures(MODEL, channel, grid, reps, seed)


def test_z_terms_are_standard_normal_under_the_null():
    """Each realization against the mean of the others: z ≈ N(0, 1) per term (ADEV, PSD bands)."""
    grid, sims = _grid_and_sims("gyro_x", 8192, 40, 11)
    z = loo_z(sims, grid)
    terms = gap_terms(sims[0], ModelSummary.from_signatures(sims[1:]), grid)
    for kind in ("adev", "psd_band"):
        zk = z[:, terms.kind == kind]
        # 40 draws per term: the variance estimate has ≈ 22 % standard error; pooled over the
        # terms of a kind the mean variance must be 1 within 0.25, the mean within 0.35
        assert np.mean(zk.var(axis=0)) == pytest.approx(1.0, abs=0.25)
        assert abs(zk.mean()) < 0.35
    assert np.mean(z ** 2) == pytest.approx(1.0, abs=0.2)


def test_prediction_of_an_added_effect_matches_its_simulation():
    """ModelSummary.predict(+white noise) ≈ the summary of the model simulated with it."""
    n = 8192
    grid, sims = _grid_and_sims("accel_y", n, 16, 2)
    base = ModelSummary.from_signatures(sims)
    dens = 1e-3
    inc = th.Increment(dens ** 2 / grid.tau_s, np.full(grid.nperseg // 2 + 1, 2 * dens ** 2), 2 * dens ** 2 / grid.dt_s)
    pred = base.predict(inc, grid)
    model2 = MODEL.with_effect({"name": "white_noise", "channel": "accel_y", "params": {"density": dens}})
    sim2 = ModelSummary.from_signatures(simulate_signatures(model2, "accel_y", grid, 16, 3))
    # 16 realizations: ln σ at short τ within 2 %, band PSD within 5 %
    np.testing.assert_allclose(pred.ln_adev[:6], sim2.ln_adev[:6], atol=0.02)
    lo, hi = grid.band_start[0], grid.bin_stop
    assert np.mean(pred.psd[lo:hi]) == pytest.approx(np.mean(sim2.psd[lo:hi]), rel=0.05)
    assert pred.diff_var == pytest.approx(sim2.diff_var, rel=0.03)


def test_localize_reports_tau_ranges_and_bands():
    grid, sims = _grid_and_sims("gyro_y", 8192, 8, 4)
    x = np.random.default_rng(9).standard_normal(8192) * 1.454e-3 * 2  # white level doubled
    terms = gap_terms(series_signature(x, grid), ModelSummary.from_signatures(sims), grid)
    loc = localize(terms)
    assert loc["tau_ranges_s"] and loc["tau_ranges_s"][0]["from"] == pytest.approx(0.01)
    assert loc["tau_ranges_s"][0]["direction"] == "measured above model"
    assert loc["bands_hz"] and loc["bands_hz"][-1]["direction"] == "measured above model"
    assert loc["top"][0]["z"] > 3
    assert sum(loc["share"].values()) == pytest.approx(terms.gap)
