"""Integrity checks of an IMU log and the repairs a user may ask for.

Checks (all vectorised over the whole log): non-finite values per column, implausible
magnitudes (:data:`MAX_ABS_SI`: a single 1e300 sample is named with its row), duplicated rows,
non-increasing or jittery time stamps, gaps, constant (stuck) channels, too few samples. The
reader's checks of the values themselves (an accelerometer unit slip, stale samples, clipped
channels, an implausible temperature) are in :mod:`budget.noise.log_values`. The sampling
period comes from the stamps' span, not their median step (:func:`nominal_period`): stamps
rounded to a millisecond step unevenly at 128 or 400 Hz.
Rows are reported as spreadsheet rows of the file (header = row 1, first sample = row 2; blank
or comment lines shift this numbering).

Repairs happen only on request and every one is listed: exact duplicate rows are dropped;
a row whose stamp repeats the one before or is missing while its neighbours' stamps are two
periods apart (the sample in its place, its stamp misprinted) is given the midpoint of theirs;
other rows whose time does not increase are dropped (the first occurrence kept); rows without a time
stamp are dropped; missing channel values are linearly interpolated between neighbours; and
across gaps only the longest gap-free stretch is kept (interpolating across a gap would invent
low-noise data and bias the Allan variance). Implausible samples are treated as missing. A
repair that would keep less than :data:`MIN_KEPT_FRACTION` of the rows, or interpolate more
than 1 − :data:`MIN_KEPT_FRACTION` of a channel, is refused (ValueError naming the numbers).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd


#: Largest plausible magnitude of a sample in SI: an angular rate (rad/s, ≈ 57 000 deg/s) and a
#: specific force (m/s², ≈ 10 000 g); larger values are corrupt samples or a wrong unit.
MAX_ABS_SI = {"gyro": 1e3, "accel": 1e5}
#: A repair may drop or interpolate at most 1 − this fraction of the samples (per column);
#: a log that needs more is refused rather than turned into a short or invented record.
MIN_KEPT_FRACTION = 0.9
#: Sampling rates (Hz) outside this range mean a misread time column (e.g. ns read as s).
PLAUSIBLE_RATE_HZ = (1e-3, 1e6)
#: A step longer than this many nominal periods is a gap.
GAP_FACTOR = 1.5
#: Relative RMS jitter of the sampling period above which a warning is raised.
JITTER_WARN = 0.01
#: |mean| (rad/s) of a gyro at rest above which a warning says the unit or the record is wrong:
#: 200 deg/s, well beyond consumer MEMS turn-on biases (≤ ±75 deg/s) and Earth's rate (15 deg/h);
#: raw counts of a ±250 deg/s part (131 per deg/s) read as deg/s pass it from a 1.5 deg/s bias on.
GYRO_REST_MAX_RAD_S = math.radians(200.0)
MAX_ROWS_LISTED = 5


@dataclass(frozen=True)
class LogIssue:
    """One finding: ``severity`` is ``error`` (analysis would be wrong), ``warning`` or ``info``."""

    kind: str
    severity: str
    message: str
    count: int = 0
    rows: tuple[int, ...] = ()
    column: str | None = None

    def text(self) -> str:
        where = f" [{self.column}]" if self.column else ""
        rows = ""
        if self.rows:
            more = ", …" if self.count > len(self.rows) else ""
            rows = f" (rows {', '.join(map(str, self.rows))}{more})"
        return f"{self.severity}: {self.kind}{where}: {self.message}{rows}"



@dataclass
class LogReport:
    """All issues found in one log, and the repairs applied (empty unless asked for)."""

    issues: list[LogIssue] = field(default_factory=list)
    repairs: list[str] = field(default_factory=list)

    @property
    def errors(self) -> list[LogIssue]:
        return [i for i in self.issues if i.severity == "error"]

    @property
    def ok(self) -> bool:
        """True when no error-level issue is left (after repairs, if any)."""
        return not self.errors or bool(self.repairs)

    def summary(self) -> str:
        lines = [i.text() for i in self.issues] or ["no issues found"]
        lines += [f"repaired: {r}" for r in self.repairs]
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([{"kind": i.kind, "severity": i.severity, "column": i.column,
                              "count": i.count, "rows": list(i.rows), "message": i.message}
                             for i in self.issues])

    def to_dict(self) -> dict:
        return {"issues": [{"kind": i.kind, "severity": i.severity, "column": i.column,
                            "count": i.count, "rows": list(i.rows), "message": i.message}
                           for i in self.issues],
                "repairs": list(self.repairs)}


def listed_rows(idx: np.ndarray) -> tuple[int, ...]:
    """Data indices → spreadsheet rows (header is row 1)."""
    return tuple(int(i) + 2 for i in idx[:MAX_ROWS_LISTED])


#: Steps per window of the first period estimate (:func:`nominal_period`).
PERIOD_WINDOW = 64


def nominal_period(t: np.ndarray) -> float | None:
    """Sampling period (s) of the time stamps ``t`` (s), None when no step is positive.

    Time stamps are often rounded to a resolution near the period (integer milliseconds at
    128 Hz step by 7 or 8 ms; three decimals of a second at 400 Hz by 2 or 3 ms), so the median
    step is not the period: it read 125 Hz and 333 Hz there. First estimate: the median over
    windows of :data:`PERIOD_WINDOW` consecutive steps of their mean step (a gap spoils only
    its window; rounding errs by the resolution over a window). When the stamps increase, the
    period is then the record's span over the periods it holds — its samples less one plus
    those lost in gaps (:func:`_missing_samples`) — exact to the resolution over the span.
    """
    t = t[np.isfinite(t)]
    dt = np.diff(t)
    pos = dt[dt > 0]
    if not pos.size:
        return None
    m = min(PERIOD_WINDOW, max(1, dt.size // 8))
    win = dt[: dt.size // m * m].reshape(-1, m)
    whole = np.all(win > 0, axis=1)
    period = float(np.median(win[whole].mean(axis=1))) if whole.any() else float(np.median(pos))
    if pos.size == dt.size:  # increasing stamps: the span over the periods it holds
        gaps = np.flatnonzero(dt > GAP_FACTOR * period) + 1
        periods = dt.size + int(np.sum(np.maximum(_missing_samples(t, gaps, period), 0)))
        period = float((t[-1] - t[0]) / periods)
    return period


def stamp_resolution(dt: np.ndarray, period: float) -> float | None:
    """The resolution (s) the time stamps are rounded to when it is coarse — the steps ``dt``
    (s, gaps left out) take at most three values, ≥ 1 % of ``period`` apart — else None."""
    dt = dt[np.isfinite(dt) & (dt > 0)]
    if dt.size < 3:
        return None
    levels = np.unique(np.round(dt / period, 6))
    if not 2 <= levels.size <= 3:
        return None
    res = float(np.min(np.diff(levels))) * period
    return res if res >= 0.01 * period else None


#: Share of a log's steps that must be zero (a stamp equal to the one before on a row whose values
#: differ) for non-decreasing stamps to be read as rounded coarser than the sampling period.
COARSE_ZERO_SHARE = 0.05


#: A positive step of stamps rounded coarser than the period is a whole multiple of their
#: quantum within this fraction of it. Stamps rounded twice — float32 values (quantum 2⁻⁷ s =
#: 7.8125 ms at 86 400 s) printed to 0.1 ms — step by 0.0078 and 0.0079 s, 1.3 % apart; steps of
#: no common quantum would each pass by chance with probability 0.1, so all of a log's hundreds
#: of steps do not.
COARSE_MULTIPLE_TOL = 0.05


def coarse_resolution(t: np.ndarray, same: np.ndarray | None = None) -> float | None:
    """The resolution (s) of time stamps rounded coarser than the sampling period — integer
    milliseconds at 2 kHz step by 0 or 1 ms, seconds since the epoch printed to 9 digits by 0 or
    1 s, float32 stamps at 1 kHz from 86 400 s by 0 or 7.8 ms — or None. Such stamps never step
    back, at least :data:`COARSE_ZERO_SHARE` of their steps are zero (``same``: steps whose row
    repeats the one before entirely, duplicate rows, left out) and each positive step is a whole
    multiple of a quantum (within :data:`COARSE_MULTIPLE_TOL`: the median positive step, then
    the least-squares quantum of them all, Σ steps / Σ multiples). Read as "non-increasing
    time" they would send a user to a repair that drops half the samples."""
    dt = np.diff(t)
    if same is not None:
        dt = dt[~same]
    dt = dt[np.isfinite(dt)]
    if dt.size < 3 or np.any(dt < 0):
        return None
    pos = dt[dt > 0]
    if not pos.size or dt.size - pos.size < COARSE_ZERO_SHARE * dt.size:
        return None
    k = pos / float(np.median(pos))
    whole = np.rint(k)
    if np.any(whole < 1) or np.any(np.abs(k - whole) > COARSE_MULTIPLE_TOL):
        return None
    return float(pos.sum() / whole.sum())


