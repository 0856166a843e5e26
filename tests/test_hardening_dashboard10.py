"""Dashboard: what the library reads and says since the clock-text logs, the digitised curves and the
stated defaults — shown on the pages as the CLI shows it, in the dashboard's words.

* noise lab: a log whose time is a ``Time (UTC)`` ISO column and a log in ``mdps``/``µg`` are read
  with the reader's finding and units; an allantools-style table shows how it was read (adev_err
  not used); a digitised datasheet curve (``tau (s), sigma (deg/h)``, six points) is read without a
  record when the user says there is none (``record behind the curve``), with the library's note,
  values and upper limits (no sample count invented by the page's default rate and length);
* scenario page: where a bound stops constraining (:meth:`BoundsTable.limit_notes`) at a very
  short Tc, and the keys a preset or an uploaded file leaves out (:meth:`Scenario.defaults_note`)
  while their fields still hold the defaults; the check matrix states them as ``sar-budget check``.

Expectations come from the inputs written here and the library's own result for them.
"""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest

from app_harness import open_app

from budget.bounds import compute_bounds, scenario_keys
from budget.check import check_scenario_keys
from budget.errors import in_words_of
from budget.noise import characterize, fit_noise_terms, read_adev_table, read_log
from budget.presets import get_preset

UPLOAD = "upload a log or an Allan table"
OPTION = "--"  # a command-line option's prefix: never in a dashboard message
RATE_HZ, N = 100.0, 6000


def _noise(seed: int = 3) -> dict[str, np.ndarray]:
    """White noise on six channels (SI: rad/s, m/s²), accelerometers around 1 g on z."""
    rng = np.random.default_rng(seed)
    out = {f"gyro_{a}": rng.normal(0.0, 1e-3, N) for a in "xyz"}
    out.update({f"accel_{a}": rng.normal(0.0, 1e-3, N) for a in "xyz"})
    out["accel_z"] = out["accel_z"] + 9.80665
    return out


def _iso_log() -> str:
    x = _noise()
    t0 = pd.Timestamp("2024-05-01T12:00:00")
    df = pd.DataFrame({"Time (UTC)": [(t0 + pd.Timedelta(seconds=i / RATE_HZ)).isoformat(timespec="milliseconds")
                                      for i in range(N)]})
    for ch, v in x.items():
        df[f"{ch}_{'rps' if ch.startswith('gyro') else 'mps2'}"] = v
    return df.to_csv(index=False, float_format="%.9g")


def _mdps_ug_log() -> str:
    x = _noise()
    df = pd.DataFrame({"time_s": np.arange(N) / RATE_HZ})
    for ch, v in x.items():
        df[f"{ch} [{'mdps' if ch.startswith('gyro') else 'µg'}]"] = (
            np.degrees(v) * 1e3 if ch.startswith("gyro") else v / 9.80665 * 1e6)
    return df.to_csv(index=False, float_format="%.9g")


def _datasheet_curve() -> str:
    """Six points read off a datasheet figure: ARW 0.3 deg/√h and a 3.3 deg/h floor, no rate."""
    tau = np.array([0.01, 0.1, 1.0, 10.0, 100.0, 1000.0])
    sigma = np.hypot(0.3 * 60.0 / np.sqrt(tau), 3.32)
    return "tau (s),sigma (deg/h)\n" + "".join(f"{t:g},{s:.6g}\n" for t, s in zip(tau, sigma))


def _allantools_table() -> tuple[str, int]:
    """allantools' oadev saved with pandas: index, taus, adev, adev_err, n (n = N + 1 − 2m)."""
    from budget.noise import allan_deviation

    r = allan_deviation(_noise()["gyro_z"], RATE_HZ, channel="gyro_z", unit="rad/s")
    adev = np.degrees(r.adev) * 3600.0
    n = N + 1 - 2 * np.rint(r.tau_s * RATE_HZ).astype(int)
    buf = io.StringIO()
    pd.DataFrame({"taus": r.tau_s, "adev (deg/h)": adev, "adev_err": adev / np.sqrt(n), "n": n}).to_csv(buf)
    return buf.getvalue(), N


