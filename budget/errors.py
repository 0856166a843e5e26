"""Error types for bad user input and unusable outputs, and the one-line text a user sees.

Every reader of user data (catalog CSV, scenario JSON/YAML, IMU logs, Allan tables, noise
models) raises :class:`InputError`; an output that cannot be written (missing or read-only
folder, ``/proc``) raises :class:`OutputError`. :func:`describe_error` turns *any* exception
into one line and an exit status — the single error boundary the CLI and the dashboard share:
2 = bad input, 1 = environment (unwritable output, out of memory, unexpected failure),
130 = cancelled. Values quoted in messages are shortened with :mod:`reprlib`, so a 5 MB cell
or a billion-laughs YAML tree never reaches ``repr`` whole.

A message that names a way out by an option (``repair=True``, ``--channels``, fewer workers)
writes it as one of the :class:`Way` constants; :data:`WAYS` holds each in the words of every
interface, and ``describe_error(err, interface="dashboard")`` says it as the dashboard offers it
(its tick box, its channel choice, the sidebar) — the one home of those words.
"""

from __future__ import annotations

import numbers
import reprlib
from dataclasses import dataclass
from pathlib import Path
from typing import get_args

from pydantic import ValidationError

#: Exit status of bad input, of an environment problem and of a cancelled run.
EXIT_INPUT, EXIT_ENVIRONMENT, EXIT_CANCELLED = 2, 1, 130

_short = reprlib.Repr()
_short.maxstring = 80
_short.maxother = 80
_short.maxlong = 40
_short.maxlist = _short.maxtuple = _short.maxdict = _short.maxset = 6
_short.maxlevel = 2


def _plain(value: object) -> object:
    """A numpy scalar as the Python number it holds (``-0.25``, not ``np.float64(-0.25)``)."""
    if type(value).__module__ == "numpy" and getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
        return value.item()
    return value


def short_repr(value: object) -> str:
    """``repr(value)`` cut to about 80 characters (nested containers to two levels, numpy
    scalars shown as plain numbers); never expands a huge or deeply shared structure, never fails."""
    try:
        if isinstance(value, (tuple, list)) and len(value) <= 16:
            value = (tuple if isinstance(value, tuple) else list)(_plain(v) for v in value)
        return _short.repr(_plain(value))
    except Exception:  # noqa: BLE001 — a broken __repr__ must not hide the real error
        return f"<{type(value).__name__}>"


def _short_text(text: str | None, limit: int = 200) -> str | None:
    if text is None or len(text) <= limit:
        return text
    return text[:limit - 1] + "…"


class InputError(ValueError):
    """Bad user input.

    ``str(err)`` reads like ``catalog.csv, row 7, column gyro_arw_deg_rt_h: got 'abc';
    expected a number in deg/√h, ≥ 0``.
    """

    def __init__(self, message: str, *, file: str | Path | None = None, row: int | None = None,
                 field: str | None = None, value: object = None, expected: str | None = None):
        self.file = str(file) if file is not None else None
        self.row = row
        self.field = _short_text(str(field)) if field is not None else None
        self.value = value  # shown through short_repr: it may be huge (a 5 MB cell, an alias tree)
        self.expected = expected
        self.reason = message
        #: every error a combined error stands for (:func:`combine_errors`); () for one error
        self.errors: tuple[InputError, ...] = ()
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
            where.append(f"option {self.field}" if self.field.startswith("--") else f"field {self.field}")
        text = ", ".join(where)
        msg = self.reason
        if self.value is not None:
            msg += f" (got {short_repr(self.value)})"
        if self.expected:
            msg += f"; expected {self.expected}"
        return f"{text}: {msg}" if text else msg


class OutputError(OSError):
    """An output (``--json``, ``--out``, ``--report``, ``--append`` …) that cannot be written:
    an environment problem (exit status 1), found before any computation starts."""

    def __init__(self, message: str, *, file: str | Path | None = None, option: str | None = None):
        self.file = str(file) if file is not None else None
        self.option = option
        self.reason = message
        where = ", ".join(x for x in (option, self.file) if x)
        super().__init__(f"{where}: {message}" if where else message)

    def __str__(self) -> str:
        return str(self.args[0])


