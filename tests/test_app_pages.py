"""Dashboard pages through ``streamlit.testing.v1.AppTest``: each page loads, its main interaction
works, and the numbers shown are the library's (the app is a thin layer)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from budget.bounds import DerivedAssumptions, compute_bounds
from budget.catalog.io import load_catalog
from budget.check import check_parts
from budget.presets import get_preset
from budget.scenario import Scenario

AppTest = pytest.importorskip("streamlit.testing.v1", reason="streamlit not installed").AppTest

APP_DIR = Path(__file__).resolve().parents[1] / "app"
MAIN = str(APP_DIR / "main.py")
if str(APP_DIR) not in sys.path:
    sys.path.insert(0, str(APP_DIR))

import page_registry  # noqa: E402

PRESET = "airborne_xband"  # the sidebar's default


def _app(page: str | None = None) -> AppTest:
    at = AppTest.from_file(MAIN, default_timeout=60).run()
    if page:
        at.switch_page(page).run()
    _no_failure(at)
    return at


def _no_failure(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]


def _metric(at: AppTest, label_start: str) -> str:
    return next(m.value for m in at.metric if m.label.startswith(label_start))


def _edited(**changes) -> Scenario:
    return Scenario(**{**get_preset(PRESET).model_dump(), **changes})


@pytest.mark.parametrize("entry", page_registry.available(), ids=lambda e: e.url_path)
def test_every_registered_page_loads(entry):
    at = _app(entry.path)
    assert at.title[0].value  # each page draws its title


def test_scenario_page_shows_library_tc_and_bounds_after_editing_slant_range():
    at = _app()
    assert _metric(at, "Tc") == f"{get_preset(PRESET).tc_s:.4g} s"
    at.number_input(key="scn_slant_range_m").set_value(20_000.0).run()
    _no_failure(at)
    s = _edited(slant_range_m=20_000.0)
    assert _metric(at, "Tc") == f"{s.tc_s:.4g} s"
    assert _metric(at, "aperture length") == f"{s.aperture_length_m:.4g} m"
    table = at.dataframe[0].value
    for mode in ("paper", "derived", "no-autofocus"):
        ds = compute_bounds(np.array([s.tc_s]), s.range_resolution_m, mode, wavelength_m=s.wavelength_m).datasheet()
        shown = dict(zip(table["key"], table[mode]))
        for key, vals in ds.items():
            assert shown[key] == pytest.approx(float(vals[0]), rel=1e-12), (mode, key)


def test_picking_a_preset_fills_the_fields():
    at = _app()
    at.selectbox(key="scn_preset").set_value("sas_100khz").run()
    _no_failure(at)
    sas = get_preset("sas_100khz")
    assert at.number_input(key="scn_slant_range_m").value == sas.slant_range_m
    assert at.selectbox(key="scn_medium").value == "sonar"
    assert _metric(at, "Tc") == f"{sas.tc_s:.4g} s"


def test_derived_assumptions_edit_changes_the_derived_column():
    at = _app()
    at.selectbox(key="da_combine").set_value("rss").run()
    _no_failure(at)
    s = get_preset(PRESET)
    ds = compute_bounds(np.array([s.tc_s]), s.range_resolution_m, "derived",
                        assumptions=DerivedAssumptions(combine="rss")).datasheet()
    table = at.dataframe[0].value
    shown = dict(zip(table["key"], table["derived"]))
    assert shown["accel_bias_ug"] == pytest.approx(float(ds["accel_bias_ug"][0]), rel=1e-12)


def test_invalid_scenario_value_is_a_message_naming_the_field_not_a_traceback():
    at = _app()
    at.number_input(key="scn_range_resolution_m").set_value(0.0).run()
    assert not at.exception
    assert any("range_resolution_m" in e.value for e in at.error)
    assert any("Fix the inputs" in w.value for w in at.warning)


def test_check_page_verdicts_and_margins_are_check_parts():
    at = _app("pages/check.py")
    s = get_preset(PRESET)
    parts = list(load_catalog().values())
    recs = check_parts(parts, s, "paper").to_dict()["scenarios"][0]["parts"]
    table = at.table[0].value
    assert list(table["part_id"]) == [r["part_id"] for r in recs]
    assert list(table["verdict"]) == [r["verdict"] for r in recs]
    arw = table.set_index("part_id")["gyro ARW margin (bound/spec)"]  # margins, labelled as such
    for r in recs:
        if "gyro_arw_deg_rt_h" in r["margins"]:
            assert arw[r["part_id"]] == pytest.approx(r["margins"]["gyro_arw_deg_rt_h"], rel=1e-12)
    n_pass = sum(r["verdict"] == "pass" for r in recs)
    assert _metric(at, "pass") == str(n_pass)


def test_check_page_follows_scenario_edit_and_mode():
    at = _app("pages/check.py")
    at.number_input(key="scn_slant_range_m").set_value(60_000.0).run()
    at.radio(key="bounds_mode").set_value("derived").run()
    _no_failure(at)
    recs = check_parts(list(load_catalog().values()), _edited(slant_range_m=60_000.0),
                       "derived").to_dict()["scenarios"][0]["parts"]
    assert list(at.table[0].value["verdict"]) == [r["verdict"] for r in recs]
    assert "fail" in [r["verdict"] for r in recs]  # the edit matters: a longer Tc fails some parts


def test_no_autofocus_mode_on_a_sonar_preset_uses_its_wavelength():
    at = _app("pages/check.py")
    at.selectbox(key="scn_preset").set_value("sas_100khz").run()
    at.radio(key="bounds_mode").set_value("no-autofocus").run()
    _no_failure(at)
    recs = check_parts(list(load_catalog().values()), get_preset("sas_100khz"),
                       "no-autofocus").to_dict()["scenarios"][0]["parts"]
    assert list(at.table[0].value["verdict"]) == [r["verdict"] for r in recs]
    assert any("pick one of them" in c.value for c in at.caption)  # no grade advice without PGA bounds


def test_scenario_edits_survive_a_page_switch():
    at = _app()
    at.number_input(key="scn_slant_range_m").set_value(12_345.0).run()
    at.switch_page("pages/catalog.py").run()
    at.switch_page("pages/scenario.py").run()
    _no_failure(at)
    assert at.number_input(key="scn_slant_range_m").value == 12_345.0
    assert _metric(at, "Tc") == f"{_edited(slant_range_m=12_345.0).tc_s:.4g} s"
