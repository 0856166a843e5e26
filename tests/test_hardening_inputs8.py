"""Log time columns and header units users actually have.

1. A time column of clock text (``Time (UTC)``: ISO 8601 date-times with or without a zone, or
   times of day) is read as seconds from the first sample — midnight rollovers and UTC offsets
   included — and a mix or an unreadable stamp is refused naming its row and value.
2. Header units µg (U+00B5 and U+03BC), ug, mg, mdps, mdeg/s are read; a noise density
   (µg/√Hz) is refused as no sample's unit.
3. A mapping reaches a time column whose header carries a bracketed unit (``timestamp [ns]``,
   ``t [ms]``): by its full name, its name without the unit, or the target ``time``.

Every log is written the way a logger or exporter writes it, in tmp_path; the expectations come
from the values written (rate, σ of the white noise: a sample variance within the χ² band of its
sample size).
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from scipy.stats import chi2

from budget.cli.main import main
from budget.errors import InputError
from budget.noise.log_mapping import LogMapping
from budget.noise.logs import read_log
from budget.units import DEG, G0

RATE = 400.0
N = 6000
SIGMA_DPS = 0.1           # white gyro noise written, deg/s
T0 = pd.Timestamp("2026-03-01T12:00:00")


def _gyro(n=N, seed=8):
    return np.random.default_rng(seed).normal(0.0, SIGMA_DPS, (n, 3))


def _band(n, p=1e-7):
    """Ratio band of a sample variance (n samples, mean removed) to the true one."""
    return chi2.ppf(p, n - 1) / (n - 1), chi2.ppf(1 - p, n - 1) / (n - 1)


def _assert_white(x_si, sigma_si, rate_read):
    """The noise density σ/√rate of ``x_si`` read at ``rate_read`` matches the one written, within
    the χ² band of the sample size (and the rate read is the rate written, 1e-6)."""
    assert rate_read == pytest.approx(RATE, rel=1e-6)
    lo, hi = _band(x_si.size)
    ratio = (np.var(x_si, ddof=1) / rate_read) / (sigma_si**2 / RATE)
    assert lo < ratio < hi


def _write(path, time_header, stamps, gyro, units="deg/s", extra=None):
    cols = {time_header: stamps}
    cols |= {f"gyro_{a} [{units}]": gyro[:, i] for i, a in enumerate("xyz")}
    cols |= extra or {}
    pd.DataFrame(cols).to_csv(path, index=False)
    return path


def _times(n=N, rate=RATE, start=T0):
    return start + pd.to_timedelta(np.arange(n) * round(1e9 / rate), unit="ns")


def _notes(log, kind="clock_time"):
    return [i for i in log.issues.issues if i.kind == kind]


# --- 1. clock text --------------------------------------------------------------------------


ISO_FORMATS = {
    # a logger writing UTC with a Z, microseconds
    "iso_z": lambda t: t.strftime("%Y-%m-%dT%H:%M:%S.%f") + "Z",
    # a spreadsheet export: a space, milliseconds, no zone
    "iso_space_ms": lambda t: t.strftime("%Y-%m-%d %H:%M:%S.%f").str[:-3],
    # a local clock with its UTC offset
    "iso_offset": lambda t: (t + pd.Timedelta(hours=1)).strftime("%Y-%m-%dT%H:%M:%S.%f").str[:-3] + "+01:00",
    # time of day only, milliseconds
    "time_of_day": lambda t: t.strftime("%H:%M:%S.%f").str[:-3],
}


@pytest.mark.parametrize("style", list(ISO_FORMATS))
def test_clock_text_reads_as_seconds_at_the_written_rate(tmp_path, style):
    g = _gyro()
    path = _write(tmp_path / f"{style}.csv", "Time (UTC)", ISO_FORMATS[style](_times()), g)
    log = read_log(path)
    _assert_white(log.channels["gyro_x"], SIGMA_DPS * DEG, log.rate_hz)
    assert log.time_s[0] == 0.0
    # stamps written to the ms at 2.5 ms steps: within half a ms of the grid
    assert np.max(np.abs(log.time_s - np.arange(N) / RATE)) <= 0.5e-3 + 1e-9
    (note,) = _notes(log)
    assert note.severity == "info" and note.column == "Time (UTC)" and "clock text" in note.message
    assert not log.issues.errors


def test_plain_time_header_with_clock_text_and_gzip(tmp_path):
    g = _gyro()
    path = tmp_path / "log.csv.gz"
    cols = {"timestamp": ISO_FORMATS["iso_z"](_times())}
    cols |= {f"gyro_{a}_dps": g[:, i] for i, a in enumerate("xyz")}
    pd.DataFrame(cols).to_csv(path, index=False, compression="gzip")
    log = read_log(path)
    _assert_white(log.channels["gyro_z"], SIGMA_DPS * DEG, log.rate_hz)
    assert _notes(log)


def test_time_of_day_rollover_at_midnight_across_chunks(tmp_path):
    n, rate = 3000, 100.0
    t = _times(n, rate, pd.Timestamp("2026-03-01T23:59:50"))  # midnight at row 1000 + 2
    g = _gyro(n)
    path = _write(tmp_path / "midnight.csv", "Time", t.strftime("%H:%M:%S.%f").str[:-4], g)
    for chunk_rows in (250_000, 700, 1000):  # the rollover inside a chunk, at a chunk's start
        log = read_log(path, chunk_rows=chunk_rows)
        assert log.rate_hz == 100.0
        np.testing.assert_allclose(log.time_s, np.arange(n) / rate, atol=1e-9)
        (note,) = _notes(log)
        assert "1 midnight rollover" in note.message
        assert not log.issues.errors


def test_utc_offsets_change_within_the_log(tmp_path):
    """Local clock text with its offset across a daylight-saving change (01:59:59+01:00 is followed
    by 03:00:00+02:00): converted to UTC the stamps go on evenly — no gap of an hour."""
    n, rate = 2000, 100.0
    utc = _times(n, rate, pd.Timestamp("2026-03-29T00:59:55"))
    local = utc.tz_localize("UTC").tz_convert("Europe/Berlin")
    text = [ts.isoformat(timespec="milliseconds") for ts in local]
    assert text[0].endswith("+01:00") and text[-1].endswith("+02:00")
    path = _write(tmp_path / "dst.csv", "Time (local)", text, _gyro(n))
    log = read_log(path)
    assert log.rate_hz == 100.0
    np.testing.assert_allclose(log.time_s, np.arange(n) / rate, atol=1e-9)
    assert not [i for i in log.issues.issues if i.kind == "gap"]


def test_numeric_time_column_wins_over_clock_text(tmp_path):
    g = _gyro()
    path = _write(tmp_path / "both.csv", "time_s", np.arange(N) / RATE, g,
                  extra={"Time (UTC)": ISO_FORMATS["iso_z"](_times(start=T0 + pd.Timedelta(days=3)))})
    log = read_log(path)
    assert log.rate_hz == RATE and not _notes(log)
    assert [i.column for i in log.issues.issues if i.kind == "ignored_column"] == ["Time (UTC)"]


def _with_cell(path, row, value):
    """Replace the time cell of file row ``row`` (header = row 1) by ``value``."""
    lines = path.read_text().splitlines()
    rest = lines[row - 1].split(",", 1)[1]
    lines[row - 1] = f"{value},{rest}"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("style, bad, why", [
    ("iso_z", "2026-03-01T12:00:05.000", "without a time zone among ISO 8601 date-times with a time zone"),
    ("iso_space_ms", "2026-03-01T12:00:05.000Z", "with a time zone among ISO 8601 date-times without"),
    ("iso_z", "12:00:05.000", "times of day among"),
    ("time_of_day", "01/03/2026 12:00:05", "not clock text"),
    ("time_of_day", "25:00:00.000", "not clock text"),
    ("time_of_day", "43205.0", "not clock text"),
    ("iso_space_ms", "2026-02-30 12:00:05.000", "not a valid date"),
])
def test_mixed_or_unreadable_clock_text_is_refused_with_row_and_value(tmp_path, style, bad, why):
    path = _write(tmp_path / "bad.csv", "Time (UTC)", ISO_FORMATS[style](_times()), _gyro())
    row = 2 + 2345
    _with_cell(path, row, bad)
    for chunk_rows in (250_000, 1000):
        with pytest.raises(InputError) as err:
            read_log(path, chunk_rows=chunk_rows)
        text = str(err.value)
        assert str(path) in text and f"row {row}" in text and "Time (UTC)" in text
        assert repr(bad) in text and why in text and "expected" in text


def test_first_cell_decides_and_a_bad_first_stamp_is_named(tmp_path):
    path = _write(tmp_path / "first.csv", "Time (UTC)", ISO_FORMATS["iso_z"](_times()), _gyro())
    text = path.read_text().replace("2026-03-01T12:00:00.002500Z", "2026-3-1 12:00", 1)
    path.write_text(text)
    with pytest.raises(InputError, match=r"row 3, field Time \(UTC\).*not clock text.*'2026-3-1 12:00'"):
        read_log(path)


def test_empty_stamp_is_a_missing_time_repaired_on_request(tmp_path):
    path = _write(tmp_path / "hole.csv", "Time (UTC)", ISO_FORMATS["iso_z"](_times()), _gyro())
    _with_cell(path, 500, "")
    with pytest.raises(InputError, match="row"):
        read_log(path)
    log = read_log(path, repair=True)
    assert log.rate_hz == pytest.approx(RATE, rel=1e-6) and log.issues.repairs


def test_clock_text_in_a_seconds_column_says_how_it_is_read(tmp_path):
    path = _write(tmp_path / "s.csv", "time_s", ISO_FORMATS["time_of_day"](_times()), _gyro())
    with pytest.raises(InputError, match=r"row 2, field time_s.*not a number.*clock text is read"):
        read_log(path)


def test_two_clock_columns_need_a_mapping(tmp_path):
    g = _gyro()
    path = _write(tmp_path / "two.csv", "Time (UTC)", ISO_FORMATS["iso_z"](_times()), g,
                  extra={"Time (local)": ISO_FORMATS["iso_offset"](_times())})
    with pytest.raises(InputError, match=r"clock text: which is the time.*\"time\""):
        read_log(path)
    log = read_log(path, LogMapping(columns={"Time (local)": "time"}))
    assert log.rate_hz == pytest.approx(RATE, rel=1e-6)
    assert _notes(log)[0].column == "Time (local)"


def test_mapping_sends_a_clock_column_of_any_name_to_time(tmp_path):
    path = _write(tmp_path / "zeit.csv", "Zeit (UTC)", ISO_FORMATS["iso_z"](_times()), _gyro())
    with pytest.raises(InputError, match="no time column"):
        read_log(path)
    log = read_log(path, LogMapping(columns={"Zeit (UTC)": "time"}))
    _assert_white(log.channels["gyro_y"], SIGMA_DPS * DEG, log.rate_hz)


def test_mapping_to_time_without_unit_or_clock_text_is_refused(tmp_path):
    path = _write(tmp_path / "n.csv", "stamp", np.arange(N) / RATE, _gyro())
    with pytest.raises(InputError, match=r"field stamp.*mapped to time.*no time unit"):
        read_log(path, LogMapping(columns={"stamp": "time"}))


# --- 2. header units ------------------------------------------------------------------------


@pytest.mark.parametrize("gyro_unit, per_dps", [("mdps", 1e3), ("mdeg/s", 1e3), ("m°/s", 1e3),
                                                ("deg/s", 1.0)])
@pytest.mark.parametrize("accel_unit, per_g", [("µg", 1e6), ("μg", 1e6), ("ug", 1e6), ("uG", 1e6),
                                               ("mg", 1e3)])
def test_milli_and_micro_units_in_headers(tmp_path, gyro_unit, per_dps, accel_unit, per_g):
    assert "\u00b5" in "µg" and "\u03bc" in "μg"  # the micro sign and the Greek mu
    n = 4000
    rng = np.random.default_rng(3)
    g = rng.normal(0.0, SIGMA_DPS, (n, 3))
    sigma_g = 200e-6
    a = rng.normal(0.0, sigma_g, (n, 3)) + np.array([0.0, 0.0, 1.0])  # 1 g on z
    cols = {"time [s]": np.arange(n) / RATE}
    cols |= {f"gyro_{x} [{gyro_unit}]": g[:, i] * per_dps for i, x in enumerate("xyz")}
    cols |= {f"acc_{x} [{accel_unit}]": a[:, i] * per_g for i, x in enumerate("xyz")}
    path = tmp_path / "u.csv"
    pd.DataFrame(cols).to_csv(path, index=False, encoding="utf-8")
    log = read_log(path)
    _assert_white(log.channels["gyro_x"], SIGMA_DPS * DEG, log.rate_hz)
    _assert_white(log.channels["accel_x"], sigma_g * G0, log.rate_hz)
    assert np.mean(log.channels["accel_z"]) == pytest.approx(G0, rel=1e-3)
    assert log.source_units["gyro_x"] == ("dps" if per_dps == 1 else "mdps")
    assert log.source_units["accel_z"] == ("ug" if per_g == 1e6 else "mg")


def test_unit_tags_in_canonical_names(tmp_path):
    n = 4000
    rng = np.random.default_rng(4)
    cols = {"time_s": np.arange(n) / RATE, "gyro_x_mdps": rng.normal(0, 100.0, n),
            "accel_z_ug": rng.normal(1e6, 200.0, n)}
    path = tmp_path / "tags.csv"
    pd.DataFrame(cols).to_csv(path, index=False)
    log = read_log(path)
    _assert_white(log.channels["gyro_x"], 0.1 * DEG, log.rate_hz)
    _assert_white(log.channels["accel_z"], 200e-6 * G0, log.rate_hz)


@pytest.mark.parametrize("column", ["acc_x [µg/√Hz]", "acc_x [ug/rtHz]", "gyro_x [deg/√h]",
                                    "gyro_x [mdps/sqrt(Hz)]"])
def test_noise_density_unit_is_no_sample_unit(tmp_path, column):
    path = tmp_path / "d.csv"
    pd.DataFrame({"time_s": np.arange(10) / RATE, column: np.zeros(10) + 1e-3}).to_csv(path, index=False)
    with pytest.raises(InputError) as err:
        read_log(path)
    text = str(err.value)
    assert str(path) in text and "row 1" in text and column in text
    assert "noise density" in text and "accepted:" in text


def test_a_gyro_unit_on_an_accelerometer_is_refused(tmp_path):
    path = tmp_path / "w.csv"
    pd.DataFrame({"time_s": np.arange(10) / RATE, "accel_x [mdps]": np.zeros(10)}).to_csv(path, index=False)
    with pytest.raises(InputError, match=r"row 1, field accel_x \[mdps\].*not understood for accel_x"):
        read_log(path)


# --- 3. a mapping to a time column with a bracketed unit ------------------------------------


def _logger_log(tmp_path, time_header, stamps):
    """A logger's layout: its own sensor names with units in brackets."""
    g = _gyro()
    cols = {time_header: stamps} | {f"Gyr{a.upper()} [deg/s]": g[:, i] for i, a in enumerate("xyz")}
    path = tmp_path / "logger.csv"
    pd.DataFrame(cols).to_csv(path, index=False)
    return path


