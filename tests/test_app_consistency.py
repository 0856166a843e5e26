"""The dashboard gives the CLI's numbers for the same scenario: the bounds and the check take the
scenario's ``platform_accel_m_s2`` (and refuse 0 as the CLI does), the Monte Carlo's analytic
check uses the sidebar's bounds mode, the trade study runs the aiding mode it shows, the scenario
page shows the lever-arm bounds and the PGA-limited grade, the sweep's time estimate and cell
limit are stated, the check's JSON download is what ``sar-budget check --json`` writes, and the
before-PGA phase column is labelled as what it holds.

Every expected number here is computed independently of the app: by the CLI
(:func:`budget.cli.main.main`) or the library, on a scenario file written by the test."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from app_harness import REPO, open_app, page_errors
from formatting import fmt_value
from budget.bounds import BOUND_FIELDS, scenario_assumptions
from budget.catalog.io import load_catalog
from budget.check import check_parts
from budget.cli.main import main as cli
from budget.errors import InputError
from budget.mc.options import McOptions
from check_view import MARGIN_LABELS  # the check matrix labels margins as margins
from budget.plots.mc import METRIC_LABELS
from budget.presets import get_preset
from budget.scenario import Scenario

PRESET = "airborne_xband"  # the sidebar's default


def _scenario_file(tmp_path, **changes) -> tuple[Scenario, str]:
    """The sidebar's default preset with ``changes``, as the file a CLI user would pass."""
    s = get_preset(PRESET).model_copy(update=changes)
    path = tmp_path / "scenario.json"
    path.write_text(json.dumps(s.model_dump(mode="json")))
    return Scenario.load(path), str(path)


def _cli_json(tmp_path, *args: str) -> dict:
    out = tmp_path / f"cli_{len(list(tmp_path.iterdir()))}.json"
    assert cli([*args, "--json", str(out)]) == 0
    return json.loads(out.read_text())


def _cli_bounds(tmp_path, scenario_path: str, mode: str) -> dict[str, float]:
    """``sar-budget bounds --scenario F --mode M --json``: the datasheet-unit bounds at the scenario's Tc."""
    row = _cli_json(tmp_path, "bounds", "--scenario", scenario_path, "--mode", mode)["bounds"]["rows"][0]
    return {k: row[k] for k in BOUND_FIELDS}


def _frame_with(at, column: str):
    """The one table on the page with ``column`` (AppTest's dataframes carry no key)."""
    found = [d.value for d in at.dataframe if column in d.value.columns]
    assert len(found) == 1, [list(d.value.columns) for d in at.dataframe]
    return found[0]


def _shown_bounds(at, mode: str) -> dict[str, float]:
    """The scenario page's bounds table (one column per mode, "key" the CLI's JSON key)."""
    table = _frame_with(at, "key")
    return dict(zip(table["key"], table[mode].astype(float)))


@pytest.fixture
def downloads(monkeypatch) -> dict[str, bytes]:
    """The bytes of every download button drawn, by file name (the media store of ``AppTest``)."""
    from streamlit.runtime.memory_media_file_storage import MemoryMediaFileStorage

    got: dict[str, bytes] = {}
    original = MemoryMediaFileStorage.load_and_get_id

    def record(self, path_or_data, mimetype, kind, filename=None):
        if filename is not None and isinstance(path_or_data, bytes):
            got[filename] = path_or_data
        return original(self, path_or_data, mimetype, kind, filename)

    monkeypatch.setattr(MemoryMediaFileStorage, "load_and_get_id", record)
    return got


# --- 1. the scenario's platform_accel_m_s2 is the one source of the derived acceleration level ----

def test_scenario_page_derived_and_no_autofocus_bounds_equal_the_cli_at_platform_accel_20(tmp_path):
    """The derived table showed accel SF 10456 ppm / misalignment 10.46 mrad (the values at g) for a
    scenario flown at 20 m/s², where `sar-budget bounds --mode derived` gives 5127 / 5.127."""
    at = open_app()
    at.sidebar.number_input(key="scn_platform_accel_m_s2").set_value(20.0).run()
    assert not page_errors(at)
    _, path = _scenario_file(tmp_path, platform_accel_m_s2=20.0)
    for mode in ("derived", "no-autofocus", "paper"):
        expected, shown = _cli_bounds(tmp_path, path, mode), _shown_bounds(at, mode)
        for key in BOUND_FIELDS:
            assert shown[key] == pytest.approx(expected[key], rel=1e-12), (mode, key)
    assert _shown_bounds(at, "derived")["accel_scale_factor_ppm"] == pytest.approx(5127.09, rel=1e-5)
    assert _shown_bounds(at, "derived")["misalignment_mrad"] == pytest.approx(5.12711, rel=1e-5)
    # the page says which acceleration level was used, and the sidebar has one input for it
    said = " ".join(m.value for m in at.markdown)
    assert "derived: acceleration level 20 m/s² — the scenario's platform_accel_m_s2" in said
    assert not [w for w in at.sidebar.number_input if w.key in ("da_accel_level_m_s2", "na_accel_level_m_s2")]
    assert any("platform_accel_m_s2 = 20 m/s²" in c.value for c in at.sidebar.caption)


