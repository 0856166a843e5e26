"""Review of scenario validation, bounds notes and check/MC output: every error of a file at once,
a platform acceleration the paper bounds do not use (and one in the wrong unit), the long lever
arm's wording, the MC's aperture note once, the compared check named, why no grade suffices,
errors with got/expected, an output folder created and said, and the lever-arm misalignment
limit capped at 90°. Test data inline: a Ku-band UAV strip-map (16 GHz, 2 km, 0.3 m, 40 m/s)."""

from __future__ import annotations

import json
import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from budget import compute_bounds
from budget.bounds import lever_arm_terms
from budget.bounds.lever_arm import MISALIGNMENT_CAP_RAD, LeverArmAssumptions, pga_limited_bounds
from budget.catalog.io import load_grades
from budget.cli.main import main
from budget.errors import InputError
from budget.parameters import BY_COLUMN, grade_value
from budget.presets import get_preset
from budget.recommend import lowest_sufficient_grades
from budget.report import check_vs_mc, check_vs_mc_text
from budget.scenario import HIGH_PLATFORM_ACCEL_M_S2, TYPICAL_PRESET, Scenario
from budget.units import G0

#: a Ku-band UAV strip-map (what the reviewer's files start from)
KU_UAV = {"name": "ku_uav", "medium": "radar", "carrier_frequency_hz": 16.0e9, "slant_range_m": 2000.0,
          "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3, "platform_speed_m_s": 40.0,
          "depression_deg": 30.0}


def _yaml(path, data: dict):
    path.write_text("".join(f"{k}: {json.dumps(v)}\n" for k, v in data.items()))
    return path


