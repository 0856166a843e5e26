"""Validation of catalog CSV text: reading it safely, then checking every cell column by column.

:func:`validate_parts_table` is the single validator of parts CSV files: for a large regular
file pandas' C reader parses the text and every column is checked as a whole (numbers finite,
≥ 0 and ≤ the plausible maximum of :data:`~budget.catalog.schema.PART_NUMERIC_COLUMNS`; ids,
grades, conventions; formula-looking text, OWASP's leading ``= + - @`` tab CR; control
characters; duplicate ids, also ids differing only in letter case; the bias-convention rule);
smaller or irregular files go through the exact record-by-record path, which gives the same
result (tests/test_fuzz_readers.py checks both agree cell for cell). The first bad cell raises :class:`~budget.errors.InputError` naming
file, row, column, value and what was expected; :func:`collect_errors` lists every bad cell and
every problem across rows of a file in one pass. An unknown header column is answered with the
column it most likely meant only when that column has the same unit
(:mod:`budget.catalog.header_units`); a row with more cells than the header is checked for an
unquoted decimal comma (``…,0,42,…``).
"""

from __future__ import annotations

import csv
import io
import math
import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .. import units as u
from ..errors import InputError
from ..fileio import read_text
from ..safe_text import FORMULA_START, looks_like_formula
from .header_units import quantity_table, respell, suggest, unit_words
from .across_rows import ACROSS_ROWS, check_rows, row_problems
from .decimal_comma import decimal_comma_split
from .schema import (BIAS_CONVENTIONS, GRADES, PART_COLUMNS, PART_NUMERIC_COLUMNS, PART_REQUIRED,
                     VERIFIED_STATES, expected_text)

#: Largest catalog file read (bytes) and longest cell (characters).
MAX_BYTES = 64_000_000
MAX_CELL_CHARS = 10_000
_CHUNK = 20_000
#: Files from this size on are parsed by pandas' C reader (smaller ones faster without it).
FAST_PATH_CHARS = 1_000_000

#: Alternative header → (canonical column, conversion to the canonical unit; all linear).
ALT_UNIT_COLUMNS: dict[str, tuple[str, callable]] = {
    "gyro_bias_instability_deg_s": ("gyro_bias_instability_deg_h", lambda v: v * 3600.0),
    "gyro_bias_repeatability_deg_s": ("gyro_bias_repeatability_deg_h", lambda v: v * 3600.0),
    "gyro_arw_deg_s_rt_hz": ("gyro_arw_deg_rt_h", lambda v: v * 60.0),
    "gyro_arw_rad_s_rt_hz": ("gyro_arw_deg_rt_h", u.rad_s_rt_hz_to_deg_rt_h),
    "gyro_arw_deg_h_rt_hz": ("gyro_arw_deg_rt_h", u.deg_h_rt_hz_to_deg_rt_h),
    "gyro_scale_factor_pct": ("gyro_scale_factor_ppm", lambda v: v * 1e4),
    "gyro_misalignment_deg": ("gyro_misalignment_mrad", lambda v: u.rad_to_mrad(u.deg_to_rad(v))),
    "accel_bias_instability_mg": ("accel_bias_instability_ug", lambda v: v * 1e3),
    "accel_bias_repeatability_mg": ("accel_bias_repeatability_ug", lambda v: v * 1e3),
    "accel_vrw_ug_rt_hz": ("accel_vrw_m_s_rt_h", u.ug_rt_hz_to_m_s_rt_h),
    "accel_vrw_m_s2_rt_hz": ("accel_vrw_m_s_rt_h", u.m_s2_rt_hz_to_m_s_rt_h),
    "accel_vrw_mg_rt_hz": ("accel_vrw_m_s_rt_h", u.mg_rt_hz_to_m_s_rt_h),
    "accel_vrw_ft_s_rt_h": ("accel_vrw_m_s_rt_h", u.ft_s_rt_h_to_m_s_rt_h),
    "accel_scale_factor_pct": ("accel_scale_factor_ppm", lambda v: v * 1e4),
    "accel_misalignment_deg": ("accel_misalignment_mrad", lambda v: u.rad_to_mrad(u.deg_to_rad(v))),
}

