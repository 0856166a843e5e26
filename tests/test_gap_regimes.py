"""A log channel with two noise levels (a fan or a vehicle switched on mid-record) is reported and
not worked on: no effect of the vocabulary changes the noise level mid-record, and the workflow
had named six (heavy tails, bias instability, a low-pass, a Gauss–Markov term, a ramp, outliers)
on the real ADIS16405 log with gyro_x × 3 from its middle. The log is written here with NumPy
(white rate noise at the model's ARW), independently of the model gap's simulator."""

from __future__ import annotations

import math

import numpy as np

from budget.gap import run_gap
from budget.imu import NoiseModel

RATE_HZ = 100.0
N = 60_000  # 10 min
ARW_DEG_RT_H = 0.5
MODEL = NoiseModel(part_id="white", source="synthetic", gyro_arw_deg_rt_h=ARW_DEG_RT_H)


def _log(path, gain_after: float, seed: int = 4):
    """gyro_x and gyro_y, white rate noise at ARW_DEG_RT_H (deg/s); gyro_x × ``gain_after`` from
    the record's middle on."""
    rng = np.random.default_rng(seed)
    sigma = ARW_DEG_RT_H / 60.0 * math.sqrt(RATE_HZ)
    x, y = rng.normal(0.0, sigma, (2, N))
    x[N // 2:] *= gain_after
    t = np.arange(N) / RATE_HZ
    path.write_text("time_s,gyro_x_dps,gyro_y_dps\n"
                    + "".join(f"{a:.4f},{b:.9g},{c:.9g}\n" for a, b, c in zip(t, x, y)))
    return path


def test_a_channel_with_two_noise_levels_is_reported_and_not_worked_on(tmp_path):
    report = run_gap(_log(tmp_path / "two.csv", 3.0), MODEL, seed=1, realizations=8)
    assert not [s for s in report.steps if s.channel == "gyro_x"], report.summary()
    notes = [n for n in report.notes if "not one stationary regime" in n and "gyro_x" in n]
    assert notes and "no effect is named on gyro_x" in notes[0], report.notes
    assert "two noise regimes" in report.stop_reason
    assert not [s for s in report.steps if s.channel == "gyro_y"]  # the other channel follows the model


def test_one_noise_level_is_worked_on_as_before(tmp_path):
    report = run_gap(_log(tmp_path / "one.csv", 1.0), MODEL, seed=1, realizations=8)
    assert not [n for n in report.notes if "not one stationary regime" in n], report.notes
    assert report.within_noise, report.summary()