def float32_stamps(t: np.ndarray, q: float) -> bool:
    """True when stamps ``t`` (s) quantised to ``q`` (s) look like float32 values: ``q`` is the
    spacing of float32 numbers (2^(⌊log₂|t|⌋ − 23), a 24-bit significand) at the stamps' largest
    magnitude, within 2 % (or at the smallest, for stamps that cross a power of two)."""
    fin = np.abs(t[np.isfinite(t) & (t != 0)])
    if not fin.size or not q > 0:
        return False
    return any(abs(q / 2.0 ** (math.floor(math.log2(m)) - 23) - 1) <= 0.02
               for m in (float(fin.max()), float(fin.min())))


def coarse_time_span_check(t: np.ndarray, q: float, rate_hz: float, column: str) -> LogIssue:
    """With a rate given for a log whose stamps are rounded to ``q`` s, coarser than its period:
    a warning when the stamps' span is what ``t.size`` samples at ``rate_hz`` span, within the
    stamps' resolution (and one period), else an error naming the samples missing (or the rate
    that is wrong)."""
    fin = t[np.isfinite(t)]
    span = float(fin[-1] - fin[0])
    expected = (t.size - 1) / rate_hz
    if abs(span - expected) <= q + 1.0 / rate_hz:
        return LogIssue("coarse_time", "warning",
                        f"time stamps rounded to {q:.3g} s, coarser than the period {1 / rate_hz:.3g} s: "
                        f"read at the given {rate_hz:.6g} Hz, which their span ({span:.6g} s) agrees with "
                        f"to their resolution; missing samples are seen only in that span, fewer than "
                        f"{q * rate_hz + 1:.0f} not at all",
                        0, (), column)
    missing = span * rate_hz - (t.size - 1)
    return LogIssue("coarse_time", "error",
                    f"time stamps rounded to {q:.3g} s span {span:.6g} s, but {t.size} samples at the given "
                    f"{rate_hz:.6g} Hz span {expected:.6g} s: about {abs(missing):.0f} samples "
                    f"{'missing (gaps)' if missing > 0 else 'too many'}, or the rate is "
                    f"{(t.size - 1) / span if span > 0 else float('nan'):.6g} Hz", 0, (), column)