#: Unit of each alternative-unit column, as written in messages (the limits are shown in it).
ALT_UNIT_LABELS: dict[str, str] = {
    "gyro_bias_instability_deg_s": "deg/s",
    "gyro_bias_repeatability_deg_s": "deg/s",
    "gyro_arw_deg_s_rt_hz": "deg/s/√Hz",
    "gyro_arw_rad_s_rt_hz": "rad/s/√Hz",
    "gyro_arw_deg_h_rt_hz": "deg/h/√Hz",
    "gyro_scale_factor_pct": "%",
    "gyro_misalignment_deg": "deg",
    "accel_bias_instability_mg": "mg",
    "accel_bias_repeatability_mg": "mg",
    "accel_vrw_ug_rt_hz": "µg/√Hz",
    "accel_vrw_m_s2_rt_hz": "m/s²/√Hz",
    "accel_vrw_mg_rt_hz": "mg/√Hz",
    "accel_vrw_ft_s_rt_h": "ft/s/√h",
    "accel_scale_factor_pct": "%",
    "accel_misalignment_deg": "deg",
}

_PART_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._\-]{0,63}")
_BAD_CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")
#: A number written with a comma (``0,4``, ``1,000``): a spreadsheet's decimal comma or separator.
_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+")
#: A number whose mantissa has a non-zero digit (so a float of 0.0 from it is an underflow).
_NONZERO_MANTISSA = re.compile(r"\s*[+-]?\d*\.?\d*[1-9]")
_BOOL_CELL = re.compile(r'(?im)(^|,)[ \t"]*(true|false)[ \t"]*(,|\r?$)')
_TEXT_COLUMNS = tuple(c for c in PART_COLUMNS if c not in PART_NUMERIC_COLUMNS)


# --- reading -----------------------------------------------------------------------------------

def _read_text(path: Path) -> str:
    """The text of a catalog CSV (:func:`budget.fileio.read_text`, at most :data:`MAX_BYTES`)."""
    return read_text(path, MAX_BYTES, expected="a UTF-8 catalog CSV file (header row and parts)")


def _iter_rows(path: Path, text: str):
    """(spreadsheet row, stripped cells) of every non-blank record; the first is the header."""
    csv.field_size_limit(max(MAX_CELL_CHARS * 4, 131072))
    reader = csv.reader(io.StringIO(text, newline=""))
    number = 0
    while True:
        try:
            r = next(reader)
        except StopIteration:
            return
        except csv.Error as err:
            raise InputError(f"malformed CSV near line {reader.line_num}: {err}", file=path,
                             row=number + 1, expected=f"cells of at most {MAX_CELL_CHARS:,} "
                             "characters, quotes closed") from None
        number += 1  # a spreadsheet row: blank records and rows of empty cells count too
        cells = [c.strip() for c in r]
        if not any(cells):
            continue
        yield number, cells


def _read_rows(path: Path) -> tuple[list[str], list[tuple[int, dict[str, str]]]]:
    """Header and (spreadsheet row, row as a dict of stripped text) pairs (small files: the
    grades table)."""
    rows = _iter_rows(path, _read_text(path))
    first = next(rows, None)
    if first is None:
        raise InputError("file has no header", file=path, expected="a header row")
    header = first[1]
    _check_not_comment(header, path, first[0])
    out = []
    for i, r in rows:
        _check_length(r, header, path, i)
        out.append((i, dict(zip(header, r))))
    return header, out


def _check_not_comment(r: list[str], path: Path, i: int) -> None:
    """A record starting with ``#`` is a comment line, which CSV does not have (no part id or
    column name starts with ``#``): named as such, not as a short row or an unknown column."""
    if r and r[0].startswith("#"):
        raise InputError("a comment line: a catalog CSV has no comment lines", file=path, row=i,
                         value=",".join(r), expected="only the header and part rows (delete the "
                         "line, or put the text in the notes column of a part)")


