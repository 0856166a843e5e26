"""Dashboard workbench features through ``AppTest`` and the app's helpers: scenario files in and
out (edited scenarios renamed), Allan tables accepted, the check's flag shown, exports, the
trade-study page, and the ARMA pipeline shared with the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest

from budget.errors import InputError
from budget.presets import get_preset

from app_harness import MAIN, REPO, AppTest


def _app(page: str | None = None) -> AppTest:
    at = AppTest.from_file(MAIN, default_timeout=180).run()
    if page:
        at.switch_page(page).run()
    _ok(at)
    return at


def _ok(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]


def test_scenario_upload_is_parsed_and_every_error_listed():
    import sidebar

    s = get_preset("missile_borne")
    text = (REPO / "examples" / "scenarios" / "missile_borne.json").read_bytes()
    assert sidebar.scenario_from_upload(text, "missile_borne.json") == s
    yaml_text = (REPO / "examples" / "scenarios" / "automotive_24ghz.yaml").read_bytes()
    assert sidebar.scenario_from_upload(yaml_text, "a.yaml") == get_preset("automotive_24ghz")
    bad = json.dumps({**s.model_dump(mode="json"), "slant_range_m": -5, "platform_speed_m_s": "fast"}).encode()
    with pytest.raises(InputError) as err:
        sidebar.scenario_from_upload(bad, "bad.json")
    assert "bad.json" in str(err.value) and "slant_range_m" in str(err.value) \
        and "platform_speed_m_s" in str(err.value)
    with pytest.raises(InputError, match="not valid JSON/YAML"):
        sidebar.scenario_from_upload(b"{: [", "x.json")


def test_edited_scenario_gets_its_own_name_in_pages_and_downloads():
    at = _app()
    assert at.download_button(key="scn_download").proto.label  # drawn
    at.number_input(key="scn_slant_range_m").set_value(20_000.0).run()
    _ok(at)
    caption = " ".join(c.value for c in at.caption)
    assert "airborne_xband_edited" in caption
    # choosing the preset again restores its name
    at.selectbox(key="scn_preset").set_value("automotive_77ghz").run()
    assert "automotive_77ghz_edited" not in " ".join(c.value for c in at.caption)
    assert "scenario **automotive_77ghz**" in " ".join(c.value for c in at.caption)


def test_pages_without_scenario_do_not_draw_the_scenario_sidebar():
    for page in ("pages/noise_lab.py", "pages/model_gap.py", "pages/focus.py"):
        at = _app(page)
        assert not [w for w in at.sidebar.number_input if w.key == "scn_slant_range_m"], page
    at = _app("pages/check.py")
    assert [w for w in at.sidebar.number_input if w.key == "scn_slant_range_m"]


def test_check_page_shows_the_flag_and_exports(tmp_path):
    from budget.catalog.io import load_catalog
    from budget.check import check_parts

    at = _app("pages/check.py")
    res = check_parts(load_catalog().values(), get_preset("airborne_xband"))
    flagged = [r["part_id"] for r in res.to_dict()["scenarios"][0]["parts"] if r.get("flag")]
    warnings = " ".join(w.value for w in at.warning)
    for pid in flagged:
        assert pid in warnings
    assert at.button(key="chk_build_report")
    at.button(key="chk_build_report").click().run()
    _ok(at)
    assert at.get("download_button")  # CSV, JSON and the report


def test_check_page_judges_the_rotation_terms_on_the_chosen_motion():
    at = _app("pages/check.py")
    assert not any("judged against the motion flown" in cap.value for cap in at.caption)
    at.selectbox(key="chk_platform_motion").set_value("attitude_change").run()
    _ok(at)
    line = [cap.value for cap in at.caption if "judged against the motion flown" in cap.value]
    assert line and "gyro SF bound × 3.36" in line[0]
    at.selectbox(key="chk_platform_motion").set_value("straight").run()
    _ok(at)
    assert any("not exercised" in cap.value for cap in at.caption)


def test_allan_table_upload_reads_like_the_cli(shared_data):
    import upload_tables

    from budget.noise import read_adev_table

    path = shared_data / "adev" / "adis16405.csv"
    data = path.read_bytes()
    assert upload_tables.is_adev_table(data, path.name)
    got = upload_tables.read_uploaded_adev(data, path.name, 100.0, 1_000_000)
    ref = read_adev_table(path, 100.0, 1_000_000)
    assert list(got) == list(ref)
    for ch in ref:
        np.testing.assert_array_equal(got[ch].adev, ref[ch].adev)
        assert got[ch].source == path.name
    log = (REPO / "tests").glob("*.py")  # any non-table text is not taken for a table
    assert not upload_tables.is_adev_table(next(log).read_bytes(), "x.csv")


def test_noise_arma_cli_and_dashboard_render_one_pipeline(tmp_path, capsys):
    """``sar-budget noise arma --json`` is :func:`analyse_arma` ``.to_dict()``; the page's table is
    the same selection."""
    from budget.cli.main import main
    from budget.noise import read_log
    from budget.noise.pipeline import analyse_arma

    at = _app("pages/noise_lab.py")
    csv = tmp_path / "example.csv"
    csv.write_text(at.session_state["noise_example_csv"])
    assert main(["noise", "arma", str(csv), "--channel", "gyro_x", "--json", "-", "--quiet"]) == 0
    cli = json.loads(capsys.readouterr().out)
    log = read_log(csv)
    res = analyse_arma(log.channels["gyro_x"], log.rate_hz, channel="gyro_x")
    assert cli["selected"] == res.selection.selected.name
    assert cli["variance_after"] == pytest.approx(res.filtered.variance_after, rel=1e-12)
    assert [c["order"] for c in cli["candidates"]] == [c.name for c in res.selection.candidates]
    at.selectbox(key="noise_channel").set_value("gyro_x").run()
    _ok(at)
    n = at.number_input(key="noise_arma_samples").value
    page = analyse_arma(log.channels["gyro_x"][:n], log.rate_hz, channel="gyro_x")
    table = next(d.value for d in at.dataframe if "aic" in d.value.columns)
    assert table["aic"].tolist() == pytest.approx([c.aic for c in page.selection.candidates], rel=1e-12)


def test_sweep_page_runs_and_shows_the_library_table():
    from budget.api import sweep

    at = _app("pages/sweep.py")
    at.selectbox(key="scn_preset").set_value("automotive_24ghz").run()
    at.multiselect(key="sw_parts").set_value(["STIM300"]).run()
    at.multiselect(key="sw_scenarios").set_value(["current scenario (sidebar)", "automotive_77ghz"]).run()
    at.number_input(key="sw_trials").set_value(2).run()
    at.button(key="sw_run_grid").click().run()
    _ok(at)
    ref = sweep(["STIM300"], ["automotive_24ghz", "automotive_77ghz"], 2, int(at.number_input(key="sw_seed").value))
    shown = at.session_state["sw_grid_last"][1]  # (inputs, table)
    assert shown["p_pass_after"].tolist() == ref["p_pass_after"].tolist()
    assert at.get("plotly_chart")


def test_scenario_file_loaded_in_the_sidebar_and_aiding_mode_selectable():
    from budget.scenario import Scenario

    path = REPO / "examples" / "scenarios" / "airborne_xband_gnss_smoothed.yaml"
    at = _app("pages/sweep.py")
    at.sidebar.file_uploader(key="scn_upload").set_value((path.name, path.read_bytes(), "application/yaml")).run()
    _ok(at)
    assert at.session_state["ctx"].scenario == Scenario.load(path)
    assert any(f"file {path.name}" in c.value for c in at.sidebar.caption)
    assert at.selectbox(key="sw_aiding_mode").value == "smoothed"  # aiding settings offered
    bad = b"name: x\nslant_range_m: -3\nplatform_speed_m_s: fast\n"
    at.sidebar.file_uploader(key="scn_upload").set_value(("bad.yaml", bad, "application/yaml")).run()
    text = " ".join(e.value for e in at.sidebar.error)
    assert "bad.yaml" in text and "slant_range_m" in text and "platform_speed_m_s" in text
    assert at.session_state["ctx"].scenario == Scenario.load(path)  # the last good one is kept


@pytest.mark.slow  # the model-gap workflow on a published Allan curve (≈ 20–60 s)
def test_model_gap_page_accepts_an_allan_table(shared_data):
    from budget.gap import run_gap

    path = shared_data / "adev" / "adis16405.csv"
    at = AppTest.from_file(MAIN, default_timeout=600).run()
    at.switch_page("pages/model_gap.py").run()
    at.radio(key="gap_source").set_value("upload a log or an Allan table").run()
    at.file_uploader(key="gap_upload").set_value((path.name, path.read_bytes(), "text/csv")).run()
    _ok(at)
    at.number_input(key="gap_realizations").set_value(4).run()
    at.button(key="gap_run").click().run()
    _ok(at)
    ref = run_gap(path, "ADIS16405", seed=0, realizations=4, rate_hz=100.0, samples=1_000_000)
    shown = {m.label: m.value for m in at.metric}
    assert shown["gap before (mean z²)"] == f"{ref.gap_before:.3g}"
    assert shown["gap after (mean z²)"] == f"{ref.gap_after:.3g}"