def check_log(data: np.ndarray, names: tuple[str, ...], time_index: int | None,
              channel_index: dict[str, int]) -> list[LogIssue]:
    """Every integrity issue of ``data`` (rows × columns, SI already), none repaired."""
    issues: list[LogIssue] = []
    for j, name in enumerate(names):
        bad = np.flatnonzero(~np.isfinite(data[:, j]))
        if bad.size:
            issues.append(LogIssue("missing_value", "error", f"{bad.size} empty, NaN or infinite "
                                   "value(s)", int(bad.size), listed_rows(bad), name))
    for ch, j in channel_index.items():
        big = _implausible(data[:, j], ch)
        if big.size:
            issues.append(LogIssue("implausible_value", "error",
                                   f"{big.size} sample(s) beyond ±{max_abs_si(ch):g} "
                                   f"{'rad/s' if ch.startswith('gyro') else 'm/s²'} (in SI), e.g. "
                                   f"{data[big[0], j]:.3g} (corrupt sample or wrong unit?)",
                                   int(big.size), listed_rows(big), names[j]))
    if time_index is not None:
        issues += _time_issues(data, time_index)
    for ch, j in channel_index.items():
        col = data[:, j]
        fin = col[np.isfinite(col)]
        if fin.size > 1 and fin.min() == fin.max():
            issues.append(LogIssue("constant_channel", "warning",
                                   f"all samples equal {fin[0]:.6g} (stuck or unused sensor); "
                                   "it carries no noise to analyse", int(fin.size), (), names[j]))
        elif ch.startswith("gyro") and fin.size and abs(float(fin.mean())) > GYRO_REST_MAX_RAD_S:
            issues.append(LogIssue("gyro_rate_at_rest", "warning",
                                   f"mean {math.degrees(float(fin.mean())):.4g} deg/s on a static log, "
                                   f"beyond any gyro's turn-on bias (≤ {math.degrees(GYRO_REST_MAX_RAD_S):g} "
                                   "deg/s): raw counts without their scale, another unit, or a turning "
                                   "unit? every noise figure of this channel scales with its unit",
                                   int(fin.size), (), names[j]))
    return issues