def _check_length(r: list[str], header: list[str], path: Path, i: int) -> None:
    _check_not_comment(r, path, i)
    if len(r) != len(header):
        hint = decimal_comma_split(r, header, _cell_fits) if len(r) > len(header) else None
        if hint is not None:
            reason, field, value, write = hint
            raise InputError(f"has {len(r)} cells but the header has {len(header)}; {reason}", file=path,
                             row=i, field=field, value=value,
                             expected=f"one cell per header column: {write} with a decimal point "
                                      "(or quote cells that contain commas)")
        raise InputError(f"has {len(r)} cells but the header has {len(header)}", file=path, row=i,
                         expected="one cell per header column (quote cells that contain commas)")
    if max(map(len, r), default=0) > MAX_CELL_CHARS:
        j = max(range(len(r)), key=lambda k: len(r[k]))
        raise InputError(f"cell of {len(r[j]):,} characters", file=path, row=i, field=header[j],
                         value=r[j], expected=f"at most {MAX_CELL_CHARS:,} characters")


def _cell_fits(cell: str, col: str) -> bool:
    """Whether ``cell`` would pass the checks of header column ``col`` (numbers and choices)."""
    canon = ALT_UNIT_COLUMNS[col][0] if col in ALT_UNIT_COLUMNS else col
    if canon in PART_NUMERIC_COLUMNS:
        if cell == "":
            return True
        try:
            v = float(cell)
        except ValueError:
            return False
        if col != canon:
            v = float(ALT_UNIT_COLUMNS[col][1](v))
        return math.isfinite(v) and 0 <= v <= PART_NUMERIC_COLUMNS[canon][1] and (v > 0 or canon != "rate_hz")
    if canon in _CHOICES:
        return cell == "" and canon not in PART_REQUIRED or _CHOICES[canon](cell)
    return True


def _column_guess(col: str, names) -> str | None:
    """The column ``col`` was most likely meant to be, never one in another unit: the one it
    equals once lower-cased and respelt (:func:`~budget.catalog.header_units.respell`), else the
    closest name that is no numeric column of the parts table (difflib, cutoff 0.85) and has the
    same unit words, else None. A numeric column of the parts table is guessed by unit
    (:func:`_unknown_column`)."""
    import difflib

    key = respell(col)
    names = list(names)
    if key in names:
        return key
    text = [n for n in names if n not in PART_NUMERIC_COLUMNS and n not in ALT_UNIT_COLUMNS]
    close = difflib.get_close_matches(key, text, n=1, cutoff=0.85)
    # a name of another table (grades.csv: gyro_bias_deg_h_min) is offered only in the same unit
    return close[0] if close and unit_words(close[0]) == unit_words(key) else None


#: Quantity → its accepted columns (unit, factor to the canonical unit), from the column table.
QUANTITY_COLUMNS = quantity_table(PART_NUMERIC_COLUMNS, ALT_UNIT_COLUMNS, ALT_UNIT_LABELS)


def _unknown_column(col: str, path: Path, allowed: tuple[str, ...],
                    alt: Mapping[str, tuple[str, callable]]) -> InputError:
    """The error for a header column the table does not accept, with what it most likely meant:
    a respelling of an accepted column, else (parts table) the column of the same quantity *in
    the same unit* — a unit the catalog has no column for is named with the factor to each
    accepted one (:func:`~budget.catalog.header_units.suggest`) — else the closest text column."""
    every = f"one of {', '.join(allowed)}" + (f" or an alternative-unit column ({', '.join(alt)})"
                                              if alt else "")
    guess = _column_guess(col, (*allowed, *alt))
    hint = suggest(col, QUANTITY_COLUMNS) if alt and respell(col) != guess else None
    if hint is None:
        return InputError("unknown column" + (f" (did you mean {guess!r}?)" if guess else ""), file=path,
                          row=1, field=col, expected=every)
    if hint.column:
        return InputError(f"unknown column (did you mean {hint.column!r}?): {hint.note}", file=path,
                          row=1, field=col, expected=hint.expected)
    return InputError(f"unknown column: {hint.note}", file=path, row=1, field=col, expected=hint.expected)


