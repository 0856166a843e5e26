"""The model's exact variance of a linear statistic (time slope, temperature coefficient).

:func:`budget.gap.regression_var.model_weight_variance` is checked against the scatter of the
same statistic over 2000 realizations drawn by the package's generator, effect by effect: the
sample variance of 2000 normal draws has a relative standard deviation √(2/1999) = 3.2 %, so
4.5σ = 14 % bounds a correct formula with probability > 0.99999 per case. Quantizers are taken
where their stated approximation holds (noise spanning several steps); where it does not
(a step 5× the noise) the output rounding's variance is 9 % below δ²/12 — said in the docstring,
not tested. Every registered effect has an entry (``None`` means an unknown effect).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from budget.gap.metric import LinearMoments, ModelSummary, gap_terms
from budget.gap.regression_var import model_weight_mean, model_weight_variance
from budget.gap.signatures import Signature, SignatureGrid
from budget.imu import Effect, NoiseModel, generate_imu_errors
from budget.imu.registry import REGISTRY
from registry_examples import EXAMPLE_PARAMS

RATE, N, TRIALS = 100.0, 4096, 2000
TOL = 4.5 * math.sqrt(2.0 / (TRIALS - 1))


def _weights():
    t = np.arange(N) / RATE
    tc = t - t.mean()
    temp = 25.0 + 10.0 * (1.0 - np.exp(-t / 10.0)) + 0.5 * np.sin(2 * np.pi * t / 7.0)
    wt = temp - temp.mean()
    wt = wt - np.dot(tc, wt) / np.dot(tc, tc) * tc
    return temp, {"slope": tc / np.dot(tc, tc), "temperature": wt / np.dot(wt, wt)}


def _e(name, **params):
    return Effect(name=name, channel="gyro_x", params=params)


WHITE = _e("white_noise", density=1e-4)  # per-sample σ = 1e-3
CASES = {
    "white": [WHITE],
    "bias_instability": [WHITE, _e("bias_instability", B=2e-4)],
    "gauss_markov": [WHITE, _e("gauss_markov", tau_s=3.0, sigma=3e-4)],
    "rate_random_walk": [WHITE, _e("rate_random_walk", K=1e-4)],
    "sinusoid": [WHITE, _e("sinusoid", frequency_hz=0.05, amplitude=1e-3)],
    "vibration": [WHITE, _e("vibration", center_hz=0.3, width_hz=0.1, sigma=1e-3)],
    "heavy_tailed": [_e("heavy_tailed", density=1e-4, dof=5.0)],
    "outliers": [WHITE, _e("outliers", rate=1e-2, magnitude=1e-2)],
    "lowpass": [WHITE, _e("gauss_markov", tau_s=0.05, sigma=3e-3), _e("lowpass", cutoff_hz=0.5)],
    "quantization": [WHITE, _e("quantization", Q=2e-5)],
    "rate_quantization": [WHITE, _e("rate_quantization", step=5e-4)],
    "deterministic": [WHITE, _e("rate_ramp", R=1e-5), _e("temperature_sensitivity", coefficient=1e-4)],
    "transient_and_step": [WHITE, _e("warmup_transient", amplitude=1e-3, tau_s=5.0),
                           _e("bias_step", amplitude=-2e-3, time_s=17.3)],
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_exact_variance_matches_the_generator(case):
    temp, weights = _weights()
    model = NoiseModel(rate_hz=RATE, effects=tuple(CASES[case]))
    x = generate_imu_errors(model, TRIALS, N, RATE, np.random.default_rng(11), temp_c=temp).gyro_rad_s[:, :, 0]
    effects = model.to_si().channel_effects("gyro_x")
    for kind, w in weights.items():
        theory = model_weight_variance(effects, w, 1.0 / RATE)
        stat = x @ w
        ratio = float(np.var(stat, ddof=1) / theory)
        assert abs(ratio - 1.0) < TOL, f"{case}, {kind}: scatter/theory = {ratio:.3f}"
        # the mean: within 4.5 standard errors of the closed form
        mean = model_weight_mean(effects, w, RATE, temp)
        assert abs(stat.mean() - mean) < 4.5 * math.sqrt(theory / TRIALS), f"{case}, {kind}: mean"


def test_every_registered_effect_has_a_variance():
    _, weights = _weights()
    params = EXAMPLE_PARAMS
    assert set(params) == set(REGISTRY), "a registered effect is missing from this test"
    for name, p in params.items():
        v = model_weight_variance([WHITE, _e(name, **p)], weights["slope"], 1.0 / RATE)
        assert v is not None and v > 0, name
    unknown = Effect.model_construct(name="not_an_effect", channel="gyro_x", params={})
    assert model_weight_variance([WHITE, unknown], weights["slope"], 1.0 / RATE) is None


def test_deterministic_means():
    """Ramp and temperature terms move the statistics' means by R·Σw·t and c·Σw·(T − T0)."""
    temp, weights = _weights()
    effects = [WHITE, _e("rate_ramp", R=1e-5), _e("temperature_sensitivity", coefficient=1e-4)]
    model = NoiseModel(rate_hz=RATE, effects=tuple(effects)).to_si().channel_effects("gyro_x")
    t = np.arange(N) / RATE
    assert model_weight_mean(model, weights["slope"], RATE, temp) == pytest.approx(
        1e-5 + 1e-4 * float(np.dot(weights["slope"], temp - temp[0])), rel=1e-12)
    assert model_weight_mean(model, weights["temperature"], RATE, temp) == pytest.approx(
        1e-5 * float(np.dot(weights["temperature"], t)) + 1e-4, rel=1e-9)
    assert model_weight_mean(model, weights["slope"], RATE, None) is None


def test_exact_moments_make_the_slope_z_normal():
    """With the exact moments the slope z is (meas − mean)/√var, not a t score."""
    grid = SignatureGrid.for_log(8192, RATE)
    sig = lambda s: Signature(avar=np.ones(grid.m.size), psd=np.ones(grid.nperseg // 2 + 1),  # noqa: E731
                              kurtosis=0.0, diff_var=1.0, sigma_r=1.0, tail_count=5, tail2_count=0,
                              spike_count=0, spike_magnitude=0.0, diff_max=1.0, slope=s)
    sims = [sig(s) for s in np.linspace(-1.0, 1.0, 12)]
    exact = ModelSummary.from_signatures(sims, LinearMoments(0.1, 0.25))
    assert exact.linear_exact and exact.slope_var == 0.25 and exact.slope == 0.1
    terms = gap_terms(sig(2.0), exact, grid)
    z = float(terms.z[terms.kind == "slope"][0])
    assert z == pytest.approx((2.0 - 0.1) / math.sqrt(0.25), rel=1e-12)
    # a log with a temperature column needs both statistics' moments, or neither is used
    assert not ModelSummary.from_signatures(
        [replace(s_, temp_coef=0.0) for s_ in sims], LinearMoments(0.1, 0.25)).linear_exact
    scatter = ModelSummary.from_signatures(sims)
    assert not scatter.linear_exact
    z_t = float(gap_terms(sig(2.0), scatter, grid).z[terms.kind == "slope"][0])
    t = (2.0 - scatter.slope) / math.sqrt(scatter.slope_var * (1 + 1 / 12))
    assert abs(z_t) < abs(t)  # the t score is shrunk to the normal score of its tail
