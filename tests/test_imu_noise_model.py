"""Noise model: catalog fields + effects, validation with clear errors, JSON round trip."""

from __future__ import annotations

import json
import math

import pytest

from budget import units as u
from budget.catalog.schema import PartSpec
from budget.errors import InputError
from budget.imu.noise_model import EFFECT_NAMES, EFFECT_PARAMS, Effect, NoiseModel


def _part() -> PartSpec:
    return PartSpec(part_id="TEST1", grade="tactical", source="unit test",
                    gyro_bias_instability_deg_h=0.5, gyro_arw_deg_rt_h=0.15, gyro_rrw_deg_h_rt_h=2.0,
                    gyro_bias_repeatability_deg_h=1.0, accel_vrw_m_s_rt_h=0.03,
                    accel_bias_instability_ug=50.0, accel_scale_factor_ppm=300.0,
                    accel_misalignment_mrad=0.5)


def test_vocabulary_is_the_shared_one_plus_lowpass_vibration_heavy_tails_thermal_lag_warmup_step():
    """The effect/parameter table is pinned: changing it is a deliberate act."""
    assert set(EFFECT_NAMES) == {"white_noise", "quantization", "rate_quantization", "bias_instability",
                                 "rate_random_walk", "rate_ramp", "warmup_transient", "bias_step", "sinusoid", "gauss_markov",
                                 "temperature_sensitivity", "temperature_lag", "outliers", "lowpass", "vibration",
                                 "heavy_tailed"}
    assert EFFECT_PARAMS["temperature_lag"].keys() == {"coefficient", "tau_s"}
    assert EFFECT_PARAMS["warmup_transient"].keys() == {"amplitude", "tau_s"}
    assert EFFECT_PARAMS["bias_step"].keys() == {"amplitude", "time_s"}
    assert EFFECT_PARAMS["rate_quantization"].keys() == {"step"}
    assert EFFECT_PARAMS["vibration"].keys() == {"center_hz", "width_hz", "sigma"}
    assert EFFECT_PARAMS["heavy_tailed"].keys() == {"density", "dof"}


def test_from_part_converts_through_partspec_to_si():
    part = _part()
    si = NoiseModel.from_part(part).to_si()
    assert si.errors == part.to_si()
    assert math.isclose(si.errors.gyro_arw_rad_s_rt_hz, u.deg_rt_h_to_rad_s_rt_hz(0.15))
    effects = {(e.name, e.channel): e for e in si.channel_effects("gyro_y")}
    assert math.isclose(effects["white_noise", "gyro_y"].param("density"), u.deg_rt_h_to_rad_s_rt_hz(0.15))
    # adev_min convention: IEEE B = floor / 0.664
    assert math.isclose(effects["bias_instability", "gyro_y"].param("B"),
                        u.deg_h_to_rad_s(0.5) / math.sqrt(2 * math.log(2) / math.pi))
    assert math.isclose(effects["rate_random_walk", "gyro_y"].param("K"), u.deg_h_rt_h_to_rad_s_rt_s(2.0))
    acc = {e.name for e in si.channel_effects("accel_z")}
    assert acc == {"white_noise", "bias_instability"}
    assert math.isclose(si.scale_factor("accel"), 300e-6)
    assert math.isclose(si.misalignment("accel"), 0.5e-3)
    assert si.turn_on_bias("accel") == 0.0


def test_absent_fields_are_zero_and_identity_optional():
    m = NoiseModel()
    si = m.to_si()
    assert si.channel_effects("gyro_x") == [] and si.errors.gyro_arw_rad_s_rt_hz == 0.0
    assert m.part_id is None and m.grade is None


def test_json_round_trip_and_atomic_save(tmp_path):
    m = NoiseModel.from_part(_part()).with_effect(
        {"name": "sinusoid", "channel": "accel_z", "params": {"frequency_hz": 7.0, "amplitude": 1e-3}})
    m = m.with_effect(Effect(name="quantization", channel="gyro_x", params={"Q": 1e-6}))
    path = tmp_path / "model.json"
    m.save(path)
    data = json.loads(path.read_text())
    assert data["gyro_arw_deg_rt_h"] == 0.15 and data["part_id"] == "TEST1"
    assert data["effects"][0] == {"name": "sinusoid", "channel": "accel_z",
                                  "params": {"frequency_hz": 7.0, "amplitude": 1e-3}}
    assert "gyro_scale_factor_ppm" not in data  # absent stays absent
    back = NoiseModel.load(path)
    assert back == m
    assert not list(tmp_path.glob(".*.tmp"))
    ypath = tmp_path / "model.yaml"
    m.save(ypath)
    assert NoiseModel.load(ypath) == m