def max_abs_si(channel: str) -> float:
    """:data:`MAX_ABS_SI` of ``channel`` (``gyro_*``: rad/s, else m/s²)."""
    return MAX_ABS_SI["gyro" if channel.startswith("gyro") else "accel"]


def _implausible(col: np.ndarray, channel: str) -> np.ndarray:
    """Indices of finite samples whose magnitude exceeds :data:`MAX_ABS_SI` for ``channel``."""
    with np.errstate(invalid="ignore"):
        return np.flatnonzero(np.isfinite(col) & (np.abs(col) > max_abs_si(channel)))


def check_header(names: list[str], path) -> list[str]:
    """``names`` unchanged, or :class:`InputError` if the reader had to rename a repeated column
    (pandas turns a second ``gyro_x_dps`` into ``gyro_x_dps.1``)."""
    from ..errors import InputError

    seen = set(names)
    for n in names:
        base, dot, num = n.rpartition(".")
        if dot and num.isdigit() and base in seen:
            raise InputError(f"column {base!r} appears more than once in the header", file=path,
                             row=1, field=base, expected="each column name once")
    return names


def check_rate(rate_hz: float, source: str = "time stamps") -> str | None:
    """Why ``rate_hz`` cannot be a sampling rate (None if it can): outside
    :data:`PLAUSIBLE_RATE_HZ`, usually a time column in another unit than its name says."""
    lo, hi = PLAUSIBLE_RATE_HZ
    if lo <= rate_hz <= hi:
        return None
    return (f"the {source} give a sampling rate of {rate_hz:.3g} Hz, outside {lo:g} … {hi:g} Hz; "
            "is the time column in another unit? name it time_s, time_ms, time_us or time_ns "
            "after its unit")


#: Samples on each side of a long time step whose stamps place it on the nominal grid.
GRID_SAMPLES = 16


def _missing_samples(t: np.ndarray, steps: np.ndarray, period: float) -> np.ndarray:
    """Samples missing at each long step (data index ``steps``: the first sample after it): the
    offset of the stamps from the nominal grid, t_j − j·period, by its median over the
    :data:`GRID_SAMPLES` samples after the step minus the median over those before, in periods,
    rounded. A lost sample moves every later stamp by one period; jitter moves one stamp, and a
    step made long by it is followed by a short one (0 missing). Local medians, so a slow clock
    drift over the record does not count.

    Stamps rounded coarser than half the period make many ordinary steps long (2 ms stamps at
    400 Hz step by 0.8 or 1.6 periods), and each within :data:`GRID_SAMPLES` of a gap saw the
    gap's shift in its window — one gap was counted as several, its samples as many times. Long
    steps that see a shift and lie closer than that to one another are one stretch: its loss is
    measured once (before its first step, after its last) and given to its steps that are gaps
    on their own (≥ 2.5 periods, more than rounding finer than a period can make of one period),
    largest first, each its own length at most; what is left, or all when no step is that
    long, goes to the longest step (:func:`_share_loss`)."""
    steps = np.asarray(steps, dtype=np.int64)
    out = _grid_shifts(t, steps, period)
    seen = np.flatnonzero(out != 0)
    start = 0
    while start < seen.size:
        stop = start
        while stop + 1 < seen.size and steps[seen[stop + 1]] - steps[seen[stop]] < GRID_SAMPLES:
            stop += 1
        if stop > start:
            group = seen[start:stop + 1]
            total = _grid_shift(t, int(steps[group[0]]), int(steps[group[-1]]), period)
            out[group] = _share_loss(t, steps[group], total, period)
        start = stop + 1
    return out


