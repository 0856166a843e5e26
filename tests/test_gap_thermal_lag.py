"""The thermal lag (``temperature_lag``): the package's discrete filter against the closed-form
response of ``gap_truth`` (no package code), what it leaves in the statistics the model-gap
workflow judges (the regression on T, the slow modes), and the workflow on a lagged log."""

from __future__ import annotations

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import log_from_arrays, run_gap
from budget.gap import walk
from budget.gap.regression_var import model_weight_mean
from budget.imu import Effect, NoiseModel, generate_imu_errors
from budget.imu.effects import thermal_lag

N = gt.ONE_HOUR
DT = 1.0 / gt.RATE


@pytest.mark.parametrize("tau_s", [2.0, 30.0, 300.0, 1200.0])
def test_discrete_lag_matches_the_closed_form(tau_s):
    """Exact zero-order-hold discretisation vs the continuous closed form: they differ by at
    most dt/2 × the largest temperature rate (0.022 °C/s) ≈ 1.1e-4 °C."""
    T = gt.temperature(N)
    got = thermal_lag(T, tau_s, DT)
    want = gt.lagged_temperature(N, tau_s)
    assert np.max(np.abs(got - want)) < 2e-4
    assert got[0] == 0.0


def test_generator_drives_the_lag_from_the_temperature_column():
    c, tau = 2e-5, 300.0
    model = NoiseModel(rate_hz=gt.RATE, effects=(
        Effect(name="temperature_lag", channel="gyro_z", params={"coefficient": c, "tau_s": tau}),))
    T = gt.temperature(N)
    e = generate_imu_errors(model, 1, N, gt.RATE, np.random.default_rng(0), temp_c=T)
    np.testing.assert_allclose(e.gyro_rad_s[0, :, 2], c * gt.lagged_temperature(N, tau), atol=c * 2e-4)


def test_lag_leaves_a_mean_in_the_slow_modes_and_the_regressions():
    """An instantaneous sensitivity is projected out of the slow modes; a lag is not: its mean
    there is c × the modes of the closed-form lagged series, and the mean of a regression
    statistic is c·Σ w·(T_e − T_0)."""
    T = gt.temperature(N)
    lay = walk.layout(N, DT, T)
    c, tau = 2e-5, 300.0
    lagged = gt.lagged_temperature(N, tau)
    mean = walk.effect_mean("temperature_lag", {"coefficient": c, "tau_s": tau}, lay, T)
    want = c * walk.modes(lagged, lay)
    np.testing.assert_allclose(mean, want, rtol=0, atol=2e-3 * np.abs(want).max())
    assert not np.any(walk.effect_mean("temperature_sensitivity", {"coefficient": c}, lay, T))
    assert walk.effect_mean("temperature_lag", {"coefficient": c, "tau_s": tau}, lay, None) is None
    w = np.random.default_rng(1).standard_normal(N)
    w -= w.mean()
    eff = NoiseModel(rate_hz=gt.RATE, effects=(Effect(name="temperature_lag", channel="gyro_z",
                                                      params={"coefficient": c, "tau_s": tau}),)
                     ).to_si().channel_effects("gyro_z")
    assert model_weight_mean(eff, w, gt.RATE, T) == pytest.approx(c * float(np.dot(w, lagged)), rel=1e-3)


def _first(name: str, seed: int):
    x, temp, truth = gt.make(name, N, 1000 + seed)
    log = log_from_arrays({"gyro_z": x["gyro_z"]}, gt.RATE, temp_c=temp, source=f"{name} seed {seed}")
    rep = run_gap(log, NoiseModel.model_validate(gt.base_model_dict()), seed=seed, max_steps=3,
                  channels=["gyro_z"])
    return (rep.steps[0] if rep.steps else None), truth


@pytest.mark.slow  # two whole run_gap on one-hour logs (≈ 15 s quiet)
def test_a_lagged_gyro_is_named_a_lag_and_an_instantaneous_one_is_not():
    """gyro_z alone, 1 h: a 300-s lag whose part beyond an instantaneous sensitivity has an
    Allan deviation 3× the base's (gap_truth's sizing of the lag) is named ``temperature_lag``
    with c within 30 % and τ within 50 %; the log with an instantaneous sensitivity keeps the
    simpler ``temperature_sensitivity``. ``benchmarks/bench_gap.py`` gives the rate over seeds."""
    first, truth = _first("temperature_lag", 0)
    assert first is not None and first.name == "temperature_lag", first
    assert first.params["coefficient"] == pytest.approx(truth["params"]["coefficient"], rel=0.3)
    assert first.params["tau_s"] == pytest.approx(truth["params"]["tau_s"], rel=0.5)
    first, truth = _first("temperature_sensitivity", 0)
    assert first is not None and first.name == "temperature_sensitivity", first
    assert first.params["coefficient"] == pytest.approx(truth["params"]["coefficient"], rel=0.3)
