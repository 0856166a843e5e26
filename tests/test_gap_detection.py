"""Model-gap workflow on logs with a hidden effect, and on logs that follow their model.

Every log is drawn by the IMU generator (:func:`budget.imu.simulate_static_log`) from the base
model plus one hidden vocabulary effect on one channel; the workflow compares it with the base
model alone. It must name the hidden effect on the right channel *first*, with parameters
within the tolerances below, and shrink the gap of that channel. Logs drawn from the base
model itself must get no effect at all.

Magnitudes: "obvious" effects raise the channel gap 10–1000×; "near" effects are set near
the detection limit for the log length used (channel gap ≈ 1.5–3× its null threshold), where
the right name is still expected but a third of the gap is not (the gap cannot fall below
its null level ≈ 1); there the test asks for a channel gap within noise after the step.
Parameter tolerances are stated per case (relative, or in Hz for frequencies): they are the
estimation scatter seen over 10 seeds (``benchmarks/bench_gap.py``) with a margin, not a
property of the code.
"""

from __future__ import annotations

import numpy as np
import pytest

from budget.gap import log_from_arrays, run_gap
from budget.imu import NoiseModel, simulate_static_log

RATE = 100.0
N_LOG = 32_768  # 5.5 min at 100 Hz
#: Base model: a tactical-grade catalog row (gyro ARW 0.5 deg/√h, bias instability 5 deg/h;
#: accel VRW 0.05 m/s/√h, bias instability 50 µg). Gyro white σ per sample 1.45e-3 rad/s,
#: accel 8.3e-3 m/s².
BASE = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=0.5, gyro_bias_instability_deg_h=5.0,
                  accel_vrw_m_s_rt_h=0.05, accel_bias_instability_ug=50.0)


def temp_profile(n: int) -> np.ndarray:
    """Warm-up plus ±3 °C chamber cycling with a 60 s period, °C."""
    t = np.arange(n) / RATE
    return 25.0 + 5.0 * (1.0 - np.exp(-t / 200.0)) + 3.0 * np.sin(2.0 * np.pi * t / 60.0)


#: effect → [(level, channel, params, tolerances)], tolerance: relative error, or Hz for frequency.
CASES = {
    "white_noise": [("obvious", "gyro_y", {"density": 1.5e-4}, {"density": 0.08}),
                    ("near", "gyro_y", {"density": 5e-5}, {"density": 0.25})],
    "quantization": [("obvious", "accel_z", {"Q": 2.1e-5}, {"Q": 0.15}),
                     ("near", "gyro_x", {"Q": 2.1e-6}, {"Q": 0.3})],
    "bias_instability": [("obvious", "accel_y", {"B": 3e-3}, {"B": 0.15}),
                         ("near", "accel_y", {"B": 8e-4}, {"B": 0.4})],
    "rate_random_walk": [("obvious", "gyro_x", {"K": 1e-4}, {"K": 0.35}),
                         ("near", "gyro_x", {"K": 4e-5}, {"K": 0.5})],
    "rate_ramp": [("obvious", "accel_z", {"R": 2e-4}, {"R": 0.5}),
                  ("near", "accel_z", {"R": 6e-5}, {"R": 0.6})],
    "sinusoid": [("obvious", "accel_x", {"frequency_hz": 7.3, "amplitude": 2e-3},
                  {"frequency_hz": 0.05, "amplitude": 0.12}),
                 ("near", "accel_x", {"frequency_hz": 7.3, "amplitude": 1.1e-3},
                  {"frequency_hz": 0.05, "amplitude": 0.25})],
    "gauss_markov": [("obvious", "gyro_z", {"tau_s": 2.0, "sigma": 3e-4}, {"tau_s": 0.5, "sigma": 0.2}),
                     ("near", "gyro_z", {"tau_s": 2.0, "sigma": 1.5e-4}, {"tau_s": 1.0, "sigma": 0.35})],
    "temperature_sensitivity": [("obvious", "gyro_y", {"coefficient": 2e-4}, {"coefficient": 0.3}),
                                ("near", "gyro_y", {"coefficient": 4e-5}, {"coefficient": 0.6})],
    "outliers": [("obvious", "gyro_z", {"rate": 1e-3, "magnitude": 0.015}, {"rate": 0.4, "magnitude": 0.1}),
                 ("near", "gyro_z", {"rate": 3e-4, "magnitude": 0.012}, {"rate": 0.7, "magnitude": 0.2})],
    "lowpass": [("obvious", "gyro_x", {"cutoff_hz": 15.0}, {"cutoff_hz": 0.05}),
                ("near", "gyro_x", {"cutoff_hz": 60.0}, {"cutoff_hz": 0.15})],
}


def make_log(effect: str | None, channel: str | None, params: dict | None, n: int, seed: int):
    """A simulated static log of BASE (+ one hidden effect); temperature only for that effect."""
    model = BASE if effect is None else BASE.with_effect({"name": effect, "channel": channel, "params": params})
    temp = temp_profile(n) if effect == "temperature_sensitivity" else None
    x = simulate_static_log(model, n, RATE, np.random.default_rng(10_000 + seed), temp_c=temp)
    return log_from_arrays(x, RATE, temp_c=temp, source=f"hidden {effect} seed {seed}")


#: Near-limit cases probe the *significance* limit of the detectors, so they run with the
#: practical-size stop switched off (``tolerance_db=0``); with the default 0.5 dB a channel whose
#: misfit is significant but smaller than that is (by design) left alone.
TOLERANCE_DB = {"obvious": None, "near": 0.0}


