"""Integrity checks of an IMU log and the repairs a user may ask for.

Checks (all vectorised over the whole log): non-finite values per column, duplicated rows,
non-increasing or jittery time stamps, gaps, constant (stuck) channels, too few samples.
Rows are reported as spreadsheet rows of the file (header = row 1, first sample = row 2; blank
or comment lines shift this numbering).

Repairs happen only on request and every one is listed: exact duplicate rows are dropped;
rows whose time does not increase are dropped (the first occurrence kept); rows without a time
stamp are dropped; missing channel values are linearly interpolated between neighbours; and
across gaps only the longest gap-free stretch is kept (interpolating across a gap would invent
low-noise data and bias the Allan variance).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

#: A step longer than this many nominal periods is a gap.
GAP_FACTOR = 1.5
#: Relative RMS jitter of the sampling period above which a warning is raised.
JITTER_WARN = 0.01
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


def _rows(idx: np.ndarray) -> tuple[int, ...]:
    """Data indices → spreadsheet rows (header is row 1)."""
    return tuple(int(i) + 2 for i in idx[:MAX_ROWS_LISTED])


def nominal_period(t: np.ndarray) -> float | None:
    """Median of the positive time steps (s), None when there is none."""
    dt = np.diff(t[np.isfinite(t)])
    dt = dt[dt > 0]
    return float(np.median(dt)) if dt.size else None


def check_log(data: np.ndarray, names: tuple[str, ...], time_index: int | None,
              channel_index: dict[str, int]) -> list[LogIssue]:
    """Every integrity issue of ``data`` (rows × columns, SI already), none repaired."""
    issues: list[LogIssue] = []
    for j, name in enumerate(names):
        bad = np.flatnonzero(~np.isfinite(data[:, j]))
        if bad.size:
            issues.append(LogIssue("missing_value", "error", f"{bad.size} empty, NaN or infinite "
                                   "value(s)", int(bad.size), _rows(bad), name))
    if time_index is not None:
        issues += _time_issues(data, time_index)
    for ch, j in channel_index.items():
        col = data[:, j]
        fin = col[np.isfinite(col)]
        if fin.size > 1 and fin.min() == fin.max():
            issues.append(LogIssue("constant_channel", "warning",
                                   f"all samples equal {fin[0]:.6g} (stuck or unused sensor); "
                                   "it carries no noise to analyse", int(fin.size), (), names[j]))
    return issues


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
                               "row exactly", int(dup.size), _rows(dup), None))
    back = np.flatnonzero((dt <= 0) & ~same) + 1
    if back.size:
        issues.append(LogIssue("non_monotonic_time", "error",
                               f"{back.size} time stamp(s) not after the previous one",
                               int(back.size), _rows(back), "time"))
    period = nominal_period(t)
    if period is None:
        return issues
    # Forward step from the latest earlier time: a stray out-of-order row is not also a gap.
    fwd = t[1:] - np.fmax.accumulate(t)[:-1]
    fin = np.isfinite(fwd)
    gaps = np.flatnonzero(fin & (fwd > GAP_FACTOR * period)) + 1
    if gaps.size:
        lost = int(np.round(np.sum(fwd[gaps - 1]) / period - gaps.size))
        issues.append(LogIssue("gap", "error", f"{gaps.size} gap(s) longer than {GAP_FACTOR}× the "
                               f"period {period:.6g} s (about {lost} samples missing)",
                               int(gaps.size), _rows(gaps), "time"))
    normal = dt[np.isfinite(dt) & (dt > 0) & (dt <= GAP_FACTOR * period)]
    if normal.size > 2:
        jitter = float(np.std(normal) / period)
        if jitter > JITTER_WARN:
            issues.append(LogIssue("jitter", "warning", f"sampling period varies by {100 * jitter:.2g} % "
                                   "RMS; the analysis assumes uniform sampling at the nominal rate",
                                   int(normal.size), (), "time"))
    return issues


def repair_log(data: np.ndarray, names: tuple[str, ...], time_index: int | None,
               channel_index: dict[str, int]) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Apply the documented repairs; returns (data, kept original indices, what was done)."""
    done: list[str] = []
    keep = np.arange(data.shape[0])
    if time_index is not None:
        t = data[:, time_index]
        same = np.zeros(data.shape[0], bool)
        same[1:] = np.all((data[1:] == data[:-1]) | (np.isnan(data[1:]) & np.isnan(data[:-1])), axis=1)
        if same.any():
            done.append(f"dropped {int(same.sum())} exact duplicate row(s)")
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
            col[bad] = np.interp(np.flatnonzero(bad), good, col[good])
            done.append(f"interpolated {int(bad.sum())} missing value(s) in {name} linearly "
                        "between neighbouring samples")
    if time_index is not None and data.shape[0] > 2:
        t = data[:, time_index]
        period = nominal_period(t)
        if period is not None:
            breaks = np.flatnonzero(np.diff(t) > GAP_FACTOR * period) + 1
            if breaks.size:
                edges = np.concatenate(([0], breaks, [t.size]))
                k = int(np.argmax(np.diff(edges)))
                a, b = int(edges[k]), int(edges[k + 1])
                done.append(f"kept the longest gap-free stretch, rows {int(keep[a]) + 2}–"
                            f"{int(keep[b - 1]) + 2} ({b - a} of {t.size} samples), across "
                            f"{breaks.size} gap(s)")
                data, keep = data[a:b], keep[a:b]
    return data, keep, done