def test_sidebar_assumption_edits_are_completed_from_the_scenario_as_the_library_does():
    """An edited assumption (rss combination) keeps the scenario's acceleration level."""
    from budget.api import compute_bounds

    at = open_app()
    at.sidebar.number_input(key="scn_platform_accel_m_s2").set_value(20.0).run()
    at.sidebar.selectbox(key="da_combine").set_value("rss").run()
    assert not page_errors(at)
    s = get_preset(PRESET).model_copy(update={"platform_accel_m_s2": 20.0})
    ds = compute_bounds(s, "derived", {"combine": "rss"}).datasheet()
    shown = _shown_bounds(at, "derived")
    for key in BOUND_FIELDS:
        assert shown[key] == pytest.approx(float(ds[key][0]), rel=1e-12), key
    assert scenario_assumptions("derived", s, {"combine": "rss"}).accel_level_m_s2 == 20.0
    assert "assumptions edited in the sidebar: combine = rss" in " ".join(m.value for m in at.markdown)


def test_check_matrix_in_derived_mode_equals_the_library_at_platform_accel_20():
    """The derived check showed STIM300's accel SF margin 34.85 (at g) where
    `budget.check_parts(..., mode="derived")` gives 17.09."""
    at = open_app("pages/check.py")
    at.sidebar.radio(key="bounds_mode").set_value("derived").run()
    at.sidebar.number_input(key="scn_platform_accel_m_s2").set_value(20.0).run()
    assert not page_errors(at)
    s = get_preset(PRESET).model_copy(update={"platform_accel_m_s2": 20.0})
    catalog = load_catalog()
    recs = check_parts(list(catalog.values()), s, mode="derived").to_dict()["scenarios"][0]["parts"]
    table = at.table[0].value.set_index("part_id")
    for rec in recs:
        for param, margin in rec["margins"].items():
            shown = table.loc[rec["part_id"], MARGIN_LABELS[param]]
            assert (math.isnan(shown) and math.isnan(margin)) or shown == pytest.approx(margin, rel=1e-12)
    assert table.loc["STIM300", MARGIN_LABELS["accel_scale_factor_ppm"]] == pytest.approx(17.0903, rel=1e-4)
    assert any("acceleration level 20 m/s²" in c.value for c in at.caption)


def test_platform_accel_0_is_the_librarys_refusal_on_the_scenario_and_check_pages():
    """0 m/s² was computed at g; `sar-budget bounds --mode derived` refuses it."""
    s0 = get_preset(PRESET).model_copy(update={"platform_accel_m_s2": 0.0})
    with pytest.raises(InputError) as refused:
        scenario_assumptions("derived", s0)
    at = open_app()
    at.sidebar.number_input(key="scn_platform_accel_m_s2").set_value(0.0).run()
    errors = page_errors(at)
    for mode in ("derived", "no-autofocus"):
        assert any(e.startswith(f"{mode} bounds not computed") and refused.value.reason in e for e in errors), errors
        assert all(math.isnan(v) for v in _shown_bounds(at, mode).values())  # no number computed at g
    # paper bounds do not use the acceleration level: still shown, and the lever-arm ones
    assert _shown_bounds(at, "paper")["gyro_arw_deg_rt_h"] == pytest.approx(22.7464, rel=1e-4)
    assert _shown_bounds(at, "lever-arm")["gyro_arw_deg_rt_h"] == pytest.approx(0.97294, rel=1e-4)
    at.switch_page("pages/check.py").run()
    at.sidebar.radio(key="bounds_mode").set_value("derived").run()
    errors = page_errors(at)
    assert any("derived check" in e and refused.value.reason in e for e in errors), errors
    assert not at.table


# --- 1 and 7. the Monte Carlo page: its analytic check in the sidebar's mode, its labels ------------

