"""Logs and Allan tables written by other tools, round 6: text encodings, units written in
brackets in the header, a one-curve Allan table without a channel column, and gaps between
time stamps rounded coarser than half the period.

Every file is written here with plain Python/NumPy, and each number is checked against a value
computed here independently of the readers (π/180, 3600, g = 9.80665), or the words of the
one-line error (file, row, field, what was expected).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.gap.inputs import load_measured
from budget.noise import read_log
from budget.noise import read_adev_table
from budget.noise.adev_columns import looks_like_adev_table
from budget.noise.log_mapping import LogMapping
from budget.noise.measurement import read_measurement

DEG = math.pi / 180
G = 9.80665
HEADER = "time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


def _values(n: int, seed: int = 0) -> np.ndarray:
    """n rows of white gyro (0.1 deg/s) and accelerometer (0.02 m/s², z carrying gravity) noise."""
    rng = np.random.default_rng(seed)
    x = np.c_[rng.normal(0, 0.1, (n, 3)), rng.normal(0, 0.02, (n, 3))]
    x[:, 5] -= G
    return x


def _log_text(times, x, header=HEADER) -> str:
    return header + "\n" + "".join(f"{t}," + ",".join(f"{v:.6f}" for v in row) + "\n"
                                   for t, row in zip(times, x))


def _encode(text: str, codec: str) -> bytes:
    """``text`` with its byte-order mark, as spreadsheets and loggers write it."""
    bom = {"utf-8": b"\xef\xbb\xbf", "utf-16-le": b"\xff\xfe", "utf-16-be": b"\xfe\xff"}[codec]
    return bom + text.replace("\n", "\r\n").encode(codec)


TAUS = [0.01 * 2 ** k for k in range(10)]
N_DPH = 0.5  # white gyro noise, deg/√h: ADEV(τ) = N/√τ with N in deg/s/√Hz = 0.5/60


def _adev_dps(tau: float) -> float:
    return N_DPH / 60 / math.sqrt(tau)


# --- 1. encodings: one byte-order-mark detection for logs and tables ----------------------------

@pytest.mark.parametrize("codec", ["utf-8", "utf-16-le", "utf-16-be"])
def test_allan_tables_and_logs_with_a_byte_order_mark_are_read(tmp_path, codec):
    # a UTF-16 Allan table went to the log reader: "--samples is for Allan tables; a log has its own length"
    table = "channel,tau_s,adev\n" + "".join(f"gyro_z_dps,{t},{_adev_dps(t)!r}\n" for t in TAUS)
    tp = tmp_path / "curve.csv"
    tp.write_bytes(_encode(table, codec))
    assert looks_like_adev_table(tp)
    got = read_measurement(tp, rate_hz=100.0, samples=100_000)
    np.testing.assert_allclose(got["gyro_z"].adev, [_adev_dps(t) * DEG for t in TAUS], rtol=1e-12)
    x = _values(500)
    lp = tmp_path / "log.csv"
    lp.write_bytes(_encode(_log_text([f"{i / 100:.2f}" for i in range(500)], x), codec))
    assert not looks_like_adev_table(lp)
    log = read_measurement(lp)
    assert log.rate_hz == 100.0 and log.n_samples == 500
    np.testing.assert_allclose(log.channels["accel_z"], np.round(x[:, 5], 6), rtol=1e-12)
    np.testing.assert_allclose(log.channels["gyro_x"], np.round(x[:, 0], 6) * DEG, rtol=1e-12)


def test_the_byte_order_mark_is_detected_in_one_place():
    # the log and table readers each had their own decoding (UTF-16 known to one only)
    root = Path(__file__).resolve().parent.parent / "budget"
    marks = [p.relative_to(root).as_posix() for p in root.rglob("*.py")
             if re.search(r'b"\\xff\\xfe|utf-8-sig', p.read_text(encoding="utf-8"))]
    assert marks == ["fileio.py"]


def test_a_utf16_catalog_is_named_as_such_not_misread(tmp_path):
    # a catalog is appended to in UTF-8: it stays UTF-8 only, and the error says what the file is
    from budget.catalog.io import load_catalog
    p = tmp_path / "cat.csv"
    p.write_bytes(_encode("part_id,grade,source\nA,tactical,s\n", "utf-16-le"))
    with pytest.raises(InputError, match=r"UTF-16 text \(its byte-order mark\), not UTF-8"):
        load_catalog(p)


# --- 2. units written in brackets in the header -----------------------------------------------

@pytest.mark.parametrize("header, factors", [
    ("time_s,gyro_x [deg/s],gyro_y [deg/s],gyro_z [deg/s],acc_x [m/s^2],acc_y [m/s^2],acc_z [m/s^2]",
     [DEG] * 3 + [1.0] * 3),
    ("time [s],gyro_x (deg/s),gyro_y (rad/s),gyro_z (deg/h),accel_x (g),accel_y (mg),accel_z (m/s²)",
     [DEG, 1.0, DEG / 3600, G, G / 1000, 1.0]),
    ("time [ms],Gyro_X [°/s],gyro_y [dps],gyro_z [rad/s],acc_x [m/s2],acc_y [m/s^2],acc_z [m/s^2]",
     [DEG, DEG, 1.0, 1.0, 1.0, 1.0]),
])
def test_log_columns_with_their_unit_in_brackets_are_read_in_si(tmp_path, header, factors):
    n = 600
    rng = np.random.default_rng(1)
    si = np.c_[rng.normal(0, 0.1 * DEG, (n, 3)), rng.normal(0, 0.02, (n, 3))]  # rad/s, m/s²
    si[:, 5] -= G
    written = si / np.array(factors)  # each column in the unit its header names
    ms = "[ms]" in header
    times = [f"{i * (10 if ms else 0.01):.2f}" for i in range(n)]
    log = read_log(_write_text(tmp_path / "b.csv", _log_text(times, written, header)))
    assert log.rate_hz == 100.0
    for j, ch in enumerate(("gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")):
        np.testing.assert_allclose(log.channels[ch], np.round(written[:, j], 6) * factors[j], rtol=1e-9)
        assert np.std(log.channels[ch]) == pytest.approx(np.std(si[:, j]), rel=0.01)
    assert np.mean(log.channels["accel_z"]) == pytest.approx(-G, rel=1e-3)


def _write_text(path, text):
    path.write_text(text, encoding="utf-8")
    return path


def test_an_unknown_bracketed_unit_is_named_with_the_accepted_ones(tmp_path):
    x = _values(200)
    times = [f"{i / 100:.2f}" for i in range(200)]
    p = _write_text(tmp_path / "u.csv", _log_text(times, x, HEADER.replace("gyro_y_dps", "gyro_y [furlong/s]")))
    with pytest.raises(InputError) as e:
        read_log(p)
    assert e.value.row == 1 and e.value.field == "gyro_y [furlong/s]"
    assert "unit 'furlong/s' not understood for gyro_y; accepted: deg/s" in str(e.value)
    assert "rad/s" in str(e.value) and "deg/h" in str(e.value)
    p = _write_text(tmp_path / "a.csv", _log_text(times, x, HEADER.replace("gyro_y_dps", "gyro_y [m/s^2]")))
    with pytest.raises(InputError, match="unit 'm/s\\^2' not understood for gyro_y"):
        read_log(p)  # an accelerometer unit on a gyro
    p = _write_text(tmp_path / "t.csv", _log_text(times, x, HEADER.replace("time_s", "time [fortnight]")))
    with pytest.raises(InputError, match="no time column and no sampling rate; column 'time \\[fortnight\\]': "
                                         "time unit 'fortnight' not understood; accepted: s, ms"):
        read_log(p)
    # clock text some loggers add is no time column: left out, as before, and named in the notes
    clock = _log_text(times, x, HEADER + ",Time (UTC)").replace("\n", ",12:00:00\n")
    clock = clock.replace(HEADER + ",Time (UTC),12:00:00", HEADER + ",Time (UTC)")
    log = read_log(_write_text(tmp_path / "c.csv", clock))
    assert log.rate_hz == 100.0
    assert [i.column for i in log.issues.issues if i.kind == "ignored_column"] == ["Time (UTC)"]


def test_two_units_for_one_column_that_disagree_are_refused(tmp_path):
    x = _values(200)
    times = [f"{i / 100:.2f}" for i in range(200)]
    both = _write_text(tmp_path / "two.csv", _log_text(times, x, HEADER.replace("gyro_x_dps", "gyro_x_dps [rad/s]")))
    with pytest.raises(InputError) as e:
        read_log(both)
    assert e.value.field == "gyro_x_dps [rad/s]" and "two units" in str(e.value)
    agree = _write_text(tmp_path / "same.csv", _log_text(times, x, HEADER.replace("gyro_x_dps", "gyro_x_dps [deg/s]")))
    np.testing.assert_allclose(read_log(agree).channels["gyro_x"], np.round(x[:, 0], 6) * DEG, rtol=1e-12)
    # a mapping is another source of the unit: one that contradicts the header is not chosen
    head = HEADER.replace("gyro_x_dps", "GyrX [deg/s]").replace("time_s", "t (ms)")
    p = _write_text(tmp_path / "m.csv", _log_text([f"{10 * i}" for i in range(200)], x, head))
    with pytest.raises(InputError) as e:
        read_log(p, LogMapping(columns={"GyrX [deg/s]": "gyro_x_rps", "t (ms)": "time_ms"}))
    assert e.value.field == "GyrX [deg/s]" and "the two units disagree" in str(e.value)
    assert "gyro_x_dps" in str(e.value)  # what to write instead
    with pytest.raises(InputError, match="the two units disagree"):
        read_log(p, LogMapping(columns={"GyrX [deg/s]": "gyro_x_dps", "t (ms)": "time_s"}))
    log = read_log(p, LogMapping(columns={"GyrX [deg/s]": "gyro_x_dps", "t (ms)": "time_ms"}))
    assert log.rate_hz == 100.0
    np.testing.assert_allclose(log.channels["gyro_x"], np.round(x[:, 0], 6) * DEG, rtol=1e-12)
    # a bracketed word that is no unit (raw counts, read through a stated scale) is no claim
    raw = _write_text(tmp_path / "raw.csv", _log_text(times, x, HEADER.replace("gyro_x_dps", "gx [raw]")))
    log = read_log(raw, LogMapping(columns={"gx [raw]": "gyro_x_dps"}, scale={"gx [raw]": 2.0}))
    np.testing.assert_allclose(log.channels["gyro_x"], 2 * np.round(x[:, 0], 6) * DEG, rtol=1e-12)


@pytest.mark.parametrize("header, channel_cell, tau_scale, to_si", [
    ("tau [s],adev (deg/h)", None, 1.0, DEG / 3600),
    ("channel,tau (ms),adev [deg/h]", "gyro_z", 1e3, DEG / 3600),
    ("channel,Tau [s],ADEV [deg/s]", "gyro_z", 1.0, DEG),
    ("channel,tau_s,adev [deg/h]", "gyro_z_dph", 1.0, DEG / 3600),  # both say deg/h: agree
])
def test_allan_tables_with_units_in_brackets_are_read_in_si(tmp_path, header, channel_cell, tau_scale, to_si):
    p = tmp_path / "c.csv"
    rows = "".join((f"{channel_cell}," if channel_cell else "") + f"{t * tau_scale:g},{_adev_dps(t) * DEG / to_si!r}\n"
                   for t in TAUS)
    p.write_text(header + "\n" + rows)
    assert looks_like_adev_table(p)
    a = read_adev_table(p, 100.0, 100_000, channels=["gyro_z"])["gyro_z"]
    np.testing.assert_allclose(a.tau_s, TAUS, rtol=1e-12)
    np.testing.assert_allclose(a.adev, [_adev_dps(t) * DEG for t in TAUS], rtol=1e-12)


def test_allan_table_units_that_disagree_or_are_unknown_are_refused(tmp_path):
    def table(header, cell="gyro_z"):
        p = tmp_path / "c.csv"
        p.write_text(header + "\n" + "".join((f"{cell}," if cell else "") + f"{t},{_adev_dps(t) * 3600}\n"
                                             for t in TAUS))
        return p
    with pytest.raises(InputError) as e:
        read_adev_table(table("channel,tau_s,adev [deg/h]", "gyro_z_dps"), 100.0, 100_000)
    assert e.value.row == 2 and e.value.field == "channel" and "the two units disagree" in str(e.value)
    with pytest.raises(InputError) as e:
        read_adev_table(table("channel,tau_s,adev [deg/fortnight]"), 100.0, 100_000)
    assert e.value.row == 1 and e.value.field == "adev [deg/fortnight]"
    assert "accepted: deg/s" in str(e.value) and "deg/h" in str(e.value)
    with pytest.raises(InputError) as e:
        read_adev_table(table("channel,tau_s,adev"), 100.0, 100_000)
    assert e.value.row == 2 and "no unit for gyro_z" in str(e.value) and "adev [unit]" in str(e.value)
    with pytest.raises(InputError, match="names two time units"):
        read_adev_table(table("channel,tau_ms [s],adev [deg/h]"), 100.0, 100_000)
    # an Allan variance carries the square of the unit; deg/h^2 is no such square
    p = tmp_path / "v.csv"
    p.write_text("tau [s],avar [(deg/h)^2]\n" + "".join(f"{t},{(_adev_dps(t) * 3600) ** 2!r}\n" for t in TAUS))
    a = read_adev_table(p, 100.0, 100_000, channels=["gyro_z"])["gyro_z"]
    np.testing.assert_allclose(a.adev, [_adev_dps(t) * DEG for t in TAUS], rtol=1e-12)
    p.write_text(p.read_text().replace("(deg/h)^2", "deg/h^2"))
    with pytest.raises(InputError, match="an Allan variance's unit is a square"):
        read_adev_table(p, 100.0, 100_000, channels=["gyro_z"])


def test_wide_allan_table_with_bracketed_channel_units(tmp_path):
    p = tmp_path / "w.csv"
    p.write_text("tau [s],gyro_x [deg/s],acc_z [m/s^2]\n"
                 + "".join(f"{t},{_adev_dps(t)!r},{1e-3 / math.sqrt(t)!r}\n" for t in TAUS))
    got = read_adev_table(p, 100.0, 100_000)
    np.testing.assert_allclose(got["gyro_x"].adev, [_adev_dps(t) * DEG for t in TAUS], rtol=1e-12)
    np.testing.assert_allclose(got["accel_z"].adev, [1e-3 / math.sqrt(t) for t in TAUS], rtol=1e-12)


# --- 3. a one-curve Allan table without a channel column --------------------------------------

def _two_columns(tmp_path, header="tau [s],adev (deg/h)"):
    p = tmp_path / "one.csv"
    p.write_text(header + "\n" + "".join(f"{t},{_adev_dps(t) * 3600!r}\n" for t in TAUS))
    return p


def test_a_two_column_table_is_read_as_the_channel_the_user_names(tmp_path, capsys):
    p = _two_columns(tmp_path)
    with pytest.raises(InputError) as e:
        read_measurement(p, rate_hz=100.0, samples=100_000)
    msg = str(e.value)
    assert "one.csv" in msg and e.value.row == 1 and "no channel column" in msg
    assert "--channels gyro_z" in msg and "channels=['gyro_z']" in msg
    with pytest.raises(InputError, match="one curve, but 2 channels are named"):
        read_measurement(p, rate_hz=100.0, samples=100_000, channels=["gyro_z", "gyro_x"])
    got = read_measurement(p, rate_hz=100.0, samples=100_000, channels=["gyro_z"])
    assert list(got) == ["gyro_z"]
    np.testing.assert_allclose(got["gyro_z"].adev, [_adev_dps(t) * DEG for t in TAUS], rtol=1e-12)
    # the model-gap workflow reads it the same way, its channel named by channels=
    meas = load_measured(p, rate_hz=100.0, samples=100_000, channels=["gyro_z"])
    assert meas.kind == "adev_table" and meas.channels == ("gyro_z",)
    # the command line: refused with how to name it, then characterised once named
    assert main(["noise", "characterize", str(p), "--rate-hz", "100", "--samples", "100000", "-q"]) == 2
    assert "--channels gyro_z" in _one_line(capsys)
    out = tmp_path / "r.json"
    assert main(["noise", "characterize", str(p), "--rate-hz", "100", "--samples", "100000",
                 "--channels", "gyro_z", "--json", str(out), "-q"]) == 0
    part = json.loads(out.read_text())["part"]
    assert part["gyro_arw_deg_rt_h"] == pytest.approx(N_DPH, rel=0.03)


def test_a_two_column_table_without_a_unit_says_where_to_write_it(tmp_path):
    p = _two_columns(tmp_path, "tau_s,adev")
    with pytest.raises(InputError) as e:
        read_measurement(p, rate_hz=100.0, samples=100_000, channels=["gyro_z"])
    assert e.value.row == 1 and "no unit for gyro_z" in str(e.value)
    assert "adev [unit] with unit one of deg/s" in str(e.value)


# --- 4. a gap between time stamps rounded coarser than half the period --------------------------

def _coarse(t: float, res: float = 0.002) -> str:
    """A stamp rounded to ``res`` (2 ms at 400 Hz: steps of 0.8 or 1.6 periods)."""
    return f"{math.floor(t / res + 0.5) * res:.3f}"


def test_one_gap_between_coarse_time_stamps_is_counted_once(tmp_path):
    # the long steps next to the gap saw it in their windows: "10 gap(s) … (about 210 samples
    # missing)" for one gap of 40, a period of 2.45 ms (408 Hz) from the inflated count, and a
    # repair that kept rows 680– instead of 402– (278 good samples dropped)
    rate, n = 400.0, 8000
    idx = np.r_[0:400, 440:n + 40]
    p = _write_text(tmp_path / "g.csv", _log_text([_coarse(i / rate) for i in idx], _values(n)))
    with pytest.raises(InputError) as e:
        read_log(p)
    msg = str(e.value)
    assert "1 gap(s)" in msg and "about 40 samples missing" in msg and "(rows 402)" in msg
    period = float(re.search(r"the period ([0-9.e-]+) s", msg).group(1))
    assert period == pytest.approx(1 / rate, rel=1e-4)  # 2.45e-3 s before (408 Hz)
    log = read_log(p, repair=True)
    assert log.rate_hz == 400.0 and log.n_samples == n - 400
    assert "kept the longest gap-free stretch, rows 402–8001" in log.issues.repairs[-1]
    plain = read_log(_write_text(tmp_path / "p.csv", _log_text([_coarse(i / rate) for i in range(n)], _values(n))))
    assert plain.rate_hz == 400.0 and not [i for i in plain.issues.issues if i.kind == "gap"]


def test_gaps_far_apart_and_close_together_are_each_counted_with_their_own_samples(tmp_path):
    rate, n = 400.0, 8000
    far = np.r_[0:2000, 2040:5000, 5025:n + 65]   # coarse stamps: 40 and 25 samples lost
    # read "1504 gap(s) … (about 1834 samples missing)": the inflated count spoilt the period,
    # and the grid then drifted under every long step
    p = _write_text(tmp_path / "far.csv", _log_text([_coarse(i / rate) for i in far], _values(n)))
    with pytest.raises(InputError) as e:
        read_log(p)
    assert "2 gap(s)" in str(e.value) and "about 65 samples missing" in str(e.value)
    assert "(rows 2002, 4962)" in str(e.value)
    # fine stamps, two gaps 8 samples apart: their windows overlapped ("about 60" samples for 40)
    close = np.r_[0:3000, 3030:3038, 3048:n + 40]
    p = _write_text(tmp_path / "close.csv", _log_text([f"{i / rate:.6f}" for i in close], _values(n)))
    with pytest.raises(InputError) as e:
        read_log(p)
    assert "2 gap(s)" in str(e.value) and "about 40 samples missing" in str(e.value)
    assert "(rows 3002, 3010)" in str(e.value)
