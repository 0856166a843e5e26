"""Checks the log reader makes on a log's values, beyond its integrity (:mod:`budget.noise.log_checks`):
an accelerometer unit slip read off gravity (:func:`gravity_unit_slip`, :func:`gravity_unchecked`),
stale samples (rows repeating every sensor value, :func:`stale_samples`), channels clipped at a
range limit (:func:`clipped`) and a temperature outside what an IMU can hold
(:func:`implausible_temperature`). Each returns the refusal (an :class:`~budget.errors.InputError`
naming the file and columns) or the findings (:class:`~budget.noise.log_checks.LogIssue`).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import LOG_CHANNEL_WAY, InputError
from ..units import G0
from .log_checks import LogIssue, listed_rows

#: Temperatures (°C) an IMU log can hold; outside, the column's unit is probably not what it says.
TEMP_PLAUSIBLE_C = (-80.0, 200.0)


def implausible_temperature(temp_c: np.ndarray, column: str) -> list[LogIssue]:
    """A warning when the temperature (°C) leaves :data:`TEMP_PLAUSIBLE_C` (a unit misread:
    kelvin written without a unit reads ≈ 300 °C), else none."""
    lo, hi = float(np.nanmin(temp_c)), float(np.nanmax(temp_c))
    if TEMP_PLAUSIBLE_C[0] <= lo and hi <= TEMP_PLAUSIBLE_C[1]:
        return []
    return [LogIssue("implausible_temperature", "warning",
                     f"temperature spans {lo:.4g} … {hi:.4g} °C, outside {TEMP_PLAUSIBLE_C[0]:g} … "
                     f"{TEMP_PLAUSIBLE_C[1]:g} °C: is its unit right (°C, K, °F in brackets)?", 0, (), column)]


#: |mean specific force| of a static log ÷ g → what the accelerometer unit most likely was
_GRAVITY_UNIT_SLIPS = ((1.0 / G0, "g read as m/s²"), (G0, "m/s² read as g"), (1000.0, "mg read as g"))


def gravity_unit_slip(data: np.ndarray, channel_index: dict[str, int], source_units: dict[str, str],
                      path) -> InputError | None:
    """A static log's three accelerometers read gravity: a mean magnitude off by the factor of
    a unit slip (g ↔ m/s², mg ↔ g, within 25 %) means the columns carry another unit than their
    names say — every noise figure would be off by that factor; so does any other magnitude
    above 1.25 g (e.g. raw counts without their scale), as it does for one or two axes. Below
    gravity nothing is refused (a log may have had gravity removed). The error, or None."""
    axes = tuple(a for a in ("accel_x", "accel_y", "accel_z") if a in channel_index)
    if not axes:
        return None
    with np.errstate(invalid="ignore"):
        mean = np.array([np.nanmean(data[:, channel_index[a]]) for a in axes])
    ratio = float(np.linalg.norm(mean)) / G0
    if len(axes) < 3:  # part of gravity only: a magnitude above it is impossible at rest
        if math.isfinite(ratio) and ratio > 1.25:
            unit = source_units.get(axes[0], "?")
            return InputError(f"at rest {', '.join(axes)} read |mean| = {ratio:.3g} g, more than gravity: "
                              f"the values are not in {unit}", file=path,
                              field=", ".join(f"{a}_{unit}" for a in axes),
                              expected="at most ≈ 9.81 m/s² (1 g) at rest; name the columns after their "
                              "unit (accel_x_mps2 | accel_x_g | accel_x_mg) or fix the mapping's scale")
        return None
    unit = source_units.get("accel_x", "?")
    for factor, slip in _GRAVITY_UNIT_SLIPS:
        if math.isfinite(ratio) and 0.8 < ratio / factor < 1.25:
            return InputError(f"at rest the accelerometers read |mean| = {ratio * G0:.4g} m/s², "
                              f"{ratio:.3g} g: the values look like {slip}", file=path,
                              field=f"accel_x_{unit} … accel_z_{unit}",
                              expected="≈ 9.81 m/s² of gravity; name the columns after their unit "
                              "(accel_x_mps2 | accel_x_g | accel_x_mg) or fix the mapping's scale")
    if math.isfinite(ratio) and ratio > 1.25:
        # three axes see all of gravity: more than 1.25 g at rest is another unit (raw counts of
        # a ±2 g part read as m/s² give 16384 m/s², 1670 g) — every figure off by that factor
        return InputError(f"at rest the accelerometers read |mean| = {ratio * G0:.4g} m/s², "
                          f"{ratio:.3g} g, more than gravity: the values are not in {unit} (raw "
                          "counts without their scale?)", file=path,
                          field=f"accel_x_{unit} … accel_z_{unit}",
                          expected="≈ 9.81 m/s² (1 g) at rest; name the columns after their unit "
                          "(accel_x_mps2 | accel_x_g | accel_x_mg) or give the mapping's scale "
                          "(counts → unit)")
    return None


def gravity_unchecked(channel_index: dict[str, int], source_units: dict[str, str]) -> LogIssue | None:
    """An info note when a log has one or two accelerometers: their unit can be refused only
    when they read more than gravity (:func:`gravity_unit_slip`); values in g labelled m/s²
    (1 g reads 1.0, a tilted axis as much) cannot be told from a tilted axis in m/s²."""
    axes = [a for a in ("accel_x", "accel_y", "accel_z") if a in channel_index]
    if not axes or len(axes) == 3:
        return None
    unit = source_units.get(axes[0], "?")
    return LogIssue("unit_unchecked", "info",
                    f"the accelerometer unit ({unit}) is checked against gravity only with all three "
                    f"axes; with {', '.join(axes)} alone a log in g labelled m/s² (or the reverse, below "
                    "1 g) cannot be caught — every accelerometer figure would be off by 9.81×", 0, (),
                    axes[0])


#: Rows whose sensor values all repeat the previous row, beyond :data:`STALE_CHANCE` times what
#: independent channels give by chance, that make a log refused as holding stale samples: at
#: least this share of the rows (and :data:`STALE_MIN_ROWS` rows).
STALE_SHARE = 0.01
STALE_MIN_ROWS = 10
STALE_CHANCE = 3.0


def stale_samples(data: np.ndarray, names: tuple[str, ...], time_index: int | None,
                  channel_index: dict[str, int], path) -> InputError | None:
    """The error for a log whose rows repeat the previous row's sensor values while the time
    goes on — a logger that reads faster than the sensor updates writes each sample again: a
    200 Hz log of a 100 Hz sensor made the fitted ARW 0.87× the sensor's, a 100 Hz loop missing
    30 % of the updates 1.14× — or None.

    Each channel alone repeats by chance on a coarse lattice (the ADIS16405's accelerometers
    hold 26–37 % of their values), so with ≥ 2 sensor channels the rows where *all* repeat are
    compared with the product of the channels' own repeat shares (independent channels):
    refused when they are at least :data:`STALE_SHARE` of the rows, :data:`STALE_MIN_ROWS`
    rows and :data:`STALE_CHANCE` × that product (the ADIS16405 logs: 1 and 2 such rows in 10⁶). Rows that
    repeat the time stamp too are duplicate rows, reported by :func:`check_log`."""
    cols = list(channel_index.values())
    n = data.shape[0]
    if len(cols) < 2 or n < 3:
        return None
    x = data[:, cols]
    same = x[1:] == x[:-1]
    every = same.all(axis=1)
    if time_index is not None:
        every &= ~(data[1:, time_index] == data[:-1, time_index])
    count = int(every.sum())
    chance = float(np.prod(same.mean(axis=0)))
    if count < max(STALE_MIN_ROWS, STALE_SHARE * (n - 1)) or count < STALE_CHANCE * chance * (n - 1):
        return None
    rows = ", ".join(map(str, listed_rows(np.flatnonzero(every) + 1)))
    return InputError(f"{count} of {n} rows ({100 * count / n:.3g} %) repeat every sensor value of the "
                      f"row before (rows {rows}, …), where independent noise would repeat "
                      f"{100 * chance:.2g} % — stale samples: the logger read faster than the sensor "
                      "updates? every noise figure of this log would be off",
                      file=path, field=", ".join(names[j] for j in cols),
                      expected="one new sensor sample per row: log at the sensor's output rate (or keep "
                               "only the rows where the values change, with their own time stamps)")


#: A channel whose largest (smallest) value holds at least this share of its samples, piled up
#: beyond its neighbour value, is clipped: refused (fewer such samples: a warning).
CLIP_SHARE = 0.01
#: Samples at one extreme, and times the count of the next value inward, that make a pile-up.
CLIP_MIN_SAMPLES = 10
CLIP_PILE = 3.0
#: Distinct values a channel needs for a pile-up to mean clipping (not a coarse lattice).
CLIP_MIN_LEVELS = 8


#: Consecutive samples at a channel's extreme value that make it saturated whatever their share
#: of the record (a unit knocked against a ±500 deg/s range limit for 22 ms, 9 samples at 400 Hz,
#: read an ARW of 15.6 deg/√h for 0.2 and a bias instability of 8.7·10³ deg/h with only a misfit
#: warning): one more than the burst of adjacent spikes :mod:`budget.noise.spikes` replaces (3) …
CLIP_RUN = 4
#: … when the value held lies beyond this many robust standard deviations of the channel: no
#: Gaussian tail reaches 8 σ in 10¹⁴ samples, let alone in a run of one repeated value (a run nearer
#: the noise, such as a light knock, stays a warning).
CLIP_RUN_SIGMAS = 8.0


def _longest_run(mask: np.ndarray) -> tuple[int, int]:
    """(start, stop) data indices of the longest run of True in ``mask`` ((0, 0) when none)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    if not edges.size:
        return 0, 0
    starts, stops = edges[::2], edges[1::2]
    i = int(np.argmax(stops - starts))
    return int(starts[i]), int(stops[i])