#: Long steps whose windows are taken at once by :func:`_grid_shifts` (bounds its memory).
_SHIFT_BATCH = 1 << 16


def _grid_shifts(t: np.ndarray, steps: np.ndarray, period: float) -> np.ndarray:
    """:func:`_grid_shift` of each step alone, vectorised over the steps whose two windows are
    whole and finite (coarse stamps make a quarter of the steps long: one Python loop over
    them took 10 s per 10⁶ rows); the others one by one."""
    out = np.zeros(steps.size, dtype=np.int64)
    w, n = GRID_SAMPLES, t.size
    inner = np.flatnonzero((steps >= w) & (steps + w <= n))
    done = np.zeros(steps.size, dtype=bool)
    if inner.size:
        windows = np.lib.stride_tricks.sliding_window_view(t - np.arange(n) * period, w)
        for a in range(0, inner.size, _SHIFT_BATCH):
            sel = inner[a:a + _SHIFT_BATCH]
            with np.errstate(invalid="ignore"):
                shift = (np.median(windows[steps[sel]], axis=1)
                         - np.median(windows[steps[sel] - w], axis=1)) / period
            ok = np.isfinite(shift)  # a window with a missing stamp: one by one below
            out[sel[ok]] = np.rint(shift[ok]).astype(np.int64)
            done[sel[ok]] = True
    for i in np.flatnonzero(~done):
        out[i] = _grid_shift(t, int(steps[i]), int(steps[i]), period)
    return out


def _grid_shift(t: np.ndarray, first: int, last: int, period: float) -> int:
    """Periods by which the stamps' offset from the grid, t_j − j·period, moves between the
    :data:`GRID_SAMPLES` samples before data index ``first`` and those from ``last`` on (medians;
    from the two stamps alone when a side has none)."""
    a, b = max(0, first - GRID_SAMPLES), min(t.size, last + GRID_SAMPLES)
    before = t[a:first] - np.arange(a, first) * period
    after = t[last:b] - np.arange(last, b) * period
    before, after = before[np.isfinite(before)], after[np.isfinite(after)]
    if before.size and after.size:
        return int(np.rint((np.median(after) - np.median(before)) / period))
    return int(np.rint((t[last] - t[first - 1]) / period)) - (last - first + 1)


def _share_loss(t: np.ndarray, steps: np.ndarray, total: int, period: float) -> np.ndarray:
    """``total`` lost samples of a stretch of close long ``steps`` given to those steps (see
    :func:`_missing_samples`): a step of ≥ 2.5 periods is a gap by itself and takes up to its own
    length less one period, largest first; the rest goes to the longest step."""
    out = np.zeros(steps.size, dtype=np.int64)
    if total <= 0:
        return out
    with np.errstate(invalid="ignore"):
        own = np.rint((t[steps] - t[steps - 1]) / period) - 1
    own = np.where(np.isfinite(own), own, 0).astype(np.int64)
    order = np.argsort(-own, kind="stable")
    left = total
    for i in order:
        if own[i] < 2 or left <= 0:
            break
        out[i] = min(int(own[i]), left)
        left -= out[i]
    out[order[0]] += left
    return out


