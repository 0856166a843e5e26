"""Cross-validation (``budget.gap.cross_validate``) and the inputs users bring.

Synthetic: two logs of the same "part" drawn by the independent generators of
``tests/gap_truth.py``; both carry a 7.3 Hz tone on accel_x (a property of the part), only the
first carries a 12 Hz band-limited vibration (a property of that day's bench). Fitted on the
first and tested on the second, the tone carries over and the vibration is not named.
Real (the shared data set beside the repository, skipped when absent): the MPU-6050 raw-count log through the
explicit mapping in ``docs/gap/mpu6050_mapping.json``, and the two ADIS16405 logs.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import cross_validate, log_from_arrays, run_gap
from budget.imu import NoiseModel
from budget.noise import LogMapping, read_log

BASE = NoiseModel.model_validate(gt.base_model_dict())
N = 32_768
MAPPING = gt.__file__.replace("tests/gap_truth.py", "docs/gap/mpu6050_mapping.json")


def _log(seed: int, with_vibration: bool):
    rng = np.random.default_rng(seed)
    x = gt.base_channel("accel_x", N, rng)
    t = np.arange(N) / gt.RATE
    x += 6e-3 * np.sin(2 * math.pi * 7.3 * t + rng.uniform(0, 2 * math.pi))
    if with_vibration:
        v, _ = gt._vibration(N, rng, None)
        x += 8e-3 * v
    return log_from_arrays({"accel_x": x}, gt.RATE, source=f"log {seed}")


@pytest.mark.slow
def test_effect_that_does_not_carry_over_is_not_named():
    cv = cross_validate(_log(1, True), _log(2, False), BASE, seed=0, max_steps=4,
                        check_tau_range=False)
    named = {s.name for s in cv.fit.steps}
    assert {"sinusoid", "vibration"} <= named, cv.fit.summary()
    assert [c["name"] for c in cv.carried].count("sinusoid") == 1, cv.summary()
    assert "vibration" in [c["name"] for c in cv.dropped], cv.summary()
    assert "vibration" not in {f.name for f in cv.validated_model.effects}
    g_base, _ = cv.overall("base")
    g_val, _ = cv.overall("validated")
    assert g_val < g_base / 3
    out = cv.to_dict()
    assert out["not_carried_over"] and out["test"]["validated"]["gap"] == pytest.approx(g_val)


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
@pytest.mark.shared_data
def test_mpu6050_raw_counts_through_an_explicit_mapping(shared_data):
    path = shared_data / "logs" / "mpu6050" / "mpu6050_static_counts.csv"
    if not path.is_file():
        pytest.skip(f"{path} not found")
    mapping = LogMapping.load(MAPPING)
    log = read_log(path, mapping, False)
    assert log.n_samples == 44_930 and log.rate_hz == 100.0
    assert 8.5 < float(np.mean(log.channels["accel_z"])) < 9.5  # uncalibrated gravity, m/s²
    assert abs(float(np.mean(log.channels["gyro_x"]))) < 0.1    # turn-on bias, rad/s
    rep = run_gap(path, "MPU-6050", mapping=mapping, channels=["gyro_x"], max_steps=2, seed=0)
    assert rep.steps and rep.steps[0].name == "white_noise", rep.summary()
    # catalog gyro density 0.005 deg/s/√Hz; the log's is the catalog's plus the named term
    cat = 0.005 * math.pi / 180
    total = math.hypot(cat, rep.steps[0].params["density"])
    assert 1.0 < total / cat < 2.5, rep.summary()