@pytest.fixture(scope="module")
def mc_run():
    """STIM300 on automotive_77ghz, 2 trials, with the sidebar in no-autofocus mode (where that
    part fails the check, and passes it in paper mode)."""
    at = open_app("pages/monte_carlo.py")
    at.sidebar.selectbox(key="scn_preset").set_value("automotive_77ghz").run()
    at.sidebar.radio(key="bounds_mode").set_value("no-autofocus").run()
    at.multiselect(key="mc_parts").set_value(["STIM300"]).run()
    at.number_input(key="mc_trials").set_value(2).run()
    at.button(key="mc_run").click().run()
    assert not page_errors(at)
    return at


def test_monte_carlo_check_uses_the_sidebars_mode_and_says_it(mc_run):
    """In no-autofocus mode the table silently used paper mode."""
    at = mc_run
    s = get_preset("automotive_77ghz")
    part = load_catalog()["STIM300"]
    motion = McOptions(platform_motion={"kind": "straight"}).rotation_for_check
    records = {m: check_parts([part], s, m, platform_motion=motion).to_dict()["scenarios"][0]["parts"][0]
               for m in ("paper", "no-autofocus")}
    verdict = {m: r["verdict"] for m, r in records.items()}
    assert verdict == {"paper": "pass", "no-autofocus": "fail"}  # the test tells the two modes apart
    frame = _frame_with(at, "MC verdict")
    assert frame["check verdict (no-autofocus)"].tolist() == ["fail"]
    # the Monte Carlo is compared with the PGA-limited check (budget.report.check_vs_mc), said so
    limited = records["no-autofocus"]["pga_limited_verdict"]
    assert frame["compared verdict"].tolist() == [f"{limited} (PGA-limited check)"]
    assert any("**no-autofocus** bounds" in c.value for c in at.caption)


def test_before_pga_phase_column_is_labelled_as_the_whole_phase_error(mc_run):
    """'fast residual phase rms (deg)' labelled the before-PGA column too, where it holds the
    whole phase error (constant and linear removed), not what is left beyond PGA's window."""
    at = mc_run
    before_label = "whole phase error rms, constant and linear removed (deg) — before PGA"
    after_label = f"{METRIC_LABELS['residual_phase_rms_deg']} — after PGA"
    pct = _frame_with(at, "p50_before").set_index("metric")
    result = at.session_state["mc_last_run"][1].results["STIM300"]
    ref = result.to_frame().set_index("metric").loc["residual_phase_rms_deg"]
    # the table shows 4 significant figures (formatting.fmt_value), "–" in an empty cell
    assert pct.loc[before_label, "p50_before"] == fmt_value(ref["p50_before"])
    assert pct.loc[before_label, "p50_after"] == "–"
    assert pct.loc[after_label, "p50_after"] == fmt_value(ref["p50_after"])
    assert pct.loc[after_label, "p50_before"] == "–"
    assert METRIC_LABELS["residual_phase_rms_deg"] not in pct.index  # no row mixes the two
    worst = _frame_with(at, "before PGA").set_index("metric")
    assert worst.loc[before_label, "after PGA"] == "–" and worst.loc[after_label, "before PGA"] == "–"


# --- 2. the trade study runs the sidebar's aiding mode unless changed on the page -----------------

def test_trade_study_aiding_mode_follows_the_sidebar_unless_changed_there():
    path = REPO / "examples" / "scenarios" / "airborne_xband_gnss_smoothed.yaml"
    at = open_app("pages/sweep.py")
    at.sidebar.file_uploader(key="scn_upload").set_value((path.name, path.read_bytes(), "application/yaml")).run()
    assert at.selectbox(key="sw_aiding_mode").value == "smoothed"
    at.sidebar.selectbox(key="scn_aiding_mode").set_value("realtime").run()
    assert not page_errors(at)
    assert at.selectbox(key="sw_aiding_mode").value == "realtime"  # it stayed 'smoothed'
    assert any("runs aiding mode **realtime**, the sidebar scenario's" in c.value for c in at.caption)
    at.selectbox(key="sw_aiding_mode").set_value("frozen").run()  # changed on the page: kept
    at.number_input(key="sw_trials").set_value(4).run()
    assert at.selectbox(key="sw_aiding_mode").value == "frozen"
    assert any("**frozen**, chosen here" in c.value and "says **realtime**" in c.value for c in at.caption)
    at.sidebar.selectbox(key="scn_aiding_mode").set_value("feedforward").run()  # a later sidebar edit wins
    assert at.selectbox(key="sw_aiding_mode").value == "feedforward"


