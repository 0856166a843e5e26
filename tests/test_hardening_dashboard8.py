"""Dashboard messages name what the page offers (``AppTest``, inputs in memory):

* the library's ways out of a refusal (repair a log, give a rate, leave channels out, use fewer
  workers …) are said once, in ``budget.errors.WAYS``, for the CLI and for the dashboard; the
  dashboard shows them through ``describe_error(err, interface="dashboard")`` — never a Python
  argument or a command-line option the page does not have;
* the model-gap page reads a log repaired on request and compares the channels picked, the
  inputs its messages name;
* a scenario upload's error does not outlive the upload (another page, an empty uploader);
* the trade study names the scenario(s) and parts of a refused sweep, as Monte Carlo does.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import budget.errors as errors
from app_harness import REPO, AppTest, open_app as _app, page_errors as _errors
from budget.errors import WAYS, InputError, describe_error, in_words_of

UPLOAD = "upload a log or an Allan table"
#: A Python argument (``repair=True``, ``channels=``) or a command-line option (``--repair``).
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z-]+|\b[a-z_]+=(True|False|\[|/| )")


def _one_line(at: AppTest, start: str) -> str:
    got = _errors(at)
    assert len(got) == 1 and "\n" not in got[0] and got[0].startswith(start), got
    assert not OPTION.search(got[0]), got[0]  # nothing the dashboard has no input for
    return got[0]


def _log(n: int = 3000, rate: float = 100.0, nan_rows=(), header="time_s,gyro_z_dps,accel_x_mps2") -> bytes:
    rng = np.random.default_rng(8)
    rows = rng.normal(0.0, 1e-2, (n, 2)) + (0.0, 9.81)
    rows[list(nan_rows), 0] = np.nan
    return (header + "\n" + "".join(f"{i / rate:.4f},{a:.6g},{b:.6g}\n" for i, (a, b) in enumerate(rows))).encode()


def _upload(at: AppTest, radio: str, uploader: str, name: str, data: bytes) -> None:
    at.radio(key=radio).set_value(UPLOAD).run()
    at.file_uploader(key=uploader).set_value((name, data, "text/csv")).run()


# --- 1. the ways out, one home ---------------------------------------------------------------------

def test_every_way_is_said_for_each_interface_and_used_by_the_library():
    source = "\n".join(p.read_text(encoding="utf-8") for p in (REPO / "budget").rglob("*.py")
                       if p.name != "errors.py")
    names = [n for n, v in vars(errors).items() if isinstance(v, errors.Way)]
    assert len(names) == len(WAYS)
    for name in names:
        way = getattr(errors, name)
        assert f"{name}.cli" in source, f"{name} is named by no library message"
        assert not OPTION.search(way.dashboard), way
        assert in_words_of(way.cli, "dashboard") == way.dashboard  # no other way rewrites it
        assert in_words_of(way.cli) == way.cli  # the CLI's words are the library's
    with pytest.raises(ValueError, match="interface"):
        in_words_of("x", "browser")
    err = InputError("problem", expected=f"a time_s column{errors.LOG_RATE_WAY.cli}")
    assert describe_error(err).text == str(err)  # the CLI's boundary is unchanged
    assert "--rate-hz" in str(err) and "--rate-hz" not in describe_error(err, "dashboard").text


def test_the_repair_box_the_message_names_is_on_both_log_pages():
    from uploads import REPAIR_LABEL

    quoted = re.search(r"'([^']+)'", errors.REPAIR_WAY.dashboard).group(1)
    assert REPAIR_LABEL.startswith(quoted)
    for page, prefix in (("pages/noise_lab.py", "noise"), ("pages/model_gap.py", "gap")):
        at = _app(page)
        _upload(at, f"{prefix}_source", f"{prefix}_upload", "ok.csv", _log(400))
        assert at.checkbox(key=f"{prefix}_repair").label == REPAIR_LABEL


# --- 2. a log's problems: the page's tick box, on both pages --------------------------------------

@pytest.mark.parametrize("page,prefix", [("pages/noise_lab.py", "noise"), ("pages/model_gap.py", "gap")])
def test_a_log_with_gaps_points_to_the_pages_repair_box(page, prefix):
    at = _app(page)
    if prefix == "gap":
        at.radio(key="gap_model_kind").set_value("noise-model JSON").run()
        at.file_uploader(key="gap_model_upload").set_value(
            ("arw.json", b'{"gyro_arw_deg_rt_h": 0.1, "accel_vrw_m_s_rt_h": 0.05}', "application/json")).run()
    _upload(at, f"{prefix}_source", f"{prefix}_upload", "gaps.csv", _log(3000, nan_rows=(100, 101, 900)))
    text = _one_line(at, "gaps.csv")
    assert "tick 'repair the log' beside the upload" in text and "CLI" not in text, text
    at.checkbox(key=f"{prefix}_repair").check().run()
    assert not _errors(at)
    shown = " ".join(m.value for m in at.markdown) + " ".join(c.value for c in at.caption)
    assert "gaps.csv" in shown and "samples at 100 Hz" in shown, shown


def test_a_log_without_a_readable_time_column_names_no_rate_option():
    at = _app("pages/noise_lab.py")
    _upload(at, "noise_source", "noise_upload", "fortnight.csv",
            _log(300, header="time [fortnight],gyro_z_dps,accel_x_mps2"))
    text = _one_line(at, "fortnight.csv")
    assert "time unit 'fortnight' not understood" in text
    assert "--mapping" not in text and "rate_hz" not in text
    assert "'sampling rate (Hz)' under 'column mapping and sampling rate'" in text  # the page's input
    # a low rate (ms read as s?) is refused until confirmed: the error says how to write the
    # unit or confirm the rate with the page's input, not --rate-hz
    _upload(at, "noise_source", "noise_upload", "slow.csv", _log(300, rate=0.5))
    text = _one_line(at, "slow.csv")
    assert "time stamps give 0.5 Hz" in text and "time [ms]" in text and "'sampling rate (Hz)'" in text


def test_an_allan_tables_messages_name_the_inputs_beside_the_upload():
    from upload_tables import read_uploaded_adev
    from uploads import error_text

    curve = "tau [s], adev (deg/h)\n" + "".join(f"{0.01 * 2 ** k:.6g},{20 / np.sqrt(0.01 * 2 ** k) + 2:.6g}\n"
                                               for k in range(12))
    with pytest.raises(InputError) as got:
        read_uploaded_adev(curve.encode(), "one.csv", 100.0, 1_000_000, channel=None)
    assert "--channels gyro_z" in str(got.value)  # the library's own words …
    text = error_text(got.value)  # … said for the dashboard
    assert text.startswith("one.csv, row 1, field channel:") and "'channel of this curve'" in text
    assert not OPTION.search(text), text
    with pytest.raises(InputError) as got:
        read_uploaded_adev(curve.encode(), "one.csv", 37.0, 1_000_000, channel="gyro_z")
    text = error_text(got.value)
    assert "sampling rate of the record" in text and not OPTION.search(text), text


# --- 3. model gap: the channels compared ----------------------------------------------------------

def test_a_channel_the_model_gives_no_random_term_is_left_out_on_the_page():
    at = _app("pages/model_gap.py")
    at.radio(key="gap_model_kind").set_value("noise-model JSON").run()
    model = (b'{"gyro_arw_deg_rt_h": 0.1, '  # accel_x: a deterministic ramp only, no random term
             b'"effects": [{"name": "rate_ramp", "channel": "accel_x", "params": {"R": 1e-6}}]}')
    at.file_uploader(key="gap_model_upload").set_value(("ramp.json", model, "application/json")).run()
    _upload(at, "gap_source", "gap_upload", "log.csv", _log(5000))
    assert not _errors(at)
    at.number_input(key="gap_realizations").set_value(4).run()
    at.button(key="gap_run").click().run()
    text = _one_line(at, "log.csv")
    assert "no noise term for accel_x" in text and "pick them in 'channels compared' on the page" in text, text
    box = at.multiselect(key="gap_channels_gyro_z-accel_x")
    assert box.label == "channels compared" and list(box.value) == ["gyro_z", "accel_x"]
    box.set_value(["gyro_z"]).run()
    at.button(key="gap_run").click().run()
    assert not _errors(at)
    assert [m for m in at.markdown if "effect(s) named" in m.value]
    at.multiselect(key="gap_channels_gyro_z-accel_x").set_value([]).run()
    assert any("Pick at least one channel of log.csv" in i.value for i in at.info)


# --- 4. motion memory: no workers on the dashboard; the refused sweep names its scenario ----------

def test_a_refused_motion_run_names_the_scenario_and_no_workers(monkeypatch):
    import budget.motion.cost as cost

    monkeypatch.setattr(cost, "MAX_WORKING_BYTES", 1000)
    at = _app("pages/monte_carlo.py")
    at.number_input(key="mc_trials").set_value(3).run()
    at.number_input(key="mc_seed").set_value(80_808).run()
    at.button(key="mc_run").click().run()
    text = _one_line(at, "Monte Carlo of scenario airborne_xband (fields from preset airborne_xband) for ")
    assert "workers" not in text and "a lower imu rate (Hz) in the sidebar's scenario fields" in text, text
    at.switch_page("pages/sweep.py").run()
    at.multiselect(key="sw_parts").set_value(["STIM300"]).run()
    at.number_input(key="sw_trials").set_value(3).run()
    at.number_input(key="sw_seed").set_value(80_808).run()
    at.button(key="sw_run_grid").click().run()
    text = _one_line(at, "Sweep of scenarios airborne_xband (fields from preset airborne_xband), "
                         "automotive_77ghz for STIM300 not run: ")
    assert "workers" not in text and "a motion run may use" in text
    assert not at.get("progress")
    at.button(key="sw_run_line").click().run()
    _one_line(at, "Sweep over slant_range_m of scenario airborne_xband (fields from preset airborne_xband) "
                  "for STIM300 not run: ")


# --- 5. a scenario upload's error goes with the upload --------------------------------------------

def test_a_scenario_upload_error_does_not_outlive_the_upload():
    at = _app("pages/scenario.py")
    at.file_uploader(key="scn_upload").set_value(("bad.json", b'{"slant_range_m": ', "application/json")).run()
    assert _one_line(at, "bad.json").startswith("bad.json")
    at.switch_page("pages/monte_carlo.py").run()
    assert not _errors(at)
    at.switch_page("pages/scenario.py").run()
    assert not _errors(at)


def test_the_dashboard_shows_library_text_through_the_one_boundary():
    """No page prints an error's ``str`` (the CLI's words): every message passes ``error_text``."""
    pages = sorted((REPO / "app").rglob("*.py"))
    bare = [f"{p.name}:{i}" for p in pages for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
            if re.search(r"st\.(error|warning|info)\(str\(err", line)]
    assert not bare, bare
    app_text = "\n".join(p.read_text(encoding="utf-8") for p in pages)
    copies = [w.dashboard for w in WAYS if w.dashboard and w.dashboard in app_text]
    assert not copies, copies  # the dashboard's words live with the library's, once
