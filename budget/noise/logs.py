"""Read an IMU log CSV (canonical or mapped layout) into SI arrays, in bounded memory.

The file is parsed by pandas in chunks straight into one preallocated column-major float64
array (size estimated from the file, grown by 1.5× if the estimate was short), so a 10⁷-row
log at 1 kHz needs about 8 bytes × rows × columns plus one chunk — never a full DataFrame of
text. Each chunk is validated as it arrives (non-numeric cells are reported with their row).
Then :func:`~budget.noise.log_checks.check_log` looks for missing values, duplicated rows,
time stamps that go back, gaps, jitter and stuck channels. Problems that would make an analysis
wrong raise :class:`LogError` (an :class:`~budget.errors.InputError` carrying the full report)
unless ``repair=True``, in which case the documented repairs are applied and listed.
The file itself is only ever read.
"""

from __future__ import annotations

import csv
import gzip
import io
import math
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import LOG_CHANNEL_WAY, LOG_MAPPING_WAY, LOG_RATE_WAY, LOG_TIME_UNIT_WAY, REPAIR_WAY, InputError
from ..fileio import (EIGHT_BIT_CODEC, check_input_file, compression_of, input_encoding, open_input,
                      require_file)
from ..units import CHANNELS
from . import log_checks as lc
from . import log_values as lv
from .log_clock import ClockColumn, clock_kind, is_clock_text
from .log_counter import unwrap_counter
from .log_mapping import (ColumnPlan, LogMapping, clock_candidates, mapping_by_column, plan_columns,
                          time_unit_hint, unread_channel)

CHUNK_ROWS = 250_000


class LogError(InputError):
    """A log with error-level issues; ``.report`` holds every finding."""

    def __init__(self, message: str, report: lc.LogReport, **kw):
        self.report = report
        super().__init__(message, **kw)


@dataclass
class ImuLog:
    """An IMU log in SI: ``channels['gyro_x']`` in rad/s, ``channels['accel_x']`` in m/s²."""

    source: str
    channels: dict[str, np.ndarray]
    rate_hz: float
    time_s: np.ndarray | None
    temp_c: np.ndarray | None
    issues: lc.LogReport
    source_units: dict[str, str]

    @property
    def n_samples(self) -> int:
        return int(next(iter(self.channels.values())).size)

    @property
    def duration_s(self) -> float:
        return self.n_samples / self.rate_hz

    def summary(self) -> str:
        head = (f"{self.source}: {self.n_samples} samples at {self.rate_hz:.6g} Hz "
                f"({self.duration_s:.6g} s); channels "
                + ", ".join(f"{c} [{self.source_units[c]}]" for c in self.channels)
                + ("; temperature" if self.temp_c is not None else ""))
        return head + "\n" + self.issues.summary()

    def to_dict(self) -> dict:
        """JSON-ready description of the log (source, rate, samples, channels with their source
        units, the checks' report); the samples themselves are in :meth:`to_frame`."""
        return {"source": self.source, "rate_hz": float(self.rate_hz), "n_samples": self.n_samples,
                "duration_s": float(self.duration_s), "channels": list(self.channels),
                "source_units": dict(self.source_units), "temperature": self.temp_c is not None,
                "issues": self.issues.to_dict()}

    def to_frame(self) -> pd.DataFrame:
        """Channels in SI (rad/s, m/s²), indexed by time in seconds."""
        t = self.time_s if self.time_s is not None else np.arange(self.n_samples) / self.rate_hz
        cols = {f"{c}_{'rps' if c.startswith('gyro') else 'mps2'}": v for c, v in self.channels.items()}
        if self.temp_c is not None:
            cols["temp_c"] = self.temp_c
        return pd.DataFrame(cols, index=pd.Index(t, name="time_s"))


#: pandas ``compression`` of each container :func:`~budget.fileio.check_input_file` detects
_PANDAS_COMPRESSION = {None: None, "gzip": "gzip", "bzip2": "bz2", "xz": "xz", "zip": "zip"}
def _text_format(path: Path, kind: str | None) -> dict:
    """How pandas reads ``path``: its compression as detected by content (``kind``, not the
    suffix: a gzip log named ``log`` or ``log.gzip`` is still gzip), the text encoding its
    byte-order mark names (UTF-8 without one, Windows-1252 when the file's start is not UTF-8:
    ``gyro_x [°/s]`` written by a Windows logger; :func:`~budget.fileio.input_encoding`), and
    bytes that are not valid in it replaced (a stray byte in a column the reader ignores must not
    refuse the log; in a number it is reported as not a number, with its row)."""
    return {"compression": _PANDAS_COMPRESSION[kind], "encoding": input_encoding(path),
            "encoding_errors": "replace"}


