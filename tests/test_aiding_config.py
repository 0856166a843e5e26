"""Aiding configs: valid scenarios parse; bad ones give one clear InputError naming the field."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from budget.aiding_spec import AidingPlan, GnssAiding, MasterInsAiding, parse_aiding
from budget.errors import InputError

GOOD = [
    {"type": "gnss", "rate_hz": 10, "sigma_m": 0.05, "latency_s": 0.05, "lever_arm_m": [0.5, 0, 0.3]},
    {"type": "dvl", "rate_hz": 5, "sigma_m_s": [0.01, 0.01, 0.02], "bias_sigma_m_s": 0.003},
    {"type": "master_ins", "rate_hz": 1, "sigma_position_m": 2, "sigma_velocity_m_s": 0.02,
     "lever_arm_m": [1.8, 0.5, -0.7],
     "flexure": {"frequency_hz": 3, "damping_ratio": 0.05, "amplitude_m": [0, 0, 0.01]}},
    {"type": "star_tracker", "rate_hz": 1, "sigma_arcsec": 15},
]


def test_good_list_parses_with_types_and_three_sigmas():
    out = parse_aiding(GOOD, imu_rate_hz=100)
    assert [a.type for a in out] == ["gnss", "dvl", "master_ins", "star_tracker"]
    assert out[0].sigma_m == (0.05, 0.05, 0.05)
    assert out[2].flexure.frequency_hz == 3
    assert parse_aiding(None) == [] and parse_aiding([]) == []


@pytest.mark.parametrize("item, field, words", [
    ({"type": "gnss", "rate_hz": 150, "sigma_m": 1}, "aiding[0].rate_hz", "above the IMU rate"),
    ({"type": "gnss", "rate_hz": 1, "sigma_m": -1}, "aiding[0].sigma_m", "> 0"),
    ({"type": "gnss", "rate_hz": 1, "sigma_m": 0}, "aiding[0].sigma_m", "> 0"),
    ({"type": "dvl", "rate_hz": 1, "sigma_m_s": [0.1, float("nan"), 0.1]}, "aiding[0].sigma_m_s", "finite"),
    ({"type": "gnss", "rate_hz": 1, "sigma_m": 1, "lever_arm_m": [0, float("nan"), 0]},
     "aiding[0].lever_arm_m[1]", "finite"),
    ({"type": "master_ins", "rate_hz": 1, "sigma_position_m": 1, "sigma_velocity_m_s": 0.1,
      "lever_arm_m": [1, 2, float("inf")]}, "aiding[0].lever_arm_m[2]", "finite"),
    ({"type": "gnss", "rate_hz": -2, "sigma_m": 1}, "aiding[0].rate_hz", "greater than 0"),
    ({"type": "gnss", "rate_hz": 1, "sigma_m": 1, "latency_s": -0.1}, "aiding[0].latency_s", "greater than or equal"),
    ({"type": "radar_altimeter", "rate_hz": 1}, "aiding[0].type", "unknown aiding type"),
    ({"rate_hz": 1}, "aiding[0].type", "needs a 'type'"),
    ({"type": "star_tracker", "rate_hz": 1}, "aiding[0].sigma_arcsec", "required"),
    ({"type": "dvl", "rate_hz": 1, "sigma_m_s": 0.1, "sigma_m": 1}, "aiding[0].sigma_m", "Extra inputs"),
    ({"type": "master_ins", "rate_hz": 1, "sigma_position_m": 1, "sigma_velocity_m_s": 0.1,
      "lever_arm_m": [0, 0, 0], "flexure": {"frequency_hz": 2, "damping_ratio": 1.2,
                                              "amplitude_m": [0, 0, 0.01]}},
     "aiding[0].flexure.damping_ratio", "less than 1"),
])
def test_bad_aiding_gives_clear_error(item, field, words):
    with pytest.raises(InputError) as exc:
        parse_aiding([GOOD[3], item][1:], imu_rate_hz=100, source="scenario.yaml")
    err = exc.value
    assert err.field == field
    assert words in str(err)
    assert "scenario.yaml" in str(err)


def test_second_entry_is_named_by_index():
    with pytest.raises(InputError) as exc:
        parse_aiding([GOOD[0], {"type": "gnss", "rate_hz": 1, "sigma_m": -3}])
    assert exc.value.field == "aiding[1].sigma_m"


def test_not_a_list_and_bad_imu_rate():
    with pytest.raises(InputError, match="must be a list"):
        parse_aiding({"type": "gnss"})
    with pytest.raises(InputError, match="IMU rate"):
        parse_aiding(GOOD, imu_rate_hz=float("nan"))


def test_rate_check_through_pydantic_context():
    GnssAiding.model_validate({"rate_hz": 50, "sigma_m": 1}, context={"imu_rate_hz": 50})
    with pytest.raises(ValidationError, match="above the IMU rate"):
        GnssAiding.model_validate({"rate_hz": 51, "sigma_m": 1}, context={"imu_rate_hz": 50})


def test_plan_round_trip_modes_and_label():
    plan = AidingPlan.model_validate({"aiding": GOOD, "mode": "smoothed", "warmup_s": 30})
    assert isinstance(plan.aiding[2], MasterInsAiding)
    again = AidingPlan.model_validate(plan.model_dump())
    assert again == plan
    assert plan.label() == "gnss+dvl+master_ins+star_tracker, smoothed, 30 s warm-up"
    assert AidingPlan().mode == "frozen" and AidingPlan().label() == "none"
    with pytest.raises(ValidationError):
        AidingPlan.model_validate({"aiding": GOOD, "mode": "ukf"})
    with pytest.raises(ValidationError):
        AidingPlan.model_validate({"aiding": GOOD, "smoother": "rts"})  # renamed: mode


def test_typed_configs_are_accepted_as_they_are():
    typed = parse_aiding(GOOD, imu_rate_hz=100)
    assert parse_aiding(tuple(typed), imu_rate_hz=100) == typed