def _map_header(header: list[str], path: Path, allowed: tuple[str, ...], required: tuple[str, ...],
                alt: Mapping[str, tuple[str, callable]]) -> dict[str, str]:
    """Header column → canonical column; raises on unknown, duplicate or missing columns."""
    mapping: dict[str, str] = {}
    seen: dict[str, str] = {}
    for j, col in enumerate(header):
        if col == "":
            raise InputError(f"empty column name in the header (column {j + 1} of {len(header)})", file=path,
                             row=1, expected="a name for every column (empty columns at the end of the "
                             "header are often left by a spreadsheet: delete them)")
        if col in allowed:
            canon = col
        elif col in alt:
            canon = alt[col][0]
        else:
            sep = next((c for c in ";\t|" if c in col), None) if len(header) == 1 else None
            if sep is not None:
                raise InputError(f"the header is a single column holding {sep!r}: the file seems to "
                                 f"use {sep!r} as its delimiter", file=path, row=1, field=col,
                                 expected="comma-separated columns and decimal points (save the sheet as CSV with "
                                 "commas; a spreadsheet set to a decimal-comma locale writes ';' and 0,4)")
            raise _unknown_column(col, path, allowed, alt)
        if col in mapping:
            raise InputError("duplicate column", file=path, row=1, field=col)
        if canon in seen:
            raise InputError(f"gives {canon} twice (as {seen[canon]!r} and {col!r})", file=path,
                             row=1, field=col, expected="one column per quantity")
        mapping[col] = canon
        seen[canon] = col
    missing = [c for c in required if c not in seen]
    if missing:
        raise InputError(f"missing required column(s) {', '.join(missing)}", file=path, row=1)
    return mapping


def _numbers(cells: tuple[str, ...], rows: list[int], path: Path, col: str, canon: str) -> np.ndarray:
    """One numeric column → float array in the canonical unit (NaN = empty cell), checked."""
    unit = _column_unit(col, canon)
    empty = np.fromiter((c == "" for c in cells), bool, len(cells))
    try:
        vals = np.fromiter((float(c) if c else 0.0 for c in cells), float, len(cells))
    except ValueError:
        k = next(k for k, c in enumerate(cells) if c and not _is_float(c))
        comma = _DECIMAL_COMMA.fullmatch(cells[k])
        raise InputError("not a number" + (" (a decimal comma or a thousands separator?)" if comma else ""),
                         file=path, row=rows[k], field=col, value=cells[k],
                         expected=f"a number in {unit}"
                         + (f" with a decimal point (e.g. {cells[k].replace(',', '.')} if the comma is decimal)"
                            if comma else "") + " (or an empty cell if unknown)") from None
    # Python's float() also reads 1_0 as 10, and 1e-400 underflows to a "perfect" 0: neither is
    # what a datasheet cell means
    suspect = [k for k in np.flatnonzero((vals == 0.0) & ~empty) if _NONZERO_MANTISSA.match(cells[k])]
    if any("_" in c for c in cells):
        suspect = sorted(set(suspect) | {k for k, c in enumerate(cells) if "_" in c})
    if suspect:
        c = cells[suspect[0]]
        raise InputError("not a plain decimal number" + (" (an underscore)" if "_" in c else " (it underflows to 0)"),
                         file=path, row=rows[suspect[0]], field=col, value=c,
                         expected=f"a number in {unit} written with digits, a decimal point and an "
                                  "exponent within ±300 (or an empty cell if unknown)")
    return _check_numbers(vals, empty, rows, path, col, canon, lambda k: cells[k])


def _check_numbers(vals: np.ndarray, empty: np.ndarray, rows: list[int], path: Path, col: str,
                   canon: str, cell) -> np.ndarray:
    """Finite, in range (after conversion to the canonical unit); NaN where the cell is empty."""
    unit = _column_unit(col, canon)
    bad = ~np.isfinite(vals) & ~empty
    if bad.any():
        k = int(np.argmax(bad))
        raise InputError("not a finite number", file=path, row=rows[k], field=col, value=cell(k),
                         expected=f"a finite number in {unit}")
    if col != canon:
        vals = np.asarray(ALT_UNIT_COLUMNS[col][1](vals), float)
    lim = PART_NUMERIC_COLUMNS[canon][1]
    with np.errstate(invalid="ignore"):
        low = (vals <= 0) if canon == "rate_hz" else (vals < 0)
        high = vals > lim
    shown = _limit_in_column_unit(col, canon)  # the limit as the user's column writes it
    for mask, msg in ((low & ~empty, "Input should be greater than " + ("0" if canon == "rate_hz" else
                                                                         "or equal to 0")),
                      (high & ~empty, f"Input should be less than or equal to {shown}")):
        if mask.any():
            k = int(np.argmax(mask))
            raise InputError(msg, file=path, row=rows[k], field=col, value=cell(k),
                             expected=expected_text(canon, unit) if col == canon else
                             f"a number in {unit}, 0 … {shown}")
    vals = np.array(vals, float)
    vals[empty] = np.nan
    return vals


