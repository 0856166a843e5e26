"""Progress on stderr for the long CLI runs (``mc``, ``sweep``, ``gap``, ``noise``, ``report``).

On a terminal a tqdm bar (done/total, rate, time left) or, when the library gives no count, a
ticking "still working" line with the elapsed time. When stderr is not a terminal (CI, a pipe,
a log file) no carriage-return animation is written: one line when the work starts, a line at
every further 25 % (or every 30 s without a count) and one when it ends, so a log shows that the
run is alive without filling up. ``--quiet`` silences all of it; results still go to stdout.
"""

from __future__ import annotations

import sys
import threading
import time
from contextlib import contextmanager

#: Seconds between "still working" lines when stderr is not a terminal.
PLAIN_INTERVAL_S = 30.0


def add_quiet_option(parser) -> None:
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="no progress messages on stderr (results and errors are still written)")


class Progress:
    """A ``progress(done, total)`` callable for the library's callbacks, drawn on ``stream``."""

    def __init__(self, label: str, unit: str = "trials", *, quiet: bool = False, stream=None):
        self.label, self.unit, self.quiet = label, unit, quiet
        self.stream = stream if stream is not None else sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._bar = None
        self._last_quarter = -1
        self._t0 = time.monotonic()
        if not quiet and not self.tty:  # a log shows at once that the run has started
            print(f"{label}: started", file=self.stream, flush=True)

    def __call__(self, done: int, total: int) -> None:
        if self.quiet:
            return
        if self.tty:
            if self._bar is None:
                from tqdm import tqdm

                self._bar = tqdm(total=total, desc=self.label, unit=self.unit[:-1] if
                                 self.unit.endswith("s") else self.unit, file=self.stream,
                                 dynamic_ncols=True, leave=True)
            self._bar.total = total
            self._bar.update(done - self._bar.n)
            if done >= total:
                self.close()
            return
        quarter = int(4 * done / max(total, 1))
        if quarter > self._last_quarter:
            self._last_quarter = quarter
            dt = time.monotonic() - self._t0
            print(f"{self.label}: {done}/{total} {self.unit} ({dt:.0f} s)", file=self.stream, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


@contextmanager
def progress(label: str, unit: str = "trials", *, quiet: bool = False, stream=None):
    """``with progress("STIM300") as p: run_mc(..., progress=p)`` — closes the bar at the end."""
    p = Progress(label, unit, quiet=quiet, stream=stream)
    try:
        yield p
    finally:
        p.close()


@contextmanager
def working(label: str, *, quiet: bool = False, stream=None, interval_s: float | None = None):
    """Show that a run without a progress count is alive: a ticking elapsed-time line on a
    terminal, a line every ``interval_s`` (default :data:`PLAIN_INTERVAL_S`) otherwise, and the
    total time at the end."""
    stream = stream if stream is not None else sys.stderr
    if quiet:
        yield
        return
    tty = bool(getattr(stream, "isatty", lambda: False)())
    interval = interval_s if interval_s is not None else (0.5 if tty else PLAIN_INTERVAL_S)
    stop = threading.Event()
    t0 = time.monotonic()
    if not tty:
        print(f"{label} …", file=stream, flush=True)

    def tick() -> None:
        while not stop.wait(interval):
            dt = time.monotonic() - t0
            if tty:
                stream.write(f"\r{label} … {dt:.0f} s")
                stream.flush()
            else:
                print(f"{label}: still working ({dt:.0f} s)", file=stream, flush=True)

    thread = threading.Thread(target=tick, daemon=True)
    thread.start()
    ok = False
    try:
        yield
        ok = True
    finally:
        stop.set()
        thread.join()
        dt = time.monotonic() - t0
        end = "done" if ok else "stopped"
        print(("\r" if tty else "") + f"{label}: {end} in {dt:.1f} s", file=stream, flush=True)
