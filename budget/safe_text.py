"""Text that is safe where it goes: CSV cells a spreadsheet will not run as formulas (OWASP
"CSV injection"), and printable text without terminal escapes or control characters."""

from __future__ import annotations

import csv
import io
import re

import numpy as np

#: First characters that make a spreadsheet read a cell as a formula (OWASP "CSV injection").
FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
_PLAIN_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_CONTROL = re.compile(r"\x1b\[[0-?]*[ -/]*[@-~]|\x1b[@-_]|[\x00-\x08\x0b-\x1f\x7f-\x9f]")


def looks_like_formula(text: str) -> bool:
    """True if ``text`` starts with = + - @ TAB or CR and is not a plain number (``-2.5``, ``1e-3``)."""
    return bool(text) and text[0] in FORMULA_START and not _PLAIN_NUMBER.fullmatch(text)


def safe_csv_text(value):
    """``value`` as it may go into a CSV cell: text a spreadsheet would run as a formula gets a
    leading ``'`` (OWASP); numbers and plain numeric strings pass unchanged."""
    if value is None or isinstance(value, (bool, int, float, np.number)):
        return value
    text = str(value)
    return "'" + text if looks_like_formula(text) else text


def csv_text(rows, header=None, *, lineterminator: str = "\n") -> str:
    """CSV text of ``rows`` (and ``header``) with every text cell through :func:`safe_csv_text`;
    floats written with ``repr`` (round-trip exact), ``None`` as an empty cell."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator=lineterminator)
    if header is not None:
        w.writerow([safe_csv_text(h) for h in header])
    for row in rows:
        w.writerow(["" if v is None else (repr(float(v)) if isinstance(v, (float, np.floating))
                                          else safe_csv_text(v)) for v in row])
    return buf.getvalue()


def frame_csv_text(frame) -> str:
    """``DataFrame.to_csv`` text with every text cell (and column name) made spreadsheet-safe."""
    from pandas.api.types import is_bool_dtype, is_numeric_dtype

    out = frame.copy()
    for col in out.columns:
        if not (is_numeric_dtype(out[col].dtype) or is_bool_dtype(out[col].dtype)):
            out[col] = out[col].map(lambda v: v if _missing(v) else safe_csv_text(v))
    out.columns = [safe_csv_text(str(c)) for c in out.columns]
    return out.to_csv(index=False, lineterminator="\n")


def _missing(v) -> bool:
    import pandas as pd

    if v is None or isinstance(v, (list, tuple, dict, set, np.ndarray)):
        return v is None
    try:
        return bool(pd.isna(v))
    except (TypeError, ValueError):
        return False


def printable(text: object, limit: int | None = None) -> str:
    """``text`` without ANSI escape sequences and control characters (tab and newline become a
    space), optionally cut to ``limit`` characters — for anything printed to a terminal."""
    s = _CONTROL.sub("", str(text).replace("\t", " ").replace("\n", " "))
    if limit is not None and len(s) > limit:
        s = s[:limit - 1] + "…"
    return s
