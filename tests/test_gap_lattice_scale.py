"""The robust scale of first differences on a lattice (quantized output) moves continuously with the
distribution, so the tail statistics of a quantized log and of its model's realizations agree."""

from __future__ import annotations

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import log_from_arrays, run_gap
from budget.gap.signatures import grouped_median
from budget.imu import NoiseModel


@pytest.mark.parametrize("step", [0.5, 1.0, 2.0])
def test_grouped_median_is_continuous_where_the_plain_median_jumps(step):
    """|N(0, σ²)| rounded to a lattice: as σ grows by 0.5 % steps the plain median sits on a
    lattice level and jumps by a whole step; the grouped median follows σ (its ratio to the
    continuous median 0.6745σ stays within 6 %, and each 0.5 % step moves it by < 2 %)."""
    z = np.abs(np.random.default_rng(3).standard_normal(200_000))
    sigmas = 3.0 * 1.005 ** np.arange(20)
    plain, grouped = [], []
    for s in sigmas:
        v = np.abs(np.round(z * s / step) * step)
        plain.append(np.median(v))
        grouped.append(grouped_median(v, step))
    grouped, plain = np.asarray(grouped), np.asarray(plain)
    ratio = grouped / (0.6745 * sigmas)
    assert np.all(np.abs(ratio - 1.0) < 0.06), ratio
    assert np.max(np.abs(np.diff(grouped) / grouped[:-1])) < 0.02
    assert np.unique(plain).size <= 3  # the plain median only takes lattice values


@pytest.mark.slow
def test_quantized_log_follows_its_own_model():
    """A one-hour log from the independent generator (tests/gap_truth.py) whose gyro_x has its
    integrated output floored at 2× the model's Allan deviation at τ = dt: with that quantizer in
    the model the channel is within noise. With the plain median its tail statistics disagreed
    (z ≈ −540: a gap of 1.8e4) on this seed, and the workflow named the wrong quantizer."""
    saved = gt.RATIO
    gt.RATIO = 2.0
    try:
        x, temp, truth = gt.make("quantization", gt.ONE_HOUR, 1001)
    finally:
        gt.RATIO = saved
    model = gt.base_model_dict()
    model["effects"] = [*model.get("effects", []), {"name": "quantization", "channel": "gyro_x",
                                                     "params": dict(truth["params"])}]
    rep = run_gap(log_from_arrays(x, gt.RATE, temp_c=temp), NoiseModel.model_validate(model), seed=1,
                  max_steps=0)
    gyro_x = rep.to_dict()["channels"]["gyro_x"]
    assert gyro_x["state_after"] == "ok" and gyro_x["within_noise_after"], rep.summary()