def _cause(error: dict) -> InputError | None:
    """The :class:`InputError` one of our validators raised for a pydantic error, or None."""
    cause = (error.get("ctx") or {}).get("error")
    return cause if isinstance(cause, InputError) else None


def from_validation_error(err: ValidationError, *, file: str | Path | None = None,
                          row: int | None = None) -> InputError:
    """Turn the first pydantic error into an :class:`InputError` naming the field; every further
    error is named in its message. An error one of our validators raised as an
    :class:`InputError` keeps its own words, value and expectation."""
    errors = err.errors(include_url=False)
    first = errors[0]
    field = ".".join(str(p) for p in first.get("loc", ())) or None
    value = first.get("input")
    if isinstance(value, dict):
        value = None
    msg = first.get("msg", "invalid value")
    if msg.startswith("Value error, "):  # pydantic's prefix for errors raised by our validators
        msg = msg[len("Value error, "):]
    expected = None
    own = _cause(first)
    if own is not None:
        field, value, msg, expected = own.field or field, own.value, own.reason, own.expected
    msg = _short_text(msg, 400)
    others = []  # every further error is named too, not only counted
    for e in errors[1:]:
        loc = ".".join(str(p) for p in e.get("loc", ())) or "(model)"
        cause = _cause(e)
        if cause is not None:
            others.append(error_item_text(cause, loc))
            continue
        m = e.get("msg", "invalid value").removeprefix("Value error, ")
        v = e.get("input")
        got = "" if isinstance(v, dict) or v is None else f" (got {short_repr(v)})"
        others.append(_short_text(f"field {loc}: {m}{got}", 200))
    if others and expected:  # the first error's expectation stays beside it
        got = "" if value is None else f" (got {short_repr(value)})"
        msg, value, expected = f"{msg}{got}; expected {expected}", None, None
    if others:
        if value is not None:  # keep the first error's value next to it, before the others
            msg, value = f"{msg} (got {short_repr(value)})", None
        msg += f"; {len(others)} more error{'s' if len(others) > 1 else ''}: " + "; ".join(others)
    return InputError(msg, file=file, row=row, field=field, value=value, expected=expected)


def error_item_text(err: InputError, field: str | None = None, *, limit: int = 400) -> str:
    """One error of a list, as the further errors of a message name it:
    ``field F: reason (got V; expected E)``."""
    where = err.field or field
    extra = "; ".join(x for x in ((f"got {short_repr(err.value)}" if err.value is not None else ""),
                                  (f"expected {err.expected}" if err.expected else "")) if x)
    text = f"{err.reason}{f' ({extra})' if extra else ''}"
    return _short_text(f"field {where}: {text}" if where else text, limit)


def combine_errors(errors, *, file: str | Path | None = None) -> InputError:
    """One :class:`InputError` for every error of ``errors`` (InputErrors, in the order found): the
    error itself when there is one; otherwise the first one's field, its message with its value
    and expectation, and ``; N more errors: field F: … (got V; expected E); …``. The combined
    error keeps the list in ``errors`` (each error's own field, value and expectation)."""
    errors = list(errors)
    if not errors:
        raise ValueError("combine_errors needs at least one error")
    if len(errors) == 1:
        one = errors[0]
        return one.rename_file(file) if file is not None and one.file is None else one
    first, rest = errors[0], errors[1:]
    head = first.reason
    if first.value is not None:
        head += f" (got {short_repr(first.value)})"
    if first.expected:
        head += f"; expected {first.expected}"
    seen = {first.expected}
    items = []
    for e in rest:  # an expectation said once (two unknown keys share theirs)
        if e.expected in seen:
            e = InputError(e.reason, file=e.file, row=e.row, field=e.field, value=e.value)
        else:
            seen.add(e.expected)
        items.append(error_item_text(e))
    others = "; ".join(items)
    out = InputError(f"{head}; {len(rest)} more error{'s' if len(rest) > 1 else ''}: {others}",
                     file=file if file is not None else first.file, row=first.row, field=first.field)
    out.errors = tuple(errors)
    return out