def _column_unit(col: str, canon: str) -> str:
    """Unit of a numeric header column as messages write it: the canonical column's unit, or
    the alternative column's own (``gyro_arw_deg_s_rt_hz`` → ``deg/s/√Hz``)."""
    return PART_NUMERIC_COLUMNS[canon][0] if col == canon else ALT_UNIT_LABELS[col]


def _limit_in_column_unit(col: str, canon: str) -> str:
    """The plausible maximum of ``canon`` written in the unit of header column ``col``; for an
    alternative-unit column also in the canonical unit (``16.67 deg/s/√Hz (= 1000 deg/√h)``)."""
    unit, lim = PART_NUMERIC_COLUMNS[canon]
    if col == canon:
        return f"{lim:g}"
    per_unit = float(ALT_UNIT_COLUMNS[col][1](1.0))  # the conversions are linear
    return f"{lim / per_unit:.4g} {ALT_UNIT_LABELS[col]} (= {lim:g} {unit})"


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _check_text(cells: tuple[str, ...], rows: list[int], path: Path, col: str) -> None:
    """Formula guard and control characters, for every text cell of one column."""
    for k, c in enumerate(cells):
        if c and (c[0] in FORMULA_START and looks_like_formula(c)):
            raise InputError("text starting with =, +, -, @, tab or CR looks like a spreadsheet "
                             "formula", file=path, row=rows[k], field=col, value=c,
                             expected="plain text (start it with a letter, digit or quote)")
        if c and _BAD_CONTROL.search(c):
            raise InputError("contains control characters or terminal escape sequences", file=path,
                             row=rows[k], field=col, value=c, expected="printable text")


def _check_choice(cells, rows, path, col, canon, ok, required: bool) -> None:
    for k, c in enumerate(cells):
        if not ok(c) and (c != "" or required):
            raise InputError(_choice_message(canon, c), file=path, row=rows[k], field=col,
                             value=c, expected=expected_text(canon, ""))


def _choice_message(canon: str, value: str) -> str:
    if value == "":
        return "Field required" if canon != "source" else "String should have at least 1 character"
    if canon == "part_id":
        return "String should match pattern '^[A-Za-z0-9][A-Za-z0-9._\\-]{0,63}$'"
    return "Input should be one of the allowed values"


_CHOICES = {
    "part_id": lambda c: bool(_PART_ID.fullmatch(c)),
    "grade": lambda c: c in GRADES,
    "source": lambda c: c != "",
    "bias_instability_convention": lambda c: c in BIAS_CONVENTIONS,
    "verified": lambda c: c in VERIFIED_STATES,
}


def validate_parts_table(path: str | Path, text: str | None = None) -> tuple[dict[str, object], list[int]]:
    """Validate a parts CSV column by column (vectorised; no model per row).

    ``text``, if given, is checked instead of the file's content (``path`` then only names the
    file in messages): :mod:`budget.catalog.io` checks what it is about to write this way.

    Returns (canonical column → values, spreadsheet row numbers): numeric columns as float
    arrays in the canonical unit (NaN = empty cell), text columns as tuples of str. The first
    bad cell raises :class:`InputError` naming file, row, column, value and what was expected.
    A large regular file (every record as long as the header, numbers parseable) is parsed by
    pandas' C reader; anything else goes through the exact record-by-record path (both give
    the same result: tests/test_fuzz_readers.py).
    """
    path = Path(path)
    if text is None:
        text = _read_text(path)
    fast = _table_fast(path, text) if len(text) >= FAST_PATH_CHARS else None
    return fast if fast is not None else _table_row_by_row(path, text)