def _header(path: Path, mapping: LogMapping | None, fmt: dict) -> list[str]:
    try:
        head = pd.read_csv(path, sep=mapping.delimiter if mapping else ",", nrows=0, **fmt,
                           decimal=mapping.decimal if mapping else ".",
                           comment=mapping.comment if mapping else None, skipinitialspace=True,
                           skiprows=mapping.skip_rows if mapping else 0)
    except pd.errors.EmptyDataError:
        raise InputError("file is empty (no header)", file=path,
                         expected="a CSV with a header row: time_s, gyro_x_dps, …") from None
    except (UnicodeDecodeError, OSError, pd.errors.ParserError) as err:
        raise InputError(f"not a readable CSV ({err.__class__.__name__})", file=path) from None
    return lc.check_header([str(c).strip() for c in head.columns], path)


def _estimate_rows(path: Path, kind: str | None = "auto") -> int | None:
    """Rough row count from the (uncompressed) size and the first lines; None if unknown
    (``kind``: the compression found by content, ``"auto"``: find it here)."""
    try:
        if kind == "auto":
            kind = compression_of(path)
        size = path.stat().st_size
        if kind == "gzip":
            with open(path, "rb") as fh:  # gzip trailer: uncompressed size mod 2**32
                fh.seek(-4, 2)
                isize = int.from_bytes(fh.read(4), "little")
            if isize < size or isize > 64 * size:  # wrapped (> 4 GiB) or forged: unknown
                return None
            size = isize
            opener = gzip.open
        elif kind is None:
            opener = open
        else:
            return None
        with opener(path, "rb") as fh:
            sample = fh.read(1 << 20)
        lines = sample.count(b"\n")
        return int(size / (len(sample) / lines)) if lines > 1 else None
    except (OSError, EOFError, gzip.BadGzipFile, InputError):
        return None


def _bad_cell(series: pd.Series, base_row: int, path: Path, col: str) -> None:
    conv = pd.to_numeric(series, errors="coerce")
    text = series.astype(str).str.strip()
    bad = conv.isna() & series.notna() & (text != "") & (text.str.lower() != "nan")
    if bad.any():
        i = int(np.flatnonzero(bad.to_numpy())[0])
        expected = "a decimal number"
        if clock_kind(series.iloc[i]) is not None:
            expected = ("a number in the column's unit; clock text is read from a time column whose "
                        "header writes no unit (Time, Time (UTC)) or that a mapping sends to \"time\"")
        elif str(series.iloc[i]).lstrip().startswith("#"):
            expected = ("a number; a line starting with '#' is a comment a mapping's \"comment\": \"#\" "
                        "skips")
        elif decimal_comma(series.iloc[i]):
            expected = ("a number with a decimal point; a log written with decimal commas is read "
                        "with a mapping's \"decimal\": \",\" (and its \"delimiter\", e.g. \";\")")
        raise InputError("not a number", file=path, row=base_row + i + 2, field=col,
                         value=series.iloc[i], expected=expected)


def decimal_comma(cell) -> bool:
    """True when ``cell`` is text that reads as a number once its one comma is a point
    (``'0,0125'``: a decimal comma, as spreadsheets in many locales write)."""
    text = str(cell).strip()
    if text.count(",") != 1:
        return False
    try:
        float(text.replace(",", "."))
    except ValueError:
        return False
    return True


def _chunks_without_lost_fields(reader, path: Path, mapping: LogMapping | None, fmt: dict):
    """The chunks of ``reader``; a row with more fields than the header (which pandas would cut
    with only a warning, shifting nothing but losing data) is an error naming its line."""
    while True:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", pd.errors.ParserWarning)
            chunk = next(reader, None)
        if any(issubclass(w.category, pd.errors.ParserWarning) for w in caught):
            bad = _row_with_extra_fields(path, mapping, fmt["encoding"])
            if bad is not None:
                reader.close()
                line_no, got, want = bad
                raise InputError(f"row has {got} fields, the header {want}: the extra ones would be dropped",
                                 file=path, row=line_no, expected=f"{want} fields like the header")
        if chunk is None:
            return
        yield chunk


