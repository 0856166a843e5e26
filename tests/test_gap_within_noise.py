"""'Within noise' is both tests the gap definition names: every channel within its own
threshold and the overall gap (the channels' mean) within the overall one."""

from __future__ import annotations

import dataclasses

import numpy as np

from budget.gap import log_from_arrays, run_gap
from budget.gap.metric import NullModel
from budget.imu import Effect, NoiseModel


class _Null(NullModel):
    """The run's null with thresholds set by hand (the tests of the report, not of the null)."""

    def __init__(self, base: NullModel, channel: float, overall: float):
        super().__init__(base.eigen, base.alpha, base.samples, base.blocks)
        object.__setattr__(self, "_c", channel)
        object.__setattr__(self, "_o", overall)

    def channel_threshold(self, channel: str) -> float:
        return self._c

    @property
    def overall_threshold(self) -> float:
        return self._o


def _report():
    rate, n = 100.0, 30_000
    rng = np.random.default_rng(4)
    x = {ch: 1e-3 * rng.standard_normal(n) for ch in ("gyro_x", "gyro_y")}
    model = NoiseModel(rate_hz=rate, effects=tuple(Effect(name="white_noise", channel=ch, params={"density": 1e-4})
                                                   for ch in x))
    return run_gap(log_from_arrays(x, rate, source="white"), model, seed=1, max_steps=0)


def test_overall_gap_above_its_threshold_is_not_within_noise():
    rep = _report()
    g = rep.gap_after
    worst = max(c.gap_after for c in rep.channels.values())
    # every channel within, the mean above: not within noise, and the summary says which test failed
    r = dataclasses.replace(rep, null_after=_Null(rep.null_after, channel=worst * 1.01, overall=0.99 * g))
    assert r.channels_within_noise and not r.overall_within_noise and not r.within_noise
    assert "NOT within noise: overall threshold" in r.summary() and "exceeded" in r.summary()
    assert r.to_dict()["within_noise_after"] is False
    # both within: within noise
    r = dataclasses.replace(rep, null_after=_Null(rep.null_after, channel=worst * 1.01, overall=1.01 * g))
    assert r.within_noise and r.to_dict()["within_noise_after"] is True
    assert "exceeded" not in r.summary().splitlines()[1]
    # a channel above its own threshold: not within noise, the channel named
    low = min(c.gap_after for c in rep.channels.values())
    assert low < worst  # two independent channels' gaps
    r = dataclasses.replace(rep, null_after=_Null(rep.null_after, channel=0.5 * (low + worst), overall=10 * g))
    assert r.overall_within_noise and not r.within_noise and "exceeded on" in r.summary()