def _run(effect, channel, params, seed, level):
    kw = {} if TOLERANCE_DB[level] is None else {"tolerance_db": TOLERANCE_DB[level]}
    return run_gap(make_log(effect, channel, params, N_LOG, seed), BASE, seed=seed, **kw)


def check_case(effect: str, level: str, channel: str, params: dict, tol: dict, seed: int):
    report = _run(effect, channel, params, seed, level)
    assert report.steps, f"{effect} ({level}, seed {seed}) not detected: {report.summary()}"
    first = report.steps[0]
    assert (first.name, first.channel) == (effect, channel), report.summary()
    for key, t in tol.items():
        got, want = first.params[key], params[key]
        err = abs(got - want) if key == "frequency_hz" else abs(got / want - 1.0)
        assert err <= t, f"{effect}.{key} = {got:.4g}, hidden {want:.4g} (tolerance {t})"
    if level == "obvious":
        assert first.gap_after <= first.gap_before / 3.0
        assert report.gap_after <= report.gap_before / 3.0
    else:
        assert first.gap_after <= report.null_after.channel_threshold(channel)
    return report


@pytest.mark.slow
@pytest.mark.parametrize("effect", list(CASES))
def test_obvious_effect_is_named_first(effect):
    level, channel, params, tol = CASES[effect][0]
    report = check_case(effect, level, channel, params, tol, seed=1)
    # the other channels follow the model: nothing named there
    assert {s.channel for s in report.steps} == {channel}


@pytest.mark.slow
@pytest.mark.parametrize("effect", list(CASES))
def test_near_limit_effect_is_named_first(effect):
    """Near the limit a realization can mimic a neighbour (flicker ↔ a Gauss–Markov hump, ramp ↔
    random walk): the right name is required in ≥ 2 of 3 seeds, a named effect on the right
    channel with the gap brought within noise in all 3 (rates over more seeds: bench_gap.py)."""
    level, channel, params, tol = CASES[effect][1]
    right = 0
    for seed in (2, 3, 4):
        try:
            check_case(effect, level, channel, params, tol, seed)
            right += 1
        except AssertionError:
            rep = _run(effect, channel, params, seed, level)
            assert rep.steps and rep.steps[0].channel == channel, rep.summary()
            assert rep.channels[channel].gap_after <= rep.null_after.channel_threshold(channel)
    assert right >= 2


@pytest.mark.slow
@pytest.mark.parametrize("effect", ["sinusoid", "bias_instability", "outliers"])
def test_obvious_effect_other_seeds(effect):
    level, channel, params, tol = CASES[effect][0]
    for seed in (5, 6):
        check_case(effect, level, channel, params, tol, seed)


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_log_following_its_model_names_nothing():
    for seed in (0, 1):
        report = run_gap(make_log(None, None, None, 16_384, seed), BASE, seed=seed)
        assert report.steps == [], report.summary()
        assert report.gap_before == report.gap_after
        assert report.gap_before <= report.null_before.overall_threshold


@pytest.mark.slow
def test_false_positive_rate_over_seeds():
    """120 logs of the base model at reduced size: at most 3 (2.5 %) may get an effect (the
    target is ≤ 2 %; P(≥ 4 of 120) is 3 % at a 1 % rate per log). Formerly 20 logs with at most
    one, a rate of 5 % allowed and a weak test of it: with the slope judged against the model's
    exact moments seed 103's gyro_x slope stands at 3.9σ (a 1-in-10⁴ draw per channel) and is
    named a ramp, beside seed 105's quantization that was there before — 2 of 120 in all. With
    the early statistic (budget.gap.walk.early_z) 3 of 120, at the limit: 103's ramp, 184's
    bias instability on accel_y and 209's transient on gyro_x (early z 3.6, a draw of about 1 in
    3 000 per channel); 105 no longer. On the one-hour benchmark the same change
    took the false positives from 1/50 to 0/50."""
    named = [seed for seed in range(100, 220)
             if run_gap(make_log(None, None, None, 16_384, seed), BASE, seed=seed).steps]
    assert len(named) <= 3, f"effects named on model-following logs, seeds {named}"


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_rerun_with_updated_model_names_nothing(tmp_path):
    level, channel, params, tol = CASES["sinusoid"][0]
    log = make_log("sinusoid", channel, params, N_LOG, 7)
    first = run_gap(log, BASE, seed=7)
    assert [s.name for s in first.steps] == ["sinusoid"]
    path = tmp_path / "updated.json"
    first.updated_model.save(path)
    again = run_gap(log, path, seed=8)
    assert again.steps == [], again.summary()
    assert again.gap_before <= again.null_before.overall_threshold


@pytest.mark.slow
def test_two_hidden_effects_on_two_channels():
    model = BASE.with_effect({"name": "sinusoid", "channel": "accel_x",
                              "params": {"frequency_hz": 3.1, "amplitude": 3e-3}})
    model = model.with_effect({"name": "white_noise", "channel": "gyro_z", "params": {"density": 1.5e-4}})
    x = simulate_static_log(model, N_LOG, RATE, np.random.default_rng(77))
    report = run_gap(log_from_arrays(x, RATE), BASE, seed=3)
    named = {(s.name, s.channel) for s in report.steps}
    assert named == {("sinusoid", "accel_x"), ("white_noise", "gyro_z")}, report.summary()
    assert report.within_noise
