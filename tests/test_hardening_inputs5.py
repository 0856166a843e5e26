"""Logs and Allan tables written by other tools, round 5: what such files hold that the readers
read wrongly or refused without saying why.

Every test builds its files in ``tmp_path`` and checks the number against a value computed here
independently, or the words of the one-line error (file, row, field, what was expected).
"""

from __future__ import annotations

import bz2
import gzip
import math

import numpy as np
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.noise import characterize, read_log
from budget.noise import read_adev_table
from budget.noise.adev_columns import looks_like_adev_table
from budget.noise.log_mapping import LogMapping

HEADER = "time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"
DEG = math.pi / 180


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


def _values(n: int, seed: int = 0, gyro_sd: float = 0.1) -> np.ndarray:
    """n rows of white gyro (deg/s) and accelerometer (m/s², z carrying gravity) noise."""
    rng = np.random.default_rng(seed)
    x = np.c_[rng.normal(0, gyro_sd, (n, 3)), rng.normal(0, 0.02, (n, 3))]
    x[:, 5] -= 9.80665
    return x


def _write(path, times, x, header=HEADER, sep=",", decimal="."):
    lines = [header.replace(",", sep)]
    for t, row in zip(times, x):
        cells = [t] + [f"{v:.6f}" for v in row]
        lines.append(sep.join(c.replace(".", decimal) for c in cells))
    path.write_text("\n".join(lines) + "\n")
    return path


# --- 1. time stamps rounded to a resolution near the period -----------------------------------

@pytest.mark.parametrize("rate, stamp, expected", [
    (400.0, lambda t: f"{t:.3f}", 400.0),             # 3 decimals of a second: steps of 2 or 3 ms
    (128.0, lambda t: f"{t:.3f}", 128.0),             # ms at 128 Hz: steps of 7 or 8 ms
    (1 / 0.01024, lambda t: f"{int(t * 1e3) / 1e3:.3f}", 1 / 0.01024),  # Arduino millis(), 10.24 ms
])
def test_time_stamps_rounded_near_the_period_give_the_rate_of_their_span(tmp_path, rate, stamp, expected):
    # the median step read 333 Hz, 125 Hz and 100 Hz: ARW 10 %, 1 % and 1.2 % off, a jitter warning only
    n = 12_000
    x = _values(n)
    log = read_log(_write(tmp_path / "log.csv", [stamp(i / rate) for i in range(n)], x))
    assert log.rate_hz == pytest.approx(expected, rel=2e-5)
    issue = next(i for i in log.issues.issues if i.kind == "stamp_resolution")
    assert "rounded to 0.001 s" in issue.message and issue.severity == "info"
    assert not [i for i in log.issues.issues if i.kind in ("jitter", "gap")]
    # white noise: N = σ/√rate (σ of the samples, computed here), within the fit's scatter
    fit = characterize(log).channels["gyro_x"]
    assert fit.N == pytest.approx(np.std(x[:, 0]) * DEG / math.sqrt(rate), rel=0.04)


def test_a_gap_between_rounded_time_stamps_is_still_counted(tmp_path):
    rate, n = 400.0, 8000
    idx = np.r_[0:3000, 3040:n + 40]
    log_path = _write(tmp_path / "gap.csv", [f"{i / rate:.3f}" for i in idx], _values(n))
    with pytest.raises(InputError) as e:
        read_log(log_path)
    assert "1 gap(s)" in str(e.value) and "about 40 samples missing" in str(e.value)
    assert "rows 3002" in str(e.value)


# --- 2. compression, encoding and decimal marks of other tools ---------------------------------

def test_compressed_logs_are_read_by_content_whatever_their_name(tmp_path):
    # pandas took the compression from the suffix: a gzip log named 'log' or 'log.csv.gzip',
    # was "not a readable CSV (UnicodeDecodeError)" although the README says "detected by content"
    x = _values(400)
    plain = _write(tmp_path / "log.csv", [f"{i / 100:.2f}" for i in range(400)], x)
    ref = read_log(plain)
    for name, data in (("log", gzip.compress(plain.read_bytes())),
                       ("log.csv.gzip", gzip.compress(plain.read_bytes())),
                       ("log.dat", bz2.compress(plain.read_bytes()))):
        (tmp_path / name).write_bytes(data)
        got = read_log(tmp_path / name)
        assert got.rate_hz == 100.0
        np.testing.assert_allclose(got.channels["gyro_x"], np.round(x[:, 0], 6) * DEG, rtol=1e-12)
        np.testing.assert_array_equal(got.channels["accel_z"], ref.channels["accel_z"])


