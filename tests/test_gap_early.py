"""The early statistic (budget.gap.walk.early_z): a linear statistic of the slow modes that says
whether the record's start stands apart from the rest, which tells a turn-on transient (a mean)
from a random walk or a flicker term (spread). Its variance against independently drawn
processes and the separation it gives on the benchmark's transient and walk (tests/gap_truth.py,
written without budget code); its null distribution on independent model-following logs is checked beside the slow-mode
statistic's (tests/test_gap_walk.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import walk
from budget.imu import NoiseModel
from test_gap_walk import _PARAMS, DT, N_SHORT, _draw

BASE = NoiseModel.model_validate(gt.base_model_dict())


def test_the_pattern_is_a_unit_vector_blind_to_bias_and_trend():
    """v is the modes of e^(−t/τ₀) with τ₀ = 1/8 of the record, normalised; a bias and a trend
    added to a series leave vᵀy unchanged (the modes are orthogonal to both)."""
    lay = walk.layout(N_SHORT, DT)
    assert np.linalg.norm(lay.early) == pytest.approx(1.0, abs=1e-12)
    t = np.arange(N_SHORT) * DT
    expect = walk.modes(np.exp(-t / (N_SHORT * DT / 8.0)), lay)
    assert np.allclose(lay.early, expect / np.linalg.norm(expect), rtol=0, atol=1e-12)
    x = np.random.default_rng(2).standard_normal(N_SHORT)
    assert lay.early @ walk.modes(x + 4.0 - 0.3 * t, lay) == pytest.approx(lay.early @ walk.modes(x, lay),
                                                                           abs=1e-9 * math.sqrt(N_SHORT))


@pytest.mark.parametrize("kind", sorted(_PARAMS))
def test_variance_matches_independent_draws(kind):
    """vᵀy over 400 independent draws of each process has the variance vᵀCv of the closed-form
    covariance within 20 % (the sampling scatter of a variance from 400 draws is √(2/400) = 7 %)."""
    rng = np.random.default_rng(23)
    lay = walk.layout(N_SHORT, DT)
    cov = sum(walk.effect_cov(name, p, lay) for name, p in _PARAMS[kind])
    s = np.array([lay.early @ walk.modes(_draw(kind, rng, N_SHORT), lay) for _ in range(400)])
    assert np.mean(s * s) == pytest.approx(walk.early_var(cov, lay), rel=0.2)


def test_it_separates_the_benchmark_transient_from_a_walk():
    """Exact moments on the one-hour layout, accel_z of the base model. The benchmark's 3×
    transient (600 s) shifts the statistic's mean by more than 5 standard deviations of the
    model; a rate random walk that adds as much slow power (the same excess of the quadratic
    slow-mode statistic's mean, Σ w_i·E[ξ_i²]) has zero mean and widens the spread instead, so
    explaining the transient's shift with a walk costs z² + ln(var'/var) ≥ 4 more than the
    transient itself (which leaves z ≈ 0). Measured: shift 7.4σ; the walk (K = 1.2e-4) widens
    the spread 16.6× in variance; cost 6.2."""
    n = gt.ONE_HOUR
    lay = walk.layout(n, 1.0 / gt.RATE)
    cov = walk.model_cov(BASE.to_si().channel_effects("accel_z"), lay)
    amp = gt.calibrate("warmup_transient", n)
    mean = walk.effect_mean("warmup_transient", {"amplitude": amp, "tau_s": gt.WARMUP_TAU_S}, lay, None)
    v0 = walk.early_var(cov, lay)
    shift = float(lay.early @ mean) / math.sqrt(v0)
    assert abs(shift) > 5.0
    # the walk with the same mean excess of T = Σ w ξ² as the transient's mean gives
    w, r = walk.weights(cov, lay)
    excess = float(np.dot(w, (r @ mean) ** 2))
    unit = float(np.sum(w * np.diag(r @ lay.unit @ r.T)))
    k2 = excess / unit
    v1 = walk.early_var(cov + k2 * lay.unit, lay)
    assert v1 > v0
    cost = shift ** 2 * v0 / v1 + math.log(v1 / v0)
    assert cost > 4.0, (shift, v1 / v0, cost)
