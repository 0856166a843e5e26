"""Monte Carlo with aiding from the scenario: validation, determinism, and what smoothing buys."""

import pytest

from budget.catalog.io import get_part
from budget.errors import InputError
from budget.mc import run_mc
from budget.presets import get_preset
from budget.scenario import Scenario

GNSS = {"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02}


def aided(preset: str, **upd) -> Scenario:
    return Scenario.model_validate(get_preset(preset).model_dump() | upd)


@pytest.mark.parametrize("entry,words", [
    ({"type": "gnss", "rate_hz": 1000.0, "sigma_m": 0.02}, "above the IMU rate"),
    ({"type": "gnss", "rate_hz": 10.0, "sigma_m": -1.0}, "sigma_m"),
    ({"type": "master_ins", "rate_hz": 1.0, "sigma_position_m": 2.0, "sigma_velocity_m_s": 0.02,
      "lever_arm_m": [1.0, float("nan"), 0.0]}, "lever_arm_m"),
    ({"type": "sonar_magic"}, "type"),
])
def test_bad_aiding_in_scenario(entry, words):
    with pytest.raises(InputError, match=words):
        Scenario.from_dict(get_preset("airborne_xband").model_dump() | {"aiding": [entry]})


def test_aided_run_is_deterministic_and_bounded():
    s = aided("automotive_77ghz", aiding=[GNSS], aiding_warmup_s=5.0)
    a = run_mc(s, get_part("MPU-6050"), 64, 4).to_json_dict()
    b = run_mc(s, get_part("MPU-6050"), 64, 4).to_json_dict()
    assert a["metrics_after"] == b["metrics_after"]
    # GNSS at 2 cm bounds the error: no trial migrates by more than a range cell (δr = 0.1 m)
    assert a["failure_reasons"]["range_migration"] == 0


def test_smoothing_beats_realtime_filter_for_a_consumer_imu():
    # A real-time filter jumps at every fix (fast phase at 77 GHz); the RTS smoother does not.
    kf = aided("automotive_77ghz", aiding=[GNSS], aiding_warmup_s=5.0)
    rts = aided("automotive_77ghz", aiding=[GNSS], aiding_warmup_s=5.0, aiding_smoother="rts")
    p_kf = run_mc(kf, get_part("MPU-6050"), 64, 5).p_pass_after
    p_rts = run_mc(rts, get_part("MPU-6050"), 64, 5).p_pass_after
    assert p_rts >= p_kf