def _time_issues(data: np.ndarray, ti: int) -> list[LogIssue]:
    issues: list[LogIssue] = []
    t = data[:, ti]
    if t.size < 2:
        return issues
    dt = np.diff(t)
    same = np.all((data[1:] == data[:-1]) | (np.isnan(data[1:]) & np.isnan(data[:-1])), axis=1)
    dup = np.flatnonzero(same) + 1
    if dup.size:
        issues.append(LogIssue("duplicate_rows", "error", f"{dup.size} row(s) repeat the previous "
                               "row exactly", int(dup.size), listed_rows(dup), None))
    q = coarse_resolution(t, same)
    if q is not None:  # rounded coarser than the period: zero steps are no disorder, no gap is seen
        zero = np.flatnonzero((dt == 0) & ~same) + 1
        fin = t[np.isfinite(t)]
        span = float(fin[-1] - fin[0])
        said = f" (≈ {(fin.size - 1) / span:.6g} Hz from their span)" if span > 0 else ""
        why = (f" — float32 stamps: a 24-bit significand resolves {q * 1e3:.3g} ms at "
               f"{float(np.max(np.abs(fin))):.6g} s" if float32_stamps(fin, q) else "")
        issues.append(LogIssue("coarse_time", "error",
                               f"time stamps are rounded to {q:.3g} s, coarser than the sampling "
                               f"period{said}{why}: {zero.size} of {dt.size} steps are zero, so the "
                               "samples' rate, order and gaps cannot be read from them",
                               int(zero.size), listed_rows(zero), "time"))
        return issues
    back = np.flatnonzero((dt <= 0) & ~same) + 1
    if back.size:
        issues.append(LogIssue("non_monotonic_time", "error",
                               f"{back.size} time stamp(s) not after the previous one",
                               int(back.size), listed_rows(back), "time"))
    period = nominal_period(t)
    if period is None:
        return issues
    # Forward step from the latest earlier time: a stray out-of-order row is not also a gap.
    fwd = t[1:] - np.fmax.accumulate(t)[:-1]
    fin = np.isfinite(fwd)
    gaps = np.flatnonzero(fin & (fwd > GAP_FACTOR * period)) + 1
    lost_at = _missing_samples(t, gaps, period)
    gaps, lost_at = gaps[lost_at > 0], lost_at[lost_at > 0]  # a long step followed by a short one is jitter
    if gaps.size:
        lost = int(np.sum(lost_at))
        issues.append(LogIssue("gap", "error", f"{gaps.size} gap(s) longer than {GAP_FACTOR}× the "
                               f"period {period:.6g} s (about {lost} samples missing)",
                               int(gaps.size), listed_rows(gaps), "time"))
    normal = np.delete(dt, gaps - 1)
    normal = normal[np.isfinite(normal) & (normal > 0)]
    if normal.size > 2:
        jitter = float(np.std(normal) / period)
        res = stamp_resolution(normal, period)
        if res is not None:
            issues.append(LogIssue("stamp_resolution", "info", f"time stamps are rounded to "
                                   f"{res:.3g} s ({100 * res / period:.2g} % of the period {period:.6g} s): "
                                   "their steps vary by that much; the rate is taken from their span",
                                   int(normal.size), (), "time"))
        elif jitter > JITTER_WARN:
            issues.append(LogIssue("jitter", "warning", f"sampling period varies by {100 * jitter:.2g} % "
                                   "RMS; the analysis assumes uniform sampling at the nominal rate",
                                   int(normal.size), (), "time"))
    return issues