def test_utf16_logs_and_a_latin1_degree_sign_in_the_temperature_column_are_read(tmp_path):
    x = _values(300)
    text = HEADER + ",Temp (°C)\n" + "".join(
        f"{i / 100:.2f}," + ",".join(f"{v:.6f}" for v in row) + ",25.0\n" for i, row in enumerate(x))
    (tmp_path / "u16.csv").write_bytes(text.replace("\n", "\r\n").encode("utf-16"))
    (tmp_path / "lat1.csv").write_bytes(text.encode("latin-1"))
    for name in ("u16.csv", "lat1.csv"):  # both were "not a readable CSV (UnicodeDecodeError)"
        log = read_log(tmp_path / name)
        np.testing.assert_allclose(log.channels["gyro_y"], x[:, 1] * DEG, rtol=0, atol=1e-6 * DEG)
        # the temperature column is read (°C from its bracketed unit), not left out
        assert not [i for i in log.issues.issues if i.kind == "ignored_column"]
        np.testing.assert_allclose(log.temp_c, 25.0)


def test_decimal_commas_are_named_and_read_through_the_mapping(tmp_path):
    x = _values(300)
    p = _write(tmp_path / "de.csv", [f"{i / 100:.2f}" for i in range(300)], x, sep=";", decimal=",")
    with pytest.raises(InputError) as e:
        read_log(p, LogMapping(delimiter=";"))
    msg = str(e.value)
    assert e.value.row == 2 and e.value.field == "time_s" and "'0,00'" in msg
    assert 'decimal commas is read with a mapping\'s "decimal": ","' in msg
    log = read_log(p, LogMapping(delimiter=";", decimal=","))
    assert log.rate_hz == 100.0
    np.testing.assert_allclose(log.channels["gyro_z"], np.round(x[:, 2], 6) * DEG, rtol=1e-12)
    with pytest.raises(ValueError, match="decimal mark and delimiter are both ','"):
        LogMapping(decimal=",")


# --- 3. Allan tables in the layouts other tools write ------------------------------------------

TAUS = [0.01, 0.02, 0.04, 0.08, 0.16, 0.32, 0.64, 1.28]


def _adev(tau):
    return 0.01 / math.sqrt(tau)  # white noise, N = 0.01 deg/s/√Hz


@pytest.mark.parametrize("name, text", [
    ("semi.csv", "channel;tau_s;adev\n" + "".join(f"gyro_z_dps;{t};{_adev(t)}\n" for t in TAUS)),
    ("tab.csv", "channel\ttau_s\tadev\n" + "".join(f"gyro_z_dps\t{t}\t{_adev(t)}\n" for t in TAUS)),
    ("quoted.csv", '"channel","tau_s","adev"\n' + "".join(f'"gyro_z_dps",{t},{_adev(t)}\n' for t in TAUS)),
    ("comment.csv", "# written by allantools\n# rate 100 Hz\nchannel,tau_s,adev\n"
     + "".join(f"gyro_z_dps,{t},{_adev(t)}\n" for t in TAUS)),
    ("trailing.csv", "channel,tau_s,adev,\n" + "".join(f"gyro_z_dps,{t},{_adev(t)},\n" for t in TAUS)),
    ("wide_ms.csv", "tau_ms,gyro_z_dps\n" + "".join(f"{t * 1e3:g},{_adev(t)}\n" for t in TAUS)),
])
def test_allan_tables_other_tools_write_are_recognised_and_read(tmp_path, name, text):
    # each went to the log reader: "--samples is for Allan tables; a log has its own length",
    # or was refused for an empty trailing column
    p = tmp_path / name
    p.write_text(text)
    assert looks_like_adev_table(p)
    a = read_adev_table(p, 100.0, 60_000)["gyro_z"]
    np.testing.assert_allclose(a.tau_s, TAUS, rtol=1e-12)
    np.testing.assert_allclose(a.adev, [_adev(t) * DEG for t in TAUS], rtol=1e-12)


def test_compressed_allan_table_under_any_name_goes_to_the_table_reader(tmp_path, capsys):
    text = "channel,tau_s,adev\n" + "".join(f"gyro_z_dps,{t},{_adev(t)}\n" for t in TAUS)
    (tmp_path / "curve.bz2").write_bytes(bz2.compress(text.encode()))
    (tmp_path / "curve").write_bytes(gzip.compress(text.encode()))
    for name in ("curve.bz2", "curve"):
        assert looks_like_adev_table(tmp_path / name)
        a = read_adev_table(tmp_path / name, 100.0, 60_000)["gyro_z"]
        np.testing.assert_allclose(a.adev, [_adev(t) * DEG for t in TAUS], rtol=1e-12)
    out = tmp_path / "c.json"
    assert main(["noise", "characterize", str(tmp_path / "curve.bz2"), "--rate-hz", "100",
                 "--samples", "60000", "--json", str(out), "-q"]) == 0
    import json
    arw = json.loads(out.read_text())["part"]["gyro_arw_deg_rt_h"]
    assert arw == pytest.approx(0.01 * 60, rel=0.02)  # N·60 deg/√h


