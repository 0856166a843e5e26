"""Held-out audit of the logs users bring (timing, formats, bad values), each case written by an
independent generator here — NumPy only, not :mod:`budget.imu.generator`: white noise of a
stated density plus flicker (bias instability) shaped by FFT to the IEEE-952 two-sided PSD
B²/(2πf), whose Allan floor is 0.664·B. Tactical magnitudes: ARW 0.2 deg/√h, bias instability
3 deg/h, VRW 0.05 m/s/√h, accelerometer bias instability 30 µg."""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.errors import InputError
from budget.noise import allan_deviation, read_log

ARW_DPH, BI_DPH, VRW, ABI_UG = 0.2, 3.0, 0.05, 30.0
N_GYRO = math.radians(ARW_DPH) / 60.0          # rad/s/√Hz (rad/√s)
B_GYRO = math.radians(BI_DPH) / 3600.0         # rad/s
N_ACC = VRW / 60.0                             # m/s²/√Hz
B_ACC = ABI_UG * 1e-6 * 9.80665                # m/s²
HEADER = "time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"


def _flicker(n: int, fs: float, b: float, rng) -> np.ndarray:
    spec = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1.0 / fs)
    shape = np.zeros_like(f)
    shape[1:] = np.sqrt(b * b / (2.0 * np.pi * f[1:]) * fs)
    return np.fft.irfft(spec * shape, n)


def static_imu(n: int, fs: float, seed: int = 0) -> dict[str, np.ndarray]:
    """Six channels in deg/s and m/s² (z down: accel_z ≈ −g), with turn-on biases."""
    rng = np.random.default_rng(seed)
    out = {}
    for ax, bias in zip("xyz", (0.06, -0.03, 0.045)):
        x = N_GYRO * math.sqrt(fs) * rng.standard_normal(n) + _flicker(n, fs, B_GYRO, rng)
        out[f"gyro_{ax}_dps"] = np.degrees(x) + bias
    for ax, g in zip("xyz", (0.05, -0.03, -9.80665)):
        out[f"accel_{ax}_mps2"] = N_ACC * math.sqrt(fs) * rng.standard_normal(n) + _flicker(n, fs, B_ACC, rng) + g
    return out


