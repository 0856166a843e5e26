"""Dashboard: the noise lab's catalog entry offers what its messages name — keep the spikes, the grade.

A characterisation replaces isolated spikes that would decide the short-τ Allan deviation and says
how to keep them; the dashboard says it as its own tick box (not a CLI option) and the box keeps
them. The grade of the catalog row is inferred unless the user picks one.
"""

from __future__ import annotations

import numpy as np
import pytest

from app_harness import open_app

from budget.catalog.schema import GRADES

UPLOAD = "upload a log or an Allan table"


def _spiky_log(n: int = 6000, rate: float = 100.0) -> bytes:
    """White gyro noise (1e-3 deg/s) with 6 isolated spikes of 0.5 deg/s: they carry most of the
    sample-to-sample variance, so the fit replaces them by default."""
    rng = np.random.default_rng(21)
    gyro = rng.normal(0.0, 1e-3, n)
    gyro[np.linspace(500, n - 500, 6).astype(int)] += 0.5
    accel = 9.81 + rng.normal(0.0, 1e-3, n)
    lines = "".join(f"{i / rate:.4f},{g:.6g},{a:.6g}\n" for i, (g, a) in enumerate(zip(gyro, accel)))
    return ("time_s,gyro_z_dps,accel_z_mps2\n" + lines).encode()


def _row(at, column: str) -> str:
    """A value of the catalog row the page shows (its table of column → value)."""
    rows = next(d.value for d in at.dataframe if list(d.value.columns) == ["column", "value"]
                and "gyro_arw_deg_rt_h" in set(d.value["column"]))
    return rows.set_index("column").loc[column, "value"]


def _warnings(at) -> list[str]:
    assert not at.exception, [e.value for e in at.exception]
    return [w.value for w in at.warning]


@pytest.fixture(scope="module")
def page():
    at = open_app("pages/noise_lab.py")
    at.radio(key="noise_source").set_value(UPLOAD).run()
    at.file_uploader(key="noise_upload").set_value(("spiky.csv", _spiky_log(), "text/csv")).run()
    return at


def test_the_spike_warning_names_the_tick_box_and_the_box_keeps_them(page):
    replaced = [w for w in _warnings(page) if "isolated spike" in w]
    assert replaced and "tick 'keep spikes' to keep them" in replaced[0], _warnings(page)
    assert "--keep-spikes" not in replaced[0] and "keep_spikes=True" not in replaced[0]
    arw_replaced = float(_row(page, "gyro_arw_deg_rt_h"))
    page.checkbox(key="noise_keep_spikes").check().run()
    kept = [w for w in _warnings(page) if "isolated spike" in w]
    assert kept and "kept on request" in kept[0], kept
    # the spikes carry ≈ 6·0.5²/6000 = 2.5e-4 (deg/s)² against the noise's 1e-6: kept, they
    # raise the white-noise level ≈ 16× (3× is a safe floor for the fit over octave τ)
    assert float(_row(page, "gyro_arw_deg_rt_h")) > 3 * arw_replaced
    page.checkbox(key="noise_keep_spikes").uncheck().run()




def test_the_grade_is_inferred_unless_picked(page):
    inferred = _row(page, "grade")
    assert inferred in GRADES
    other = next(g for g in GRADES if g != inferred)
    page.selectbox(key="noise_grade").set_value(other).run()
    assert _row(page, "grade") == other and not page.exception
    page.selectbox(key="noise_grade").set_value("inferred").run()
    assert _row(page, "grade") == inferred


# --- a logger's log on the dashboard: the mapping and the rate the messages name -------------------

def _logger_log(n: int = 4000) -> bytes:
    """A logger's layout: its own column names, raw counts of a ±250 deg/s gyro (131 LSB per
    deg/s) and a ±2 g accelerometer (16384 LSB per g), no time column."""
    rng = np.random.default_rng(5)
    gyro = np.round(rng.normal(0.0, 60.0, n)).astype(int)
    accel = 16384 + np.round(rng.normal(0.0, 80.0, n)).astype(int)
    return ("GyroZ,AccZ\n" + "".join(f"{g},{a}\n" for g, a in zip(gyro, accel))).encode()


MAPPING = (b'{"columns": {"GyroZ": "gyro_z_dps", "AccZ": "accel_z_g"}, '
           b'"scale": {"GyroZ": 0.0076335877862595, "AccZ": 6.103515625e-05}}')


@pytest.mark.parametrize("page,prefix", [("pages/noise_lab.py", "noise"), ("pages/model_gap.py", "gap")])
def test_a_loggers_log_is_read_through_an_uploaded_mapping_and_rate(page, prefix):
    at = open_app(page)
    at.radio(key=f"{prefix}_source").set_value(UPLOAD).run()
    at.file_uploader(key=f"{prefix}_upload").set_value(("logger.csv", _logger_log(), "text/csv")).run()
    said = " ".join(e.value for e in at.error)
    assert "'column mapping' uploaded beside the log" in said and "--mapping" not in said, said
    at.file_uploader(key=f"{prefix}_mapping").set_value(("map.json", MAPPING, "application/json")).run()
    said = " ".join(e.value for e in at.error)
    assert "no time column" in said and "'sampling rate (Hz)'" in said and "--rate-hz" not in said, said
    at.number_input(key=f"{prefix}_rate_hz").set_value(200.0).run()
    assert not at.exception and not at.error, [e.value for e in at.error]
    shown = " ".join(m.value for m in (*at.markdown, *at.caption))
    assert "4000 samples at 200 Hz" in shown, shown


def test_a_bad_mapping_file_is_named_on_the_page():
    at = open_app("pages/noise_lab.py")
    at.radio(key="noise_source").set_value(UPLOAD).run()
    at.file_uploader(key="noise_upload").set_value(("logger.csv", _logger_log(), "text/csv")).run()
    bad = b'{"columns": {"GyroZ": "gyro_z_furlongs"}}'
    at.file_uploader(key="noise_mapping").set_value(("map.json", bad, "application/json")).run()
    said = [e.value for e in at.error]
    assert not at.exception and len(said) == 1, said
    assert said[0].startswith("map.json") and "GyroZ" in said[0] and "tmp" not in said[0], said