def _row_with_extra_fields(path: Path, mapping: LogMapping | None,
                           encoding: str = "utf-8") -> tuple[int, int, int] | None:
    """(line number, fields, header fields) of the first data row with more non-empty trailing
    fields than the header — pandas drops them with a warning — or None when the extra fields
    are only trailing delimiters (``1,2,3,``), which lose nothing."""
    delim = mapping.delimiter if mapping else ","
    comment = mapping.comment if mapping else None
    skip = mapping.skip_rows if mapping else 0
    with open_input(path) as fh:
        text = io.TextIOWrapper(fh, encoding=encoding, errors="replace", newline="")
        width = None
        for line_no, row in enumerate(csv.reader(text, delimiter=delim), start=1):
            if line_no <= skip or not row or (comment and row[0].lstrip().startswith(comment)):
                continue
            while row and not row[-1].strip():
                row = row[:-1]
            if width is None:
                width = len(row)
            elif len(row) > width:
                return line_no, len(row), width
    return None


def _clock_column(path: Path, header: list[str], mapping: LogMapping | None, fmt: dict) -> str | None:
    """The column of :func:`~budget.noise.log_mapping.clock_candidates` whose first cells are
    clock text (``Time (UTC)``: ``2026-03-01T12:00:00.005Z``), or None; two are refused unless a
    mapping sends one to ``time``."""
    candidates = clock_candidates(header, mapping)
    if not candidates:
        return None
    try:
        head = pd.read_csv(path, sep=mapping.delimiter if mapping else ",", nrows=50, dtype=str,
                           comment=mapping.comment if mapping else None, skipinitialspace=True,
                           skiprows=mapping.skip_rows if mapping else 0, index_col=False, **fmt)
    except (ValueError, OSError, pd.errors.ParserError, EOFError):
        return None  # the full read names what is wrong
    head.columns = [str(c).strip() for c in head.columns]
    found = [c for c in candidates if c in head.columns and is_clock_text(head[c].tolist())]
    targets = mapping_by_column(header, mapping)[0]
    mapped = [c for c in found if targets.get(c) == "time"]
    if len(found) > 1 and not mapped:
        raise InputError(f"columns {', '.join(map(repr, found))} all hold clock text: which is the time?",
                         file=path, row=1 + (mapping.skip_rows if mapping else 0), field=found[1],
                         expected='a mapping sending one of them to "time" ({"columns": {"'
                                  + found[0] + '": "time"}})')
    return (mapped or found or [None])[0]


def _read_chunks(path: Path, plan: ColumnPlan, mapping: LogMapping | None,
                 max_rows: int | None, chunk_rows: int, kind: str | None, fmt: dict,
                 clock: ClockColumn | None = None) -> np.ndarray:
    est = _estimate_rows(path, kind)
    cap = int(est * 1.02) + chunk_rows if est else 4 * chunk_rows
    if max_rows is not None:
        cap = min(cap, max_rows)
    ncol = len(plan.sources)
    data = np.empty((max(cap, 1), ncol), order="F")
    n = 0
    try:
        reader = pd.read_csv(path, sep=mapping.delimiter if mapping else ",",
                             comment=mapping.comment if mapping else None, skipinitialspace=True,
                             skiprows=mapping.skip_rows if mapping else 0,
                             chunksize=chunk_rows, nrows=max_rows, index_col=False, **fmt,
                             decimal=mapping.decimal if mapping else ".")
        for chunk in _chunks_without_lost_fields(reader, path, mapping, fmt):
            chunk.columns = [str(c).strip() for c in chunk.columns]
            m = len(chunk)
            if n + m > data.shape[0]:
                grown = np.empty((max(int(data.shape[0] * 1.5), n + m), ncol), order="F")
                grown[:n] = data[:n]
                data = grown
            for j, (col, factor) in enumerate(zip(plan.sources, plan.factors)):
                s = chunk[col]
                if clock is not None and col == clock.column:
                    data[n:n + m, j] = clock.seconds(s, n) * factor
                    continue
                if not pd.api.types.is_numeric_dtype(s.dtype):
                    _bad_cell(s, n, path, col)
                    s = pd.to_numeric(s, errors="coerce")
                data[n:n + m, j] = s.to_numpy(dtype=np.float64, na_value=np.nan) * factor
            n += m
    except pd.errors.ParserError as err:
        msg = str(err).split("C error: ")[-1].strip()
        raise InputError(f"malformed CSV: {msg}", file=path,
                         expected=f"{len(plan.sources)}+ comma-separated fields on every row") from None
    except (UnicodeDecodeError, EOFError, gzip.BadGzipFile, OSError) as err:
        raise InputError(f"file could not be read to the end ({err.__class__.__name__}: {err})",
                         file=path) from None
    return data[:n] if n * 1.1 >= data.shape[0] else data[:n].copy(order="F")


