"""Validate an uploaded parts CSV without trusting it (no Streamlit here; unit-testable).

The bytes are size-checked, written to a private temporary file and read with
:func:`budget.catalog.io.read_parts` — the same validator as the CLI. The file is text only: it
is never executed or unpickled. ``read_parts`` stops at the first bad cell; to show the user
every bad row at once, each data row is then validated on its own (header + that row) and
its errors are reported with the row number of the uploaded file.
"""

from __future__ import annotations

import csv
import io
import tempfile
from dataclasses import dataclass
from pathlib import Path

from budget.catalog.io import read_parts
from budget.catalog.schema import PartSpec
from budget.errors import InputError
from budget.safe_text import printable

MAX_UPLOAD_BYTES = 5_000_000
#: At most this many errors are listed; at most this many rows are re-validated one by one.
MAX_REPORTED_ERRORS = 50
MAX_SCANNED_ROWS = 2_000


@dataclass(frozen=True)
class UploadCheck:
    """Outcome of validating one upload: ``parts`` when valid, else ``errors`` (first error first)."""

    filename: str
    parts: dict[str, PartSpec] | None
    errors: tuple[InputError, ...] = ()
    truncated: bool = False

    @property
    def ok(self) -> bool:
        return self.parts is not None and not self.errors

    def error_rows(self) -> list[dict]:
        """One dict per error: row, column, value, problem, expected (for a table)."""
        return [{"row": e.row, "column": e.field,
                 "value": None if e.value is None else printable(str(e.value), 80),
                 "problem": e.reason, "expected": e.expected} for e in self.errors]


def _rename(err: InputError, filename: str, row: int | None = None) -> InputError:
    """The same error naming the uploaded file (not the temporary copy) and its own row number."""
    return InputError(err.reason, file=filename, row=row if row is not None else err.row, field=err.field,
                      value=err.value, expected=err.expected)


def _row_errors(text: str, tmp: Path, filename: str) -> tuple[list[InputError], bool]:
    """Validate each data row alone; rows are numbered as ``read_parts`` numbers them (as a
    spreadsheet does: blank records are skipped but counted)."""
    rows = [(i, r) for i, r in enumerate(csv.reader(io.StringIO(text, newline="")), start=1)
            if any(c.strip() for c in r)]
    errors: list[InputError] = []
    truncated = len(rows) - 1 > MAX_SCANNED_ROWS
    header = rows[0][1]
    for number, row in rows[1:MAX_SCANNED_ROWS + 1]:
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows([header, row])
        tmp.write_text(buf.getvalue(), encoding="utf-8")
        try:
            read_parts(tmp)
        except InputError as err:
            errors.append(_rename(err, filename, row=number))
            if len(errors) >= MAX_REPORTED_ERRORS:
                return errors, True
    return errors, truncated


def check_upload(data: bytes, filename: str, max_bytes: int = MAX_UPLOAD_BYTES) -> UploadCheck:
    """Validate uploaded CSV bytes; returns the parts or every error found (never raises)."""
    name = Path(filename or "upload.csv").name[:200] or "upload.csv"
    if len(data) == 0:
        return UploadCheck(name, None, (InputError("file is empty", file=name,
                                                   expected="a header row and at least one part"),))
    if len(data) > max_bytes:
        return UploadCheck(name, None, (InputError(f"file is {len(data)} bytes", file=name,
                                                   expected=f"at most {max_bytes} bytes"),))
    with tempfile.TemporaryDirectory(prefix="sar_budget_upload_") as d:
        tmp = Path(d) / "upload.csv"
        tmp.write_bytes(data)
        try:
            return UploadCheck(name, read_parts(tmp))
        except InputError as err:
            first = _rename(err, name)
        if first.row is None or first.row < 2:  # file- or header-level: nothing row-wise to add
            return UploadCheck(name, None, (first,))
        rows, truncated = _row_errors(data.decode("utf-8-sig"), Path(d) / "row.csv", name)
    if not any(e.row == first.row for e in rows):  # e.g. a duplicate part_id across rows
        rows.append(first)
    rows.sort(key=lambda e: e.row or 0)
    return UploadCheck(name, None, tuple(rows), truncated)