GYROS = {f"Gyr{a.upper()} [deg/s]": f"gyro_{a}_dps" for a in "xyz"}
NS = (1_772_366_400 * 10**9 + np.arange(N) * 2_500_000).astype(np.int64)  # epoch ns at 400 Hz


@pytest.mark.parametrize("header, stamps, key, target", [
    ("timestamp [ns]", NS, "timestamp [ns]", "time"),
    ("timestamp [ns]", NS, "timestamp", "time_ns"),
    ("timestamp [ns]", NS, "timestamp", "time"),
    ("t [ms]", np.arange(N) * 2.5, "t [ms]", "time"),
    ("t [ms]", np.arange(N) * 2.5, "t", "time_ms"),
    ("t [ms]", np.arange(N) * 2.5, "t [ms]", "time [ms]"),
    ("sensor time (us)", np.arange(N) * 2500, "sensor time (us)", "time"),
])
def test_mapping_reaches_a_time_column_with_a_bracketed_unit(tmp_path, header, stamps, key, target):
    path = _logger_log(tmp_path, header, stamps)
    log = read_log(path, LogMapping(columns={key: target} | GYROS))
    _assert_white(log.channels["gyro_x"], SIGMA_DPS * DEG, log.rate_hz)
    assert log.time_s[-1] - log.time_s[0] == pytest.approx((N - 1) / RATE, rel=1e-6)