def write_log(path, time: np.ndarray, ch: dict[str, np.ndarray], *, time_fmt: str = "{:.6f}",
              header: str = HEADER, sep: str = ",") -> str:
    lines = [header]
    values = np.column_stack(list(ch.values()))
    for t, row in zip(time, values):
        lines.append(sep.join([time_fmt.format(t), *(f"{v:.9g}" for v in row)]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def _arw_at_1s(log, ch="gyro_x") -> float:
    r = allan_deviation(log.channels[ch], log.rate_hz, "octave")
    i = int(np.argmin(np.abs(np.asarray(r.tau_s) - 1.0)))
    return float(r.adev[i] * math.sqrt(r.tau_s[i]))


# --- 1. time stamps rounded coarser than the sampling period ---------------------------------------

def test_millisecond_stamps_of_a_2khz_log_are_named_and_read_at_the_given_rate(tmp_path):
    fs, n = 2000.0, 20_000
    path = write_log(tmp_path / "ms.csv", np.arange(n) / fs, static_imu(n, fs), time_fmt="{:.3f}")
    with pytest.raises(InputError) as err:  # not "time goes back: --repair" (a repair drops half)
        read_log(path)
    text = str(err.value)
    assert "rounded to 0.001 s, coarser than the sampling period" in text and "time_s" in text
    assert "--rate-hz" in text and "repair" not in text
    log = read_log(path, rate_hz=fs)
    assert log.rate_hz == fs and log.n_samples == n
    assert [i.kind for i in log.issues.issues if i.severity == "warning"] == ["coarse_time"]
    assert abs(_arw_at_1s(log) / N_GYRO - 1.0) < 0.15  # white + flicker at τ ≈ 1 s, 10 s record
    with pytest.raises(InputError, match="samples too many, or the rate is 2000"):
        read_log(path, rate_hz=1000.0)


def test_epoch_seconds_printed_to_nine_digits_are_coarse_not_out_of_order(tmp_path):
    fs, n = 400.0, 8_000
    path = write_log(tmp_path / "epoch.csv", 1.7e9 + np.arange(n) / fs, static_imu(n, fs, 1),
                     time_fmt="{:.9g}")
    with pytest.raises(InputError, match="coarser than the sampling period"):
        read_log(path)
    assert read_log(path, rate_hz=fs).rate_hz == fs


def test_coarse_stamps_with_a_gap_the_span_shows_are_refused_at_the_given_rate(tmp_path):
    fs, n = 2000.0, 20_000
    t = np.arange(n + 400) / fs
    keep = np.r_[0:10_000, 10_400:n + 400]  # 200 ms lost
    path = write_log(tmp_path / "gap.csv", t[keep], static_imu(n, fs, 2), time_fmt="{:.3f}")
    with pytest.raises(InputError, match=r"about 40\d samples missing"):
        read_log(path, rate_hz=fs)


# --- 2. a sensor column the reader does not know, its unit written in brackets ---------------------

def test_gyro_columns_named_gx_with_a_rate_unit_are_a_warning_naming_their_mapping(tmp_path):
    fs, n = 400.0, 8_000
    ch = static_imu(n, fs, 3)
    for ax in "xyz":
        ch[f"gyro_{ax}_dps"] = np.radians(ch[f"gyro_{ax}_dps"])      # rad/s
        ch[f"accel_{ax}_mps2"] = ch[f"accel_{ax}_mps2"] / 9.80665    # g
    header = "time(s),gx(rad/s),gy(rad/s),gz(rad/s),acc_x[g],acc_y[g],acc_z[g]"
    path = write_log(tmp_path / "gx.csv", np.arange(n) / fs, ch, header=header)
    log = read_log(path)
    assert sorted(log.channels) == ["accel_x", "accel_y", "accel_z"]
    warned = {i.column: i.message for i in log.issues.issues if i.severity == "warning"}
    assert set(warned) == {"gx(rad/s)", "gy(rad/s)", "gz(rad/s)"}  # not an info note: a sensor is missing
    assert '{"columns": {"gy(rad/s)": "gyro_y_rps"}}' in warned["gy(rad/s)"]
    from budget.noise import LogMapping
    mapped = read_log(path, LogMapping(columns={f"g{a}(rad/s)": f"gyro_{a}_rps" for a in "xyz"}))
    assert np.allclose(mapped.channels["gyro_y"], ch["gyro_y_dps"], rtol=1e-8, atol=0)  # rad/s as written
    # a column whose bracket is no channel unit stays an info note
    other = write_log(tmp_path / "mag.csv", np.arange(n) / fs, {**static_imu(n, fs, 4), "mag": np.ones(n)},
                      header=HEADER + ",mag_x [uT]")
    assert [i.severity for i in read_log(other).issues.issues if i.column == "mag_x [uT]"] == ["info"]


# --- 3. a run of full-scale values (the unit knocked), below the share a noise tail is refused at --

def test_a_run_at_full_scale_is_refused_naming_its_rows_whatever_its_share(tmp_path):
    fs, n = 400.0, 8_000
    ch = static_imu(n, fs, 5)
    ch["gyro_z_dps"][3000:3030] = 500.0  # 30 samples (0.4 %) held at a ±500 deg/s range limit
    path = write_log(tmp_path / "sat.csv", np.arange(n) / fs, ch)
    with pytest.raises(InputError) as err:  # before: a warning, and a bias instability of ~10⁴ deg/h
        read_log(path)
    text = str(err.value)
    assert "gyro_z_dps" in text and "30 consecutive samples (rows 3002–3031)" in text and "500" in text
    assert read_log(path, channels=["gyro_x", "gyro_y"]).n_samples == n  # the way out it names
    ch["gyro_z_dps"][3000:3030] = static_imu(n, fs, 5)["gyro_z_dps"][3000:3030]
    ch["gyro_z_dps"][5000:5006] = -500.0  # 15 ms: past the 3-sample bursts the spike filter replaces
    with pytest.raises(InputError, match=r"6 consecutive samples \(rows 5002–5007\).*smallest value -500"):
        read_log(write_log(tmp_path / "sat6.csv", np.arange(n) / fs, ch))
    # a noise tail clipped at 3σ (isolated samples at the limit) stays a warning
    tail = static_imu(n, fs, 6)
    x = tail["gyro_y_dps"]
    limit = np.mean(x) + 3.0 * np.std(x)
    tail["gyro_y_dps"] = np.minimum(x, limit)
    log = read_log(write_log(tmp_path / "tail.csv", np.arange(n) / fs, tail))
    assert [i.kind for i in log.issues.issues if i.column == "gyro_y_dps"] == ["clipped"]


# --- 4. a whitespace-delimited log: the refusal names the delimiter, not preamble lines -----------

def test_a_space_delimited_log_is_refused_naming_the_delimiter_that_reads_it(tmp_path):
    fs, n = 400.0, 4_000
    ch = static_imu(n, fs, 7)
    path = write_log(tmp_path / "ws.txt", np.arange(n) / fs, ch, header=HEADER.replace(",", "   "), sep="   ")
    with pytest.raises(InputError) as err:
        read_log(path)
    assert '"delimiter": " "' in str(err.value) and "skip_rows" not in str(err.value)
    from budget.noise import LogMapping
    log = read_log(path, LogMapping(delimiter=" "))
    assert log.rate_hz == fs and np.allclose(log.channels["accel_z"], ch["accel_z_mps2"], rtol=1e-8)


# --- 5. a time stamp printed twice (the sample in its place), a clock reset ------------------------

def test_a_repeated_stamp_is_restamped_by_the_repair_and_a_clock_reset_names_what_it_dropped(tmp_path):
    from budget.noise import LogError

    fs, n = 400.0, 8_000
    ch = static_imu(n, fs, 8)
    t = np.arange(n) / fs
    t[4001] = t[4000]  # the logger read its clock twice; the sample is the 4002nd
    path = write_log(tmp_path / "dup.csv", t, ch)
    with pytest.raises(LogError, match=r"non_monotonic_time.*rows 4003"):
        read_log(path)
    log = read_log(path, repair=True)  # before: "would keep only 4,001 of 8,000 samples (50 %)"
    assert log.n_samples == n and log.rate_hz == fs
    assert any("re-stamped 1 row(s) whose time stamp repeated" in r and "4003" in r for r in log.issues.repairs)
    assert np.allclose(log.channels["gyro_x"], np.radians(ch["gyro_x_dps"]), rtol=1e-8)  # no sample lost
    reset = t.copy()
    reset[4001] = t[4001]
    reset[5000:] -= reset[5000]  # clock reset: a refusal that says what the repair would drop
    with pytest.raises(LogError, match=r"keep only 5,000 of 8,000.*dropped 3000 row\(s\) whose time stamp"):
        read_log(write_log(tmp_path / "reset.csv", reset, ch), repair=True)


# --- 6. '#': NumPy's savetxt header, comment lines --------------------------------------------------

def test_a_savetxt_header_and_comment_lines_are_read_or_named(tmp_path):
    fs, n = 400.0, 4_000
    ch = static_imu(n, fs, 9)
    cols = np.column_stack([np.arange(n) / fs, *ch.values()])
    path = tmp_path / "savetxt.csv"
    np.savetxt(path, cols, delimiter=",", header=HEADER, fmt="%.9g")  # "# time_s,gyro_x_dps,…"
    log = read_log(path)  # before: "no time column and no sampling rate"
    assert log.rate_hz == fs and sorted(log.channels) == sorted(c.rsplit("_", 1)[0] for c in ch)
    assert [i.kind for i in log.issues.issues] == ["header_comment_mark"]
    no_time = tmp_path / "no_time.csv"  # without a time column the first channel was dropped unsaid
    np.savetxt(no_time, cols[:, 1:], delimiter=",", header=HEADER.split(",", 1)[1], fmt="%.9g")
    assert "gyro_x" in read_log(no_time, rate_hz=fs).channels
    # comment lines: the refusal names the mapping's "comment"
    text = path.read_text().replace("# time_s", "# logger 1.2\ntime_s", 1)
    (tmp_path / "pre.csv").write_text(text)
    with pytest.raises(InputError, match='"comment": "#" skips them'):
        read_log(tmp_path / "pre.csv")
    lines = text.splitlines()
    lines.insert(100, "# resync")
    (tmp_path / "mid.csv").write_text("\n".join(lines[1:]) + "\n")
    with pytest.raises(InputError, match=r"row 100.*'#' is a comment a mapping's \"comment\": \"#\" skips"):
        read_log(tmp_path / "mid.csv")
    from budget.noise import LogMapping
    assert read_log(tmp_path / "mid.csv", LogMapping(comment="#")).n_samples == n


def test_a_blank_stamp_mid_log_is_restamped_by_the_repair_not_cut_at(tmp_path):
    fs, n = 400.0, 8_000
    ch = static_imu(n, fs, 10)
    path = write_log(tmp_path / "blank.csv", np.arange(n) / fs, ch)
    lines = open(path).read().splitlines()
    lines[4001] = "," + lines[4001].split(",", 1)[1]  # row 4002: its time cell empty
    open(path, "w").write("\n".join(lines) + "\n")
    log = read_log(path, repair=True)  # before: dropped, a gap, "would keep only 4,000 of 7,999 (50 %)"
    assert log.n_samples == n and log.rate_hz == fs
    assert any("re-stamped 1 row(s) without a time stamp" in r and "4002" in r for r in log.issues.repairs)


# --- 7. a header written by Windows (cp1252): ° and µ are one byte ------------------------------

def test_a_windows_1252_header_with_degree_and_micro_signs_is_read_in_its_units(tmp_path):
    fs, n = 400.0, 4_000
    ch = static_imu(n, fs, 11)
    for ax in "xyz":
        ch[f"accel_{ax}_mps2"] = ch[f"accel_{ax}_mps2"] / 9.80665 * 1e6  # µg
    header = ("time [s],gyro_x [°/s],gyro_y [°/s],gyro_z [°/s],accel_x [µg],accel_y [µg],accel_z [µg]")
    path = tmp_path / "win.csv"
    write_log(path, np.arange(n) / fs, ch, header=header)
    path.write_bytes(path.read_text(encoding="utf-8").encode("cp1252"))
    log = read_log(path)  # before: "unit '\ufffd/s' not understood for gyro_x; accepted: deg/s, °/s, …"
    assert log.source_units == {**{f"gyro_{a}": "dps" for a in "xyz"}, **{f"accel_{a}": "ug" for a in "xyz"}}
    assert np.allclose(log.channels["gyro_z"], np.radians(ch["gyro_z_dps"]), rtol=1e-8)
    assert np.allclose(log.channels["accel_z"], ch["accel_z_mps2"] * 9.80665e-6, rtol=1e-8)
    assert "text_encoding" in [i.kind for i in log.issues.issues]