def _table_fast(path: Path, text: str):
    import pandas as pd

    first = next(_iter_rows(path, text), None)
    if first is None:
        raise InputError("file has no header", file=path, expected="a header row")
    header = first[1]
    _check_not_comment(header, path, first[0])
    mapping = _map_header(header, path, PART_COLUMNS, PART_REQUIRED, ALT_UNIT_COLUMNS)
    if '"' not in text and "\r" not in text:  # no quoting: a record is a line
        lens = np.fromiter((line.count(",") + 1 if line else 0 for line in text.split("\n")), int)
    else:
        lens = np.fromiter(map(len, csv.reader(io.StringIO(text, newline=""))), int)
    last = np.flatnonzero(lens > 0)
    lens = lens[:last[-1] + 1] if last.size else lens[:0]
    if lens.size < 2 or np.any(lens != len(header)):
        return None  # blank lines (they shift the spreadsheet rows), short or long records:
        # let the exact path number and name them
    numeric = [c for c in header if mapping[c] in PART_NUMERIC_COLUMNS]
    if numeric and _BOOL_CELL.search(text):
        return None  # pandas would read TRUE/FALSE in a number column as 1/0; float() refuses
    try:
        df = pd.read_csv(io.StringIO(text), header=0, names=header, dtype={c: (np.float64 if c in numeric else str)
                                                                  for c in header},
                         keep_default_na=False, na_values={c: [""] for c in numeric},
                         skipinitialspace=True, skip_blank_lines=True, engine="c")
    except (ValueError, pd.errors.ParserError, csv.Error):
        return None  # a cell that is not a number (or odd quoting): the exact path names it
    if len(df) != lens.size - 1:
        return None
    text_cols = {c: df[c].str.strip() for c in header if c not in numeric}
    blank = np.ones(len(df), bool)
    for c in numeric:
        blank &= df[c].isna().to_numpy()
    for c in text_cols.values():
        blank &= (c == "").to_numpy()
    if blank.any():
        return None  # rows of empty cells are skipped by the exact path
    rows = list(range(2, len(df) + 2))
    table: dict[str, object] = {}
    for col in header:
        canon = mapping[col]
        if canon in PART_NUMERIC_COLUMNS:
            vals = df[col].to_numpy(dtype=np.float64, copy=True)
            table[canon] = _check_numbers(vals, np.isnan(vals), rows, path, col, canon,
                                          lambda k, c=col: df[c].iloc[k])
        else:
            s = text_cols[col]
            long = (s.str.len() > MAX_CELL_CHARS).to_numpy(dtype=bool)
            if long.any():
                k = int(np.argmax(long))
                raise InputError(f"cell of {len(s.iloc[k]):,} characters", file=path, row=rows[k],
                                 field=col, value=s.iloc[k],
                                 expected=f"at most {MAX_CELL_CHARS:,} characters")
            _check_text_fast(s, rows, path, col)
            if canon in _CHOICES:
                ok = np.array(_choice_mask(s, canon), bool)
                if canon not in PART_REQUIRED:
                    ok |= (s == "").to_numpy()
                if not ok.all():
                    k = int(np.argmax(~ok))
                    v = s.iloc[k]
                    raise InputError(_choice_message(canon, v), file=path, row=rows[k], field=col,
                                     value=v, expected=expected_text(canon, ""))
            table[canon] = tuple(s.tolist())
    check_rows(table, rows, path, {mapping[c]: c for c in header})
    return table, rows


def _choice_mask(s, canon: str) -> np.ndarray:
    if canon == "part_id":
        return s.str.fullmatch(_PART_ID.pattern).to_numpy(dtype=bool)
    if canon == "source":
        return (s != "").to_numpy()
    allowed = {"grade": GRADES, "bias_instability_convention": BIAS_CONVENTIONS,
               "verified": VERIFIED_STATES}[canon]
    return s.isin(allowed).to_numpy()


def _check_text_fast(s, rows: list[int], path: Path, col: str) -> None:
    cand = s.str[:1].isin(FORMULA_START).to_numpy() | s.str.contains(
        _BAD_CONTROL.pattern, regex=True).to_numpy(dtype=bool)
    if cand.any():
        idx = np.flatnonzero(cand)
        _check_text(tuple(s.iloc[idx]), [rows[k] for k in idx], path, col)


