"""Held-out scenarios as a new user writes them: a file that leaves keys out gets their defaults,
and every result computed from those keys says which it took (bounds, check, Monte Carlo, report).

Expectations come from the files written here and the closed form Tc = a_w λ R / (2 δℓ V sin θ)."""

from __future__ import annotations

import json
import math

import pytest
import yaml

from budget.api import load_scenario, run_mc
from budget.cli.main import main

#: a Ku-band UAV strip-map at 2 km, written without imu_rate_hz, depression, window or squint
KU_UAV = {"name": "ku_uav_2km", "medium": "radar", "carrier_frequency_hz": 16.7e9,
          "slant_range_m": 2000.0, "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3,
          "platform_speed_m_s": 30.0, "lever_arm_m": [0.2, 0.0, -0.1]}
#: a 300 kHz synthetic-aperture sonar on an AUV at 3 knots, written without the speed of sound
SAS_300K = ("# 300 kHz SAS on an AUV at 3 knots\nname: sas300_auv\nmedium: sonar\n"
            "carrier_frequency_hz: 300000   # 300 kHz\nslant_range_m: 150\nazimuth_resolution_m: 0.03\n"
            "range_resolution_m: 0.03\nplatform_speed_m_s: 1.543      # 3 kn\ndepression_deg: 15\n"
            "lever_arm_m: [0.5, 0.0, 0.2]\nimu_rate_hz: 100\n")
#: every key that has a default, written out
EVERY_KEY = {**KU_UAV, "propagation_speed_m_s": 299792458.0, "squint_deg": 0.0, "depression_deg": 35.0,
             "window_broadening": 1.0, "platform_accel_m_s2": 9.80665, "platform_rate_deg_s": 0.0,
             "imu_rate_hz": 200.0}


def _write(tmp_path, name, data):
    p = tmp_path / name
    p.write_text(data if isinstance(data, str) else json.dumps(data))
    return p


def test_a_sonar_file_without_the_speed_of_sound_states_the_1500_m_s_its_tc_rests_on(tmp_path, capsys):
    p = _write(tmp_path, "sas300.yaml", SAS_300K)
    tc = 1500.0 / 300e3 * 150.0 / (2 * 0.03 * 1.543)  # λ R / (2 δℓ V), λ = 1500 m/s / 300 kHz
    assert main(["bounds", "--scenario", str(p)]) == 0
    out = capsys.readouterr().out
    assert f"{tc:.4g}" in out
    assert "not in the scenario, taken at their defaults" in out
    assert "propagation_speed_m_s = 1500 m/s (sonar)" in out and "window_broadening = 1" in out
    assert "squint_deg = 0 (broadside)" in out
    assert "imu_rate_hz" not in out.split("taken at their defaults")[1]  # the file sets it
    js = tmp_path / "b.json"
    assert main(["bounds", "--scenario", str(p), "--json", str(js)]) == 0
    d = json.loads(js.read_text())
    assert d["scenario_defaults"] == {"propagation_speed_m_s": 1500.0, "squint_deg": 0.0,
                                      "window_broadening": 1.0}
    assert d["tc_s"][0] == pytest.approx(tc, rel=1e-12)


def test_the_lever_arm_bounds_state_a_turn_rate_the_file_does_not_give(tmp_path, capsys):
    p = _write(tmp_path, "ku.json", KU_UAV)
    assert main(["bounds", "--scenario", str(p), "--mode", "lever-arm"]) == 0
    out = capsys.readouterr().out
    assert "platform_rate_deg_s = 0 deg/s (no turn)" in out
    assert "lever_arm_m" not in out.split("taken at their defaults")[1]  # the file sets it
    # the paper bounds use neither: not listed there
    assert main(["bounds", "--scenario", str(p)]) == 0
    assert "platform_rate_deg_s" not in capsys.readouterr().out


def test_a_file_with_every_key_gets_no_defaults_line(tmp_path, capsys):
    p = _write(tmp_path, "all.json", EVERY_KEY)
    assert load_scenario(str(p)).defaults_taken() == {}
    assert main(["bounds", "--scenario", str(p), "--mode", "lever-arm"]) == 0
    assert main(["check", "--scenario", str(p), "--part", "STIM300"]) == 0
    assert "taken at their defaults" not in capsys.readouterr().out


