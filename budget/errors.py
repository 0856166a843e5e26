"""One exception type for bad user input, with a message that says where and what was expected.

Every reader of user data (catalog CSV, scenario JSON/YAML, IMU logs, Allan tables, noise
models) raises :class:`InputError`; the CLI and the dashboard print its message as one line and
never show a traceback.
"""

from __future__ import annotations

from pathlib import Path

from pydantic import ValidationError


class InputError(ValueError):
    """Bad user input.

    ``str(err)`` reads like ``catalog.csv, row 7, column gyro_arw_deg_rt_h: got 'abc';
    expected a number in deg/√h, ≥ 0``.
    """

    def __init__(self, message: str, *, file: str | Path | None = None, row: int | None = None,
                 field: str | None = None, value: object = None, expected: str | None = None):
        self.file = str(file) if file is not None else None
        self.row = row
        self.field = field
        self.value = value
        self.expected = expected
        self.reason = message
        super().__init__(self._format())

    def rename_file(self, file: str | Path) -> "InputError":
        """The same error naming ``file`` instead (e.g. an upload's name, not its temporary copy)."""
        self.file = str(file)
        self.args = (self._format(),)
        return self

    def _format(self) -> str:
        where = []
        if self.file:
            where.append(self.file)
        if self.row is not None:
            where.append(f"row {self.row}")
        if self.field:
            where.append(f"field {self.field}")
        text = ", ".join(where)
        msg = self.reason
        if self.value is not None:
            msg += f" (got {self.value!r})"
        if self.expected:
            msg += f"; expected {self.expected}"
        return f"{text}: {msg}" if text else msg


def from_validation_error(err: ValidationError, *, file: str | Path | None = None,
                          row: int | None = None) -> InputError:
    """Turn the first pydantic error into an :class:`InputError` naming the field."""
    first = err.errors()[0]
    field = ".".join(str(p) for p in first.get("loc", ())) or None
    value = first.get("input")
    if isinstance(value, dict):
        value = None
    msg = first.get("msg", "invalid value")
    if msg.startswith("Value error, "):  # pydantic's prefix for errors raised by our validators
        msg = msg[len("Value error, "):]
    more = len(err.errors()) - 1
    if more:
        msg += f" (and {more} more error{'s' if more > 1 else ''})"
    return InputError(msg, file=file, row=row, field=field, value=value)