def clipped(data: np.ndarray, names: tuple[str, ...], channel_index: dict[str, int], path,
            factors: tuple[float, ...] | None = None) -> tuple[InputError | None, list[LogIssue]]:
    """Channels clipped at a range limit (a sensor or ADC at full scale, a logger's integer
    limit): the largest or smallest value is held by at least :data:`CLIP_MIN_SAMPLES` samples
    and :data:`CLIP_PILE` × the next value inward, on a channel with at least
    :data:`CLIP_MIN_LEVELS` distinct values (a noise distribution thins towards its extremes;
    clipping piles the tail beyond the limit onto it). A white gyro clipped at 1.5 σ read an ARW
    0.88× its own. A run of :data:`CLIP_RUN` consecutive samples there, beyond
    :data:`CLIP_RUN_SIGMAS` robust σ of the channel, is an error whatever its share (a held,
    saturated input, not a noise tail). ``factors``: each column's factor to SI, to state the value in the column's
    own unit. (error for the first channel with at least :data:`CLIP_SHARE` of its samples there,
    or None; warnings for the others)."""
    warn: list[LogIssue] = []
    for ch, j in channel_index.items():
        col = data[:, j]
        col = col[np.isfinite(col)]
        if col.size < CLIP_MIN_SAMPLES:
            continue
        values, counts = np.unique(col, return_counts=True)
        if values.size < CLIP_MIN_LEVELS:
            continue
        med = float(np.median(col))
        spread = 1.4826 * float(np.median(np.abs(col - med)))
        for end, inner, side in ((-1, -2, "largest"), (0, 1, "smallest")):
            k = int(counts[end])
            shown = values[end] / factors[j] if factors else values[end]
            if k >= CLIP_RUN and spread > 0 and abs(values[end] - med) > CLIP_RUN_SIGMAS * spread:
                a, b = _longest_run(data[:, j] == values[end])
                if b - a >= CLIP_RUN:  # held far beyond the noise, not a tail: any share spoils the channel
                    return InputError(f"{b - a} consecutive samples (rows {a + 2}–{b + 1}) sit at the "
                                      f"channel's {side} value {shown:.6g}, of {k} there in all — saturated "
                                      "(the unit knocked or moved, the sensor at its range limit): every noise "
                                      "figure of this channel would be off", file=path, field=names[j],
                                      expected=f"a static log without the event (its rows before row {a + 2}, "
                                      f"or a new record), or {LOG_CHANNEL_WAY.cli}"), warn
            if k < CLIP_MIN_SAMPLES or k < CLIP_PILE * counts[inner]:
                continue
            share = k / col.size
            text = (f"{k} of {col.size} samples ({100 * share:.3g} %) sit at the channel's {side} value "
                    f"{shown:.6g}, {k / counts[inner]:.3g}× the next value inward — clipped at a "
                    "range limit (sensor full scale, saturated ADC)?")
            if share >= CLIP_SHARE:
                return InputError(text + " every noise figure of this channel would be off", file=path,
                                  field=names[j], expected="a static log within the sensor's range (a "
                                  f"larger range setting), or {LOG_CHANNEL_WAY.cli}"), warn
            rows = np.flatnonzero(data[:, j] == values[end])
            warn.append(LogIssue("clipped", "warning", text, k, listed_rows(rows), names[j]))
    return None, warn