@pytest.mark.parametrize("key, target", [("t [ms]", "time_s"), ("t", "time_ns"), ("t [ms]", "time [s]")])
def test_mapping_time_unit_that_contradicts_the_header_is_refused(tmp_path, key, target):
    path = _logger_log(tmp_path, "t [ms]", np.arange(N) * 2.5)
    with pytest.raises(InputError, match=r"row 1, field t \[ms\].*two units disagree"):
        read_log(path, LogMapping(columns={key: target} | GYROS))


def test_mapping_key_naming_two_columns_is_refused(tmp_path):
    path = _logger_log(tmp_path, "t [ms]", np.arange(N) * 2.5)
    df = pd.read_csv(path)
    df["t [s]"] = df["t [ms]"] / 1e3
    df.to_csv(path, index=False)
    with pytest.raises(InputError, match=r"'t' is the name of 2 columns.*map the full name"):
        read_log(path, LogMapping(columns={"t": "time_ms"} | GYROS))


def test_mapping_target_with_unknown_time_unit_is_refused_when_loaded(tmp_path):
    mp = tmp_path / "map.json"
    mp.write_text(json.dumps({"columns": {"t [ms]": "time [fortnight]"}}))
    with pytest.raises(InputError, match="fortnight"):
        LogMapping.load(mp)


