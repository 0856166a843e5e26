"""Values that parse but mean something else are refused with the field named: true/false where
a number is expected (pydantic would read 1 and 0), a key given twice in JSON/YAML (a reader
would keep one silently), bounds options that cannot apply, an empty part list, a scenario whose
simulated scene does not fit its slant range, a log channel with no noise to model."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

import budget
from budget.bounds import LeverArmAssumptions, compute_bounds
from budget.cli.main import main
from budget.errors import InputError
from budget.structured import read_structured
from budget.imu.noise_model import NoiseModel
from budget.noise import LogMapping
from budget.noise.pipeline import analyse_arma
from budget.presets import get_preset
from budget.sar.geometry import SarGeometry
from budget.scenario import Scenario


def _scenario_dict(**changes) -> dict:
    data = get_preset("airborne_xband").model_dump(mode="json")
    data.update(changes)
    return data


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err, err
    return err


# --- true/false where a number is expected ---------------------------------------------------

def test_json_true_for_a_number_is_refused_not_read_as_one(tmp_path):
    p = tmp_path / "s.json"
    p.write_text(json.dumps(_scenario_dict(slant_range_m=True)))
    with pytest.raises(InputError) as e:
        Scenario.load(p)
    assert e.value.field == "slant_range_m" and "true/false" in str(e.value) and "s.json" in str(e.value)


@pytest.mark.parametrize("word", ["yes", "on", "true", "off"])
def test_yaml_boolean_words_for_a_number_are_refused(tmp_path, word):
    text = yaml.safe_dump(_scenario_dict(), sort_keys=False)
    p = tmp_path / "s.yaml"
    p.write_text(text.replace("squint_deg: 0.0", f"squint_deg: {word}"))
    with pytest.raises(InputError) as e:
        Scenario.load(p)
    assert e.value.field == "squint_deg"


def test_boolean_inside_a_number_list_is_refused():
    with pytest.raises(InputError) as e:
        Scenario.from_dict(_scenario_dict(lever_arm_m=[True, 0.0, 0.0]))
    assert e.value.field == "lever_arm_m"


def test_boolean_in_an_aiding_sensor_names_its_field():
    aid = {"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02, "latency_s": True}
    with pytest.raises(InputError) as e:
        Scenario.from_dict(_scenario_dict(aiding=[aid]))
    assert e.value.field == "aiding[0].latency_s"
    # a field that is a bool stays a bool
    ok = Scenario.from_dict(_scenario_dict(aiding=[{"type": "master_ins", "rate_hz": 10.0,
                                                    "sigma_position_m": 0.01, "sigma_velocity_m_s": 0.01,
                                                    "lever_arm_m": [1.0, 0.0, 0.0],
                                                    "estimate_flexure": False}]))
    assert ok.aiding[0].estimate_flexure is False


def test_boolean_in_a_noise_model_and_a_log_mapping_is_refused():
    with pytest.raises(InputError) as e:
        NoiseModel.from_dict({"gyro_arw_deg_rt_h": True})
    assert e.value.field == "gyro_arw_deg_rt_h"
    with pytest.raises(Exception) as e:
        LogMapping.model_validate({"rate_hz": True})
    assert "true/false" in str(e.value)
    assert LogMapping.model_validate({"rate_hz": 100}).rate_hz == 100.0


# --- a key given twice --------------------------------------------------------------------------

@pytest.mark.parametrize("name,text,field,said", [
    ("s.yaml", "name: a\nslant_range_m: 5000\nslant_range_m: 6000\n", "slant_range_m", "lines 2 and 3"),
    ("s.json", '{"name": "a", "inner": {"k": 1, "k": 2}}', "k", "s.json")])
def test_a_key_given_twice_is_refused(tmp_path, name, text, field, said):
    p = tmp_path / name
    p.write_text(text)
    with pytest.raises(InputError) as e:
        read_structured(p, "a scenario")
    assert e.value.field == field and said in str(e.value)


def test_yaml_merge_key_still_merges(tmp_path):
    p = tmp_path / "m.yaml"
    p.write_text("base: &b {x: 1, y: 2}\nother:\n  <<: *b\n  x: 3\n")
    assert read_structured(p, "a mapping")["other"] == {"x": 3, "y": 2}


# --- bounds: options that cannot apply, bad wavelength / lever arm ------------------------------

@pytest.mark.parametrize("extra, option", [
    (["--mode", "no-autofocus", "--wavelength", "nan"], "--wavelength"),
    (["--mode", "no-autofocus", "--wavelength", "-1"], "--wavelength"),
    (["--mode", "lever-arm", "--wavelength", "0.03", "--lever-arm", "nan", "0", "0"], "--lever-arm"),
    (["--mode", "lever-arm", "--wavelength", "0.03", "--lever-arm", "1e9", "0", "0"], "--lever-arm"),
    (["--mode", "lever-arm", "--wavelength", "0.03", "--platform-rate", "-1"], "--platform-rate"),
    (["--lever-arm", "1", "0", "0"], "--lever-arm"),          # paper mode would ignore it
    (["--platform-rate", "2"], "--platform-rate"),
])
def test_bounds_options_are_checked(extra, option, capsys):
    assert main(["bounds", "--tc", "1", "--range-resolution", "0.1", *extra]) == 2
    assert f"option {option}" in _one_line(capsys)


def test_lever_arm_bounds_refuse_non_finite_lever_arm_and_name_bad_modes():
    with pytest.raises(ValueError):
        LeverArmAssumptions(lever_arm_m=(float("nan"), 0.0, 0.0))
    ok = compute_bounds(1.0, 0.1, "lever-arm", wavelength_m=0.03,
                        assumptions=LeverArmAssumptions(lever_arm_m=(1.0, 0.0, 0.0)))
    assert np.all(np.isfinite(ok.gyro_arw_rad_s_rt_hz))
    with pytest.raises(InputError) as e:
        compute_bounds(1.0, 0.1, "papr")
    assert e.value.field == "mode"
    with pytest.raises(InputError) as e:
        compute_bounds(1.0, 0.1, "no-autofocus", wavelength_m=-1.0)
    assert e.value.field == "wavelength_m"


# --- check, SAR geometry, ARMA ------------------------------------------------------------------

def test_check_of_no_parts_is_an_input_error():
    with pytest.raises(InputError) as e:
        budget.check_parts([], "airborne_xband")
    assert e.value.field == "parts"


def test_check_table_keeps_long_binding_names_in_their_column():
    text = budget.check_parts(["ADIS16460"], "airborne_xband").summary()
    header, row = text.splitlines()[:2]
    assert row.index("pass", row.index("gyro_")) == header.index("PGA-limited")


def test_scene_larger_than_the_slant_range_names_the_slant_range():
    s = Scenario.from_dict(_scenario_dict(slant_range_m=1.0))  # a 0.5 m cell needs R > 0.5 m
    with pytest.raises(InputError) as e:
        SarGeometry.from_scenario(s)
    assert e.value.field == "slant_range_m" and "≥ 120 m" in str(e.value)


def test_constant_channel_names_the_channel_and_the_log(tmp_path, capsys):
    with pytest.raises(InputError) as e:
        analyse_arma(np.zeros(1000), 100.0, channel="gyro_x")
    assert e.value.field == "gyro_x"
    log = tmp_path / "flat.csv"
    log.write_text("time_s,gyro_x_dps\n" + "".join(f"{i / 100:.2f},0.5\n" for i in range(500)))
    assert main(["noise", "arma", str(log), "--channel", "gyro_x", "-q"]) == 2
    err = _one_line(capsys)
    assert "flat.csv" in err and "field gyro_x" in err


def test_a_folder_given_as_a_scenario_is_called_a_folder(tmp_path):
    with pytest.raises(InputError) as e:
        Scenario.load(tmp_path)
    assert "is a folder" in str(e.value) and "not found" not in str(e.value)


def test_numpy_values_in_messages_read_as_plain_numbers():
    err = InputError("not a positive finite number", field="adev", value=np.float64(-0.25))
    assert "(got -0.25)" in str(err)
    err = InputError("need lci ≤ adev ≤ uci", field="lci",
                     value=(np.float64(0.3), np.float64(0.25), np.float64(0.2)))
    assert "(got (0.3, 0.25, 0.2))" in str(err)


def test_disturbance_file_is_read_with_the_structured_file_limits(tmp_path):
    from budget.nav.platform import Disturbance

    p = tmp_path / "d.json"
    p.write_text('{"sinusoids": [{"axis": "heave", "frequency_hz": 0.5, "amplitude_m": 0.1,'
                 ' "amplitude_m": 100.0}]}')
    with pytest.raises(InputError) as e:
        Disturbance.load(p)
    assert e.value.field == "amplitude_m" and "twice" in str(e.value)
    p.write_text("[1, 2]")
    with pytest.raises(InputError, match="mapping"):
        Disturbance.load(p)


def test_dashboard_upload_reads_with_the_cli_rules():
    import sys
    from pathlib import Path

    app_dir = str(Path(__file__).resolve().parents[1] / "app")
    if app_dir not in sys.path:
        sys.path.insert(0, app_dir)
    sidebar = pytest.importorskip("sidebar")
    text = yaml.safe_dump(_scenario_dict(), sort_keys=False) + "slant_range_m: 9000\n"
    with pytest.raises(InputError) as e:
        sidebar.scenario_from_upload(text.encode(), "up.yaml")
    assert e.value.field == "slant_range_m" and "twice" in str(e.value) and "up.yaml" in str(e.value)


def test_sar_sinusoid_faster_than_the_pulses_is_refused_not_aliased(capsys):
    assert main(["sar", "--preset", "automotive_24ghz", "--sinusoid-cycles", "1e6"]) == 2
    err = _one_line(capsys)
    assert "option --sinusoid-cycles" in err and "≤ 50" in err


def test_semicolon_catalog_is_named_as_a_delimiter_problem(tmp_path):
    from budget.catalog.io import read_parts

    p = tmp_path / "semi.csv"
    p.write_text("part_id;grade;source;gyro_arw_deg_rt_h\nX1;tactical;ds;0.15\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert "';' as its delimiter" in str(e.value) and e.value.row == 1


def test_catalog_row_says_which_values_the_record_did_not_resolve(tmp_path):
    from budget.noise import characterize, read_log

    rng = np.random.default_rng(0)
    n = 20_000  # 200 s of white noise at 100 Hz: no bias instability the record could resolve
    g = rng.normal(0.0, 0.01, (n, 3))
    a = rng.normal(0.0, 0.003, (n, 3))
    a[:, 2] -= 9.80665
    x = np.column_stack([g, a])
    p = tmp_path / "white.csv"
    header = "time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2\n"
    p.write_text(header + "".join(f"{i / 100:.4f}," + ",".join(f"{v:.6g}" for v in row) + "\n"
                                  for i, row in enumerate(x)))
    res = characterize(read_log(p))
    # an unresolved figure is left empty in the row (the catalog's "unspecified"), not written
    # as if it were a datasheet figure, and the row and the summary say why
    assert res.part.gyro_bias_instability_deg_h is None
    assert "gyro_bias_instability_deg_h" in res.left_empty
    assert "gyro_bias_instability_deg_h" in res.part.notes and "not resolved" in res.part.notes
    assert res.part.gyro_arw_deg_rt_h is not None  # … ARW is resolved
    assert "gyro_arw_deg_rt_h" not in res.left_empty
    assert "left empty" in res.summary()


@pytest.mark.parametrize("medium, speed, hint", [("radar", 1500.0, "sonar"),
                                                 ("sonar", 299_792_458.0, "radar")])
def test_propagation_speed_of_the_other_medium_is_refused(medium, speed, hint):
    changes = dict(medium=medium, propagation_speed_m_s=speed)
    if medium == "sonar":
        changes.update(carrier_frequency_hz=100e3)
    with pytest.raises(InputError) as e:
        Scenario.from_dict(_scenario_dict(**changes))
    assert e.value.field == "propagation_speed_m_s" and f"medium '{hint}'" in str(e.value)
    # the speeds of the media themselves stay accepted (water: radio c/9, sound 1480 m/s)
    ok = 1480.0 if medium == "sonar" else 299_792_458.0 / 9
    assert Scenario.from_dict(_scenario_dict(**{**changes, "propagation_speed_m_s": ok})).c_m_s == ok


@pytest.mark.parametrize("tag, scale, slip", [("mps2", 1.0, "g read as m/s²"),
                                              ("g", 9.80665, "m/s² read as g")])
def test_static_log_whose_gravity_is_off_by_a_unit_factor_is_refused(tmp_path, tag, scale, slip):
    from budget.noise import read_log

    rng = np.random.default_rng(3)
    n = 2000
    acc = rng.normal(0.0, 3e-4, (n, 3)) * scale
    acc[:, 2] -= scale  # 1 g written as 1 (or 9.81 m/s² written as 9.81) under a wrong unit tag
    p = tmp_path / "acc.csv"
    p.write_text(f"time_s,accel_x_{tag},accel_y_{tag},accel_z_{tag}\n"
                 + "".join(f"{i / 100:.2f},{a:.6g},{b:.6g},{c:.6g}\n" for i, (a, b, c) in enumerate(acc)))
    with pytest.raises(InputError) as e:
        read_log(p)
    assert slip in str(e.value) and e.value.field == f"accel_x_{tag} … accel_z_{tag}"
    # the same numbers under the right unit read fine, gravity ≈ 1 g
    right = "g" if tag == "mps2" else "mps2"
    p.write_text(p.read_text().replace(f"_{tag}", f"_{right}", 3))
    log = read_log(p)
    assert abs(np.linalg.norm([log.channels[a].mean() for a in ("accel_x", "accel_y", "accel_z")])
               - 9.80665) < 0.05


def test_model_gap_refuses_a_dead_channel(tmp_path):
    """A channel with one constant value has a zero Allan deviation and PSD: the gap would be
    inf → inf; the comparison is refused naming the log and the channel."""
    from budget.gap import run_gap
    from budget.gap.inputs import log_from_arrays
    rng = np.random.default_rng(4)
    n = 20_000
    chans = {c: rng.normal(0.0, 1e-3, n) for c in ("gyro_x", "gyro_y", "gyro_z")}
    chans["gyro_y"] = np.full(n, 0.01)
    log = log_from_arrays(chans, 100.0, source="dead.csv")
    with pytest.raises(InputError) as e:
        run_gap(log, "STIM300")
    assert "gyro_y" in str(e.value) and "dead.csv" in str(e.value) and "constant" in str(e.value)


def test_mc_acceptance_file_is_read_with_the_structured_file_rules(tmp_path, capsys):
    spec = tmp_path / "acc.json"
    spec.write_text('{"max_broadening": 0.1, "max_broadening": 0.5}')
    assert main(["mc", "--preset", "automotive_24ghz", "--part", "STIM300", "--trials", "8",
                 "--acceptance", str(spec), "-q"]) == 2
    err = _one_line(capsys)
    assert "max_broadening" in err and "acc.json" in err


def test_log_rows_with_more_fields_than_the_header_are_refused_not_cut(tmp_path):
    """Every data row one field longer than the header (a column without a name): pandas would
    drop the last field with only a warning; the row is named instead. Trailing delimiters
    (``1,2,3,``) lose nothing and still read."""
    from budget.noise.logs import read_log
    head = "time_s,gyro_x_rps,gyro_y_rps,gyro_z_rps\n"
    extra = tmp_path / "extra.csv"
    extra.write_text(head + "".join(f"{0.01 * i:.2f},1,2,3,{i}\n" for i in range(8)))
    with pytest.raises(InputError) as e:
        read_log(extra)
    assert e.value.row == 2 and "5 fields" in str(e.value)
    trail = tmp_path / "trail.csv"
    trail.write_text(head + "".join(f"{0.01 * i:.2f},1,2,{i},\n" for i in range(8)))
    assert read_log(trail).channels["gyro_z"].tolist() == list(range(8))


def test_a_time_column_in_ms_named_time_s_is_refused_unless_the_rate_is_confirmed(tmp_path):
    """100 Hz time stamps written in ms under ``time_s`` read as 0.1 Hz, and every noise figure
    scales with the rate (a warning let ARW 31.6× too large into an appended catalog row): the
    reading is refused, naming the column to use and how to confirm the rate; a given rate
    that confirms 0.1 Hz reads it, and 100 Hz is refused too: the column declares s, and the
    tool cannot tell whether the column or the rate is wrong."""
    from budget.noise.logs import read_log
    p = tmp_path / "ms.csv"
    rng = np.random.default_rng(2)
    p.write_text("time_s,gyro_x_rps\n" + "".join(f"{10 * i},{rng.normal(0, 1e-3):.6g}\n" for i in range(64)))
    with pytest.raises(InputError) as e:
        read_log(p)
    assert e.value.field == "time_s" and "ms.csv" in str(e.value)
    assert "0.1 Hz" in str(e.value) and "time_ms" in str(e.value) and "--rate-hz" in str(e.value)
    assert read_log(p, rate_hz=0.1).rate_hz == pytest.approx(0.1)
    with pytest.raises(InputError, match="time_ms") as e:
        read_log(p, rate_hz=100.0)
    assert e.value.field == "time_s"