def read_log(path: str | Path, mapping: LogMapping | None = None, repair: bool = False, *,
             rate_hz: float | None = None, channels: Iterable[str] | None = None,
             max_rows: int | None = None, min_samples: int = 3,
             chunk_rows: int = CHUNK_ROWS) -> ImuLog:
    """Read an IMU log CSV (plain, gzip, bzip2, xz or a one-file zip, found by content whatever
    the file's name; UTF-8 with or without a byte-order mark, or UTF-16/32 with one) into an :class:`ImuLog` (SI units).

    ``mapping`` renames non-canonical columns; ``rate_hz`` (or ``mapping.rate_hz``) is needed
    when there is no time column; with one, it may only confirm the rate of the time stamps
    (a rate that differs by more than 1 % is refused, naming the column: :func:`_rate`). ``channels`` restricts which sensor channels are
    kept (e.g. ``["gyro_z"]``); ``max_rows`` reads only the first rows. Error-level issues raise
    :class:`LogError` unless ``repair`` — then they are repaired and listed in ``issues.repairs``.
    A transient event below full scale (a knock) that decides a channel's Allan fit is refused,
    a smaller one is a warning (:func:`_transients`).
    """
    path = Path(path)
    require_file(path)
    if path.stat().st_size == 0:
        raise InputError("file is empty", file=path)
    kind = check_input_file(path)  # readable, complete, not an archive, size-limited when compressed
    fmt = _text_format(path, kind)
    if max_rows is not None and max_rows < 1:
        raise InputError("max_rows must be ≥ 1", field="max_rows", value=max_rows)
    header = _header(path, mapping, fmt)
    plan = plan_columns(header, mapping, str(path), _clock_column(path, header, mapping, fmt))
    clock = ClockColumn(plan.time_clock, path) if plan.time_clock is not None else None
    if channels is not None:
        plan = _restrict(plan, list(channels), path)
    rate_given = rate_hz if rate_hz is not None else (mapping.rate_hz if mapping else None)
    if plan.time_index is None and rate_given is None:
        raise InputError("no time column and no sampling rate" + time_unit_hint(plan.ignored), file=path,
                         expected=f"a time_s column (or time [s], time [ms]){LOG_RATE_WAY.cli}")
    if rate_given is not None and not (math.isfinite(rate_given) and rate_given > 0):
        raise InputError("sampling rate must be a positive number", field="rate_hz", value=rate_given)
    data = _read_chunks(path, plan, mapping, max_rows, chunk_rows, kind, fmt, clock)
    if data.shape[0] == 0:
        raise InputError("no data rows after the header", file=path)
    wraps = (unwrap_counter(data[:, plan.time_index], plan.factors[plan.time_index])
             if plan.time_index is not None and clock is None else None)
    report = lc.LogReport(issues=[_ignored_column_issue(c) for c in plan.ignored]
                          + [lc.LogIssue("temperature_column", "info", t) for t in plan.temp_notes]
                          + [lc.LogIssue("header_comment_mark", "info", t) for t in plan.header_notes]
                          + ([lc.LogIssue("text_encoding", "info", "the file is not UTF-8 and has no byte-order "
                                          f"mark: read as {EIGHT_BIT_CODEC} (Windows' 8-bit text, where ° and µ "
                                          "are one byte each)")] if fmt["encoding"] == EIGHT_BIT_CODEC else [])
                          + ([lc.LogIssue("clock_time", "info", clock.note(), 0, (), clock.column)]
                             if clock is not None else [])
                          + ([lc.LogIssue("counter_wrap", "info", wraps.note(plan.sources[plan.time_index]),
                                          int(wraps.rows.size), lc.listed_rows(wraps.rows),
                                          plan.sources[plan.time_index])]
                             if wraps is not None else []))
    report.issues += lc.check_log(data, plan.targets, plan.time_index, plan.channel_index)
    coarse = next((i for i in report.issues if i.kind == "coarse_time"), None)
    if coarse is not None:  # a repair cannot help: it would drop every row whose stamp repeats
        if rate_given is None:
            raise InputError(coarse.message, file=path, row=coarse.rows[0] if coarse.rows else None,
                             field=plan.sources[plan.time_index],
                             expected=f"stamps printed finer than the sampling period{LOG_RATE_WAY.cli}: the "
                                      "log is then read at that rate and the stamps' span checks it")
        t_col = data[:, plan.time_index]
        checked = lc.coarse_time_span_check(t_col, lc.coarse_resolution(t_col), rate_given,
                                            plan.sources[plan.time_index])
        if checked.severity == "error":
            raise InputError(checked.message, file=path, field=plan.sources[plan.time_index],
                             value=rate_given, expected="the rate the sensor was logged at, or a log without gaps")
        report.issues[report.issues.index(coarse)] = checked
    slip = lv.gravity_unit_slip(data, plan.channel_index, plan.source_units, path)
    if slip is not None:
        raise slip
    stale = lv.stale_samples(data, plan.targets, plan.time_index, plan.channel_index, path)
    if stale is not None:
        raise stale
    clip, clip_warnings = lv.clipped(data, plan.targets, plan.channel_index, path, plan.factors)
    if clip is not None:
        raise clip
    report.issues += clip_warnings
    unchecked = lv.gravity_unchecked(plan.channel_index, plan.source_units)
    if unchecked is not None:
        report.issues.append(unchecked)
    if report.errors:
        if not repair:
            first = "; ".join(i.text() for i in report.errors[:3])
            more = f" (+{len(report.errors) - 3} more)" if len(report.errors) > 3 else ""
            raise LogError(f"{len(report.errors)} problem(s) in the log: {first}{more}; nothing "
                           f"was changed — {REPAIR_WAY.cli} to drop duplicate "
                           "and out-of-order rows, interpolate missing values and keep the "
                           "longest gap-free stretch", report, file=path)
        try:
            # stamps coarser than the period (read at the given rate): no row is dropped for them
            data, _, report.repairs = lc.repair_log(data, plan.targets,
                                                    None if coarse is not None else plan.time_index,
                                                    plan.channel_index)
        except ValueError as err:
            raise LogError(f"cannot repair: {err}", report, file=path) from None
    n = data.shape[0]
    if n < min_samples:
        raise InputError(f"only {n} sample(s)", file=path,
                         expected=f"at least {min_samples} samples for the requested analysis")
    time_s = data[:, plan.time_index] if plan.time_index is not None else None
    rate = (float(rate_given) if coarse is not None else
            _rate(time_s, rate_given, path,
                  *((plan.sources[plan.time_index], plan.factors[plan.time_index], clock is not None)
                    if plan.time_index is not None else ())))
    chans = {ch: data[:, plan.channel_index[ch]] for ch in CHANNELS if ch in plan.channel_index}
    temp = data[:, plan.temp_index] + plan.temp_offset_c if plan.temp_index is not None else None
    if temp is not None:
        report.issues += lv.implausible_temperature(temp, plan.sources[plan.temp_index])
    report.issues += _transients(chans, rate, plan, bool(report.repairs), path)
    return ImuLog(str(path), chans, rate, time_s, temp, report,
                  {c: plan.source_units[c] for c in chans})


