"""The temperature statistic is a GLS coefficient under the model's noise spectrum
(budget.gap.gls): its algebra, its gain over ordinary least squares, and what it changes in the
workflow on logs from the independent generators of ``gap_truth`` (no package code)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import log_from_arrays, run_gap
from budget.gap.gls import model_spectrum, regression_weights
from budget.gap.signatures import SignatureGrid
from budget.imu import Effect, NoiseModel

RATE = gt.RATE


def warm_up(n: int) -> np.ndarray:
    """Another temperature history than gap_truth's: 8 °C warm-up with a 10-min time constant
    and a ±1 °C cycle of 500 s, °C."""
    t = np.arange(n) / RATE
    return 22.0 + 8.0 * (1.0 - np.exp(-t / 600.0)) + 1.0 * np.sin(2 * math.pi * t / 500.0)


def accel_spectrum():
    return model_spectrum([Effect(name="white_noise", channel="accel_x", params={"density": gt.ACCEL_N}),
                           Effect(name="bias_instability", channel="accel_x",
                                  params={"B": gt.ACCEL_FLOOR / gt.FLOOR_PER_B})], 1.0 / RATE)


def test_gls_weights_are_a_coefficient_blind_to_mean_and_trend():
    n = 50_000
    T = warm_up(n)
    w = regression_weights(T, RATE, accel_spectrum())
    t = np.arange(n) / RATE
    assert np.dot(w, T) == pytest.approx(1.0, rel=1e-9)
    assert abs(np.dot(w, t)) < 1e-9 * np.dot(np.abs(w), t)
    assert abs(w.sum()) < 1e-9 * np.abs(w).sum()
    # a temperature that only rises linearly cannot be told from a ramp: no statistic
    assert regression_weights(3.0 + 0.01 * t, RATE, accel_spectrum()) is None


def test_with_a_white_spectrum_gls_is_ordinary_least_squares():
    """S(f) flat: the DCT weighting is the identity and GLS is OLS given intercept and trend."""
    n = 20_000
    T = warm_up(n)
    flat = model_spectrum([Effect(name="white_noise", channel="gyro_x", params={"density": 1.0})], 1 / RATE)
    ols = SignatureGrid.for_log(n, RATE, T).temp_w
    gls = regression_weights(T, RATE, flat)
    np.testing.assert_allclose(gls, ols, rtol=1e-8, atol=1e-12 * np.abs(ols).max())


@pytest.mark.slow
def test_gls_coefficient_scatters_less_than_ols_under_flicker_noise():
    """Over 80 one-hour draws of the independent generator's accelerometer noise (white +
    flicker) with the warm-up above, the GLS coefficient's standard deviation is below OLS's
    (predicted in the DCT basis: 0.70×; asserted < 0.85×, the 80-draw ratio's ≈ 3σ margin)
    and both are unbiased on a known coefficient."""
    n = gt.ONE_HOUR
    T = warm_up(n)
    w_gls = regression_weights(T, RATE, accel_spectrum())
    w_ols = SignatureGrid.for_log(n, RATE, T).temp_w
    rng = np.random.default_rng(3)
    c = 2e-4
    est = np.array([[np.dot(w, x) for w in (w_gls, w_ols)]
                    for x in (gt.base_channel("accel_x", n, rng) + c * (T - T[0]) for _ in range(80))])
    sd = est.std(axis=0, ddof=1)
    assert sd[0] < 0.85 * sd[1]
    # unbiased: the mean within 4 standard errors of the truth
    assert np.all(np.abs(est.mean(axis=0) - c) < 4 * sd / math.sqrt(len(est)))


def _log_with_temperature(seed: int, n: int = gt.ONE_HOUR):
    """Six channels of the base model, accel_x with a temperature sensitivity sized so that its
    Allan deviation is 3× the base's at its most telling τ (as gap_truth sizes every effect)."""
    rng = np.random.default_rng(seed)
    logs = {ch: gt.base_channel(ch, n, rng) for ch in gt.CHANNELS}
    T = warm_up(n)
    m = gt.octave_m(n)
    rho = gt.adev(T - T[0], m) / gt.base_adev("accel_x", m / RATE)
    c = math.sqrt(gt.RATIO ** 2 - 1.0) / float(np.nanmax(rho))
    logs["accel_x"] = logs["accel_x"] + c * (T - T[0])
    logs["accel_z"] = logs["accel_z"] - gt.G0
    temp = T + 0.02 * rng.standard_normal(n)
    return log_from_arrays(logs, RATE, temp_c=temp, source=f"warm-up seed {seed}"), c


def _first_named(seed: int):
    log, c = _log_with_temperature(seed)
    rep = run_gap(log, NoiseModel.model_validate(gt.base_model_dict()), seed=0)
    first = rep.steps[0] if rep.steps else None
    return first, c


@pytest.mark.slow  # a whole run_gap on a one-hour log (≈ 8 s quiet); the over-seeds check is slow too
def test_a_temperature_sensitivity_on_an_accelerometer_is_named_as_such():
    """One seed of the faster warm-up on accel_x: named first, coefficient within 30 %."""
    first, c = _first_named(5)
    assert first is not None and (first.name, first.channel) == ("temperature_sensitivity", "accel_x")
    assert first.params["coefficient"] == pytest.approx(c, rel=0.3)


@pytest.mark.slow
def test_temperature_sensitivity_named_first_over_seeds():
    """10 seeds: named first on the right channel in ≥ 9, coefficient within 30 % each time."""
    hits = 0
    for seed in range(10):
        first, c = _first_named(100 + seed)
        if first is not None and (first.name, first.channel) == ("temperature_sensitivity", "accel_x"):
            hits += 1
            assert first.params["coefficient"] == pytest.approx(c, rel=0.3)
    assert hits >= 9
