"""IMU log reader: canonical and mapped layouts, units, chunked reading, every bad-log case."""

import gzip
import hashlib
import math

import numpy as np
import pytest

from budget.errors import InputError
from budget.noise import LogError, LogMapping, read_log
from budget.units import DEG, G0

HEADER = "time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"


def _rows(n, rate=100.0, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    data = rng.normal(size=(n, 6))
    return t, data


def _write(path, t, data, header=HEADER, fmt="%.9g"):
    lines = [header] + [",".join([f"{ti:.6f}"] + [fmt % v for v in row]) for ti, row in zip(t, data)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_canonical_log_units_and_rate(tmp_path):
    t, d = _rows(500)
    p = _write(tmp_path / "log.csv", t, d)
    log = read_log(p)
    assert log.rate_hz == 100.0 and log.n_samples == 500 and log.temp_c is None
    assert list(log.channels) == ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
    np.testing.assert_allclose(log.channels["gyro_y"], d[:, 1] * DEG, rtol=1e-8)
    np.testing.assert_allclose(log.channels["accel_z"], d[:, 5], rtol=1e-8)
    assert log.issues.issues == [] and log.issues.ok
    assert log.to_frame().shape == (500, 6)


def test_mapping_other_layout_units_and_time(tmp_path):
    t, d = _rows(300, rate=250.0)
    header = "ms,gx,gy,gz,ax,ay,az,T,status"
    lines = [header] + [",".join([f"{ti * 1e3:.4f}"] + [f"{v:.9g}" for v in row] + ["21.5", "0"])
                        for ti, row in zip(t, d)]
    p = tmp_path / "other.csv"
    p.write_text("\n".join(lines) + "\n")
    m = LogMapping(columns={"ms": "time_ms", "gx": "gyro_x_rps", "gy": "gyro_y_rps", "gz": "gyro_z_dph",
                            "ax": "accel_x_g", "ay": "accel_y_g", "az": "accel_z_mg", "T": "temp_c"})
    log = read_log(p, m)
    assert log.rate_hz == 250.0
    np.testing.assert_allclose(log.channels["gyro_x"], d[:, 0], rtol=1e-8)
    np.testing.assert_allclose(log.channels["gyro_z"], d[:, 2] * DEG / 3600, rtol=1e-8)
    np.testing.assert_allclose(log.channels["accel_y"], d[:, 4] * G0, rtol=1e-8)
    np.testing.assert_allclose(log.channels["accel_z"], d[:, 5] * G0 * 1e-3, rtol=1e-8)
    np.testing.assert_allclose(log.temp_c, 21.5)
    assert [i.kind for i in log.issues.issues] == ["ignored_column"]  # status reported, not read


def test_mapping_file_and_bad_target(tmp_path):
    f = tmp_path / "map.json"
    f.write_text('{"columns": {"gx": "gyro_x_deg"}}')
    with pytest.raises(InputError, match="gyro_x_deg"):
        LogMapping.load(f)
    f.write_text('{"columns": {"gx": "gyro_x_rps"}, "rate_hz": 50}')
    assert LogMapping.load(f).rate_hz == 50


def test_no_time_column_needs_rate(tmp_path):
    p = tmp_path / "notime.csv"
    p.write_text("gyro_z_dps\n" + "\n".join(str(v) for v in range(10)) + "\n")
    with pytest.raises(InputError, match="no time column"):
        read_log(p)
    log = read_log(p, rate_hz=50.0)
    assert log.rate_hz == 50.0 and log.time_s is None


def test_chunked_read_with_growth_equals_single_read(tmp_path):
    t, d = _rows(2345)
    p = tmp_path / "log.csv.gz"
    with gzip.open(p, "wt") as fh:
        fh.write(HEADER + "\n" + "\n".join(",".join([f"{a:.6f}"] + [f"{v:.9g}" for v in r])
                                           for a, r in zip(t, d)) + "\n")
    whole = read_log(p)
    small = read_log(p, chunk_rows=100)  # many chunks; estimate-then-grow path
    for ch in whole.channels:
        np.testing.assert_array_equal(whole.channels[ch], small.channels[ch])
    assert read_log(p, max_rows=1000).n_samples == 1000


@pytest.mark.parametrize("content, match", [
    ("", "empty"),
    (HEADER + "\n", "no data rows"),
    ("a,b,c\n1,2,3\n", "no sensor channel"),
    ("time_s,gyro_x_deg\n0,1\n", "gyro_x_deg"),
    ("time_s,gyro_x_dps,gyro_x_rps\n0,1,2\n", "given twice"),
])
def test_structural_errors(tmp_path, content, match):
    p = tmp_path / "bad.csv"
    p.write_text(content)
    with pytest.raises(InputError, match=match):
        read_log(p)


def test_missing_file():
    with pytest.raises(InputError, match="not found"):
        read_log("/nonexistent/log.csv")


def test_non_numeric_cell_reports_row_and_column(tmp_path):
    t, d = _rows(20)
    p = _write(tmp_path / "log.csv", t, d)
    lines = p.read_text().splitlines()
    lines[8] = lines[8].replace(lines[8].split(",")[3], "abc", 1)  # spreadsheet row 9
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as err:
        read_log(p)
    assert err.value.row == 9 and err.value.field == "gyro_z_dps" and "abc" in str(err.value)


def test_malformed_row(tmp_path):
    t, d = _rows(20)
    p = _write(tmp_path / "log.csv", t, d)
    text = p.read_text().splitlines()
    text[5] += ",1,2"
    p.write_text("\n".join(text) + "\n")
    with pytest.raises(InputError, match="malformed CSV"):
        read_log(p)


def _bad_log(tmp_path):
    """NaN at row 5, row 10 repeated as row 11, a stray earlier time at row 21, a gap at row 42."""
    t, d = _rows(100)
    d[3, 2] = np.nan
    t[38:] += 0.5  # 50 missing samples before sample 38
    t, d = np.insert(t, 9, t[8]), np.insert(d, 9, d[8], axis=0)          # duplicate row
    t, d = np.insert(t, 19, t[17] - 0.005), np.insert(d, 19, d[0], axis=0)  # out of order
    return _write(tmp_path / "bad.csv", t, d)


def test_bad_log_raises_with_every_issue_and_file_untouched(tmp_path):
    p = _bad_log(tmp_path)
    before = _digest(p)
    with pytest.raises(LogError) as err:
        read_log(p)
    rep = err.value.report
    kinds = {i.kind: i for i in rep.issues}
    assert kinds["missing_value"].rows == (5,) and kinds["missing_value"].column == "gyro_z_dps"
    assert kinds["duplicate_rows"].rows == (11,)
    assert kinds["non_monotonic_time"].rows == (21,)
    assert kinds["gap"].rows == (42,) and "50 samples missing" in kinds["gap"].message
    assert "repair" in str(err.value) and "nothing was changed" in str(err.value)
    assert _digest(p) == before


def test_repair_lists_what_was_done(tmp_path, monkeypatch):
    # this log keeps 62 % after its gap: below the default 90 % floor (tests/test_hardening_logs.py),
    # so the floor is lowered here to check the list of repairs itself
    from budget.noise import log_checks
    monkeypatch.setattr(log_checks, "MIN_KEPT_FRACTION", 0.5)
    p = _bad_log(tmp_path)
    before = _digest(p)
    log = read_log(p, repair=True)
    text = " | ".join(log.issues.repairs)
    assert "dropped 1 exact duplicate" in text
    assert "did not increase" in text
    assert "interpolated 1 missing value(s) in gyro_z_dps" in text
    assert "longest gap-free stretch" in text
    assert np.all(np.isfinite(log.channels["gyro_z"])) and np.all(np.diff(log.time_s) > 0)
    assert np.max(np.diff(log.time_s)) < 1.5 / log.rate_hz
    assert log.n_samples == 100 - 38  # the 62 samples after the gap
    assert _digest(p) == before


def test_constant_channel_and_jitter_are_warnings(tmp_path):
    rng = np.random.default_rng(4)
    t, d = _rows(400)
    t = t + rng.normal(0, 0.0008, t.size)  # 8 % jitter, still increasing
    t.sort()
    d[:, 0] = 0.25
    log = read_log(_write(tmp_path / "j.csv", t, d))
    kinds = {i.kind: i.severity for i in log.issues.issues}
    assert kinds == {"constant_channel": "warning", "jitter": "warning"}
    assert math.isclose(log.rate_hz, 100.0, rel_tol=0.05)


def test_too_short_for_analysis(tmp_path):
    t, d = _rows(5)
    with pytest.raises(InputError, match="at least 100 samples"):
        read_log(_write(tmp_path / "s.csv", t, d), min_samples=100)


def test_channel_selection(tmp_path):
    t, d = _rows(50)
    p = _write(tmp_path / "log.csv", t, d)
    assert list(read_log(p, channels=["gyro_z"]).channels) == ["gyro_z"]
    with pytest.raises(InputError, match="gyro_w missing from the log"):
        read_log(p, channels=["gyro_w"])


@pytest.mark.shared_data
def test_real_log_partial_read(shared_data):
    p = shared_data / "logs" / "adis16405_static_1.csv.gz"
    log = read_log(p, max_rows=20_000)
    assert log.rate_hz == 100.0 and log.n_samples == 20_000
    # the only findings: the bench settling in the first 7 s (accel_z swings by 0.6 m/s² at 3.3 s),
    # kept as warnings by the transient check (budget.noise.transients)
    found = [i for i in log.issues.issues if i.severity != "info"]
    assert {i.kind for i in found} <= {"transient"} and all(i.severity == "warning" for i in found)
    assert all(i.column.startswith("accel_") and max(i.rows) < 1_000 for i in found)
    # accel z carries gravity (−1 g); gyro values are multiples of the 0.05 deg/s LSB
    assert abs(np.mean(log.channels["accel_z"]) + G0) < 0.3
    lsb = log.channels["gyro_x"] / DEG / 0.05
    np.testing.assert_allclose(lsb, np.round(lsb), atol=1e-6)


def test_time_jitter_without_lost_samples_is_not_a_gap(tmp_path):
    """Gaussian stamp jitter of 10 % of the period makes some steps longer than 1.5 periods, but
    every sample is there: a warning (jitter), not a gap; a real lost sample is still a gap."""
    rng = np.random.default_rng(7)
    t, d = _rows(20_000)
    t = t + rng.normal(0, 0.001, t.size)  # σ = 1 ms at 100 Hz, still increasing
    assert np.all(np.diff(t) > 0) and np.sum(np.diff(t) > 0.015) >= 1
    log = read_log(_write(tmp_path / "jit.csv", t, d))
    kinds = {i.kind: i.severity for i in log.issues.issues}
    assert kinds == {"jitter": "warning"} and log.n_samples == 20_000
    keep = np.delete(np.arange(t.size), [12_345])  # one sample lost
    with pytest.raises(LogError, match="about 1 samples missing") as err:
        read_log(_write(tmp_path / "lost.csv", t[keep], d[keep]))
    assert {i.kind: i.rows for i in err.value.report.issues}["gap"] == (12_345 + 2,)


def test_given_rate_that_contradicts_the_time_stamps_is_refused(tmp_path):
    t, d = _rows(500)
    p = _write(tmp_path / "log.csv", t, d)
    with pytest.raises(InputError, match=r"time stamps give 100 Hz, the given rate is 200 Hz") as err:
        read_log(p, rate_hz=200.0)
    assert "log.csv" in str(err.value)
    assert read_log(p, rate_hz=100.5).rate_hz == 100.5  # within 1 %: the given rate, no issue
    # time in ms under a column that declares s (×10³): the tool cannot tell whether the column
    # or the given rate is wrong (a 0.1 Hz slip on 100 Hz stamps once wrote ARW ×√1000 into a
    # catalog row), so it refuses and names both remedies
    ms = _write(tmp_path / "ms.csv", t * 1e3, d)
    with pytest.raises(InputError, match=r"×1000") as err:
        read_log(ms, rate_hz=100.0)
    assert "time_ms" in str(err.value) and "no rate given" in str(err.value)


def test_columns_not_read_are_named(tmp_path):
    from budget.noise import characterize
    rng = np.random.default_rng(2)
    t, d = _rows(4096)
    header = HEADER.replace("gyro_x_dps", "GyrX") + ",status"
    lines = [header] + [",".join([f"{ti:.6f}"] + [f"{v:.9g}" for v in row] + ["0"]) for ti, row in zip(t, d)]
    p = tmp_path / "other.csv"
    p.write_text("\n".join(lines) + "\n")
    c = characterize(read_log(p))
    named = [n for n in c.notes if "column not read" in n]
    assert len(named) == 2 and "[GyrX]" in named[0] and "[status]" in named[1]
    assert "gyro_x" not in c.channels and rng is not None


def test_one_accelerometer_in_m_s2_read_as_g_is_refused_and_the_reverse_is_said_unchecked(tmp_path):
    """With fewer than three accelerometers only part of gravity is seen: a mean above 1.25 g is
    impossible at rest (m/s² values labelled g: refused, naming the field), while a value in g
    labelled m/s² (1.0) cannot be told from a tilted axis and gets an info note saying so."""
    rng = np.random.default_rng(1)
    t = np.arange(5000) / 100.0
    p = _write(tmp_path / "z_g.csv", t, (G0 + 0.01 * rng.standard_normal(t.size))[:, None],
               header="time_s,accel_z_g")
    with pytest.raises(InputError) as err:
        read_log(p)
    assert err.value.field == "accel_z_g" and "more than gravity" in str(err.value)
    q = _write(tmp_path / "z_mps2.csv", t, (1.0 + 0.001 * rng.standard_normal(t.size))[:, None],
               header="time_s,accel_z_mps2")
    log = read_log(q)
    assert [i.kind for i in log.issues.issues] == ["unit_unchecked"]
    assert "9.81×" in log.issues.issues[0].message
    full = read_log(_write(tmp_path / "six.csv", *_rows(5000)))  # three axes: no such note
    assert "unit_unchecked" not in [i.kind for i in full.issues.issues]


def test_a_semicolon_log_or_a_preamble_gets_a_hint_naming_the_mapping_key(tmp_path):
    semi = tmp_path / "semi.csv"
    semi.write_text("time_s;gyro_x_dps;gyro_y_dps\n0;1;2\n0.01;1;2\n")
    with pytest.raises(InputError) as err:
        read_log(semi)
    assert "'time_s;gyro_x_dps;gyro_y_dps'" in str(err.value) and '"delimiter": \';\'' in str(err.value)
    pre = tmp_path / "pre.csv"
    pre.write_text("Device: XYZ IMU\nDate 2026\ntime_s,gyro_x_dps\n0,1\n")
    with pytest.raises(InputError) as err:
        read_log(pre)
    assert "'Device: XYZ IMU'" in str(err.value) and '"skip_rows"' in str(err.value)
