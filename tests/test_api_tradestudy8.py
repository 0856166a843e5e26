"""A trade study through the top-level API (budget.*), as a user script runs it: the rough edges
it met — bounds of a scenario without its lever arm, the lever-arm check, consistency_table by
name, a sweep table without its seed, a lever arm in cm — stay fixed."""

from __future__ import annotations

import math
import warnings

import pandas as pd
import pytest

import budget
from budget.bounds import LeverArmAssumptions, lever_arm_bounds, paper_bounds
from budget.errors import InputError

UAV = {"name": "uav_x", "medium": "radar", "carrier_frequency_hz": 9.6e9, "slant_range_m": 3000.0,
       "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3, "platform_speed_m_s": 30.0,
       "platform_rate_deg_s": 1.0}


def _wilson(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return max(0.0, c - h), min(1.0, c + h)


def test_uav_tc_is_the_readme_closed_form():
    s = budget.load_scenario(UAV)
    lam = 299_792_458.0 / 9.6e9
    assert s.tc_s == pytest.approx(lam * 3000.0 / (2 * 0.3 * 30.0), rel=1e-12)
    # seed 004's ARW bound scales as δr / Tc^2.5 (README: 784 deg/√h at Tc = 1 s, δr = 1 m, derived)
    arw = budget.compute_bounds(s).to_frame()["gyro_arw_deg_rt_h"].iloc[0]
    assert arw == pytest.approx(784 * 0.3 / s.tc_s ** 2.5, rel=0.02)


def test_compute_bounds_lever_arm_mode_uses_the_scenario_installation():
    s = budget.load_scenario("missile_borne")  # lever arm 2 m: README ARW 1612 → 0.56 deg/√h (0.9 of apertures, Taylor-weighted)
    table = budget.compute_bounds(s, "lever-arm")
    row = table.to_frame().iloc[0]
    assert row["gyro_arw_deg_rt_h"] == pytest.approx(0.556, rel=0.01)
    assert row["gyro_bias_deg_h"] == pytest.approx(1.4e5, rel=0.03)
    expected = lever_arm_bounds([s.tc_s], s.range_resolution_m, s.wavelength_m,
                                LeverArmAssumptions.from_scenario(s)).datasheet()
    assert row["gyro_arw_deg_rt_h"] == pytest.approx(float(expected["gyro_arw_deg_rt_h"][0]), rel=1e-12)
    assert table.assumptions["lever_arm_m"] == pytest.approx(list(s.lever_arm_m))
    d = table.to_dict()
    assert d["scenario"]["name"] == "missile_borne" and d["scenario"]["lever_arm_m"] == list(s.lever_arm_m)
    assert "missile_borne" in table.summary().splitlines()[0] and "lever arm" in table.summary()
    assert table.to_frame().attrs["mode"] == "lever_arm"
    # with the lever arm at 0 the lever-arm table is the paper table
    flat = budget.load_scenario({**UAV, "lever_arm_m": [0.0, 0.0, 0.0]})
    assert (budget.compute_bounds(flat, "lever-arm").to_frame()["gyro_arw_deg_rt_h"].iloc[0]
            == pytest.approx(float(paper_bounds(flat.tc_s, 0.3).datasheet()["gyro_arw_deg_rt_h"][0])))


def test_compute_bounds_derived_mode_uses_the_scenario_acceleration():
    base = budget.compute_bounds("airborne_xband", "derived").to_frame().iloc[0]
    s = budget.load_scenario({**budget.load_scenario("airborne_xband").model_dump(), "name": "x",
                              "platform_accel_m_s2": 2 * 9.80665})
    pulled = budget.compute_bounds(s, "derived").to_frame().iloc[0]
    # the scale factor acts on the specific force: twice the force, half the bound
    assert pulled["accel_scale_factor_ppm"] == pytest.approx(base["accel_scale_factor_ppm"] / 2, rel=1e-9)
    assert pulled["gyro_arw_deg_rt_h"] == pytest.approx(base["gyro_arw_deg_rt_h"], rel=1e-12)


def test_check_parts_lever_arm_mode_runs_per_scenario():
    s = budget.load_scenario("missile_borne")
    res = budget.check_parts(["ADIS16405"], [s, budget.load_scenario(UAV)], mode="lever-arm")
    f = res.to_frame().set_index("scenario")
    bound = budget.compute_bounds(s, "lever-arm").to_frame()["gyro_arw_deg_rt_h"].iloc[0]
    assert f.loc["missile_borne", "margin_gyro_arw_deg_rt_h"] == pytest.approx(bound / 2.0, rel=1e-9)
    assert f.loc["missile_borne", "verdict"] == "fail"


def test_consistency_table_by_name_and_bad_scales():
    t = budget.consistency_table("automotive_24ghz", terms="accel_bias", scales=[0.5], trials=1)
    assert list(t["term"]) == ["accel_bias"] and bool(t["simulated"].iloc[0])
    for kw in ({"scales": [-1.0]}, {"scales": [0.0]}, {"scales": [math.nan]}, {"scales": []},
               {"terms": []}):
        with pytest.raises(InputError) as e:
            budget.consistency_table("automotive_24ghz", trials=1, **kw)
        assert e.value.field in ("scales", "terms")
    from budget.mc.consistency import consistency_table
    with pytest.raises(InputError) as e:
        consistency_table("automotive_24ghz", terms=["accel_bias"], scales=[1.0], trials=1)
    assert e.value.field == "scenario"


def test_sweep_table_carries_its_seed_and_options(tmp_path):
    t = budget.sweep(["STIM300"], "automotive_24ghz", trials=2, seed=7, workers=1)
    assert list(t["seed"]) == [7]
    assert t.attrs["seed"] == 7 and t.attrs["options"]["scene"] == "realistic"  # the default scene
    path = tmp_path / "t.csv"
    t.to_csv(path, index=False)
    assert pd.read_csv(path)["seed"].tolist() == [7]
    k = int(round(t["p_pass_after"].iloc[0] * 2))
    lo, hi = _wilson(k, 2)
    assert (t["ci_after_lo"].iloc[0], t["ci_after_hi"].iloc[0]) == (pytest.approx(lo), pytest.approx(hi))
    # a scenario beyond the simulator's limits is marked, with the seed, not a stop
    slow = {"name": "lband_slow", "medium": "radar", "carrier_frequency_hz": 1.3e9, "slant_range_m": 20000.0,
            "azimuth_resolution_m": 0.2, "range_resolution_m": 0.5, "platform_speed_m_s": 3.4}
    t2 = budget.sweep(["STIM300"], [slow], trials=1, seed=3)
    assert t2["status"].iloc[0].startswith("not simulated") and t2["seed"].iloc[0] == 3


def test_mc_result_frame_says_which_verdict_it_is():
    r = budget.run_mc("automotive_24ghz", "STIM300", trials=2, seed=5, workers=1)
    a = r.to_frame().attrs
    assert (a["model"], a["scenario"], a["seed"], a["trials"]) == ("STIM300", "automotive_24ghz", 5, 2)
    assert a["p_pass_after"] == r.p_pass_after and a["ci_after"] == list(r.ci_after)
    assert a["options"]["unspecified"] == "fill_grade_typical"


def test_a_lever_arm_in_cm_is_noted():
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s = budget.load_scenario({**UAV, "lever_arm_m": [50.0, 0.0, 0.0]})
    assert any("check its unit" in str(x.message) for x in w)
    assert any("check its unit" in n for n in s.notes())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert budget.load_scenario({**UAV, "lever_arm_m": [2.0, 0.0, 0.5]}).notes() == []


def test_vary_scenario_refuses_a_vector_field_by_name():
    with pytest.raises(InputError) as e:
        budget.vary_scenario(UAV, "lever_arm_m", [0.0, 0.5, 2.0])
    assert e.value.field == "field" and "not one number" in str(e.value)


def test_vrw_unit_identity_in_the_docs():
    from budget import units

    assert units.m_s_rt_h_to_ug_rt_hz(1.0) == pytest.approx(1699.53, abs=0.01)
    assert "1699.5 µg/√Hz" in budget.__doc__


def test_check_result_carries_the_scenarios_it_was_computed_for():
    """A check read back later says what it was computed for: each scenario in full (δr, λ and
    the lever arm of a custom scenario, not only its name and Tc)."""
    from budget.catalog.io import get_part
    from budget.check import check_parts
    from budget.presets import get_preset
    s = get_preset("missile_borne").model_copy(update={"name": "my missile", "lever_arm_m": (1.0, 0.0, -0.5)})
    rec = check_parts([get_part("STIM300")], s, "lever-arm").to_dict()["scenarios"][0]
    assert rec["name"] == "my missile" and rec["scenario"]["lever_arm_m"] == [1.0, 0.0, -0.5]
    assert rec["scenario"]["range_resolution_m"] == s.range_resolution_m
    assert rec["tc_s"] == pytest.approx(s.tc_s)


def test_sweep_rows_say_what_the_verdict_was_judged_on():
    """A sweep exported to CSV still says the scene, the window and the navigation it was judged
    with (``attrs`` do not survive the export)."""
    from budget.catalog.io import get_part
    from budget.mc.sweep import sweep
    from budget.presets import get_preset
    t = sweep([get_part("STIM300")], [get_preset("automotive_77ghz")], 2, 1)
    row = t.iloc[0]
    assert row["scene"] == "realistic" and row["window"].startswith("taylor")  # the default scene
    assert row["navigation"].startswith("free inertial")