def _admits(annotation, types: tuple[type, ...]) -> bool:
    if annotation in types:
        return True
    return any(_admits(a, types) for a in get_args(annotation))


_NUMBER_FIELDS: dict[type, frozenset[str]] = {}


def _number_fields(model_cls) -> frozenset[str]:
    """Names of the fields of ``model_cls`` that hold numbers only (not ``bool``), cached."""
    names = _NUMBER_FIELDS.get(model_cls)
    if names is None:
        names = frozenset(n for n, f in model_cls.model_fields.items()
                          if _admits(f.annotation, (float, int)) and not _admits(f.annotation, (bool,)))
        _NUMBER_FIELDS[model_cls] = names
    return names


def _bool_for_number(model_cls, name, value) -> bool:
    """True if ``value`` is (or, one level deep, holds) a bool (Python or numpy) while field ``name`` of
    ``model_cls`` holds numbers only (a field that may be ``bool`` is left alone)."""
    if isinstance(value, (str, int, float)) and not isinstance(value, bool):
        return False  # the common case, decided without looking at the field
    if name not in _number_fields(model_cls):
        return False
    items = (value.values() if isinstance(value, dict)
             else value if isinstance(value, (list, tuple)) else (value,))
    return any(_is_bool(v) for v in items)


def _is_bool(v) -> bool:
    """A Python or numpy bool (numpy's is not a subclass of ``bool``)."""
    return isinstance(v, bool) or getattr(getattr(v, "dtype", None), "kind", "") == "b"


def bool_number_field(model_cls, data) -> str | None:
    """The first key of the mapping ``data`` that gives true/false for a number field of
    ``model_cls`` (see :func:`refuse_bool_numbers`), or None."""
    if isinstance(data, dict):
        for name, value in data.items():
            if _bool_for_number(model_cls, name, value):
                return name
    return None


BOOL_FOR_NUMBER = "true/false where a number is expected"


def refuse_bool_numbers(cls, value, info):
    """Pydantic ``field_validator("*", mode="before")`` body: ``true``/``false`` (JSON, or YAML's
    ``yes``/``on``/``no``/``off``) where a number is expected is refused — pydantic's lax mode
    would read them as 1 and 0. Only fields holding numbers are checked (not those that may be
    ``bool``); a list, tuple or mapping of numbers is checked one level deep
    (``lever_arm_m: [true, 0, 0]``, ``scale: {gx: true}``). Models with a discriminator field
    check their input with :func:`bool_number_field` instead."""
    if info.field_name and _bool_for_number(cls, info.field_name, value):
        raise ValueError(BOOL_FOR_NUMBER)
    return value


def whole_number(name: str, value, minimum: int, expected: str | None = None) -> int:
    """``value`` as an int if it is a whole number ≥ ``minimum`` (a Python or numpy integer);
    otherwise :class:`InputError` naming ``name``. ``True``/``False`` are refused (Python would
    count them as 1 and 0), and so are 2.5, NaN, ``"64"`` and 64.0 (say 64)."""
    expected = expected or f"a whole number ≥ {minimum}"
    if isinstance(value, bool) or getattr(getattr(value, "dtype", None), "kind", "") == "b":  # numpy bools too
        raise InputError(BOOL_FOR_NUMBER, field=name, value=value, expected=expected)
    if not isinstance(value, numbers.Integral):
        raise InputError(f"{name} must be a whole number", field=name, value=value, expected=expected)
    if value < minimum:
        raise InputError(f"{name} must be ≥ {minimum}", field=name, value=value, expected=expected)
    return int(value)


def refuse_repeats(items, key, *, field: str, what: str, cost: str = "adds identical rows") -> None:
    """:class:`InputError` naming ``field`` and the ``key`` (an id, a name) of every item of
    ``items`` given more than once: equal items, as a part id or a preset repeated in a list
    (it would add identical rows — ``cost`` says what else it would cost). Items that only share
    a key are not repeats."""
    kept: dict = {}
    repeated: list = []
    for item in items:
        k = key(item)
        same = kept.setdefault(k, [])
        if any(item is other or _equal(item, other) for other in same):
            if k not in repeated:
                repeated.append(k)
        else:
            same.append(item)
    if repeated:
        names = ", ".join(str(k) for k in repeated)
        raise InputError(f"{what} given more than once: {_short_text(names)}", field=field,
                         expected=f"each {what} once (a repeat {cost})")