def _one_line_error(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err, err
    return err


# --- 1. every error of a file at once -------------------------------------------------------------

@pytest.mark.parametrize("bad", [
    {"carrier_frequency_hz": 16.0, "slant_range_m": -2.0},        # GHz written in Hz + a negative range
    {"carrier_frequency_hz": 16.0, "platform_speed_m_s": 40000.0},  # two implausible values
])
def test_one_run_names_every_per_field_error_and_every_implausible_valid_field(tmp_path, capsys, bad):
    with pytest.raises(InputError) as e:
        Scenario.from_dict(KU_UAV | bad)
    assert [x.field for x in e.value.errors] == list(bad)  # in the file's key order
    for x in e.value.errors:  # each with its own value, or the value in its words, and what it expects
        assert x.value == bad[x.field] or (f"{bad[x.field]:.4g}" in x.reason and x.expected)
    path = _yaml(tmp_path / "multi.yaml", KU_UAV | bad)
    for argv in (["scenario", "validate", str(path)], ["bounds", "--scenario", str(path)]):
        assert main(argv) == 2
        err = _one_line_error(capsys)
        assert all(f"field {key}" in err for key in bad) and "1 more error" in err and str(path) in err


def test_each_error_alone_is_reported_as_before():
    """Fixing one of the two leaves the other, alone, with its own value and expectation."""
    with pytest.raises(InputError) as e:
        Scenario.from_dict(KU_UAV | {"carrier_frequency_hz": 16.0})
    assert e.value.field == "carrier_frequency_hz" and e.value.value == 16.0 and e.value.errors == ()
    assert f"{16.0 * 1e9:.4g} Hz if it was in GHz" in str(e.value)


# --- 2. platform_accel_m_s2: used by the derived bounds only, and a unit slip noted -----------------

@pytest.mark.parametrize("accel", [0.0, 2 * G0])  # free fall, a 2 g pull-up
def test_paper_and_lever_arm_bounds_take_g_and_say_so(accel):
    s = Scenario.from_dict(KU_UAV | {"platform_accel_m_s2": accel})
    dr, tc = s.range_resolution_m, s.tc_s
    for mode in ("paper", "lever-arm"):
        table = compute_bounds(s, mode)
        assert float(table.accel_scale_factor[0]) == pytest.approx(0.2 * dr / tc ** 2, rel=1e-12)  # seed 004 (6)
        note = " ".join(table.scenario_notes)
        assert "platform_accel_m_s2" in note and "is not used" in note and f"g = {G0:g} m/s²" in note
        assert "derived" in note and note in table.summary() and note in table.to_dict()["notes"]


def test_derived_bounds_use_the_file_value_and_say_so():
    a = 2 * G0
    s = Scenario.from_dict(KU_UAV | {"platform_accel_m_s2": a})
    table = compute_bounds(s, "derived")
    # β ≤ 2 δr/(a Tc²) with the file's a (budget.bounds.derived)
    assert float(table.accel_scale_factor[0]) == pytest.approx(2 * s.range_resolution_m / (a * s.tc_s ** 2), rel=1e-12)
    assert "use it" in table.scenario_notes[0] and f"{a:.6g} m/s²" in table.scenario_notes[0]
    assert compute_bounds(Scenario.from_dict(KU_UAV), "derived").scenario_notes == ()  # nothing set: nothing said


def test_check_states_the_acceleration_its_verdicts_use(tmp_path, capsys):
    path = _yaml(tmp_path / "pullup.yaml", KU_UAV | {"platform_accel_m_s2": 2 * G0})
    assert main(["check", "--scenario", str(path), "--part", "STIM300"]) == 0
    out = capsys.readouterr().out
    assert "platform_accel_m_s2 = 19.6133 m/s² (2 g) in the scenario is not used" in out
    assert "PGA-limited verdict" in out
    assert main(["check", "--scenario", str(path), "--part", "STIM300", "--mode", "derived", "--json", "-"]) == 0
    notes = json.loads(capsys.readouterr().out)["notes"]
    assert len(notes) == 1 and "derived bounds" in notes[0] and "use it" in notes[0]


def test_an_acceleration_in_mm_per_s2_is_noted_with_the_unit():
    a = 1000 * G0  # 1 g written in mm/s²
    with pytest.warns(UserWarning, match="platform_accel_m_s2") as rec:
        Scenario.from_dict(KU_UAV | {"platform_accel_m_s2": a})
    text = " ".join(str(w.message) for w in rec)
    assert f"{a / G0:.4g} g" in text and "mm/s²" in text and "tens of g" in text
    assert HIGH_PLATFORM_ACCEL_M_S2 == pytest.approx(100 * G0)
    with warnings.catch_warnings():  # a 40 g missile manoeuvre is a real value: nothing to say
        warnings.simplefilter("error")
        Scenario.from_dict(KU_UAV | {"platform_accel_m_s2": 40 * G0})


# --- 3. the long lever arm's wording ---------------------------------------------------------------

def test_a_lever_arm_in_cm_is_described_entry_by_entry():
    arm = [50.0, 0.0, 30.0]  # 0.5 m and 0.3 m written in cm
    length = math.hypot(50.0, 30.0)
    with pytest.warns(UserWarning, match="lever arm") as rec:
        Scenario.from_dict(KU_UAV | {"lever_arm_m": arm})
    text = next(str(w.message) for w in rec if "lever arm" in str(w.message))
    assert f"{length:.4g} m long" in text and "an entry of 50 reads as 50 m" in text
    assert f"reads as {length:.4g} m" not in text  # the old, wrong wording
    assert f"the arm {length / 100:.4g} m long" in text


# --- 4 and 5. the Monte Carlo: its aperture note once, the compared check named ---------------------

def test_mc_states_the_aperture_rounding_once_and_names_the_pga_limited_check(tmp_path, capsys):
    # W band at 100 m and 50 m/s: Tc = 31.9 ms, 6 intervals of the default 200 Hz IMU (5.9 % short)
    short = {"name": "short_tc", "medium": "radar", "carrier_frequency_hz": 94.0e9, "slant_range_m": 100.0,
             "azimuth_resolution_m": 0.1, "range_resolution_m": 0.1, "platform_speed_m_s": 50.0,
             "depression_deg": 10.0}
    path = _yaml(tmp_path / "short_tc.yaml", short)
    with warnings.catch_warnings():
        warnings.simplefilter("always")  # a repeat would be printed, not folded by Python's once-per-place rule
        assert main(["mc", "--scenario", str(path), "--part", "STIM300", "--trials", "8", "-q"]) == 0
    out, err = capsys.readouterr()
    assert err.count("IMU intervals") == 1, err
    line = next(x for x in out.splitlines() if x.startswith("check vs Monte Carlo"))
    assert "PGA-limited check" in line


def test_check_vs_mc_text_names_the_check_compared():
    """The check table's verdict (paper mode) passes, the PGA-limited one fails: the line says which."""
    record = {"part_id": "ADIS16405", "verdict": "pass", "pga_limited_verdict": "fail"}
    mc = SimpleNamespace(p_pass_after=0.0, ci_after=(0.0, 0.11))
    versus = check_vs_mc(record, mc)
    text = check_vs_mc_text(versus)
    assert versus["agree"] is True
    assert text == f"check vs Monte Carlo: agree ({versus['check_basis']} fail, MC fail)"
    assert versus["check_basis"] == "PGA-limited check"


# --- 6. why no grade suffices ----------------------------------------------------------------------

def test_no_sufficient_grade_names_the_binding_term_and_the_miss(tmp_path, capsys):
    slow = Scenario.from_dict(KU_UAV | {"name": "slow", "platform_speed_m_s": 0.5})  # Tc = 125 s
    grades = list(load_grades().values())
    rec = lowest_sufficient_grades(slow, "paper", grades)
    assert rec["pga_limited"] is None and set(rec) == {"paper", "pga_limited"}
    why = rec.why_none["pga_limited"]
    # the numbers in it, from the PGA-limited table and the best grade's best typical value
    vrw = BY_COLUMN["accel_vrw_m_s_rt_h"]
    bound = float(pga_limited_bounds(slow)[0].accel_vrw_m_s2_rt_hz[0]) / vrw.grade_to_si
    best = grade_value(load_grades()["strategic"], vrw, "best") * vrw.to_si / vrw.grade_to_si
    assert best > bound
    assert (f"fast-phase limit on accel VRW, {bound:.3g} {vrw.grade_unit}, is below the strategic grade's best "
            f"{best:.3g} {vrw.grade_unit} ({best / bound:.3g}× too large)") in why
    assert rec.text("pga_limited") == f"none — {why}"
    path = _yaml(tmp_path / "slow.yaml", slow.model_dump(exclude_unset=True))
    assert main(["check", "--scenario", str(path), "--part", "HG9900"]) == 0
    assert f"PGA-limited bounds): none — {why}" in capsys.readouterr().out
    assert main(["check", "--scenario", str(path), "--part", "HG9900", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["lowest_sufficient_grade_why_none"] == {"pga_limited": why}


def test_a_sufficient_grade_carries_no_reason():
    rec = lowest_sufficient_grades(Scenario.from_dict(KU_UAV), "paper", list(load_grades().values()))
    assert rec["paper"] and rec["pga_limited"] and rec.why_none == {}


# --- 7. errors with what was got and what is expected ----------------------------------------------

def test_yaml_in_a_txt_file_says_which_extensions_are_read(tmp_path):
    path = _yaml(tmp_path / "ku.txt", KU_UAV)
    with pytest.raises(InputError) as e:
        Scenario.load(path)
    msg = str(e.value)
    assert "holds YAML" in msg and ".txt is read as JSON" in msg and ".yaml" in msg and ".yml" in msg
    Scenario.load(_yaml(tmp_path / "ku.yaml", KU_UAV))  # the same text under a YAML name reads
    bad_json = tmp_path / "comma.json"  # JSON with a slip is not called YAML
    bad_json.write_text(json.dumps(KU_UAV)[:-1] + ",}")
    with pytest.raises(InputError) as e:
        Scenario.load(bad_json)
    assert "YAML" not in str(e.value)


@pytest.mark.parametrize("arm, got", [([0.5, math.nan, 0.0], "[0.5, nan, 0.0]"), (None, "null"), (0.5, "0.5")])
def test_a_bad_lever_arm_says_what_it_got_and_expects(arm, got):
    with pytest.raises(InputError) as e:
        Scenario.from_dict(KU_UAV | {"lever_arm_m": arm})
    msg = str(e.value)
    assert e.value.field == "lever_arm_m" and f"got {got}" in msg
    assert "expected three numbers [x, y, z] in m" in msg and "valid tuple" not in msg


def test_a_missing_key_says_what_it_is_its_unit_and_a_typical_value(tmp_path, capsys):
    data = {k: v for k, v in KU_UAV.items() if k != "range_resolution_m"}
    with pytest.raises(InputError) as e:
        Scenario.from_dict(data)
    typical = get_preset(TYPICAL_PRESET).range_resolution_m
    assert e.value.field == "range_resolution_m" and "Field required" not in str(e.value)
    assert "range resolution" in e.value.expected and "in m" in e.value.expected
    assert f"e.g. {typical:g} in preset {TYPICAL_PRESET}" in e.value.expected


# --- 8. an output folder that did not exist: created, and said --------------------------------------

def test_an_output_folder_created_is_said(tmp_path, capsys):
    out = tmp_path / "results" / "ku" / "check.json"
    assert main(["bounds", "--preset", "airborne_xband", "--json", str(out)]) == 0
    err = capsys.readouterr().err
    assert out.is_file() and "created folders" in err and str(tmp_path / "results") in err
    assert str(out.parent) in err
    assert main(["bounds", "--preset", "airborne_xband", "--json", str(out)]) == 0  # exists now: nothing said
    assert "created folder" not in capsys.readouterr().err


# --- 9. the lever-arm misalignment limit capped at 90° ----------------------------------------------

def test_lever_arm_misalignment_limit_is_capped_at_90_degrees_with_a_note(tmp_path, capsys):
    # W-band helicopter SAR turning at 5 deg/s, lever arm [0.2, 0, -0.5] m
    w94 = {"name": "w94_rate", "medium": "radar", "carrier_frequency_hz": 94.0e9, "slant_range_m": 1000.0,
           "azimuth_resolution_m": 0.15, "range_resolution_m": 0.15, "platform_speed_m_s": 30.0,
           "depression_deg": 20.0, "lever_arm_m": [0.2, 0.0, -0.5], "imu_rate_hz": 400.0,
           "platform_rate_deg_s": 5.0, "window_broadening": 1.3}
    s = Scenario.from_dict(w94)
    a = LeverArmAssumptions.from_scenario(s)
    raw = s.range_resolution_m / (a.lever_m * math.radians(s.platform_rate_deg_s) * s.tc_s)  # δr/(|d| Θ)
    assert raw > math.pi / 2
    terms = lever_arm_terms(s.tc_s, s.range_resolution_m, s.wavelength_m, a)
    mis = terms.set_index("term").loc["misalignment_mrad"]
    assert mis["lever_arm_limit"] == pytest.approx(1e3 * MISALIGNMENT_CAP_RAD) == pytest.approx(500 * math.pi)
    note = next(n for n in terms.attrs["notes"] if "misalignment" in n)
    assert "capped at 90°" in note and f"{1e3 * raw:.4g} mrad" in note
    path = _yaml(tmp_path / "w94_rate.yaml", w94)
    assert main(["bounds", "--scenario", str(path), "--mode", "lever-arm"]) == 0
    out = capsys.readouterr().out
    row = next(x for x in out.splitlines() if x.strip().startswith("misalignment_mrad"))
    assert f"{1e3 * MISALIGNMENT_CAP_RAD:.4g}" in row and f"{1e3 * raw:.4g}" not in row and note in out
    assert main(["bounds", "--scenario", str(path), "--mode", "lever-arm", "--json", "-"]) == 0
    assert note in json.loads(capsys.readouterr().out)["lever_arm"]["notes"]


def test_a_lever_arm_misalignment_limit_below_90_degrees_is_left_as_it_is():
    s = Scenario.from_dict(KU_UAV | {"lever_arm_m": [1.0, 0.0, 0.5], "platform_rate_deg_s": 30.0})
    a = LeverArmAssumptions.from_scenario(s)
    raw = s.range_resolution_m / (a.lever_m * math.radians(s.platform_rate_deg_s) * s.tc_s)
    assert raw < math.pi / 2
    terms = lever_arm_terms(s.tc_s, s.range_resolution_m, s.wavelength_m, a)
    mis = terms.set_index("term").loc["misalignment_mrad"]
    assert mis["lever_arm_limit"] == pytest.approx(1e3 * raw, rel=1e-12)
    assert not [n for n in terms.attrs["notes"] if "misalignment" in n]
    assert np.isfinite(mis["paper_bound"])
