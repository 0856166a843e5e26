"""A log quieter than its model: every candidate of the model gap adds noise, so such a gap cannot
close. Before this check the workflow named a low-pass filter and a quantizer on such a log (it
pulled the model's short-τ power down towards the log's); now the channel is not worked on and
the report says why (budget.gap.quieter). Logs from the independent generator
(tests/gap_truth.py)."""

from __future__ import annotations

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import log_from_arrays, run_gap
from budget.imu import NoiseModel

N = 60_000  # 10 min at 100 Hz


def _run(scale: float, seed: int):
    x, _, _ = gt.make(None, N, 3300 + seed)
    logs = {ch: scale * np.asarray(x[ch]) for ch in ("gyro_x", "accel_y")}
    return run_gap(log_from_arrays(logs, gt.RATE, source=f"scaled {scale}"),
                   NoiseModel.model_validate(gt.base_model_dict()), seed=seed, max_steps=2,
                   check_tau_range=False)


@pytest.mark.parametrize("seed", [0, 1])
def test_a_log_at_a_third_of_the_model_is_reported_quieter(seed):
    """The base model's own noise at 1/3 of its amplitude (−9.5 dB): both channels stay beyond
    their threshold, nothing is named (before: `lowpass` then `quantization` on one of them), and
    each gets the note with its median misfit."""
    rep = _run(1.0 / 3.0, seed)
    assert rep.steps == []
    quiet = [n for n in rep.notes if "quieter than the model" in n]
    assert sorted(n.split(":")[0] for n in quiet) == ["accel_y", "gyro_x"]
    for n in quiet:
        median = float(n.split("a median ")[1].split(" dB")[0])
        assert 7.0 < median < 12.0  # 20·log10(3) = 9.5 dB on deviations
    assert "quieter than the model" in rep.stop_reason


def test_a_model_following_log_gets_no_such_note():
    rep = _run(1.0, 0)
    assert not [n for n in rep.notes if "quieter than the model" in n]


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_a_line_standing_out_of_a_quieter_floor_is_still_named():
    """The same third-amplitude log with a 5 Hz tone on gyro_x (amplitude 10 × the white noise's
    per-sample σ of the quieter log: a PSD line far above the model): gyro_x stays open and the
    tone is named there at its frequency; accel_y, quiet and without it, gets the note."""
    x, _, _ = gt.make(None, N, 3300)
    logs = {ch: np.asarray(x[ch]) / 3.0 for ch in ("gyro_x", "accel_y")}
    sigma = float(np.std(np.diff(logs["gyro_x"]))) / np.sqrt(2.0)
    t = np.arange(N) / gt.RATE
    logs["gyro_x"] = logs["gyro_x"] + 10.0 * sigma * np.sin(2 * np.pi * 5.0 * t + 0.3)
    rep = run_gap(log_from_arrays(logs, gt.RATE, source="quiet + tone"),
                  NoiseModel.model_validate(gt.base_model_dict()), seed=0, max_steps=2,
                  check_tau_range=False)
    tones = [s for s in rep.steps if s.name == "sinusoid" and s.channel == "gyro_x"]
    assert tones and tones[0].params["frequency_hz"] == pytest.approx(5.0, rel=1e-3)
    assert [n.split(":")[0] for n in rep.notes if "quieter than the model" in n] == ["accel_y"]
