"""Time columns from integer counters that wrap (a 32-bit µs timer, a 16-bit ms timer), written
here by their own generator: the true time in whole counts, jittered, taken modulo 2ᵇ. The
reader must read them as increasing time — the same record as with the counter never wrapping —
and must still refuse a logger restart (its counter back to 0 at an arbitrary count)."""

from __future__ import annotations

import numpy as np
import pytest

from budget.errors import InputError
from budget.noise import allan_deviation, read_log
from test_user_log_audit import static_imu, write_log

FS = 100.0


def _stamps(n: int, counts_per_s: float, start: int, rng) -> np.ndarray:
    """Whole counts of a timer sampled at FS with ±20 % of a period's jitter, from ``start``."""
    period = counts_per_s / FS
    jitter = np.round(rng.uniform(-0.2, 0.2, n) * period)
    return start + np.round(np.arange(n) * period) + jitter


def _header(time_col: str) -> str:
    return time_col + ",gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"


def test_32_bit_microsecond_counter_wrap_reads_as_the_unwrapped_record(tmp_path):
    rng = np.random.default_rng(11)
    n = int(20 * 60 * FS)
    ch = static_imu(n, FS, seed=3)
    true = _stamps(n, 1e6, 2**32 - 600_000_000, rng)  # wraps 10 min in
    wrapped = np.mod(true, 2**32)
    assert np.sum(np.diff(wrapped) < 0) == 1
    plain = read_log(write_log(tmp_path / "plain.csv", true, ch, time_fmt="{:.0f}", header=_header("time_us")))
    log = read_log(write_log(tmp_path / "wrap.csv", wrapped, ch, time_fmt="{:.0f}", header=_header("time_us")))
    assert not log.issues.errors
    note = next(i for i in log.issues.issues if i.kind == "counter_wrap")
    assert note.severity == "info" and note.count == 1 and "32-bit" in note.message
    wrap_row = int(np.flatnonzero(np.diff(wrapped) < 0)[0]) + 1 + 2   # first sample after it, header row 1
    assert note.rows == (wrap_row,)
    assert log.n_samples == plain.n_samples == n
    assert log.rate_hz == pytest.approx(plain.rate_hz, rel=1e-12)
    assert log.rate_hz == pytest.approx(FS, rel=1e-4)
    a = allan_deviation(log.channels["gyro_x"], log.rate_hz, "octave")
    b = allan_deviation(plain.channels["gyro_x"], plain.rate_hz, "octave")
    np.testing.assert_allclose(a.adev, b.adev, rtol=1e-12)


def test_16_bit_millisecond_counter_wraps_every_65_s(tmp_path):
    rng = np.random.default_rng(5)
    n = int(5 * 60 * FS)
    ch = static_imu(n, FS, seed=4)
    true = _stamps(n, 1e3, 12_345, rng)
    wrapped = np.mod(true, 2**16)
    log = read_log(write_log(tmp_path / "ms16.csv", wrapped, ch, time_fmt="{:.0f}", header=_header("time_ms")))
    note = next(i for i in log.issues.issues if i.kind == "counter_wrap")
    assert note.count == int(np.sum(np.diff(wrapped) < 0)) == 4
    assert "16-bit" in note.message
    assert log.rate_hz == pytest.approx(FS, rel=1e-3)
    assert log.n_samples == n


def test_a_counter_reset_is_not_read_as_a_wrap(tmp_path):
    rng = np.random.default_rng(2)
    n = int(4 * 60 * FS)
    ch = static_imu(n, FS, seed=5)
    t = _stamps(n, 1e6, 1_700_000_000, rng)
    t[n // 2:] -= t[n // 2]  # the logger restarted: its timer from 0 again
    with pytest.raises(InputError) as err:
        read_log(write_log(tmp_path / "reset.csv", t, ch, time_fmt="{:.0f}", header=_header("time_us")))
    assert "not after the previous one" in str(err.value)
    assert f"row {n // 2 + 2}" in str(err.value) or f"rows {n // 2 + 2}" in str(err.value)


def test_fractional_seconds_that_step_back_are_not_a_counter(tmp_path):
    """A time_s column with decimals is no counter, whatever its values: a step back stays one."""
    rng = np.random.default_rng(9)
    n = int(2 * 60 * FS)
    ch = static_imu(n, FS, seed=6)
    t = np.arange(n) / FS + 65535.0 - 30.0
    t[n // 2:] -= 65536.0 - 1 / FS  # would look like a 16-bit wrap if read as whole counts
    with pytest.raises(InputError) as err:
        read_log(write_log(tmp_path / "s.csv", t + rng.uniform(0, 1e-4, n), ch))
    assert "not after the previous one" in str(err.value)