def _shown(at) -> list[str]:
    assert not at.exception, [e.value for e in at.exception]
    return [str(e.value) for kind in ("error", "warning", "info", "markdown", "caption") for e in getattr(at, kind)]


def _upload(at, name: str, text: str) -> None:
    at.radio(key="noise_source").set_value(UPLOAD).run()
    at.file_uploader(key="noise_upload").set_value((name, text.encode("utf-8"), "text/csv")).run()


def _terms(at) -> pd.DataFrame:
    """The page's IEEE-952 terms table of the channel shown (the per-channel table has a channel column)."""
    return next(d.value for d in at.dataframe if "upper_limit" in d.value.columns and "channel" not in d.value.columns)


# --- noise lab: logs the reader learnt today --------------------------------------------------------

@pytest.mark.parametrize("name,make", [("iso_time.csv", _iso_log), ("mdps_ug.csv", _mdps_ug_log)])
def test_clock_text_and_milli_unit_logs_are_read_as_the_library_reads_them(tmp_path, name, make):
    text = make()
    (tmp_path / name).write_text(text, encoding="utf-8")
    log = read_log(tmp_path / name)
    at = open_app("pages/noise_lab.py")
    _upload(at, name, text)
    shown = _shown(at)
    assert not at.error, [e.value for e in at.error]
    loaded = next(m for m in shown if "noise-loaded" in m)
    assert f"{log.n_samples} samples at {log.rate_hz:.6g} Hz" in loaded
    for ch in log.channels:  # the units the header gave, as the reader names them
        assert f"{ch} [{log.source_units[ch]}]" in loaded
    for issue in log.issues.issues:  # e.g. the clock-text column read as seconds from its first sample
        if issue.severity in ("warning", "info"):
            assert any(in_words_of(issue.text(), "dashboard") in s for s in shown), issue.text()


# --- noise lab: Allan tables written by other tools, digitised curves -------------------------------

def test_a_digitised_datasheet_curve_is_read_without_a_record_when_the_user_says_so(tmp_path):
    text = _datasheet_curve()
    path = tmp_path / "datasheet.csv"
    path.write_text(text, encoding="utf-8")
    tables = read_adev_table(path, channels=["gyro_z"])  # as `noise characterize` without a rate
    fit = fit_noise_terms(tables["gyro_z"])
    part = characterize(tables, part_id="measured_imu").part

    at = open_app("pages/noise_lab.py")
    _upload(at, "datasheet.csv", text)
    at.selectbox(key="noise_curve_channel").set_value("gyro_z").run()
    record = at.radio(key="noise_adev_record")
    assert record.value == record.options[0]  # a record known: the rate and length asked for
    record.set_value(record.options[1]).run()
    shown = _shown(at)
    assert not at.error, [e.value for e in at.error]
    assert not [n for n in at.number_input if n.key in ("noise_adev_rate", "noise_adev_samples")]
    assert any("noise-loaded" in s and "digitised curve" in s for s in shown)
    # how the table was read: the library's note, in the dashboard's words (no option named)
    for note in tables["gyro_z"].notes:
        said = in_words_of(note, "dashboard")
        assert said != note and OPTION not in said
        assert any(said in s for s in shown), said
    assert any(fit.summary().splitlines()[0] in s for s in shown)  # 'digitised curve: … uncertainty unknown'
    # the terms and the upper limits of the unresolved ones: the library's values
    frame = _terms(at).set_index("term")
    expected = fit.to_frame().set_index("term")
    for term, row in expected.iterrows():
        if np.isfinite(row["upper_limit"]):
            assert float(frame.loc[term, "upper_limit"]) == pytest.approx(row["upper_limit"], rel=1e-3)
    # the catalog row: the library's, its notes saying the limit has no confidence level
    shown_row = next(d.value for d in at.dataframe if list(d.value.columns) == ["column", "value"]
                     ).set_index("column")["value"]
    assert float(shown_row["gyro_arw_deg_rt_h"]) == pytest.approx(part.gyro_arw_deg_rt_h, rel=1e-6)
    assert shown_row["notes"] == part.notes and "no confidence level" in part.notes
    assert "rate_hz" not in shown_row.index or part.rate_hz is not None