def _misprinted_stamps(t: np.ndarray, same: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Data indices of rows whose stamp is wrong while the sample is in its place on the grid —
    the neighbours' stamps lie two nominal periods apart (within half a period): (rows whose stamp
    repeats the previous one on a row that is no duplicate — a logger's clock read twice —, rows
    whose stamp is missing). Dropping such a row would open a one-sample gap, and the repair
    would then keep only one side of it."""
    none = np.zeros(0, dtype=np.int64)
    n = t.size
    if n < 3:
        return none, none
    period = nominal_period(t)
    if period is None:
        return none, none
    i = np.arange(1, n - 1)
    with np.errstate(invalid="ignore"):
        placed = np.abs(t[i + 1] - t[i - 1] - 2.0 * period) < 0.5 * period
        repeated = (t[i] == t[i - 1]) & ~same[i] & placed
    blank = ~np.isfinite(t[i]) & placed
    return i[repeated], i[blank]


def repair_log(data: np.ndarray, names: tuple[str, ...], time_index: int | None,
               channel_index: dict[str, int]) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Apply the documented repairs; returns (data, kept original indices, what was done)."""
    done: list[str] = []
    n_in = data.shape[0]
    keep = np.arange(n_in)
    data = np.array(data, float, copy=True)
    for ch, j in channel_index.items():
        big = _implausible(data[:, j], ch)
        if big.size:
            data[big, j] = np.nan  # corrupt samples: treated as missing (interpolated below)
            done.append(f"treated {big.size} implausible sample(s) of {names[j]} as missing")
    if time_index is not None:
        t = data[:, time_index]
        same = np.zeros(data.shape[0], bool)
        same[1:] = np.all((data[1:] == data[:-1]) | (np.isnan(data[1:]) & np.isnan(data[:-1])), axis=1)
        if same.any():
            done.append(f"dropped {int(same.sum())} exact duplicate row(s)")
        repeated, blank = _misprinted_stamps(t, same)
        for rows, what in ((repeated, "whose time stamp repeated the one before"),
                           (blank, "without a time stamp")):
            if rows.size:
                t[rows] = 0.5 * (t[rows - 1] + t[rows + 1])  # t: a view of the repaired copy
                more = ", …" if rows.size > MAX_ROWS_LISTED else ""
                done.append(f"re-stamped {rows.size} row(s) {what} while their neighbours' stamps are "
                            "two periods apart (the sample in its place on the grid): given the midpoint "
                            f"of those stamps (rows {', '.join(map(str, listed_rows(rows)))}{more})")
        nan_t = ~np.isfinite(t)
        if nan_t.any():
            done.append(f"dropped {int(nan_t.sum())} row(s) without a time stamp")
        ok = ~same & ~nan_t
        # Keep a row only if its time is after every earlier kept time (first occurrence wins).
        tt = np.where(ok, t, -np.inf)
        prev_max = np.maximum.accumulate(np.concatenate(([-np.inf], tt[:-1])))
        back = ok & (t <= prev_max)
        if back.any():
            done.append(f"dropped {int(back.sum())} row(s) whose time stamp did not increase")
        keep = np.flatnonzero(ok & ~back)
        data = data[keep]
    for j, name in enumerate(names):
        if j == time_index:
            continue
        col = data[:, j]
        bad = ~np.isfinite(col)
        if bad.any():
            good = np.flatnonzero(~bad)
            if good.size == 0:
                raise ValueError(f"column {name} has no finite value to interpolate from")
            if bad.sum() > (1.0 - MIN_KEPT_FRACTION) * col.size:
                raise ValueError(f"column {name} would need {int(bad.sum())} of {col.size} values "
                                 f"({100 * bad.mean():.3g} %) interpolated; a repair may invent at "
                                 f"most {100 * (1 - MIN_KEPT_FRACTION):.0f} % of a channel")
            col[bad] = np.interp(np.flatnonzero(bad), good, col[good])
            done.append(f"interpolated {int(bad.sum())} missing value(s) in {name} linearly "
                        "between neighbouring samples")
    if time_index is not None and data.shape[0] > 2:
        t = data[:, time_index]
        period = nominal_period(t)
        if period is not None:
            breaks = np.flatnonzero(np.diff(t) > GAP_FACTOR * period) + 1
            breaks = breaks[_missing_samples(t, breaks, period) > 0]  # not the jitter of one stamp
            if breaks.size:
                edges = np.concatenate(([0], breaks, [t.size]))
                k = int(np.argmax(np.diff(edges)))
                a, b = int(edges[k]), int(edges[k + 1])
                done.append(f"kept the longest gap-free stretch, rows {int(keep[a]) + 2}–"
                            f"{int(keep[b - 1]) + 2} ({b - a} of {t.size} samples), across "
                            f"{breaks.size} gap(s)")
                data, keep = data[a:b], keep[a:b]
    if data.shape[0] < MIN_KEPT_FRACTION * n_in:
        raise ValueError(f"the repair would keep only {data.shape[0]:,} of {n_in:,} samples "
                         f"({100 * data.shape[0] / max(n_in, 1):.3g} %), less than the "
                         f"{100 * MIN_KEPT_FRACTION:.0f} % a repair may keep at least ("
                         + "; ".join(done) + "); fix the log or analyse its parts separately")
    return data, keep, done
