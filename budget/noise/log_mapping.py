"""Column/unit mapping of an IMU log CSV onto the canonical layout.

Canonical columns: ``time_s, gyro_x_dps … accel_z_mps2[, temp_c]``. Any channel column may
carry another unit tag (``gyro_x_rps``, ``accel_y_g`` …, see :data:`budget.units.CHANNEL_UNIT_TO_SI`),
the time column may be ``time_ms``, ``time_us`` or ``time_ns``. A unit written in brackets after
the channel or the time is read too (``gyro_x [deg/s]``, ``acc_z (m/s^2)``, ``time [ms]``,
:func:`budget.units.split_channel_column`); an unknown one is an error listing the accepted units,
and one that disagrees with a mapping's target (``"GyrX [deg/s]": "gyro_x_rps"``) is refused.
A time column of clock text (``Time (UTC)``: ``2026-03-01T12:00:00.005Z``, ``12:00:00.005``) is
read by :mod:`budget.noise.log_clock` when the file's first cells show it (:func:`clock_candidates`).
Other layouts are read through an explicit :class:`LogMapping` (source column → canonical name;
a time column may be mapped to ``time``, its unit then the header's own, ``"t [ms]": "time"``,
or its clock text); nothing is guessed.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from .. import units as u
from ..errors import LOG_NAMES_WAY, InputError, from_validation_error, refuse_bool_numbers
from ..structured import read_structured
from .log_clock import is_clock_name

#: Time column name → factor to seconds.
TIME_COLUMNS = {"time_s": 1.0, "time_ms": 1e-3, "time_us": 1e-6, "time_ns": 1e-9}
TEMP_COLUMN = "temp_c"
#: A mapping's target for the time column whose unit is the source header's own (``"t [ms]": "time"``)
#: or that holds clock text (``"Zeit (UTC)": "time"``).
TIME_TARGET = "time"


def _check_target(name: str) -> str:
    if name in TIME_COLUMNS or name in (TEMP_COLUMN, TIME_TARGET):
        return name
    base, written = u.split_header_unit(name)
    if written is not None and base.lower() in TIME_NAMES:  # "time [ms]": its unit must be one
        u.header_time_factor(written, name)
        return name
    u.split_channel_column(name)  # raises ValueError naming what is expected
    return name


class LogMapping(BaseModel):
    """How to read a non-canonical IMU log (a user-written JSON/YAML file).

    ``columns`` maps a source column to a canonical name, e.g.
    ``{"GyrX": "gyro_x_rps", "t": "time_ms", "AccZ": "accel_z_g"}``. Columns not listed keep
    their names (used if canonical, otherwise ignored and reported). ``rate_hz`` is needed
    when the log has no time column. ``skip_rows``: preamble lines before the header row (a
    logger's settings). ``scale``: source column → factor that turns its raw value into the
    unit of its canonical name, e.g. ``{"gx": 0.0076336}`` (1/131: counts → deg/s) with
    ``"gx": "gyro_x_dps"`` — raw counts are read through a stated scale, never guessed.
    ``decimal``: the decimal mark of the numbers, ``"."`` or ``","`` (``0,0125`` as spreadsheets
    in many locales write; the ``delimiter`` is then usually ``";"`` and must differ from it).
    """

    model_config = ConfigDict(extra="forbid")
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    columns: dict[str, str] = Field(default_factory=dict)
    rate_hz: float | None = Field(None, gt=0.0, le=1e7, allow_inf_nan=False)
    delimiter: str = Field(",", min_length=1, max_length=1)
    comment: str | None = Field(None, min_length=1, max_length=1)
    skip_rows: int = Field(0, ge=0, le=10_000)
    scale: dict[str, float] = Field(default_factory=dict)
    decimal: Literal[".", ","] = "."

    @model_validator(mode="after")
    def _decimal_not_delimiter(self) -> "LogMapping":
        if self.decimal == self.delimiter:
            raise ValueError(f"decimal mark and delimiter are both {self.decimal!r}: numbers written "
                             "with decimal commas need another delimiter (\"delimiter\": \";\")")
        return self

    @field_validator("scale")
    @classmethod
    def _scales_finite(cls, v: dict[str, float]) -> dict[str, float]:
        for src, k in v.items():
            if not (k == k and abs(k) < float("inf") and k != 0.0):
                raise ValueError(f"scale for column {src!r} must be a finite non-zero number (got {k})")
        return v

    @field_validator("columns")
    @classmethod
    def _targets_known(cls, v: dict[str, str]) -> dict[str, str]:
        for src, dst in v.items():
            try:
                _check_target(dst)
            except ValueError as err:
                raise ValueError(f"mapping for column {src!r}: {err}; or time_s|time_ms|time_us|"
                                 "time_ns|time (the header's unit or clock text)|time [unit]|temp_c") from None
        return v

    @classmethod
    def load(cls, path: str | Path) -> "LogMapping":
        """Read a mapping from a JSON or YAML file."""
        data = read_structured(path, "a column mapping", max_bytes=1_000_000)
        try:
            return cls.model_validate(data)
        except ValidationError as err:
            raise from_validation_error(err, file=path) from None


#: Header names of a time column whose unit is written in brackets (``time [s]``, ``t (ms)``).
TIME_NAMES = ("time", "t", "timestamp")


def is_channel_column(name: str) -> bool:
    """True when ``name`` is meant as a sensor channel — ``gyro_…``/``accel_…``, or a channel
    with its unit in brackets (``gyro_x [deg/s]``, ``acc_z (m/s^2)``) — so that a unit it gets
    wrong is an error rather than an ignored column."""
    if name.startswith(("gyro_", "accel_")):
        return True
    base, written = u.split_header_unit(name)
    return written is not None and (base.lower() in u.CHANNELS or base.lower() in u.CHANNEL_NAME_ALIASES)


def _time_column(name: str, path) -> float | None:
    """Factor to seconds when ``name`` is a time column (``time_s``, ``time_ms`` …, or ``time``
    with a time unit in brackets, ``time [s]``), else None. ``Time (UTC)`` has no unit: it is the
    time column only when it holds clock text (:func:`clock_candidates`), else left out and named
    by :func:`time_unit_hint` when the log then lacks one."""
    if name in TIME_COLUMNS:
        return TIME_COLUMNS[name]
    base, written = u.split_header_unit(name)
    if written is None or not (base.lower() in TIME_NAMES or base in TIME_COLUMNS):
        return None
    try:
        factor = u.header_time_factor(written, name)
    except ValueError:
        return None
    if base in TIME_COLUMNS and not math.isclose(TIME_COLUMNS[base], factor):
        raise InputError(f"column {name!r} names two time units, {base[5:]} in its name and {written!r} "
                         "in brackets", file=path, row=1, field=name, expected="one unit: write one")
    return factor


#: A temperature column: ``temp`` or ``temperature``, with an optional prefix word (``imu_temp``,
#: ``die_temperature``) and an optional unit suffix (``temp_c``, ``temperature_k``, ``temp_degf``).
_TEMP_NAME = re.compile(r"(?:[a-z0-9]+_)?(?:temp|temperature)(?:_(c|degc|k|f|degf))?")


def _temp_column(name: str, path, row: int) -> tuple[float, float, bool] | None:
    """``(scale, offset, unit_written)`` to °C when ``name`` is a temperature column (``temp_c``,
    ``temperature [°C]``, ``Temp (K)``, ``imu_temp_f``, ``temperature``), else None. A column
    with no unit is read as °C (``unit_written`` False: the reader says so); a unit in brackets
    that contradicts the name's suffix is refused."""
    base, written = u.split_header_unit(name)
    m = _TEMP_NAME.fullmatch(base.strip().lower().replace(" ", "_"))
    if m is None:
        return None
    units = [w for w in (m.group(1), written) if w]
    try:
        scales = [u.temperature_to_c(w, name) for w in units]
    except ValueError as err:
        raise InputError(str(err), file=path, row=row, field=name) from None
    if len(scales) == 2 and scales[0] != scales[1]:
        raise InputError(f"column {name!r} names two temperature units, {units[0]!r} in its name and "
                         f"{units[1]!r} in brackets", file=path, row=row, field=name,
                         expected="one unit: write one")
    return (*(scales[0] if scales else (1.0, 0.0)), bool(scales))


#: Sensor column names loggers write (GyroX, gyr_y, wz, AccX, acc_y, ax; ROS's
#: ``field.angular_velocity.x``; ``w_RS_S_x`` of public visual-inertial datasets): suggested, never
#: read without a mapping — the name does not say the unit, and a bracketed one may be wrong.
_SENSOR_NAME = re.compile(r"(?:field\.)?(?P<kind>angular_velocity|linear_acceleration|gyroscope|gyro|gyr|omega|"
                          r"rate|w|g|accelerometer|accel|acc|a)(?:[_.][a-z0-9]+)*?[ _.-]?(?P<axis>x|y|z)")
#: Names of the time column in those layouts (ROS's ``%time`` and header stamp are in ns).
_NS_STAMPS = ("%time", "field.header.stamp", "header.stamp")
_TIME_NAMES = (*TIME_NAMES, "#timestamp", *_NS_STAMPS)
#: ROS messages carry SI units (REP 103): rad/s and m/s², stamps in ns.
_ROS_KINDS = ("angular_velocity", "linear_acceleration")
_TIME_TAGS = {factor: name for name, factor in TIME_COLUMNS.items()}  # factor to s → column name


def suggest_mapping(header: list[str]) -> dict[str, str]:
    """A mapping a user could write for a header without canonical names (``GyroX`` →
    ``gyro_x_<unit>``, ``acc_z`` → ``accel_z_<unit>``, ``Time`` → ``time_<unit>``), when it
    names three axes of at least one sensor; ``{}`` otherwise. The unit is the one written in
    brackets when it is a channel's (``w_RS_S_x [rad s^-1]`` → ``gyro_x_rps``), SI for ROS names
    (REP 103), else deg/s and m/s² for the user to correct. Only said in an error, never applied:
    the units are the user's to write."""
    found: dict[str, str] = {}
    for col in header:
        base, written = u.split_header_unit(col)
        m = _SENSOR_NAME.fullmatch(base.strip().lower())
        if m is None:
            continue
        kind = "accel" if m.group("kind") in ("linear_acceleration", "accelerometer", "accel", "acc", "a") \
            else "gyro"
        tag = ("mps2" if kind == "accel" else "rps") if m.group("kind") in _ROS_KINDS else \
            ("mps2" if kind == "accel" else "dps")
        said = _written_channel_unit(written) if written is not None else None
        if said is not None and said[0] == kind:  # else the default, for the user to correct
            tag = said[1]
        found[col] = f"{kind}_{m.group('axis')}_{tag}"
    kinds = [dst.split("_")[0] for dst in found.values()]
    if not any(kinds.count(k) >= 3 for k in ("gyro", "accel")):
        return {}
    for col in header:
        base, written = u.split_header_unit(col)
        if base.strip().lower() not in _TIME_NAMES:
            continue
        factor = 1e-9 if base.strip().lower() in _NS_STAMPS else 1.0
        if written is not None and (said := _written_seconds(written)) is not None:
            factor = said
        elif written is not None:  # Time (UTC): clock text, read through the target time
            return {col: TIME_TARGET} | found
        if factor in _TIME_TAGS:
            return {col: _TIME_TAGS[factor]} | found
    return found


def unread_channel(column: str) -> str | None:
    """For a column the reader leaves out whose header writes a rate or specific-force unit
    (``gx(rad/s)``, ``AccX [g]``), the canonical name a mapping would give it (``gyro_x_rps``;
    ``gyro_?_rps`` when its name says no axis); None when it writes no such unit. Such a column is
    a sensor the result would silently lack: the reader warns and names the mapping."""
    base, written = u.split_header_unit(column)
    said = _written_channel_unit(written) if written is not None else None
    if said is None:
        return None
    m = _SENSOR_NAME.fullmatch(base.strip().lower())
    return f"{said[0]}_{m.group('axis') if m else '?'}_{said[1]}"


def mapped_columns(header: list[str], keys) -> dict[str, str]:
    """Each mapping key of ``keys`` → the header column it names: the column of that name, or the
    one column whose name it is without the unit written after it (``"t"`` names ``t [ms]``, whose
    unit is then read and checked against the target); a key naming none is kept as it is (the
    plan refuses it, naming the header)."""
    out = {}
    for key in keys:
        if key in header:
            out[key] = key
            continue
        split = {h: u.split_header_unit(h) for h in header}
        bare = [h for h, (base, written) in split.items() if written is not None and base == key]
        out[key] = bare[0] if len(bare) == 1 else key
    return out


def mapping_by_column(header: list[str],
                      mapping: LogMapping | None) -> tuple[dict[str, str], dict[str, float]]:
    """The mapping's ``columns`` and ``scale`` keyed by the header's columns (:func:`mapped_columns`)."""
    if mapping is None:
        return {}, {}
    cols = mapped_columns(header, [*mapping.columns, *mapping.scale])
    return ({cols[k]: v for k, v in mapping.columns.items()}, {cols[k]: v for k, v in mapping.scale.items()})


def clock_candidates(header: list[str], mapping: LogMapping | None) -> list[str]:
    """The columns of ``header`` that may hold clock text, to be looked at in the file: those a
    mapping sends to ``time`` without a time unit in their header, and, unmapped, those named
    like a time (:data:`budget.noise.log_clock.CLOCK_NAMES`: ``Time``, ``Time (UTC)``,
    ``timestamp [local]``) whose bracket, if any, is no time unit."""
    rename = mapping_by_column(header, mapping)[0]
    found = []
    for col in header:
        name = rename.get(col, col)
        if col in rename and name != TIME_TARGET:
            continue
        _, col_written = u.split_header_unit(col)
        if name == TIME_TARGET and (col_written is None or _written_seconds(col_written) is None):
            found.append(col)
            continue
        base, written = u.split_header_unit(name)
        if name not in TIME_COLUMNS and is_clock_name(base) \
                and (written is None or _written_seconds(written) is None):
            found.append(col)
    return found


def time_unit_hint(ignored) -> str:
    """Why a time column among the ``ignored`` ones (``time [fortnight]``) was not read — its unit
    is none of the accepted ones — or ``""``."""
    for name in ignored:
        base, written = u.split_header_unit(name)
        if written is not None and base.lower() in TIME_NAMES:
            try:
                u.header_time_factor(written, name)
            except ValueError as err:
                return f"; {err}"
    return ""


def _written_channel_unit(written: str) -> tuple[str, str] | None:
    """(``gyro``/``accel``, tag) of a channel unit written in a header, or None if it is none."""
    key = written.strip().lower().replace(" ", "")
    return next(((kind, tags[key]) for kind, tags in u.HEADER_CHANNEL_UNITS.items() if key in tags), None)


def _written_seconds(written: str) -> float | None:
    """Factor to seconds of a time unit written in a header (``ms`` → 1e-3), or None if it is none."""
    try:
        return u.header_time_factor(written)
    except ValueError:
        return None


def _check_mapped_unit(col: str, target: str, path, row: int) -> None:
    """A mapped source column whose header writes a unit (``GyrX [deg/s]``, ``t (ms)``) must agree
    with the unit of the canonical name the mapping gives it: two sources of a unit that disagree
    are refused, never one of them chosen. A bracketed word that is no rate, specific-force or
    time unit (``[raw]``, ``[LSB]``, ``(°C)``) is no claim."""
    _, written = u.split_header_unit(col)
    if written is None:
        return
    said = _written_channel_unit(written)
    seconds = _written_seconds(written)
    if said is None and seconds is None:
        return
    if target == TIME_TARGET:
        return  # the header's unit is the one read
    target_seconds = TIME_COLUMNS.get(target)
    if target_seconds is None and (t_written := u.split_header_unit(target)[1]) is not None \
            and u.split_header_unit(target)[0].lower() in TIME_NAMES:
        target_seconds = _written_seconds(t_written)  # "time [ms]"
    if target_seconds is not None:
        agree = seconds is not None and math.isclose(seconds, target_seconds)
        expected = ("the mapping's time column in the header's unit (time_s, time_ms, time_us, time_ns), "
                    "or time: the header's own unit")
    elif is_channel_column(target):
        try:
            ch, tag = u.split_channel_column(target)
        except ValueError:
            return  # the target's own error is raised where it is planned
        agree = said == ("gyro" if ch.startswith("gyro") else "accel", tag)
        expected = ("the mapping's target in the header's unit"
                    + (f" ({ch}_{said[1]})" if said and said[0] == ch.split("_")[0] else "")
                    + ", or the header without a unit")
    else:
        return
    if not agree:
        raise InputError(f"column {col!r} writes its unit as {written!r} but the mapping reads it as "
                         f"{target}: the two units disagree", file=path, row=row, field=col,
                         expected=expected)


@dataclass(frozen=True)
class ColumnPlan:
    """Which source columns are read, and into what (canonical name, factor to SI)."""

    sources: tuple[str, ...]          # source column names, in read order
    targets: tuple[str, ...]          # canonical names (same order)
    factors: tuple[float, ...]        # multiply the source value by this to get SI / seconds / °C
    time_index: int | None            # position of the time column in ``sources``
    temp_index: int | None
    channel_index: dict[str, int]     # 'gyro_x' → position
    source_units: dict[str, str]      # 'gyro_x' → 'dps'
    ignored: tuple[str, ...]          # source columns not read
    temp_offset_c: float = 0.0        # added after the factor: °C = factor·value + offset (K, °F)
    temp_notes: tuple[str, ...] = ()  # what the reader chose about temperature (said in the log's notes)
    time_clock: str | None = None     # the time column when it holds clock text (read by log_clock)
    header_notes: tuple[str, ...] = ()  # how the header row was read (a leading comment mark)


def plan_columns(header: list[str], mapping: LogMapping | None, path: str,
                 clock: str | None = None) -> ColumnPlan:
    """Resolve the header against the mapping; raise :class:`InputError` on any ambiguity.
    ``clock``: the column of :func:`clock_candidates` whose first cells are clock text — the time
    column when the log has no numeric one (or a mapping sends it to ``time``)."""
    rename, scale = mapping_by_column(header, mapping)
    missing = [src for src in rename if src not in header]
    missing += [src for src in scale if src not in header and src not in missing]
    if missing:
        full = [h for h in header if u.split_header_unit(h)[0] == missing[0]]
        said = (f"; {missing[0]!r} is the name of {len(full)} columns with a unit after it "
                f"({', '.join(map(repr, full))}): map the full name" if full else "")
        raise InputError(f"mapped column(s) not in the file: {', '.join(map(repr, missing))}{said}",
                         file=path, expected=f"one of the header columns {header}")
    dup = sorted({h for h in header if header.count(h) > 1})
    if dup:
        raise InputError(f"duplicate column name(s) {dup}", file=path, row=1)
    sources, targets, factors, ignored = [], [], [], []
    channel_index: dict[str, int] = {}
    source_units: dict[str, str] = {}
    time_index = temp_index = None
    header_row = 1 + (mapping.skip_rows if mapping else 0)
    temps = {col: t for col in header
             if (t := _temp_column(rename.get(col, col), path, header_row)) is not None}
    named = [col for col in temps if rename.get(col, col) == TEMP_COLUMN]
    if len(named) > 1:
        raise InputError("more than one temperature column", file=path, row=header_row, field=named[1],
                         expected="one column named or mapped temp_c")
    chosen = named[0] if named else next(iter(temps), None)
    temp_offset, temp_notes = 0.0, []
    if chosen is not None and not temps[chosen][2]:
        temp_notes.append(f"temperature column {chosen!r} has no unit: read as °C")
    if len(temps) > 1:
        temp_notes.append(f"temperature read from {chosen!r}; not read: "
                          + ", ".join(repr(c) for c in temps if c != chosen)
                          + " (a mapping to temp_c chooses another)")
    clock_unmapped = None
    header_notes = []
    for k, col in enumerate(header):
        name = rename.get(col, col)
        if k == 0 and col not in rename and col.startswith("#") and (bare := _commented_name(col, path)):
            name = bare  # "# time_s,gyro_x_dps,…": the header as NumPy's savetxt writes it
            header_notes.append(f"the header row starts with a comment mark (as NumPy's savetxt writes it): "
                                f"its first column {col!r} read as {bare!r}")
        if col in rename:
            _check_mapped_unit(col, name, path, 1 + (mapping.skip_rows if mapping else 0))
        if name == TIME_TARGET and col in rename:
            _, written = u.split_header_unit(col)
            time_factor = _written_seconds(written) if written is not None else None
            if time_factor is None and col != clock:
                raise InputError(f"column {col!r} is mapped to time but its header writes no time unit "
                                 "and its first cells are no clock text", file=path, row=header_row,
                                 field=col, expected="a time unit in its header (t [ms]), a mapping to "
                                 "time_s|time_ms|time_us|time_ns, or clock text (2026-03-01T12:00:00Z, "
                                 "12:00:00.005)")
        elif col == clock:
            clock_unmapped = col  # the time column unless another one is numeric
            continue
        else:
            time_factor = _time_column(name, path)
        if time_factor is None and col == clock:
            time_factor = 1.0  # log_clock reads seconds
        if time_factor is not None:
            if time_index is not None:
                raise InputError("more than one time column", file=path, row=1, field=col)
            time_index = len(sources)
            factor = time_factor
        elif col in temps:
            if col != chosen:
                continue
            temp_index = len(sources)
            factor, temp_offset, _ = temps[col]
        elif is_channel_column(name):
            try:
                ch, unit = u.split_channel_column(name)
            except ValueError as err:
                raise InputError(str(err), file=path, row=1, field=col) from None
            if ch in channel_index:
                raise InputError(f"channel {ch} given twice", file=path, row=1, field=col)
            channel_index[ch] = len(sources)
            source_units[ch] = unit
            factor = u.CHANNEL_UNIT_TO_SI[unit]
        else:
            ignored.append(col)
            continue
        sources.append(col)
        targets.append(name)
        factors.append(factor * scale.get(col, 1.0))
    time_clock = clock if clock is not None and time_index is not None and sources[time_index] == clock \
        else None
    if clock_unmapped is not None:
        if time_index is None:
            time_index, time_clock = len(sources), clock_unmapped
            sources.append(clock_unmapped)
            targets.append(TIME_TARGET)
            factors.append(1.0)
        else:
            ignored.append(clock_unmapped)
    if not channel_index:
        shown = ", ".join(repr(h) for h in header[:4]) + (", …" if len(header) > 4 else "")
        hint = ""
        joined = "".join(header)
        other = [d for d in (";", "\t", "|") if d in joined]
        if other:
            hint = (f"; the header holds {other[0]!r}: a file delimited by it needs a mapping with "
                    f"\"delimiter\": {other[0]!r}")
        elif len(header) == 1 and (words := header[0].split())[1:] and (
                any(is_channel_column(w) or w in TIME_COLUMNS for w in words) or suggest_mapping(words)):
            hint = ("; the header is one field of names separated by spaces: a file delimited by "
                    "spaces (aligned columns too) needs a mapping with \"delimiter\": \" \"")
        elif suggested := suggest_mapping(header):
            hint = ("; the header looks like sensor columns: a mapping such as {\"columns\": {"
                    + ", ".join(f'"{src}": "{dst}"' for src, dst in suggested.items())
                    + "}} reads them — write the unit each holds (gyro: dps, rps, dph; accel: "
                      "mps2, g; raw counts: with a \"scale\")")
        elif header and header[0].lstrip().startswith("#"):
            hint = ("; the file starts with comment lines ('#'): a mapping's \"comment\": \"#\" skips them "
                    "(and any further ones), \"skip_rows\" a fixed number of preamble lines")
        elif len(header) <= 2 or not any(h.replace("_", "").isalnum() for h in header):
            hint = ("; if the file starts with preamble lines (device, date, units), a mapping's "
                    "\"skip_rows\" skips them")
        raise InputError(f"no sensor channel column found in the header row ({shown}){hint}",
                         file=path, row=1 + (mapping.skip_rows if mapping else 0),
                         expected=f"columns like gyro_x_dps … accel_z_mps2, {LOG_NAMES_WAY.cli}")
    return ColumnPlan(tuple(sources), tuple(targets), tuple(factors), time_index, temp_index,
                      channel_index, source_units, tuple(ignored), temp_offset, tuple(temp_notes),
                      time_clock, tuple(header_notes))


def _commented_name(column: str, path) -> str | None:
    """The name after the comment mark of a first header column (``# time_s`` → ``time_s``) when
    it is a time or channel column the reader knows, else None (``#timestamp`` of a layout read
    through a mapping stays as it is unless it writes a time unit, ``#timestamp [ns]``)."""
    bare = column.lstrip("#").strip()
    if not bare:
        return None
    if bare in TIME_COLUMNS or _time_column(bare, path) is not None or is_channel_column(bare):
        return bare
    return None
