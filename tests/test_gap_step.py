"""The bias step (``bias_step``): the package's generator and closed forms against ``gap_truth``'s
series (no package code), the slow modes' likelihood against SciPy's multivariate normal, and
the workflow on independent logs that carry a step or a walk."""

from __future__ import annotations


import numpy as np
import pytest
from scipy import stats

import gap_truth as gt
from budget.gap import log_from_arrays, run_gap, walk
from budget.gap.regression_var import model_weight_mean
from budget.imu import Effect, NoiseModel, generate_imu_errors
from budget.imu.effects import mean_series

N = gt.ONE_HOUR
DT = 1.0 / gt.RATE


def _model(a: float, t0: float, channel: str = "accel_x") -> NoiseModel:
    return NoiseModel(rate_hz=gt.RATE, effects=(
        Effect(name="bias_step", channel=channel, params={"amplitude": a, "time_s": t0}),))


def test_generator_adds_the_step_at_its_time():
    a, t0 = -3e-4, 12.345
    e = generate_imu_errors(_model(a, t0), 2, 2_000, gt.RATE, np.random.default_rng(0))
    want = np.where(np.arange(2_000) * DT >= t0, a, 0.0)  # first sample at or after t0: k = 1235
    np.testing.assert_array_equal(e.accel_m_s2[:, :, 0], np.broadcast_to(want, (2, 2_000)))
    assert np.flatnonzero(want)[0] == 1235
    assert not np.any(e.accel_m_s2[:, :, 1:]) and not np.any(e.gyro_rad_s)


def test_step_leaves_a_mean_in_the_slow_modes_and_the_regressions():
    """Not a trend: its mean in the slow modes is A × the modes of the step, its mean in a
    regression statistic A·Σ_{t ≥ t₀} w; no variance."""
    lay = walk.layout(N, DT)
    series, unit = gt._bias_step(N, np.random.default_rng(3), None)
    a, t0 = 2e-4, unit["time_s"]
    mean = walk.effect_mean("bias_step", {"amplitude": a, "time_s": t0}, lay, None)
    want = a * walk.modes(series, lay)
    np.testing.assert_allclose(mean, want, rtol=0, atol=1e-9 * np.abs(want).max())
    assert np.linalg.norm(mean) > 0
    assert not np.any(walk.effect_cov("bias_step", {"amplitude": a, "time_s": t0}, lay))
    w = np.random.default_rng(1).standard_normal(N)
    w -= w.mean()
    eff = _model(a, t0).to_si().channel_effects("accel_x")
    assert model_weight_mean(eff, w, gt.RATE, None) == pytest.approx(a * float(np.dot(w, series)), rel=1e-9)


def test_mean_series_is_only_for_deterministic_effects():
    with pytest.raises(ValueError, match="not a deterministic effect"):
        mean_series("white_noise", {"density": 1e-3}, 10, 0.01, None)
    assert mean_series("temperature_lag", {"coefficient": 1.0, "tau_s": 5.0}, 10, 0.01, None) is None


def test_mode_likelihood_is_the_multivariate_normal_density():
    """walk.log_likelihood against SciPy's multivariate normal (its own factorisation), up to
    the constant −K/2·ln 2π the workflow's ratios cancel."""
    rng = np.random.default_rng(5)
    k = 12
    a = rng.standard_normal((k, k))
    cov = a @ a.T + k * np.eye(k)
    mean, y = rng.standard_normal(k), rng.standard_normal(k) * 3.0
    want = stats.multivariate_normal(mean, cov).logpdf(y) + 0.5 * k * np.log(2 * np.pi)
    assert walk.log_likelihood(y, mean, cov) == pytest.approx(want, rel=1e-12, abs=1e-12)
    assert walk.log_likelihood(y, None, cov) == pytest.approx(
        stats.multivariate_normal(np.zeros(k), cov).logpdf(y) + 0.5 * k * np.log(2 * np.pi), rel=1e-12)


def _first(name: str, seed: int, ratio: float, monkeypatch):
    monkeypatch.setattr(gt, "RATIO", ratio)
    x, _, truth = gt.make(name, N, 1000 + seed)
    ch = truth["channel"]
    log = log_from_arrays({ch: x[ch]}, gt.RATE, source=f"{name} seed {seed}")
    rep = run_gap(log, NoiseModel.model_validate(gt.base_model_dict()), seed=seed, max_steps=3, channels=[ch])
    return (rep.steps[0] if rep.steps else None), truth


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0])
def test_a_step_is_named_with_its_time_and_size(seed, monkeypatch):
    """accel_x alone, 1 h, a step at a drawn time sized to 3× the base Allan deviation at its
    most telling τ (the benchmark's magnitude): named first, t₀ within half the shortest period
    the slow modes hold (75 s for one hour: what the change-point scan resolves) and A within
    35 % (measured, seeds 0–3: t₀ within 60 s, A within 30 %). Before the
    effect was in the vocabulary the record named a rate random walk; with the candidate but
    without the slow modes' likelihood in Occam's step it still did (the step 0.9–2.3 better on
    Σz², under the 6.6 its second parameter must buy), and the walk is no longer listed as an
    alternative (2·ln LR 22–47 for the step)."""
    step, truth = _first("bias_step", seed, 3.0, monkeypatch)
    assert step is not None and step.name == "bias_step", step
    resolution = 0.5 * walk.layout(N, DT).shortest_period_s
    assert abs(step.params["time_s"] - truth["params"]["time_s"]) < resolution
    assert step.params["amplitude"] == pytest.approx(truth["params"]["amplitude"], rel=0.35)
    assert "rate_random_walk" not in {a["name"] for a in step.alternatives}


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_steps_on_other_seeds(seed, monkeypatch):
    test_a_step_is_named_with_its_time_and_size(seed, monkeypatch)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 3])
def test_a_walk_is_not_read_as_a_step(seed, monkeypatch):
    """On the benchmark's walks (seeds whose walk is named at 3×), the slow modes' likelihood
    does not turn the walk into a step: 2·ln LR of the best step over the walk is −18 … +4.4 on
    seeds 0–9, under the 6.6 Occam's step asks for."""
    step, truth = _first("rate_random_walk", seed, 3.0, monkeypatch)
    assert step is not None and step.name == "rate_random_walk", step


def test_located_profile_is_the_best_coefficient_and_shape():
    """walk.located_log_likelihood against a brute-force maximum: SciPy's multivariate normal
    maximised over the coefficient by a bounded scalar search, for each candidate shape."""
    from scipy import optimize

    rng = np.random.default_rng(11)
    k, m = 10, 5
    a = rng.standard_normal((k, k))
    cov = a @ a.T + k * np.eye(k)
    units = rng.standard_normal((m, k))
    base = rng.standard_normal(k)
    y = base + 2.5 * units[3] + rng.multivariate_normal(np.zeros(k), cov)
    got, i, amp = walk.located_log_likelihood(y, base, cov, units)
    best = []
    for u in units:
        res = optimize.minimize_scalar(lambda c: -stats.multivariate_normal(base + c * u, cov).logpdf(y),
                                       bounds=(-50, 50), method="bounded", options={"xatol": 1e-10})
        best.append((-res.fun + 0.5 * k * np.log(2 * np.pi), res.x))
    j = int(np.argmax([b[0] for b in best]))
    assert i == j
    assert got == pytest.approx(best[j][0], rel=1e-9, abs=1e-9)
    assert amp == pytest.approx(best[j][1], rel=1e-6)
    # at its best coefficient the profile is the plain likelihood
    assert got == pytest.approx(walk.log_likelihood(y, base + amp * units[i], cov), rel=1e-12)
