"""Monte Carlo and noise-lab pages through ``AppTest``: they load, and what they show is the
library's (P(pass) equals ``run_mc`` with the same seed; the ARMA order equals ``select_arma``)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from budget.catalog.io import load_catalog
from budget.errors import InputError
from budget.mc import McOptions, run_mc
from budget.noise import preprocess, read_log, select_arma
from budget.presets import get_preset

AppTest = pytest.importorskip("streamlit.testing.v1", reason="streamlit not installed").AppTest

APP_DIR = Path(__file__).resolve().parents[1] / "app"
MAIN = str(APP_DIR / "main.py")
if str(APP_DIR) not in sys.path:
    sys.path.insert(0, str(APP_DIR))

MC_PAGE = "pages/monte_carlo.py"
NOISE_PAGE = "pages/noise_lab.py"
MC_PRESET = "automotive_77ghz"
MC_PART = "ADIS16405"
#: Trials of the page runs: few keep the test fast; the assertion (the page shows run_mc's numbers
#: for the same seed) holds for any count.
MC_TRIALS = 16


def _app(page: str) -> AppTest:
    at = AppTest.from_file(MAIN, default_timeout=120).run()
    at.switch_page(page).run()
    _no_failure(at)
    return at


def _frame_with(at: AppTest, column: str):
    """The first table shown that has ``column`` (AppTest does not expose dataframe keys)."""
    return next(d.value for d in at.dataframe if column in d.value.columns)


def _no_failure(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]


@pytest.mark.parametrize("page", [MC_PAGE, NOISE_PAGE])
def test_page_loads(page):
    at = _app(page)
    assert at.title[0].value


def test_mc_page_p_pass_equals_run_mc_with_the_same_seed():
    at = _app(MC_PAGE)
    at.selectbox(key="scn_preset").set_value(MC_PRESET).run()
    at.multiselect(key="mc_parts").set_value([MC_PART]).run()
    at.number_input(key="mc_trials").set_value(MC_TRIALS).run()
    at.number_input(key="mc_seed").set_value(3).run()
    at.button(key="mc_run").click().run()
    _no_failure(at)
    ref = run_mc(get_preset(MC_PRESET), load_catalog()[MC_PART], MC_TRIALS, 3, options=McOptions())
    row = _frame_with(at, "P(pass) after PGA").set_index("part_id").loc[MC_PART]
    assert row["trials"] == MC_TRIALS
    assert row["P(pass) before PGA"] == ref.p_pass_before
    assert row["P(pass) after PGA"] == ref.p_pass_after
    assert (row["CI95 after low"], row["CI95 after high"]) == pytest.approx(ref.ci_after, abs=0)
    shown = {m.label: m.value for m in at.metric}
    assert shown[f"P(pass) after PGA — {MC_PART}"] == f"{ref.p_pass_after:.3f}"
    reasons = _frame_with(at, "pga_failed").set_index("part_id").loc[MC_PART]
    assert {k: int(v) for k, v in reasons.items()} == ref.agg.failure_reasons()
    # the worst-trial inspector shows the run's worst trial with its images
    assert at.selectbox(key="mc_worst_trial").value == ref.worst_trials()[0].trial
    assert at.get("plotly_chart")  # images and phase figures drawn
    # later interactions re-use the cached run (its progress bar is replayed, not re-run)
    at.selectbox(key="mc_metric").set_value("pslr_db").run()
    at.selectbox(key="mc_worst_trial").set_value(ref.worst_trials()[1].trial).run()
    _no_failure(at)
    assert _frame_with(at, "P(pass) after PGA").set_index("part_id").loc[MC_PART, "P(pass) after PGA"] \
        == ref.p_pass_after


def _run_mc_page(select_key: str, value: str) -> AppTest:
    """The MC page run on the test preset and part with one selectbox set."""
    at = _app(MC_PAGE)
    at.selectbox(key="scn_preset").set_value(MC_PRESET).run()
    at.multiselect(key="mc_parts").set_value([MC_PART]).run()
    at.number_input(key="mc_trials").set_value(MC_TRIALS).run()
    at.selectbox(key=select_key).set_value(value).run()
    at.button(key="mc_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def test_mc_page_prefilter_equals_run_mc_with_that_option():
    at = _run_mc_page("mc_prefilter", "kalman")
    try:
        ref = run_mc(get_preset(MC_PRESET), load_catalog()[MC_PART], MC_TRIALS, int(at.number_input(key="mc_seed").value),
                     options=McOptions(prefilter="kalman"))
    except InputError as err:  # the library refuses this filter: the page shows its message
        assert any(str(err) in e.value for e in at.error)
        return
    _no_failure(at)
    row = _frame_with(at, "P(pass) after PGA").set_index("part_id").loc[MC_PART]
    assert row["P(pass) after PGA"] == ref.p_pass_after


def test_mc_page_platform_motion_equals_run_mc_with_that_option():
    at = _run_mc_page("mc_platform_motion", "attitude_change")
    _no_failure(at)
    ref = run_mc(get_preset(MC_PRESET), load_catalog()[MC_PART], MC_TRIALS, int(at.number_input(key="mc_seed").value),
                 options=McOptions(platform_motion={"kind": "attitude_change"}))
    row = _frame_with(at, "P(pass) after PGA").set_index("part_id").loc[MC_PART]
    assert row["P(pass) after PGA"] == ref.p_pass_after
    assert any("rolling through" in x.value for x in at.caption)


def test_mc_page_scenario_beyond_simulation_limits_is_a_message():
    at = _app(MC_PAGE)
    at.selectbox(key="scn_preset").set_value("airborne_xband_long_range").run()
    at.button(key="mc_run").click().run()
    assert not at.exception
    try:
        run_mc(get_preset("airborne_xband_long_range"), load_catalog()[MC_PART], 1, 0)
    except Exception as err:  # noqa: BLE001 — the page must show the library's own message
        assert any(str(err) in e.value for e in at.error)
    else:
        pytest.skip("the long-range preset is within the simulation limits now")


def test_noise_page_example_arma_order_equals_select_arma(tmp_path):
    at = _app(NOISE_PAGE)
    at.selectbox(key="noise_channel").set_value("gyro_z").run()
    _no_failure(at)
    csv = tmp_path / "example.csv"
    csv.write_text(at.session_state["noise_example_csv"])
    x = read_log(csv).channels["gyro_z"][: at.number_input(key="noise_arma_samples").value]
    sel = select_arma(preprocess(x).x, method="ls")
    table = _frame_with(at, "aic")
    assert list(table.loc[table["selected"], "order"]) == [sel.selected.name]
    assert list(table["order"]) == [c.name for c in sel.candidates]
    assert table["aic"].tolist() == pytest.approx([c.aic for c in sel.candidates], rel=1e-12)


def test_mc_page_runs_a_squinted_scenario_and_says_how():
    """A squint set in the sidebar: the page shows run_mc's P(pass) for that scenario and the note of
    how a squinted aperture is simulated (its broadside equivalent, :mod:`budget.sar.squint`)."""
    at = _app(MC_PAGE)
    at.selectbox(key="scn_preset").set_value(MC_PRESET).run()
    at.number_input(key="scn_squint_deg").set_value(30.0).run()
    at.multiselect(key="mc_parts").set_value([MC_PART]).run()
    at.number_input(key="mc_trials").set_value(MC_TRIALS).run()
    at.button(key="mc_run").click().run()
    _no_failure(at)
    scen = get_preset(MC_PRESET).model_copy(update={"squint_deg": 30.0})
    ref = run_mc(scen, load_catalog()[MC_PART], MC_TRIALS, int(at.number_input(key="mc_seed").value),
                 options=McOptions())
    row = _frame_with(at, "P(pass) after PGA").set_index("part_id").loc[MC_PART]
    assert row["P(pass) after PGA"] == ref.p_pass_after
    assert any("broadside equivalent" in x.value for x in at.caption)
