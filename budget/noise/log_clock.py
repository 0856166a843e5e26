"""A log's time column written as clock text, read as seconds from the first sample.

Loggers and spreadsheet exports often stamp each row with the clock rather than a number of
seconds: ``Time (UTC)`` holding ``2026-03-01T12:00:00.005Z``, ``2026-03-01 12:00:00.005`` or
only the time of day, ``12:00:00.005``. Such a column is read when its header names a time
(``time``, ``t``, ``timestamp``, ``datetime`` …, :data:`CLOCK_NAMES`) with no time unit — a
bracket such as ``(UTC)`` or ``[local]`` is no unit — and its first cells are clock text
(:func:`is_clock_text`), or when a mapping sends it to ``time``. Three kinds are read, one per
log (a mix is refused, naming the row and the value):

* ISO 8601 date-times with a time zone (``Z``, ``+01:00``): converted to UTC, so rows written
  across a change of offset (daylight saving) keep their true spacing;
* ISO 8601 date-times without a zone: read as written (one clock);
* times of day (``HH:MM:SS[.fff]``): a step back by more than half a day is midnight passing
  (a day rollover, 24 h added); a smaller step back stays one, for the log's checks to report.

Anything else — a date written ``01/03/2026`` (day or month first?), a number, ``25:00:00`` —
is refused with its row and value: nothing is guessed. The reader says in the log's notes that
its time came from clock text (:meth:`ClockColumn.note`).
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

from ..errors import InputError

#: Header names (lower case, spaces as ``_``) of a column that may hold clock text.
CLOCK_NAMES = ("time", "t", "timestamp", "datetime", "date_time", "date/time", "utc", "time_utc",
               "utc_time", "timestamp_utc", "time_of_day")

_TIME_OF_DAY = r"(?:[01]?\d|2[0-3]):[0-5]\d:[0-5]\d(?:[.,]\d{1,9})?"
_DATE_TIME = r"\d{4}-\d{2}-\d{2}[T ]" + _TIME_OF_DAY
_ZONE = r"(?:Z|[+-]\d{2}(?::?\d{2})?)"
#: The kinds of clock text, as the notes and refusals name them.
KINDS = {"zoned": "ISO 8601 date-times with a time zone", "naive": "ISO 8601 date-times without a time zone",
         "day": "times of day"}
_PATTERNS = {"zoned": _DATE_TIME + r"\s?" + _ZONE, "naive": _DATE_TIME, "day": _TIME_OF_DAY}
EXPECTED = ("clock text of one kind on every row: ISO 8601 date-times (2026-03-01T12:00:00.005Z, "
            "2026-03-01 12:00:00.005, with or without a UTC offset) or times of day (12:00:00.005)")
DAY_NS = 86_400 * 10**9


def is_clock_name(name: str) -> bool:
    """True when the header base ``name`` (without its bracket) names a time column."""
    return name.strip().lower().replace(" ", "_") in CLOCK_NAMES


def clock_kind(cell) -> str | None:
    """The kind of clock text ``cell`` holds (a key of :data:`KINDS`), or None."""
    if not isinstance(cell, str):
        return None
    text = cell.strip()
    return next((k for k, pat in _PATTERNS.items() if re.fullmatch(pat, text)), None)


def is_clock_text(cells) -> bool:
    """True when the first non-empty cell of ``cells`` is clock text."""
    for cell in cells:
        if cell is None or (isinstance(cell, float) and np.isnan(cell)) or not str(cell).strip():
            continue
        return clock_kind(str(cell)) is not None
    return False


class ClockColumn:
    """Reads a clock-text column chunk by chunk into seconds from its first sample (the first
    stamp, the kind and the day count carry over from one chunk to the next)."""

    def __init__(self, column: str, path):
        self.column, self.path = column, path
        self.kind: str | None = None
        self.kind_row: int | None = None
        self.first_text: str | None = None
        self.t0_ns: int | None = None
        self.last_ns: int | None = None   # last time of day read (ns into its day), for rollovers
        self.days = 0
        self.rollovers = 0

    def seconds(self, series: pd.Series, base_row: int) -> np.ndarray:
        """The chunk ``series`` (its first cell on file row ``base_row + 2``) in seconds from the
        log's first stamp; empty cells are NaN (a missing stamp, reported by the log's checks)."""
        text = series.astype("string").str.strip()
        empty = (text.isna() | (text == "")).to_numpy()
        out = np.full(len(series), np.nan)
        if empty.all():
            return out
        masks = {k: text.str.fullmatch(pat).fillna(False).to_numpy(dtype=bool)
                 for k, pat in _PATTERNS.items()}
        if self.kind is None:
            first = int(np.flatnonzero(~empty)[0])
            kind = next((k for k, m in masks.items() if m[first]), None)
            if kind is None:
                self._refuse("not clock text", base_row, first, series)
            self.kind, self.kind_row, self.first_text = kind, base_row + first + 2, str(text.iloc[first])
        other = ~empty & ~masks[self.kind]
        if other.any():
            i = int(np.flatnonzero(other)[0])
            was = next((k for k, m in masks.items() if m[i]), None)
            why = (f"{KINDS[was]} among {KINDS[self.kind]} (row {self.kind_row}: "
                   f"{self.first_text!r})" if was else "not clock text")
            self._refuse(why, base_row, i, series)
        valid = ~empty
        if self.kind == "day":
            ns = pd.to_timedelta(text[valid].str.replace(",", ".", regex=False), errors="coerce")
            parsed = ns.to_numpy(dtype="timedelta64[ns]")
        else:
            stamps = pd.to_datetime(text[valid].str.replace(",", ".", regex=False), format="ISO8601",
                                    utc=self.kind == "zoned", errors="coerce")
            if self.kind == "zoned":
                stamps = stamps.dt.tz_localize(None)
            parsed = stamps.to_numpy(dtype="datetime64[ns]")
        bad = np.isnat(parsed)
        if bad.any():  # matched the pattern but is no date (2026-02-30)
            first_bad = int(np.flatnonzero(valid)[np.flatnonzero(bad)[0]])
            self._refuse("not a valid date or time", base_row, first_bad, series)
        ns = parsed.view(np.int64)
        if self.kind == "day":
            prev = np.concatenate(([self.last_ns if self.last_ns is not None else ns[0]], ns[:-1]))
            back = (ns - prev) < -DAY_NS // 2  # a step back by more than half a day: midnight
            day = self.days + np.cumsum(back)
            self.rollovers += int(back.sum())
            self.days = int(day[-1])
            self.last_ns = int(ns[-1])
            ns = ns + day * DAY_NS
        if self.t0_ns is None:
            self.t0_ns = int(ns[0])
        out[valid] = (ns - self.t0_ns) / 1e9
        return out

    def _refuse(self, why: str, base_row: int, i: int, series: pd.Series):
        raise InputError(f"time column of clock text: {why}", file=self.path, row=base_row + i + 2,
                         field=self.column, value=series.iloc[i], expected=EXPECTED)

    def note(self) -> str:
        """What the log's notes say about its time column."""
        kind = KINDS.get(self.kind or "", "clock text")
        how = {"zoned": ", converted to UTC", "naive": ", read as written (one clock, no zone)",
               "day": (f", {self.rollovers} midnight rollover(s) counted as a new day"
                       if self.rollovers else "")}.get(self.kind or "", "")
        return (f"time read from the clock text of {self.column!r} ({kind}{how}), as seconds from the "
                f"first sample {self.first_text!r}")