# --- the CLI --------------------------------------------------------------------------------


def test_cli_reads_clock_text_and_mapped_time(tmp_path, capsys):
    path = _write(tmp_path / "iso.csv", "Time (UTC)", ISO_FORMATS["iso_z"](_times()), _gyro())
    assert main(["noise", "characterize", str(path)]) == 0
    out = capsys.readouterr().out
    assert "rate 400 Hz" in out and "time read from the clock text of 'Time (UTC)'" in out

    logger = _logger_log(tmp_path, "timestamp [ns]", NS)
    mp = tmp_path / "map.json"
    mp.write_text(json.dumps({"columns": {"timestamp": "time"} | GYROS}))
    assert main(["noise", "characterize", str(logger), "--mapping", str(mp), "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["part"]["rate_hz"] == pytest.approx(RATE, rel=1e-6)


def test_cli_refuses_bad_clock_text_without_a_traceback(tmp_path, capsys):
    path = _write(tmp_path / "bad.csv", "Time (UTC)", ISO_FORMATS["iso_z"](_times()), _gyro())
    _with_cell(path, 100, "12:00:00.250")
    assert main(["noise", "characterize", str(path)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert all(s in err for s in (str(path), "row 100", "Time (UTC)", "'12:00:00.250'", "expected"))


def test_cli_refuses_a_density_unit_without_a_traceback(tmp_path, capsys):
    path = tmp_path / "d.csv"
    cols = {"time_s": np.arange(100) / RATE, "acc_z [µg/√Hz]": np.ones(100)}
    pd.DataFrame(cols).to_csv(path, index=False)
    assert main(["noise", "characterize", str(path)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "noise density" in err and "acc_z [µg/√Hz]" in err