def _equal(a, b) -> bool:
    try:
        return bool(a == b)
    except Exception:  # noqa: BLE001 — e.g. numpy arrays inside: only the same object is a repeat
        return False


@dataclass(frozen=True)
class Way:
    """A way out that a message names by an option, in each interface's words: ``cli`` is what
    the library writes (the Python argument and the command-line option — the text of
    ``str(err)`` and of the CLI), ``dashboard`` what the dashboard offers in its place (the input
    or tick box it has, or where else to do it when it has none). A message names a way with
    ``WAY.cli``; :func:`in_words_of` says it for another interface."""

    cli: str
    dashboard: str


#: A log's problems are repaired on request (both dashboard pages that read logs have the box).
REPAIR_WAY = Way("read with repair=True (CLI --repair)", "tick 'repair the log' beside the upload")
#: A log without a time column needs its rate (the dashboard's rate input beside the upload).
LOG_RATE_WAY = Way(", or rate_hz (--rate-hz / mapping rate_hz)",
                   ", or its 'sampling rate (Hz)' under 'column mapping and sampling rate'")
#: Time stamps in ms or µs read as seconds.
LOG_TIME_UNIT_WAY = Way("or give the rate (--rate-hz)", "or write the unit in its header (time [ms]), or give "
                        "the 'sampling rate (Hz)' under 'column mapping and sampling rate'")
#: A log channel that cannot be used (clipped) is left out of the reading.
LOG_CHANNEL_WAY = Way("leave this channel out (--channels, or channels= in the library)",
                      "leave this channel's column out of the uploaded file")
#: The channel of an Allan table that holds one curve and no channel column.
CURVE_CHANNEL_WAY = Way("--channels gyro_z on the command line, channels=['gyro_z'] in Python",
                        "pick it in 'channel of this curve' below the upload")
#: The rate of the record an Allan table was computed from (the table does not hold it).
TABLE_RATE_WAY = Way("--rate-hz of the record", "the sampling rate of the record")
#: An Allan table read without its record (a digitised datasheet curve): how it was asked for.
DIGITISED_WAY = Way("no --rate-hz/--samples", "'record behind the curve' set to 'not known'")
#: A log column that is no canonical name is read through a mapping (uploaded beside the log).
LOG_MAPPING_WAY = Way("and not mapped (--mapping)", "and not mapped (upload a 'column mapping' beside the log)")
#: Logger names in the header (GyroX …): the mapping that reads them.
LOG_NAMES_WAY = Way("or a --mapping that names them (source column → canonical name)",
                    "or a 'column mapping' uploaded beside the log that names them (source column → "
                    "canonical name)")
#: Isolated spikes replaced before a characterisation's fit: keeping them instead.
KEEP_SPIKES_WAY = Way("keep_spikes=True, CLI --keep-spikes, keeps them", "tick 'keep spikes' to keep them")
#: The grade of a characterised part when it cannot be inferred.
GRADE_WAY = Way("an explicit grade (--grade)", "an explicit grade (pick it in 'grade' beside the part id)")
#: The record behind an Allan table the model gap compares (a digitised curve has none).
GAP_RECORD_WAY = Way("--rate-hz F --samples N of the record the curve came from",
                     "'record behind the curve' set to 'known', with the record's sampling rate and samples")
#: Characterising a log on its own (a model of the unit rather than of the catalog part).
NOISE_ALONE_WAY = Way("`sar-budget noise`, `budget.noise`", "the Noise lab page")
#: The model-gap workflow's τ-range check, which the dashboard always makes.
GAP_TAU_CHECK_WAY = Way(" (or check_tau_range=False / --no-tau-check)", "")
#: The channels the model-gap workflow compares (a subset of the measurement's).
GAP_CHANNELS_WAY = Way("channels= / --channels", "pick them in 'channels compared' on the page")
#: A motion run's working memory: the process pool the dashboard does not let one size.
MOTION_MEMORY_WAY = Way("fewer workers, a lower imu_rate_hz", "a lower imu rate (Hz) in the sidebar's scenario fields")