def _table_row_by_row(path: Path, text: str) -> tuple[dict[str, object], list[int]]:
    """The exact path (any CSV layout: blank, short or multi-line rows): records in chunks,
    each chunk checked column by column; used when the fast path cannot be sure."""
    records = _iter_rows(path, text)
    first = next(records, None)
    if first is None:
        raise InputError("file has no header", file=path, expected="a header row")
    header = first[1]
    _check_not_comment(header, path, first[0])
    mapping = _map_header(header, path, PART_COLUMNS, PART_REQUIRED, ALT_UNIT_COLUMNS)
    columns: dict[str, list] = {mapping[c]: [] for c in header}
    row_numbers: list[int] = []
    chunk: list[list[str]] = []
    rows_chunk: list[int] = []

    def flush() -> None:
        if not chunk:
            return
        cols = list(zip(*chunk))
        for j, col in enumerate(header):
            canon = mapping[col]
            if canon in PART_NUMERIC_COLUMNS:
                columns[canon].append(_numbers(cols[j], rows_chunk, path, col, canon))
            else:
                _check_text(cols[j], rows_chunk, path, col)
                if canon in _CHOICES:
                    _check_choice(cols[j], rows_chunk, path, col, canon, _CHOICES[canon],
                                  canon in PART_REQUIRED)
                columns[canon].append(cols[j])
        row_numbers.extend(rows_chunk)
        chunk.clear()
        rows_chunk.clear()

    for i, r in records:
        _check_length(r, header, path, i)
        chunk.append(r)
        rows_chunk.append(i)
        if len(chunk) >= _CHUNK:
            flush()
    flush()
    if not row_numbers:
        raise InputError("has a header but no parts", file=path, expected="at least one data row")
    table = {c: (np.concatenate(v) if c in PART_NUMERIC_COLUMNS else
                 tuple(x for part in v for x in part)) for c, v in columns.items()}
    check_rows(table, row_numbers, path, {mapping[c]: c for c in header})
    return table, row_numbers


def count_valid_parts(path: str | Path) -> int:
    """Number of parts of a valid parts CSV (fast: no models built); raises on the first bad cell."""
    return len(validate_parts_table(path)[1])


def collect_errors(path: str | Path, limit: int = 200) -> list[InputError]:
    """Every bad cell of a parts CSV (at most ``limit``), in row then column order, each an
    :class:`InputError` naming file, row, field, value and what was expected.

    The same checks as :func:`validate_parts_table`, cell by cell (slow, so only used to report
    a file that failed), and in the same pass the checks across rows (:func:`row_problems`:
    repeated ids, ids differing only in case, the bias-convention rule) over the rows of the
    right length, each on the cells that are themselves valid. An unreadable file or a bad
    header is one error.
    """
    path = Path(path)
    text = _read_text(path)
    records = _iter_rows(path, text)
    first = next(records, None)
    if first is None:
        return [InputError("file has no header", file=path, expected="a header row")]
    header = first[1]
    try:
        _check_not_comment(header, path, first[0])
        mapping = _map_header(header, path, PART_COLUMNS, PART_REQUIRED, ALT_UNIT_COLUMNS)
    except InputError as err:
        return [err]
    # what the checks across rows need, a bad cell replaced by a neutral value ('' or NaN)
    across = [c for c in header if mapping[c] in ACROSS_ROWS]
    kept: dict[str, list] = {mapping[c]: [] for c in across}
    kept_rows: list[int] = []
    errors: list[InputError] = []
    for i, r in records:
        try:
            _check_length(r, header, path, i)
        except InputError as err:
            errors.append(err)
            continue
        for j, col in enumerate(header):
            canon, cell, rows = mapping[col], (r[j],), [i]
            value = r[j]
            try:
                if canon in PART_NUMERIC_COLUMNS:
                    value = float(_numbers(cell, rows, path, col, canon)[0])
                else:
                    _check_text(cell, rows, path, col)
                    if canon in _CHOICES:
                        _check_choice(cell, rows, path, col, canon, _CHOICES[canon],
                                      canon in PART_REQUIRED)
            except InputError as err:
                errors.append(err)
                value = float("nan") if canon in PART_NUMERIC_COLUMNS else ""
            if canon in kept:
                kept[canon].append(value)
        kept_rows.append(i)
        if len(errors) >= limit:
            return errors[:limit]
    if kept_rows and "part_id" in kept:
        table = {c: (np.array(v, float) if c in PART_NUMERIC_COLUMNS else tuple(v)) for c, v in kept.items()}
        errors += row_problems(table, kept_rows, path, {mapping[c]: c for c in header})
        errors.sort(key=lambda e: e.row or 0)  # stable: a row's cells stay in column order
    if not errors:
        try:
            validate_parts_table(path)
        except InputError as err:
            errors.append(err)
    return errors[:limit]
