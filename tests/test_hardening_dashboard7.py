"""Dashboard after the readers' and the motion engine's changes (``AppTest``, inputs in memory):

* a one-curve Allan table (``tau [s], adev (deg/h)``, no channel column) is read as the channel
  the user picks beside the upload (the choices are ``budget.units.CHANNELS``), and a message
  about it says how to name it here, not on the command line;
* headers with units in brackets and UTF-16 files reach the library's readers; a refused unit is
  the library's one-line message;
* a motion run refused for its working memory is one line on the Monte Carlo and trade-study
  pages, with no progress bar left behind;
* every page with its default inputs, and every uploader with a malformed, an empty and a
  NaN-holding file: one line of error, never an exception.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from app_harness import AppTest, open_app as _app, page_errors as _errors
from budget.errors import InputError
from budget.noise.adev_columns import needs_channel_name
from budget.units import CHANNELS

UPLOAD = "upload a log or an Allan table"
LOG_PAGES = [("pages/noise_lab.py", "noise_source", "noise_upload", "noise"),
             ("pages/model_gap.py", "gap_source", "gap_upload", "gap")]


def _one_line(at: AppTest, name: str) -> str:
    """The page's one error: a single line naming the uploaded file."""
    errors = _errors(at)
    assert len(errors) == 1, errors
    assert "\n" not in errors[0] and "Traceback" not in errors[0], errors[0]
    assert errors[0].startswith(name), errors[0]
    return errors[0]


def _curve(header: str = "tau [s], adev (deg/h)") -> str:
    """One Allan curve, τ on the 100 Hz grid (white noise + a floor), deg/h."""
    taus = 0.01 * 2.0 ** np.arange(12)
    adev = 20.0 / np.sqrt(taus) + 2.0
    return header + "\n" + "".join(f"{t:.6g},{a:.6g}\n" for t, a in zip(taus, adev))


def _log(header: str = "time [s],gyro_x [deg/s],gyro_z [deg/s]", n: int = 3000) -> str:
    rng = np.random.default_rng(5)
    rows = rng.normal(0.0, 1e-2, (n, 2))
    return header + "\n" + "".join(f"{i / 100:.2f},{a:.6g},{b:.6g}\n" for i, (a, b) in enumerate(rows))


def _upload(at: AppTest, radio: str, uploader: str, name: str, data: bytes) -> None:
    at.radio(key=radio).set_value(UPLOAD).run()
    at.file_uploader(key=uploader).set_value((name, data, "text/csv")).run()


# --- 1. one-curve Allan tables -------------------------------------------------------------------

def test_the_library_says_which_tables_need_their_channel_named(tmp_path):
    cases = {"one.csv": (_curve(), True), "bare.csv": (_curve("tau_s,adev"), True),
             "ci.csv": ("# from a vendor tool\n\ntau_s;adev;lci;uci;\n0.01;1;0.9;1.1\n", True),
             "long.csv": ("channel,tau_s,adev\ngyro_z_dps,0.01,1\n", False),
             "wide.csv": ("tau_s,gyro_x_dps\n0.01,1\n", False), "log.csv": (_log(n=3), False)}
    for name, (text, expected) in cases.items():
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        assert needs_channel_name(path) is expected, name
    wide = tmp_path / "utf16.csv"
    wide.write_bytes(_curve().encode("utf-16"))
    assert needs_channel_name(wide)


@pytest.mark.parametrize("page,radio,uploader,prefix", LOG_PAGES)
def test_a_one_curve_table_is_read_as_the_channel_picked(page, radio, uploader, prefix):
    at = _app(page)
    _upload(at, radio, uploader, "one.csv", _curve().encode())
    assert not _errors(at)
    box = at.selectbox(key=f"{prefix}_curve_channel")
    assert list(box.options) == list(CHANNELS) and box.value is None  # the library's channels, none assumed
    assert any(i.value.startswith("one.csv has no channel column") for i in at.info)
    box.set_value("gyro_z").run()
    assert not _errors(at)
    shown = " ".join(m.value for m in at.markdown) + " ".join(c.value for c in at.caption)
    assert "channel(s): gyro_z" in shown or "channels gyro_z (compared by ADEV only)" in shown, shown
    # a channel whose unit the header contradicts: the library's one line, naming the column
    at.selectbox(key=f"{prefix}_curve_channel").set_value("accel_x").run()
    assert "field adev (deg/h)" in _one_line(at, "one.csv")
    # the same table in UTF-16 (a spreadsheet's "Unicode text"): the same path, the same curve
    at.file_uploader(key=uploader).set_value(("one16.csv", _curve().encode("utf-16"), "text/csv")).run()
    at.selectbox(key=f"{prefix}_curve_channel").set_value("gyro_z").run()
    assert not _errors(at)


def test_the_channel_message_speaks_of_the_dashboard_not_the_command_line():
    from upload_tables import read_uploaded_adev

    from uploads import error_text  # the library's message in the dashboard's words (test_hardening_dashboard8)

    with pytest.raises(InputError) as got:  # no channel picked: what the library refuses
        read_uploaded_adev(_curve().encode(), "one.csv", 100.0, 1_000_000, channel=None)
    text = error_text(got.value)
    assert text.startswith("one.csv, row 1, field channel: the table has no channel column")
    assert "'channel of this curve'" in text and "--channels" not in text and "channels=" not in text
    with pytest.raises(InputError) as got:  # τ off the rate's grid: the page's input, not --rate-hz
        read_uploaded_adev(_curve().encode(), "one.csv", 37.0, 1_000_000, channel="gyro_z")
    assert "--rate-hz" not in error_text(got.value) and "sampling rate of the record" in error_text(got.value)


# --- 2. bracketed units and UTF-16 through the library's readers ----------------------------------