def test_allan_table_errors_name_the_file_line_after_a_preamble_and_a_decimal_comma(tmp_path):
    p = tmp_path / "c.csv"
    p.write_text("# preamble\nchannel;tau_s;adev\ngyro_z_dps;0,01;0,1\ngyro_z_dps;0,02;0,07\n")
    with pytest.raises(InputError) as e:
        read_adev_table(p, 100.0, 60_000)
    assert e.value.row == 3 and e.value.field == "tau_s" and "'0,01'" in str(e.value)
    assert "decimal point (0.01), not a decimal comma" in str(e.value)


# --- 4. stale and clipped samples: numbers that would be silently wrong ------------------------

def test_a_logger_repeating_stale_samples_is_refused(tmp_path, capsys):
    # a 200 Hz log of a 100 Hz sensor: ARW 0.87× the sensor's; 30 % missed updates: 1.14×
    x = np.repeat(_values(3000), 2, axis=0)
    p = _write(tmp_path / "stale.csv", [f"{i / 200:.3f}" for i in range(6000)], x)
    with pytest.raises(InputError) as e:
        read_log(p)
    msg = str(e.value)
    assert "3000 of 6000 rows (50 %) repeat every sensor value of the row before" in msg
    assert "rows 3, 5, 7, 9, 11" in msg and "stale samples" in msg
    assert "gyro_x_dps" in e.value.field and "sensor's output rate" in msg
    assert main(["noise", "characterize", str(p), "-q"]) == 2
    assert "stale.csv" in _one_line(capsys)


def test_coarse_independent_channels_repeat_by_chance_and_are_not_stale(tmp_path):
    # every channel on a lattice of its own σ: each repeats ≈ 28 % of rows, all six ≈ 0.05 %
    rng = np.random.default_rng(3)
    x = np.round(rng.normal(0, 1, (20_000, 6))) * np.array([0.05, 0.05, 0.05, 0.03, 0.03, 0.03])
    x[:, 5] -= 9.80665
    same = (x[1:] == x[:-1])
    assert 0.2 < same.mean() < 0.35 and same.all(axis=1).sum() < 50
    log = read_log(_write(tmp_path / "coarse.csv", [f"{i / 100:.2f}" for i in range(20_000)], x))
    assert log.n_samples == 20_000


def test_a_clipped_channel_is_refused_and_a_few_samples_at_a_rail_are_warned(tmp_path):
    x = _values(6000)
    clipped = x.copy()
    clipped[:, 0] = np.clip(x[:, 0], -0.15, 0.15)  # ±1.5 σ: ARW read 0.88× the sensor's
    share = np.mean(x[:, 0] >= 0.15)
    with pytest.raises(InputError) as e:
        read_log(_write(tmp_path / "clip.csv", [f"{i / 100:.2f}" for i in range(6000)], clipped))
    assert e.value.field == "gyro_x_dps" and "largest value 0.15," in str(e.value)
    assert f"({100 * share:.3g} %)" in str(e.value) and "clipped at a range limit" in str(e.value)
    # a knock of 12 samples at a 5σ rail carries 29 % of the record's variance at its 16-sample
    # scale: the transient check refuses it (it would decide the Allan fit there), naming its rows
    knock = x.copy()
    knock[100:112, 1] = 0.5
    with pytest.raises(InputError) as e:
        read_log(_write(tmp_path / "knock.csv", [f"{i / 100:.2f}" for i in range(6000)], knock))
    assert e.value.field == "gyro_y_dps" and "rows 102–113 (12 samples" in str(e.value)
    # the same knock in a 5-min record carries a fifth of that share: a clipping warning
    few = _values(30000)
    few[100:112, 1] = 0.5
    log = read_log(_write(tmp_path / "few.csv", [f"{i / 100:.2f}" for i in range(30000)], few))
    warn = [i for i in log.issues.issues if i.kind == "clipped"]
    assert len(warn) == 1 and warn[0].column == "gyro_y_dps" and warn[0].rows[0] == 102
    assert "12 of 30000 samples" in warn[0].message
    plain = read_log(_write(tmp_path / "plain.csv", [f"{i / 100:.2f}" for i in range(6000)], x))
    assert not [i for i in plain.issues.issues if i.kind == "clipped"]