def _transients(chans: dict[str, np.ndarray], rate: float, plan: ColumnPlan, repaired: bool,
                path: Path) -> list[lc.LogIssue]:
    """Transient events below full scale (:func:`~budget.noise.transients.transient_issue`): the
    error for the first channel whose event decides its Allan fit, else the warnings.

    Refused, like a saturated run (:func:`~budget.noise.log_values.clipped`), when an event carries
    ≥ 20 % of the record's variance at its own time scale: it is then an event far beyond the noise
    (threshold: a false alarm once in 10³ noise-only channels) that sets the fitted ARW and bias
    instability — a knock read 6× the ARW and 200× the bias instability with only a misfit
    warning — and no figure of the channel can be trusted; the remedy is the user's (which rows to
    cut), not a repair the reader could guess. A smaller event is a warning, as a bias step is: it
    is found, but it does not decide the figures."""
    from .stationarity import record_rows
    from .transients import transient_issue
    from ..units import channel_si_unit

    out = []
    for ch, x in chans.items():
        issue, refuse = transient_issue(x, rate, ch, channel_si_unit(ch), record_rows(repaired))
        if issue is None:
            continue
        col = plan.targets[plan.channel_index[ch]]  # named as the clipping check names it
        issue = replace(issue, column=col)
        if refuse:
            first = issue.rows[0]
            raise InputError(issue.message, file=path, field=col,
                             expected=f"a static log without the event: cut its rows (from {first:,} on, with a "
                             "margin of a second either side) from a copy of the file, or characterise the "
                             f"record before or after it; or {LOG_CHANNEL_WAY.cli}")
        out.append(issue)
    return out