def test_an_allantools_table_says_how_it_was_read(tmp_path):
    text, samples = _allantools_table()
    path = tmp_path / "oadev.csv"
    path.write_text(text, encoding="utf-8")
    tables = read_adev_table(path, RATE_HZ, samples, channels=["gyro_z"])
    assert tables["gyro_z"].notes  # adev_err not used
    at = open_app("pages/noise_lab.py")
    _upload(at, "oadev.csv", text)
    at.selectbox(key="noise_curve_channel").set_value("gyro_z").run()
    at.number_input(key="noise_adev_rate").set_value(RATE_HZ).run()
    at.number_input(key="noise_adev_samples").set_value(samples).run()
    shown = _shown(at)
    assert not at.error, [e.value for e in at.error]
    for note in tables["gyro_z"].notes:
        assert any(in_words_of(note, "dashboard") in s for s in shown), note
    fit = fit_noise_terms(tables["gyro_z"])
    frame, expected = _terms(at).set_index("term"), fit.to_frame().set_index("term")
    for term, row in expected.iterrows():
        if np.isfinite(row["upper_limit"]):
            assert float(frame.loc[term, "upper_limit"]) == pytest.approx(row["upper_limit"], rel=1e-3)


# --- scenario page and check matrix: limits and defaults ---------------------------------------------

def test_the_scenario_page_says_where_bounds_stop_constraining_and_which_keys_are_defaults():
    at = open_app("pages/scenario.py")
    s = at.session_state["ctx"].scenario
    keys = tuple(dict.fromkeys(k for m in ("paper", "derived", "no-autofocus") for k in scenario_keys(m)))
    preset = get_preset(s.name)
    assert preset.defaults_note(keys)  # the preset leaves squint out: stated as the CLI states it
    assert preset.defaults_note(keys) in [i.value for i in at.info]
    # a very short aperture: a coarse azimuth resolution flown fast
    at.number_input(key="scn_azimuth_resolution_m").set_value(50.0).run()
    at.number_input(key="scn_platform_speed_m_s").set_value(1000.0).run()
    ctx = at.session_state["ctx"]
    s = ctx.scenario
    expected = [f"{m}: {note}" for m in ("paper", "derived", "no-autofocus")
                for note in compute_bounds(np.array([s.tc_s]), s.range_resolution_m, m, wavelength_m=s.wavelength_m,
                                           assumptions=ctx.assumptions(m)).limit_notes()]
    assert expected and any("does not constrain" in e for e in expected)
    warnings = [w.value for w in at.warning]
    assert all(e in warnings for e in expected), (expected, warnings)
    # a defaulted key set by the user is the user's: no longer stated
    at.number_input(key="scn_squint_deg").set_value(5.0).run()
    assert not any("squint_deg" in i.value for i in at.info)
    assert not at.exception


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_an_uploaded_scenario_file_states_the_keys_it_left_out_on_the_check_page(tmp_path):
    base = get_preset("airborne_xband").model_dump(mode="json")
    for key in ("depression_deg", "lever_arm_m", "squint_deg"):
        base.pop(key, None)
    base["name"] = "short_file"
    import json

    from budget.scenario import Scenario

    s = Scenario.from_dict(base)
    at = open_app("pages/check.py")
    at.sidebar.get("file_uploader")[0].set_value(("short.json", json.dumps(base).encode(), "application/json")).run()
    assert not at.exception and not at.error, [e.value for e in at.error]
    note = s.defaults_note(check_scenario_keys("paper"))
    assert "depression_deg" in note and "lever_arm_m" in note
    assert note in [i.value for i in at.info], [i.value for i in at.info]
