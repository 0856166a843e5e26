"""A log's time column from a free-running integer counter that wraps, read as increasing time.

Many loggers stamp samples with a hardware timer written as an unsigned integer: a 32-bit
microsecond counter (``micros()`` on a microcontroller) returns to 0 after 2³² µs = 71.6 min, a
16-bit one after 65.5 ms of µs or 65.5 s of ms. Read as written, such a column steps back once
per wrap, and the log's checks would call it time going back (a repair would then keep only the
longest stretch between two wraps). A step back is read as a wrap of a 2ᵇ counter
(b ∈ :data:`COUNTER_BITS`) only when all of these hold, so that a logger's restart (its counter
reset to 0 at an arbitrary count) is never mistaken for one:

* every value of the column, in its own unit, is a whole number, and the column spans less than
  2ᵇ counts;
* the step back, plus 2ᵇ, gives a forward step of more than 0 and at most
  :data:`MAX_WRAP_PERIODS` sampling periods (a wrap with a sample or two lost still reads as one);
* every step back of the column is such a wrap, of the same b.

The wraps are then undone (2ᵇ counts added after each) and the log's notes say so, with rows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Widths (bits) of the counters whose wrap is recognised, narrowest first.
COUNTER_BITS = (16, 24, 31, 32)
#: A wrap's forward step is at most this many sampling periods (a few samples lost at the wrap).
MAX_WRAP_PERIODS = 8.0


@dataclass(frozen=True)
class CounterWraps:
    """Wraps found (and undone) in a time column: the counter's width ``bits``, the data indices
    of the first sample after each wrap, and the column's unit in seconds per count."""

    bits: int
    rows: np.ndarray
    seconds_per_count: float

    def note(self, column: str) -> str:
        """What the log's notes say."""
        span = 2.0 ** self.bits * self.seconds_per_count
        return (f"the time column {column!r} is a {self.bits}-bit counter that wrapped "
                f"{self.rows.size} time(s) (every {span:.6g} s): read as increasing time, "
                f"2^{self.bits} counts added after each wrap")


def unwrap_counter(t: np.ndarray, seconds_per_count: float) -> CounterWraps | None:
    """Undo the wraps of an integer counter in the time column ``t`` (s; ``t / seconds_per_count``
    is the column as written), in place. Returns what was undone, or None (``t`` unchanged) when
    the column steps back in any way that is not a counter's wrap (module docstring)."""
    if t.size < 3 or not np.isfinite(seconds_per_count) or seconds_per_count <= 0:
        return None
    fin = np.flatnonzero(np.isfinite(t))
    if fin.size < 3:
        return None
    raw = t[fin] / seconds_per_count
    if np.max(np.abs(raw - np.round(raw))) > 1e-3:  # not whole counts (rounding of ×/÷ unit < 1e-5)
        return None
    raw = np.round(raw)
    d = np.diff(raw)
    back = np.flatnonzero(d < 0)
    if not back.size:
        return None
    fwd = d[d > 0]
    if not fwd.size:
        return None
    period = float(np.median(fwd))
    width = float(raw.max() - raw.min())
    for bits in COUNTER_BITS:
        m = 2.0 ** bits
        if width >= m:
            continue
        step = d[back] + m
        if np.all((step > 0) & (step <= MAX_WRAP_PERIODS * period)):
            wraps = np.zeros(raw.size)
            wraps[back + 1] = 1.0
            t[fin] = (raw + np.cumsum(wraps) * m) * seconds_per_count
            return CounterWraps(bits, fin[back + 1], seconds_per_count)
    return None
