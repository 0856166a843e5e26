"""The report's bounds table takes the derived and no-autofocus assumptions from the scenario
(its platform_accel_m_s2), as `sar-budget bounds --scenario` and the check do: with 20 m/s² it
showed the derived accel scale factor at g (10456 ppm) beside a check computed at 20 (5127)."""

from __future__ import annotations

import json

import numpy as np

import budget
from budget.bounds import compute_bounds
from budget.cli.main import main
from budget.report.content import bounds_frame, build_report


def _at(accel):
    return budget.load_scenario("airborne_xband").model_copy(update={"platform_accel_m_s2": accel})


def test_the_reports_bounds_equal_the_cli_for_the_scenarios_acceleration(tmp_path, capsys):
    s = _at(20.0)
    path = tmp_path / "acc20.json"
    path.write_text(json.dumps(s.model_dump(mode="json")), encoding="utf-8")
    out = tmp_path / "b.json"
    assert main(["bounds", "--scenario", str(path), "--mode", "derived", "--json", str(out)]) == 0
    row = json.loads(out.read_text(encoding="utf-8"))["bounds"]["rows"][0]
    frame = bounds_frame(s).set_index("key")
    for key in ("accel_scale_factor_ppm", "misalignment_mrad", "gyro_scale_factor_ppm"):
        assert abs(frame.loc[key, "derived"] / row[key] - 1) < 1e-12, key
    # the derived accel scale factor bound scales as 1/a: half of g's at ≈ 2 g
    at_g = bounds_frame(_at(9.80665)).set_index("key")
    ratio = frame.loc["accel_scale_factor_ppm", "derived"] / at_g.loc["accel_scale_factor_ppm", "derived"]
    assert abs(ratio - 9.80665 / 20.0) < 1e-6
    # the paper column does not depend on it
    assert frame.loc["accel_scale_factor_ppm", "paper"] == at_g.loc["accel_scale_factor_ppm", "paper"]
    assert np.isfinite(compute_bounds(np.array([s.tc_s]), s.range_resolution_m, "paper").datasheet()
                       ["accel_scale_factor_ppm"]).all()


def test_a_mode_the_scenario_cannot_give_is_stated_and_the_report_still_builds():
    s = _at(0.0)
    frame = bounds_frame(s)
    assert set(frame.attrs["refused"]) == {"derived", "no-autofocus"}
    assert frame["derived"].isna().all() and frame["paper"].notna().all()
    html = build_report(s, ["STIM300"], mode="paper").html()
    assert "derived bounds not computed" in html and "platform_accel_m_s2" in html
