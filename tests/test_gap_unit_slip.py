"""A gyro column a unit factor off its model (deg/s read as rad/s, and the reverse) is reported as
a likely unit error and no effect is named on it (:mod:`budget.gap.unit_slip`); the same log in
its right unit is not. The log is written here with NumPy (white rate noise at the model's ARW),
independently of the model gap's simulator."""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.gap import run_gap
from budget.gap.unit_slip import FACTORS, slip
from budget.imu import NoiseModel

RATE_HZ = 100.0
N = 60_000  # 10 min
ARW_DEG_RT_H = 0.5
MODEL = NoiseModel(part_id="white", source="synthetic", gyro_arw_deg_rt_h=ARW_DEG_RT_H)


def _log(path, header_unit: str, scale: float, seed: int = 3):
    """A 10-min, 100 Hz gyro_x log of white rate noise at ARW_DEG_RT_H, its values in deg/s × ``scale``
    under the header suffix ``header_unit``."""
    rng = np.random.default_rng(seed)
    sigma_deg_s = ARW_DEG_RT_H / 60.0 * math.sqrt(RATE_HZ)  # deg/√h → deg/s/√Hz, per sample
    x = rng.normal(0.0, sigma_deg_s, N) * scale
    t = np.arange(N) / RATE_HZ
    path.write_text(f"time_s,gyro_x_{header_unit}\n" + "".join(f"{a:.4f},{b:.9g}\n" for a, b in zip(t, x)))
    return path


@pytest.mark.parametrize("unit,scale,sign", [("rps", 1.0, +1), ("dps", math.pi / 180.0, -1)])
def test_a_gyro_log_in_the_wrong_unit_is_named_a_likely_unit_error(tmp_path, unit, scale, sign):
    # deg/s values under _rps: read 57.3× too loud; rad/s values under _dps: 57.3× too quiet
    report = run_gap(_log(tmp_path / "slip.csv", unit, scale), MODEL, seed=1, realizations=8)
    text = report.summary()
    assert not report.steps, text  # no effect fitted to a unit error
    notes = [n for n in report.notes if "LIKELY UNIT ERROR" in n]
    assert len(notes) == 1 and notes[0].startswith("gyro_x") and "57.3" in notes[0], report.notes
    assert ("above" if sign > 0 else "below") in notes[0]


def test_the_same_log_in_its_right_unit_is_not(tmp_path):
    report = run_gap(_log(tmp_path / "right.csv", "dps", 1.0), MODEL, seed=1, realizations=8)
    assert not [n for n in report.notes if "UNIT ERROR" in n], report.notes
    assert report.within_noise, report.summary()


def test_the_rule_against_its_factors():
    rng = np.random.default_rng(0)
    scatter = rng.normal(0.0, 1.5, 40)  # a unit's own scatter about its datasheet, dB
    for factor, _ in FACTORS:
        db = 20 * math.log10(factor)
        assert slip(db + scatter)[1] == factor and slip(-db + scatter)[1] == factor
    assert slip(scatter) is None and slip(20.0 + scatter) is None  # no factor, or not a rate unit's
    # an effect at a few τ only (an offset at half the points) is not a unit slip
    assert slip(np.concatenate([scatter[:20], 35.2 + scatter[20:]])) is None
