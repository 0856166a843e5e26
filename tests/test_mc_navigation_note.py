"""Every Monte Carlo result says how the track it judged was navigated: free inertial from an
alignment at the aperture start (seed 004's assumption), or aided by the scenario's sensors."""

from __future__ import annotations

from budget.catalog.io import get_part
from budget.mc import run_mc
from budget.mc.notes import navigation_note
from budget.presets import get_preset
from budget.scenario import Scenario


def test_free_inertial_preset_says_so_with_its_aperture_time():
    s = get_preset("automotive_77ghz")
    note = navigation_note(s)
    assert note.startswith("free inertial") and f"Tc = {s.tc_s:.3g} s" in note


def test_aided_scenario_names_sensor_mode_and_warm_up():
    s = Scenario.model_validate(get_preset("airborne_xband").model_dump()
                                | {"aiding": [{"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02}],
                                   "aiding_mode": "smoothed", "aiding_warmup_s": 30.0})
    assert navigation_note(s) == "aided: gnss, smoothed, 30 s warm-up"


def test_result_carries_the_note_in_summary_and_dict():
    r = run_mc(get_preset("automotive_77ghz"), get_part("HG9900"), 4, 1)
    assert "navigation: free inertial" in r.summary()
    assert r.to_dict()["judged_on"]["navigation"] == navigation_note(get_preset("automotive_77ghz"))