def test_with_effect_leaves_original_unchanged():
    m = NoiseModel()
    m2 = m.with_effect({"name": "rate_ramp", "channel": "gyro_z", "params": {"R": -1e-7}})
    assert m.effects == () and len(m2.effects) == 1


@pytest.mark.parametrize("effect, fragment", [
    ({"name": "white_noise", "channel": "gyro_x", "params": {"density": -1.0}}, "≥ 0 rad/s/√Hz"),
    ({"name": "colour_noise", "channel": "gyro_x", "params": {}}, "unknown effect 'colour_noise'"),
    ({"name": "white_noise", "channel": "gyro_w", "params": {"density": 1.0}}, "unknown channel 'gyro_w'"),
    ({"name": "white_noise", "channel": "gyro_x", "params": {"dens": 1.0}}, "unknown parameter(s) dens"),
    ({"name": "sinusoid", "channel": "gyro_x", "params": {"amplitude": 1.0}}, "needs parameter(s) frequency_hz"),
    ({"name": "gauss_markov", "channel": "accel_x", "params": {"tau_s": 0.0, "sigma": 1.0}}, "tau_s must be > 0 s"),
    ({"name": "outliers", "channel": "accel_x", "params": {"rate": 1.5, "magnitude": 1.0}}, "at most 1"),
    ({"name": "white_noise", "channel": "accel_y", "params": {"density": float("nan")}}, "finite"),
    ({"name": "bias_instability", "channel": "accel_y", "params": {"B": -2e-4}}, "≥ 0 m/s²"),
])
def test_invalid_effects_give_clear_errors(tmp_path, effect, fragment):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"effects": [effect]}))
    with pytest.raises(InputError) as err:
        NoiseModel.load(path)
    msg = str(err.value)
    assert fragment in msg and "bad.json" in msg and "effects.0" in msg


def test_invalid_catalog_fields_and_rate():
    with pytest.raises(InputError, match="gyro_arw_deg_rt_h"):
        NoiseModel.from_dict({"gyro_arw_deg_rt_h": -0.1})
    with pytest.raises(InputError, match="unknown_key|Extra inputs"):
        NoiseModel.from_dict({"unknown_key": 1})
    with pytest.raises(InputError, match="below twice the 60 Hz sinusoid"):
        NoiseModel.from_dict({"rate_hz": 100, "effects": [
            {"name": "sinusoid", "channel": "gyro_z", "params": {"frequency_hz": 60, "amplitude": 1e-4}}]})
    with pytest.raises(InputError, match="one quantizer"):
        NoiseModel.from_dict({"effects": [
            {"name": "quantization", "channel": "gyro_z", "params": {"Q": 1e-6}},
            {"name": "quantization", "channel": "gyro_z", "params": {"Q": 2e-6}}]})
    with pytest.raises(InputError, match="one quantizer"):  # the integrated and the rounded-rate form
        NoiseModel.from_dict({"effects": [
            {"name": "quantization", "channel": "gyro_z", "params": {"Q": 1e-6}},
            {"name": "rate_quantization", "channel": "gyro_z", "params": {"step": 1e-4}}]})
    with pytest.raises(InputError, match="below twice"):
        NoiseModel(rate_hz=10).with_effect(
            {"name": "sinusoid", "channel": "gyro_z", "params": {"frequency_hz": 5, "amplitude": 1.0}})


def test_load_reports_file_problems(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        NoiseModel.load(tmp_path / "missing.json")
    bad = tmp_path / "broken.json"
    bad.write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        NoiseModel.load(bad)
    arr = tmp_path / "list.json"
    arr.write_text("[1, 2]")
    with pytest.raises(InputError, match="mapping"):
        NoiseModel.load(arr)
