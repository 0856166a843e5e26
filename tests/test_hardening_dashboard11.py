"""Dashboard, Model gap page: an uploaded Allan curve with no record behind it (a digitised
datasheet curve) is refused as the library refuses it, in the dashboard's words — it used to be
read with the page's default rate and length (100 Hz, 10⁶ samples), a record nobody had."""

from __future__ import annotations

import numpy as np

from app_harness import open_app

from budget.errors import GAP_RECORD_WAY, NOISE_ALONE_WAY

OPTION = "--"


def _datasheet_curve() -> str:
    """Six points read off a datasheet figure (ARW 0.3 deg/√h, a 3.3 deg/h floor), no rate."""
    tau = np.array([0.01, 0.1, 1.0, 10.0, 100.0, 1000.0])
    sigma = np.hypot(0.3 * 60.0 / np.sqrt(tau), 3.32)
    return "tau (s),sigma (deg/h)\n" + "".join(f"{t:g},{s:.6g}\n" for t, s in zip(tau, sigma))


def _page_with_curve():
    at = open_app("pages/model_gap.py")
    source = at.radio(key="gap_source")
    source.set_value(source.options[1]).run()
    at.file_uploader(key="gap_upload").set_value(("datasheet.csv", _datasheet_curve().encode(), "text/csv")).run()
    at.selectbox(key="gap_curve_channel").set_value("gyro_z").run()
    return at


def test_a_digitised_curve_is_refused_in_the_dashboards_words():
    at = _page_with_curve()
    record = at.radio(key="gap_adev_record")
    assert record.value == record.options[0]  # known by default: the rate and length are asked for
    record.set_value(record.options[1]).run()
    assert not [n for n in at.number_input if n.key in ("gap_adev_rate", "gap_adev_samples")]
    at.button(key="gap_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    errors = [str(e.value) for e in at.error]
    assert any("digitised Allan curve" in e for e in errors), errors
    said = next(e for e in errors if "digitised Allan curve" in e)
    assert GAP_RECORD_WAY.dashboard in said and OPTION not in said


def test_the_ways_out_have_dashboard_words_without_options():
    for way in (GAP_RECORD_WAY, NOISE_ALONE_WAY):
        assert way.cli != way.dashboard and OPTION not in way.dashboard and "sar-budget" not in way.dashboard