def _ignored_column_issue(column: str) -> lc.LogIssue:
    """The note on a column the reader leaves out; a warning when its header writes a rate or
    specific-force unit (``gx(rad/s)``): a sensor missing from every result, with its mapping."""
    target = unread_channel(column)
    if target is None:
        return lc.LogIssue("ignored_column", "info", "column not read: not a canonical name (time_s, "
                           f"gyro_x_dps, accel_x_mps2, temp_c, …) {LOG_MAPPING_WAY.cli}", 0, (), column)
    kind = "an angular-rate" if target.startswith("gyro") else "a specific-force"
    return lc.LogIssue("unread_channel", "warning",
                       f"column not read although its header writes {kind} unit: its name is no channel "
                       f"the reader knows (gyro_x, accel_x, acc_x … before the bracket) {LOG_MAPPING_WAY.cli} — "
                       f"every figure of this sensor is missing from the result; a mapping "
                       f'{{"columns": {{"{column}": "{target}"}}}} reads it', 0, (), column)


def _restrict(plan: ColumnPlan, wanted: list[str], path: Path) -> ColumnPlan:
    unknown = [c for c in wanted if c not in plan.channel_index]
    if unknown:
        raise InputError(f"channel(s) {', '.join(unknown)} missing from the log", file=path, field="channel",
                         expected=f"channels the log has: {', '.join(sorted(plan.channel_index))}")
    keep = [i for i in range(len(plan.sources))
            if i in (plan.time_index, plan.temp_index)
            or any(plan.channel_index[c] == i for c in wanted)]
    pos = {old: new for new, old in enumerate(keep)}
    return ColumnPlan(
        tuple(plan.sources[i] for i in keep), tuple(plan.targets[i] for i in keep),
        tuple(plan.factors[i] for i in keep),
        pos.get(plan.time_index) if plan.time_index is not None else None,
        pos.get(plan.temp_index) if plan.temp_index is not None else None,
        {c: pos[plan.channel_index[c]] for c in wanted},
        {c: plan.source_units[c] for c in wanted}, plan.ignored, plan.temp_offset_c, plan.temp_notes,
        plan.time_clock, plan.header_notes)


#: Below this rate (Hz) derived from the time stamps, the log says it may be a time unit slip.
LOW_RATE_HZ = 1.0
#: A given rate (``--rate-hz``, ``rate_hz=``, a mapping's ``rate_hz``) may differ from the rate of
#: the log's own time stamps by this fraction of itself: a clock's ppm drift and the jitter the
#: checks warn about (:data:`~budget.noise.log_checks.JITTER_WARN`, 1 %) stay inside it.
RATE_TOLERANCE = 0.01