#: Every way a library message names, longest first (a way's words never rewrite another's).
WAYS: tuple[Way, ...] = tuple(sorted((REPAIR_WAY, LOG_RATE_WAY, LOG_TIME_UNIT_WAY, LOG_CHANNEL_WAY, LOG_MAPPING_WAY,
                                      LOG_NAMES_WAY, CURVE_CHANNEL_WAY, TABLE_RATE_WAY, DIGITISED_WAY,
                                      GAP_CHANNELS_WAY, GAP_TAU_CHECK_WAY, MOTION_MEMORY_WAY, KEEP_SPIKES_WAY,
                                      GRADE_WAY, GAP_RECORD_WAY, NOISE_ALONE_WAY),
                                     key=lambda w: -len(w.cli)))
#: The interfaces a message can be said for.
INTERFACES = ("cli", "dashboard")


def in_words_of(text: str, interface: str = "cli") -> str:
    """``text`` (an error's message, a log finding) with every way out it names (:data:`WAYS`)
    in the words of ``interface``: ``"cli"`` leaves it as the library wrote it, ``"dashboard"``
    names the dashboard's inputs instead of options a dashboard user cannot give."""
    if interface not in INTERFACES:
        raise ValueError(f"interface must be one of {', '.join(INTERFACES)}, not {interface!r}")
    if interface == "cli":
        return text
    for way in WAYS:
        text = text.replace(way.cli, getattr(way, interface))
    return text


@dataclass(frozen=True)
class UserMessage:
    """What a user is shown for an exception: one line of ``text`` and the process ``exit_code``."""

    text: str
    exit_code: int
    kind: str  # "input" | "environment" | "cancelled" | "unexpected"


DEBUG_HINT = "rerun with --debug (or SAR_BUDGET_DEBUG=1) for the traceback, and report it"


def describe_error(err: BaseException, interface: str = "cli") -> UserMessage:
    """One line and an exit status for any exception (the CLI's and the dashboard's boundary).

    Bad input (:class:`InputError`, too deep nesting, integers too long to convert) → 2; an
    unwritable output, a file system or memory problem → 1; anything else → 1 with the
    exception type and a hint, never a traceback. ``interface`` (``"cli"`` or ``"dashboard"``)
    says an input problem's ways out in that interface's words (:func:`in_words_of`).
    """
    if isinstance(err, InputError):
        return UserMessage(in_words_of(str(err), interface), EXIT_INPUT, "input")
    if isinstance(err, ValidationError):
        return UserMessage(in_words_of(str(from_validation_error(err)), interface), EXIT_INPUT, "input")
    if isinstance(err, KeyboardInterrupt):
        return UserMessage("cancelled", EXIT_CANCELLED, "cancelled")
    if isinstance(err, RecursionError):
        return UserMessage("input nested too deeply to process (recursion limit reached)",
                           EXIT_INPUT, "input")
    if isinstance(err, ValueError) and "Exceeds the limit" in str(err) and "digits" in str(err):
        return UserMessage("a number has too many digits (more than 4300)", EXIT_INPUT, "input")
    if isinstance(err, OutputError):
        return UserMessage(str(err), EXIT_ENVIRONMENT, "environment")
    if isinstance(err, MemoryError):
        return UserMessage("out of memory: the input or the requested run is too large for this "
                           "machine (use fewer trials/rows, or a smaller file)", EXIT_ENVIRONMENT,
                           "environment")
    if isinstance(err, OSError):
        what = err.strerror or type(err).__name__
        where = f": {err.filename}" if err.filename else ""
        return UserMessage(f"{what}{where}", EXIT_ENVIRONMENT, "environment")
    text = _short_text(str(err).splitlines()[0] if str(err) else "", 200)
    return UserMessage(f"unexpected {type(err).__name__}{': ' + text if text else ''} — {DEBUG_HINT}",
                       EXIT_ENVIRONMENT, "unexpected")
