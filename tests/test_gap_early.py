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


def test_slow_mode_part_is_independent_of_the_early_statistic():
    """y' = M·y of :func:`budget.gap.walk.apart_from_early` has zero covariance with s = vᵀy
    under the model (so T on it does not count an excursion of s again), and its covariance is
    M·C·Mᵀ; on 400 independent draws of white + Gauss–Markov series the sample correlation of
    each coordinate of y' with s is within 4/√400 of 0."""
    rng = np.random.default_rng(31)
    lay = walk.layout(N_SHORT, DT)
    cov = sum(walk.effect_cov(name, p, lay) for name, p in _PARAMS["white"] + _PARAMS["gm"])
    ys = np.array([walk.modes(_draw("white", rng, N_SHORT) + _draw("gm", rng, N_SHORT), lay)
                   for _ in range(400)])
    m = walk.apart_from_early(np.eye(lay.n_modes), cov, lay)[0]    # M itself
    c2 = walk.apart_from_early(ys[0], cov, lay)[1]
    assert np.allclose(m @ cov @ lay.early, 0.0, atol=1e-9 * np.abs(cov).max())
    assert np.allclose(c2, m @ cov @ m.T)
    s = ys @ lay.early
    y2 = ys @ m.T
    corr = (y2 * s[:, None]).mean(axis=0) / np.sqrt(np.diag(c2) * float(lay.early @ cov @ lay.early))
    assert np.max(np.abs(corr)) < 4.0 / np.sqrt(400)


def test_it_separates_the_benchmark_transient_from_a_walk():
    """Exact moments on the one-hour layout, accel_z of the base model. The benchmark's 3×
    transient (600 s) shifts the statistic's mean by more than 5 standard deviations of the
    model; a rate random walk that adds as much slow power (the same excess of the quadratic
    slow-mode statistic's mean, Σ w_i·E[ξ_i²]) has zero mean and widens the spread instead, so
    explaining the transient's shift with a walk costs z² + ln(var'/var) ≥ 4 more than the
    transient itself (which leaves z ≈ 0). Measured: shift 7.4σ; the walk (K = 4.6e-5) widens
    the spread 3.3× in variance; cost 17.9."""
    n = gt.ONE_HOUR
    lay = walk.layout(n, 1.0 / gt.RATE)
    cov = walk.model_cov(BASE.to_si().channel_effects("accel_z"), lay)
    amp = gt.calibrate("warmup_transient", n)
    mean = walk.effect_mean("warmup_transient", {"amplitude": amp, "tau_s": gt.WARMUP_TAU_S}, lay, None)
    v0 = walk.early_var(cov, lay)
    shift = float(lay.early @ mean) / math.sqrt(v0)
    assert abs(shift) > 5.0
    # the walk with the same mean excess of T = Σ w ξ² (T on the modes' part apart from the
    # early statistic) as the transient's mean gives
    m2, c2, u2 = walk.apart_from_early(mean, cov, lay)
    w, r = walk.weights(c2, lay, u2)
    excess = float(np.dot(w, (r @ m2) ** 2))
    unit = float(np.sum(w * np.diag(r @ u2 @ r.T)))
    k2 = excess / unit
    v1 = walk.early_var(cov + k2 * lay.unit, lay)
    assert v1 > v0
    cost = shift ** 2 * v0 / v1 + math.log(v1 / v0)
    assert cost > 4.0, (shift, v1 / v0, cost)