def test_radar_speed_of_light_is_not_called_a_default_but_sound_is():
    radar = load_scenario(dict(KU_UAV))
    assert "propagation_speed_m_s" not in radar.defaults_taken()
    sonar = load_scenario(yaml.safe_load(SAS_300K))
    assert sonar.defaults_taken()["propagation_speed_m_s"] == 1500.0


def test_the_check_states_the_depression_its_pga_limited_verdict_used(tmp_path, capsys):
    p = _write(tmp_path, "ku.json", KU_UAV)
    assert main(["check", "--scenario", str(p), "--part", "STIM300"]) == 0
    out = capsys.readouterr().out
    assert "depression_deg = 30 (line of sight 30° below horizontal)" in out
    js = tmp_path / "c.json"
    assert main(["check", "--scenario", str(p), "--part", "STIM300", "--json", str(js)]) == 0
    defaults = json.loads(js.read_text())["scenario_defaults"]
    assert defaults["depression_deg"] == 30.0 and "lever_arm_m" not in defaults
    assert "platform_accel_m_s2" not in defaults  # paper bounds do not use it
    assert main(["check", "--scenario", str(p), "--part", "STIM300", "--mode", "derived", "--json", str(js)]) == 0
    assert json.loads(js.read_text())["scenario_defaults"]["platform_accel_m_s2"] == pytest.approx(9.80665)


def test_a_monte_carlo_verdict_says_the_imu_rate_and_geometry_it_took_by_default(tmp_path):
    p = _write(tmp_path, "ku.json", KU_UAV)
    r = run_mc(str(p), "STIM300", trials=2, seed=1)
    assert r.tc_s == pytest.approx(299792458.0 / 16.7e9 * 2000.0 / (2 * 0.3 * 30.0), rel=1e-12)
    rate = r.judged_on["imu_rate"]
    assert "imu_rate_hz = 200 Hz, the default (the scenario gives no imu_rate_hz)" in rate
    assert "the scenario's imu_rate_hz" not in rate
    note = r.judged_on["scenario_defaults"]
    assert "depression_deg = 30" in note and "window_broadening = 1" in note
    assert "squint_deg = 0" in note
    summary = r.summary()
    assert rate in summary and note in summary
    # the same scenario with every key written: the rate is the scenario's, nothing is defaulted
    full = run_mc(EVERY_KEY, "STIM300", trials=2, seed=1)
    assert "the scenario's imu_rate_hz = 200 Hz" in full.judged_on["imu_rate"]
    assert "scenario_defaults" not in full.judged_on


def test_the_report_marks_each_scenario_key_as_written_or_defaulted(tmp_path):
    p = _write(tmp_path, "sas300.yaml", SAS_300K)
    out, js = tmp_path / "r.html", tmp_path / "r.json"
    assert main(["report", "--scenario", str(p), "--part", "STIM300", "--out", str(out),
                 "--json", str(js), "--quiet"]) == 0
    html = out.read_text()
    assert "<th class='txt'>set by</th>" in html
    assert ("<td class='txt'>propagation_speed_m_s</td><td class=''>–</td>"
            "<td class='txt'>default (1500 m/s, sonar)</td>") in html
    assert "<td class='txt'>slant_range_m</td><td class=''>150</td><td class='txt'>scenario</td>" in html
    assert "<td class='txt'>window_broadening</td><td class=''>1</td><td class='txt'>default</td>" in html
    d = json.loads(js.read_text())
    assert set(d["scenario_defaults"]) == {"propagation_speed_m_s", "squint_deg", "window_broadening",
                                           "platform_accel_m_s2", "platform_rate_deg_s"}
    assert math.isclose(d["scenario_defaults"]["propagation_speed_m_s"], 1500.0)


def test_copies_varied_over_a_field_still_state_the_defaults_their_base_took(tmp_path):
    """budget.vary_scenario (sweep_over's copies) rebuilt each copy from the base's full dump, so
    every key looked written and the copies stated no default; the keys the file left out stay
    out of the copies."""
    from budget.api import vary_scenario

    base = load_scenario(_write(tmp_path, "sas300.yaml", SAS_300K))
    taken = base.defaults_taken()
    assert "propagation_speed_m_s" in taken and "window_broadening" in taken
    for copy in vary_scenario(base, "slant_range_m", [100.0, 200.0]):
        assert set(copy.defaults_taken()) == set(taken)
        assert copy.c_m_s == base.c_m_s  # the same default, still used