# --- 3. the scenario page shows the lever-arm bounds and the PGA-limited grade --------------------

def test_scenario_page_shows_lever_arm_bounds_and_the_pga_limited_grade_as_the_cli(tmp_path):
    at = open_app()
    assert not page_errors(at)
    _, path = _scenario_file(tmp_path)
    expected, shown = _cli_bounds(tmp_path, path, "lever-arm"), _shown_bounds(at, "lever-arm")
    for key in BOUND_FIELDS:
        assert shown[key] == pytest.approx(expected[key], rel=1e-12), key
    assert shown["gyro_arw_deg_rt_h"] == pytest.approx(0.97294, rel=1e-4)  # the binding bound
    grades = _cli_json(tmp_path, "check", "--scenario", path)["lowest_sufficient_grade"]
    metrics = {m.label: m.value for m in at.metric}
    assert metrics["lowest sufficient grade (PGA-limited, binding)"] == grades["pga_limited"] == "tactical"
    assert metrics["lowest sufficient grade (paper bounds)"] == grades["paper"]


# --- 4 and 5. the trade study's time estimate and its cell limit ----------------------------------

def test_trade_study_estimate_includes_the_per_cell_set_up():
    """4 cells × 8 trials read "≈ 2 s at 20 trials/s"; they took 41 s (each new cell pays its set-up)."""
    at = open_app("pages/sweep.py")
    at.number_input(key="sw_trials").set_value(8).run()
    assert not page_errors(at)
    caption = next(c.value for c in at.caption if c.value.startswith("4 cells × 8 trials"))
    estimate = float(re.search(r"≈ (\d+) s", caption).group(1))
    assert 41 / 2 <= estimate <= 41 * 2, caption  # measured 37–41 s on this machine
    assert "set-up per cell" in caption


def test_trade_study_says_why_its_button_is_disabled_above_the_cell_limit():
    """Above 200 cells the button was disabled with nothing said."""
    at = open_app("pages/sweep.py")
    assert not at.button(key="sw_run_grid").disabled
    stim = load_catalog()["STIM300"]
    at.session_state["user_parts"] = {f"COPY{i}": stim.model_copy(update={"part_id": f"COPY{i}"}) for i in range(40)}
    at.run()
    at.multiselect(key="sw_parts").set_value([f"COPY{i}" for i in range(40)]).run()
    at.multiselect(key="sw_scenarios").set_value(["automotive_24ghz", "automotive_77ghz", "missile_borne",
                                                  "sas_100khz", "airborne_xband_long_range", "airborne_xband"]).run()
    assert not page_errors(at)
    assert at.button(key="sw_run_grid").disabled
    assert any("240 part × scenario cells is more than this page runs at once (200" in w.value
               and "pick fewer parts or scenarios" in w.value for w in at.warning)
    at.multiselect(key="sw_scenarios").set_value(["automotive_24ghz"]).run()  # 40 cells: runnable, nothing said
    assert not at.button(key="sw_run_grid").disabled
    assert not [w for w in at.warning if "more than this page runs at once" in w.value]


# --- 6. the check page's JSON download is what `sar-budget check --json` writes -------------------

def test_check_json_download_holds_what_the_cli_writes(tmp_path, downloads):
    at = open_app("pages/check.py")
    at.sidebar.radio(key="bounds_mode").set_value("derived").run()
    at.sidebar.number_input(key="scn_platform_accel_m_s2").set_value(20.0).run()
    assert not page_errors(at)
    s = at.session_state["ctx"].scenario
    shown = json.loads(downloads[f"check_{s.name}.json"])
    path = tmp_path / "edited.json"  # the keys the preset left out stay out (stated as defaults by both)
    path.write_text(json.dumps(s.model_dump(mode="json", exclude_unset=True)))
    expected = _cli_json(tmp_path, "check", "--scenario", str(path), "--mode", "derived")
    assert set(shown) == set(expected)
    for key in expected:
        assert shown[key] == expected[key], key
    assert shown["lowest_sufficient_grade"] == {"derived": "industrial", "pga_limited": "tactical"}
    stim = next(p for p in shown["parts"] if p["part_id"] == "STIM300")
    assert stim["margins"]["accel_scale_factor_ppm"] == pytest.approx(17.0903, rel=1e-4)
    assert np.isfinite(shown["tc_s"])
