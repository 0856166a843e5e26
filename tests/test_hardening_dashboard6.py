"""Dashboard pages driven as a new user with held-out inputs (``AppTest``, inputs built in
tmp_path or in memory): every problem is a message on the page naming the file, the field and
what was expected, and every result states what it assumed."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from app_harness import MAIN, AppTest


def _app(page: str) -> AppTest:
    at = AppTest.from_file(MAIN, default_timeout=120).run()
    at.switch_page(page).run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def _texts(elements) -> list[str]:
    return [e.value for e in elements]


def _log_csv(path: Path, n: int, *, step_s: float = 0.01, channels=("gyro_x_rps", "gyro_z_rps")) -> Path:
    rng = np.random.default_rng(3)
    data = {"time_s": np.arange(n) * step_s}
    data.update({ch: rng.normal(0.0, 1e-3, n) for ch in channels})
    pd.DataFrame(data).to_csv(path, index=False, float_format="%.9g")
    return path


def _upload_log(at: AppTest, radio: str, uploader: str, path: Path) -> None:
    at.radio(key=radio).set_value("upload a log or an Allan table").run()
    at.file_uploader(key=uploader).set_value((path.name, path.read_bytes(), "text/csv")).run()
    assert not at.exception, [e.value for e in at.exception]


def test_mc_refusal_names_the_scenario_once_for_all_parts():
    """The long-range preset needs more pulses than the simulator forms: one message naming the
    scenario, where its fields came from and both parts, not the same line once per part."""
    at = _app("pages/monte_carlo.py")
    at.selectbox(key="scn_preset").set_value("airborne_xband_long_range").run()
    at.multiselect(key="mc_parts").set_value(["ADIS16405", "STIM300"]).run()
    at.number_input(key="mc_trials").set_value(1).run()
    at.button(key="mc_run").click().run()
    assert not at.exception
    errors = _texts(at.error)
    assert len(errors) == 1, errors
    text = errors[0]
    assert "airborne_xband_long_range" in text and "preset airborne_xband_long_range" in text
    assert "ADIS16405, STIM300" in text and "16384 pulses" in text and "field azimuth_resolution_m" in text


def test_sweep_with_the_sidebar_preset_also_in_the_list_runs_it_once():
    """Sidebar on automotive_77ghz and the default list (current scenario + automotive_77ghz): the
    library refuses a preset given twice ("field presets"), the page sweeps it once and says so."""
    at = _app("pages/sweep.py")
    at.selectbox(key="scn_preset").set_value("automotive_77ghz").run()
    at.multiselect(key="sw_parts").set_value(["STIM300"]).run()
    at.number_input(key="sw_trials").set_value(1).run()
    assert any("also picked in the list: swept once" in c for c in _texts(at.caption))
    at.button(key="sw_run_grid").click().run()
    assert not at.exception and not at.error, _texts(at.error)
    table = at.session_state["sw_grid_last"][1]  # (inputs, table)
    assert table["scenario"].tolist() == ["automotive_77ghz"]


@pytest.mark.parametrize("page,radio,uploader", [("pages/noise_lab.py", "noise_source", "noise_upload"),
                                                 ("pages/model_gap.py", "gap_source", "gap_upload")])
def test_a_log_stamped_in_ms_is_refused_on_the_page(tmp_path, page, radio, uploader):
    """time_s holding ms gives 0.1 Hz: every noise figure scales with it, so the reading stops
    with an error on the page naming the column to use (a warning, first only in a collapsed
    report, let the figures through)."""
    path = _log_csv(tmp_path / "ms_stamps.csv", 2000, step_s=10.0)
    at = _app(page)
    _upload_log(at, radio, uploader, path)
    errors = _texts(at.error)
    assert any(e.startswith("ms_stamps.csv") and "0.1 Hz" in e and "time_ms" in e for e in errors), errors


def test_a_single_accelerometer_log_says_its_unit_is_unchecked(tmp_path):
    path = _log_csv(tmp_path / "one_accel.csv", 3000, channels=("accel_z_mps2",))
    at = _app("pages/model_gap.py")
    _upload_log(at, "gap_source", "gap_upload", path)
    assert any(i.startswith("one_accel.csv:") and "unit_unchecked" in i for i in _texts(at.info))


def test_a_ten_sample_log_names_the_file_and_the_channel(tmp_path):
    path = _log_csv(tmp_path / "ten.csv", 10)
    at = _app("pages/noise_lab.py")
    _upload_log(at, "noise_source", "noise_upload", path)
    errors = _texts(at.error)
    assert errors and errors[0].startswith("ten.csv, field gyro_x: only 10 samples"), errors
    assert "expected at least 100 samples" in errors[0]  # the one minimum the ARMA analysis states


def test_an_allan_table_too_short_to_fit_names_the_file():
    data = b"channel,tau_s,adev\ngyro_x_dps,0.01,0.1\ngyro_x_dps,0.1,0.05\n"
    at = _app("pages/noise_lab.py")
    at.radio(key="noise_source").set_value("upload a log or an Allan table").run()
    at.file_uploader(key="noise_upload").set_value(("short_adev.csv", data, "text/csv")).run()
    errors = _texts(at.error)
    assert errors and errors[0].startswith("short_adev.csv: no channel could be fitted"), errors


def test_model_gap_refuses_a_model_without_noise_terms(tmp_path):
    """An empty model JSON (or a catalog part with no noise figure) gave a LinAlgError on a log
    and "constant channels" of the example; now the model and the channels are named, no Run."""
    at = _app("pages/model_gap.py")
    at.selectbox(key="gap_part").set_value("ADIS16445").run()  # only a misalignment figure
    errors = _texts(at.error)
    assert errors and errors[0].startswith("part ADIS16445: the model gives no noise term for gyro_x"), errors
    at.radio(key="gap_model_kind").set_value("noise-model JSON").run()
    at.file_uploader(key="gap_model_upload").set_value(("empty.json", b"{}", "application/json")).run()
    path = _log_csv(tmp_path / "gz.csv", 5000, channels=("gyro_z_rps",))
    _upload_log(at, "gap_source", "gap_upload", path)
    errors = _texts(at.error)
    assert errors and errors[0].startswith("empty.json: the model gives no noise term for gyro_z;"), errors
    assert "nothing to compare gz.csv with" in errors[0]
    assert not [b for b in at.button if b.key == "gap_run"]
    at.file_uploader(key="gap_model_upload").set_value(("arw.json", b'{"gyro_arw_deg_rt_h": 0.1}',
                                                        "application/json")).run()
    assert not at.error and [b for b in at.button if b.key == "gap_run"]


@pytest.mark.slow
def test_user_part_with_windows_csv_and_empty_terms_states_its_fill_in_the_mc():
    """A catalog CSV saved by Excel on Windows (BOM, CRLF), most datasheet cells empty: it merges,
    and the Monte Carlo page states every value it filled or took as zero."""
    header = ("part_id,vendor,model,grade,gyro_arw_deg_rt_h,accel_vrw_m_s_rt_h,gyro_bias_instability_deg_h,"
              "accel_bias_instability_ug,source")
    text = "\ufeff" + header + "\r\n" + "MY_IMU,,,industrial,,0.1,,,my datasheet\r\n"
    at = _app("pages/catalog.py")
    at.file_uploader(key="cat_upload").set_value(("mine.csv", text.encode(), "text/csv")).run()
    assert not at.error and any("1 parts valid" in s for s in _texts(at.success))
    at.button(key="cat_merge").click().run()
    at.switch_page("pages/monte_carlo.py").run()
    at.multiselect(key="mc_parts").set_value(["MY_IMU"]).run()
    at.number_input(key="mc_trials").set_value(2).run()
    at.button(key="mc_run").click().run()
    assert not at.exception and not at.error, _texts(at.error)
    fill = next(c for c in _texts(at.caption) if c.startswith("**MY_IMU**"))
    assert "filled from the industrial grade's typical values" in fill and "gyro_arw_deg_rt_h = 3 deg/√h" in fill
    assert "simulated as 0: gyro_rrw_deg_h_rt_h" in fill
    assert "accel_vrw_m_s_rt_h =" not in fill  # given in the file: not filled


def test_every_trial_metric_has_a_label():
    """The percentile table and the distribution picker showed the raw key fast_phase_rms_deg."""
    from budget.mc import TRIAL_METRICS
    from budget.plots.mc import METRIC_LABELS

    assert set(TRIAL_METRICS) <= set(METRIC_LABELS)


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_a_scenario_warning_is_shown_beside_the_results():
    """A sonar flown at 150 m/s: the echo delay 2R/c exceeds Tc, so stop-and-go (the bounds' and
    the simulator's geometry) does not hold. The library warns; the warning reached only the
    server log while the check matrix showed its verdicts."""
    at = _app("pages/check.py")
    at.selectbox(key="scn_preset").set_value("sas_100khz").run()
    at.sidebar.number_input(key="scn_platform_speed_m_s").set_value(150.0).run()
    assert not at.exception and not at.error
    main = [w.value for w in at.main.warning]
    assert any("echo delay 2R/c" in w and "stop-and-go" in w for w in main), main
    assert not any("echo delay 2R/c" in w.value for w in at.sidebar.warning)  # once, beside the results
    assert at.table  # the check is still shown, with the warning above it
    at.sidebar.number_input(key="scn_platform_speed_m_s").set_value(1.5).run()
    assert not [w for w in at.warning if "echo delay" in w.value]