def _rate(time_s: np.ndarray | None, given: float | None, path: Path,
          column: str | None = None, factor: float = 1.0, clock: bool = False) -> float:
    """The sampling rate (Hz) of a log: the one ``given`` when the log has no time column, else
    the rate of its time stamps ``time_s`` (s), which a given rate may only confirm.

    Every time column the reader takes declares its unit — in its name (``time_ms``), in
    brackets (``t [ms]``), through a mapping (``"t": "time_us"``) — or holds clock text, read in
    seconds: there is no time column of unknown unit. So a given rate that differs from the
    stamps' by more than :data:`RATE_TOLERANCE` contradicts the file, whatever the factor: a
    factor of 10³ or 10⁶ is a column in ms or µs under a name that says seconds (or the reverse),
    and the remedy is that column's unit, not a rate that overrides it (accepted with a warning,
    0.1 Hz given for 100 Hz stamps wrote a catalog row with ARW ×√1000). Refused (:class:`InputError`
    naming the file, the column and both rates), as stamps below :data:`LOW_RATE_HZ` with no rate
    given are: the two ways to a rate then agree — the stamps decide it, a given rate confirms it.
    ``column``: the time column's name in the file; ``factor``: its declared unit in seconds
    (1e-3 for ms); ``clock``: it holds clock text — for the messages."""
    if time_s is None:
        return float(given)
    col = column or "time"
    period = lc.nominal_period(time_s)
    if period is None:
        if given is None:
            raise InputError("cannot derive the sampling rate: time stamps never increase",
                             file=path, field=col, expected="increasing time_s, or rate_hz")
        return float(given)
    rate = 1.0 / period
    if lc.check_rate(rate) and given is None:
        raise InputError(lc.check_rate(rate), file=path, field=col)
    # time stamps printed with finite decimals: a whole rate within what they resolve over the
    # record's span (rounded stamps, lc.stamp_resolution) is that rate
    res = lc.stamp_resolution(np.diff(time_s), period) or 0.0
    span = float(np.nanmax(time_s) - np.nanmin(time_s))
    if abs(rate - round(rate)) <= max(1e-6, res / span if span > 0 else 0.0) * rate:
        rate = float(round(rate))
    if given is not None:
        if abs(given - rate) > RATE_TOLERANCE * given:
            raise _rate_contradiction(path, col, rate, float(given), factor, clock)
        return float(given)
    if rate < LOW_RATE_HZ:
        # possible for an averaged log, but it is what 100 Hz stamps written in ms under time_s
        # give, and a warning let ARW 31.6× too large into a catalog row: the user confirms it
        raise InputError(f"the time stamps give {rate:.6g} Hz, below {LOW_RATE_HZ:g} Hz: an IMU log that slow "
                         "is rare, and it is what stamps in ms (µs) under a time_s header give; every noise "
                         "figure scales with the rate", file=path, field=col,
                         expected=f"a time column named after its unit (time_ms, time_us) "
                                  f"{LOG_TIME_UNIT_WAY.cli} to confirm {rate:.6g} Hz")
    return rate


#: Time units a column may declare (seconds per unit → its name), for :func:`_rate_contradiction`.
_TIME_UNITS = {1.0: "time_s", 1e-3: "time_ms", 1e-6: "time_us", 1e-9: "time_ns"}


def _rate_contradiction(path: Path, column: str, rate: float, given: float, factor: float,
                        clock: bool) -> InputError:
    """The refusal of a given rate ``given`` (Hz) that contradicts the ``rate`` (Hz) of the time
    stamps of ``column`` (declared unit ``factor`` s; ``clock``: clock text). When another time
    unit would make the stamps give the rate given — the column in ms under a name that says s:
    a factor of 10³ — that unit is named as the other remedy (a mapping to it); otherwise the
    given rate is what is wrong, and leaving it out is the remedy."""
    ratio = given / rate
    unit = None if clock else next((name for f, name in _TIME_UNITS.items()
                                    if f != factor and abs(factor * rate / given / f - 1) <= 0.02), None)
    head = (f"the time stamps give {rate:.6g} Hz, the given rate is {given:.6g} Hz (×{ratio:.4g}, beyond "
            f"the {RATE_TOLERANCE:.0%} a clock's drift or jitter explains): the time column {column!r} "
            "declares its unit, and every noise figure scales with the rate")
    # the remedy names the rate as LOG_RATE_WAY does, which each interface says in its own words
    confirm = f"no rate given{LOG_RATE_WAY.cli} that agrees with them within {RATE_TOLERANCE:.0%}"
    if unit is not None:
        return InputError(head + f": if the column holds {unit.removeprefix('time_')} (its stamps then give "
                          f"{given:.6g} Hz), its name or mapping must say so", file=path, field=column,
                          value=given,
                          expected=f"the column's true unit: a mapping {{\"columns\": {{\"{column}\": "
                                   f"\"{unit}\"}}}} (or rename it {unit}); or, if the stamps are right "
                                   f"({rate:.6g} Hz), {confirm}")
    return InputError(head, file=path, field=column, value=given,
                      expected=f"the stamps' {rate:.6g} Hz: {confirm}; if the stamps are wrong, the time "
                               "column's true unit in its name (time_s, time_ms, time_us, time_ns) or "
                               "header (time [ms])")