@pytest.mark.parametrize("page,radio,uploader,prefix", LOG_PAGES)
def test_bracketed_units_and_utf16_logs_are_read_and_a_refused_unit_is_one_line(page, radio, uploader, prefix):
    at = _app(page)
    _upload(at, radio, uploader, "brackets.csv", _log().encode("utf-16"))
    assert not _errors(at)
    shown = " ".join(m.value for m in at.markdown) + " ".join(c.value for c in at.caption)
    assert "brackets.csv" in shown and "3000 samples at 100 Hz" in shown, shown
    for header, said in (("time [s],gyro_x [m/s^2],gyro_z [deg/s]", "row 1, field gyro_x [m/s^2]: "),
                         ("time [s],gyro_x_dps [rad/s],gyro_z [deg/s]", "row 1, field gyro_x_dps [rad/s]: "),
                         ("time [fortnight],gyro_x [deg/s],gyro_z [deg/s]", "time unit 'fortnight' not understood")):
        at.file_uploader(key=uploader).set_value(("badunit.csv", _log(header, 200).encode(), "text/csv")).run()
        assert said in _one_line(at, "badunit.csv")


# --- 3. motion runs refused for their memory ------------------------------------------------------

def test_a_motion_run_refused_for_its_memory_is_one_line_and_leaves_no_bar(monkeypatch):
    import budget.motion.cost as cost

    monkeypatch.setattr(cost, "MAX_WORKING_BYTES", 1000)
    at = _app("pages/monte_carlo.py")
    at.number_input(key="mc_trials").set_value(3).run()
    at.number_input(key="mc_seed").set_value(70_707).run()  # not cached by another test
    at.button(key="mc_run").click().run()
    text = _errors(at)
    assert len(text) == 1 and "a motion run may use" in text[0] and "\n" not in text[0], text
    assert text[0].startswith("Monte Carlo of scenario airborne_xband")
    assert not at.get("progress")
    at.switch_page("pages/sweep.py").run()
    at.multiselect(key="sw_parts").set_value(["STIM300"]).run()
    at.number_input(key="sw_trials").set_value(3).run()
    at.number_input(key="sw_seed").set_value(70_707).run()
    at.button(key="sw_run_grid").click().run()
    text = _errors(at)
    assert len(text) == 1 and text[0].startswith("Sweep of scenarios airborne_xband") and "a motion run may use" in text[0]
    assert not at.get("progress")
    assert at.button(key="sw_run_line")  # the rest of the page is still drawn


# --- 4. every page, default inputs and bad uploads ------------------------------------------------

def test_every_page_with_its_default_inputs():
    from page_registry import available

    at = _app()
    for entry in available():
        at.switch_page(entry.path).run()
        assert not at.exception, (entry.path, [e.value for e in at.exception])
        assert not at.error, (entry.path, [e.value for e in at.error])


NAN_LOG = "time_s,gyro_x_dps,gyro_z_dps\n" + "".join(f"{i / 100:.2f},nan,{(i % 7) * 1e-3:g}\n" for i in range(500))
BAD_CSV = {"malformed.csv": b'time_s,gyro_x_dps\n1,"2\n3,4,5,6\n\x00\x01', "empty.csv": b"",
           "nan_column.csv": NAN_LOG.encode()}


@pytest.mark.parametrize("page,radio,uploader,prefix", LOG_PAGES)
def test_bad_log_uploads_are_one_line(page, radio, uploader, prefix):
    at = _app(page)
    for name, data in BAD_CSV.items():
        _upload(at, radio, uploader, name, data)
        _one_line(at, name)


def test_bad_catalog_uploads_are_one_line():
    at = _app("pages/catalog.py")
    bad = dict(BAD_CSV, **{"nan_column.csv": b"part_id,grade,source,gyro_arw_deg_rt_h\nMY_IMU,tactical,me,nan\n"})
    for name, data in bad.items():
        at.file_uploader(key="cat_upload").set_value((name, data, "text/csv")).run()
        text = _one_line(at, name)
        assert "nothing was merged" in text
    assert "gyro_arw_deg_rt_h" in text  # the NaN cell's column is named


def test_bad_scenario_and_model_uploads_are_one_line():
    from budget.presets import get_preset

    scenario = json.loads(get_preset("airborne_xband").model_dump_json())
    scenario["slant_range_m"] = float("nan")
    at = _app("pages/scenario.py")
    for name, data in {"malformed.json": b'{"slant_range_m": ', "empty.json": b"",
                       "nan.json": json.dumps(scenario).encode()}.items():
        at.file_uploader(key="scn_upload").set_value((name, data, "application/json")).run()
        text = _one_line(at, name)
    assert "slant_range_m" in text and "finite" in text
    at = _app("pages/model_gap.py")
    at.radio(key="gap_model_kind").set_value("noise-model JSON").run()
    for name, data in {"malformed.json": b'{"gyro_arw_deg_rt_h": ', "empty.json": b"",
                       "nan.json": b'{"gyro_arw_deg_rt_h": NaN}'}.items():
        at.file_uploader(key="gap_model_upload").set_value((name, data, "application/json")).run()
        text = _one_line(at, name)
    assert "gyro_arw_deg_rt_h" in text and "finite" in text


def test_bad_phase_history_uploads_are_one_line():
    at = _app("pages/focus.py")
    at.radio(key="focus_source").set_value(at.radio(key="focus_source").options[1]).run()
    for name, data in {"malformed.mat": b"MATLAB 5.0 MAT-file, garbage" * 8, "empty.mat": b""}.items():
        at.file_uploader(key="focus_upload").set_value([(name, data, "application/octet-stream")]).run()
        at.button(key="focus_run").click().run()
        assert "MATLAB" in _one_line(at, name)
