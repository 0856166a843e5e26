"""Allan tables' headers and layouts: which file is an Allan table, which column is which, and the
units its header names.

A header line names a τ column (``tau_s``, ``tau``, ``tau_ms``, ``tau [ms]`` …) split by ``,``,
``;`` or a tab after ``#`` comment lines; the other columns are recognised by the names other tools
write (:data:`_ALIASES`), units in brackets after a name are read through :mod:`budget.units`, and
the wide layout (one ADEV column per channel) is turned into the long one (``channel, tau_s,
adev[, lci, uci]``). The values are read, checked and converted by
:func:`budget.noise.adev_table.read_adev_table`.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pandas as pd

from .. import units as u
from ..errors import CURVE_CHANNEL_WAY, InputError
from ..fileio import open_input, text_encoding

#: τ header names that carry their time unit in the name → factor to seconds (a unit written in
#: brackets, ``tau [ms]``, is read by :func:`budget.units.header_time_factor`)
_TAU_UNITS = {"tau_s": 1.0, "tau_ms": 1e-3, "tau_us": 1e-6}
#: Delimiters an Allan table may use; the one that splits the header into a τ column is taken.
_DELIMITERS = (",", ";", "\t")

#: Header names read as each column of a table (compared lower-case, without spaces): other
#: tools write ``Tau``, ``tau (s)``, ``ADEV``, ``sigma (deg/h)`` (datasheets), ``Allan deviation``,
#: or the Allan variance instead of the deviation (MATLAB's ``allanvar``: ``avar``,
#: ``allan_variance``, ``sigma^2`` — read as a variance, its square root taken, never as a
#: deviation). allantools' ``oadev`` written with pandas adds ``adev_err`` (its adev/√n) and ``n``
#: (the number of overlapping differences): read by :func:`_pairs_check` and :data:`ERR_NOTE`.
_ALIASES = {"tau_s": ("tau", "taus") + tuple(_TAU_UNITS), "channel": ("channel",),
            "adev": ("adev", "oadev", "sigma", "allandeviation", "allan_deviation", "allan_dev"),
            "avar": ("avar", "oavar", "allanvar", "allanvariance", "allan_variance", "allan_var",
                     "sigma2", "sigma^2", "sigma²"),
            "lci": ("lci",), "uci": ("uci",),
            "adev_err": ("adev_err", "adev_error", "ade"), "n": ("n", "ns", "n_pairs")}
_CANON = {a: c for c, names in _ALIASES.items() for a in names}


def _key(col) -> str:
    """A header cell as compared: lower case, without spaces or surrounding quotes."""
    return str(col).strip().strip("\"'").lower().replace(" ", "")


def _split(col) -> tuple[str, str | None]:
    """(name, unit written in brackets after it or None): ``'adev (deg/h)'`` → ``('adev', 'deg/h')``."""
    return u.split_header_unit(str(col).strip().strip("\"'"))


def canonical(col: str) -> str | None:
    """The column a header cell reads as (:data:`_ALIASES`), a unit in brackets after it
    left aside (``tau [s]``, ``adev (deg/h)``); None for any other cell."""
    return _CANON.get(_key(_split(col)[0]))


#: Lines read from the top of a file to find an Allan table's header (comment lines first).
_HEADER_LINES = 50


def table_header(path: str | Path) -> tuple[str, int] | None:
    """(delimiter, lines before the header) when ``path`` is an Allan table — a header line that
    names a τ column (``tau_s``, ``tau``, ``tau_ms`` …) split by ``,``, ``;`` or a tab, after
    blank and ``#`` comment lines — else None. The file's compression is found by content
    (gzip, bzip2, xz, zip, whatever its suffix)."""
    try:
        with open_input(path) as fh:
            raw = fh.read(1 << 16)
    except InputError:
        return None
    lines = raw.decode(text_encoding(raw[:4]), errors="replace").splitlines()
    for pre, line in enumerate(lines[:_HEADER_LINES]):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        for delim in _DELIMITERS:
            if any(canonical(c) == "tau_s" for c in line.split(delim)):
                return delim, pre
        return None
    return None


def looks_like_adev_table(path: str | Path) -> bool:
    """True when ``path``'s header names a τ column (``tau_s``, ``tau``, …) or has the
    ``channel, tau_s, adev`` columns (:func:`table_header`): an Allan table, in any of the
    layouts :func:`read_adev_table` reads (or refuses with a message about the layout); a log
    has no τ."""
    return table_header(path) is not None


def needs_channel_name(path: str | Path) -> bool:
    """True when ``path`` is an Allan table of one curve without a channel column (``tau_s, adev``,
    ``tau [s], adev (deg/h)``, with or without ``lci, uci``): :func:`read_adev_table` reads it only
    with the channel its curve belongs to (``channels=["gyro_z"]``). False for a table that names
    its channels (a channel column, or one ADEV column per channel) and for anything else; a
    header that cannot be read is left to :func:`read_adev_table` to refuse."""
    found = table_header(path)
    if found is None:
        return False
    delim, pre = found
    try:
        with open_input(path) as fh:
            raw = fh.read(1 << 16)
    except InputError:
        return False
    lines = [ln for ln in raw.decode(text_encoding(raw[:4]), errors="replace").splitlines()[pre:] if ln.strip()]
    if not lines:
        return False
    cells = [c for c in lines[0].split(delim) if c.strip().strip("\"'")]  # trailing delimiters: no column
    names = [canonical(c) for c in cells]
    return (None not in names and "tau_s" in names and "channel" not in names
            and ("adev" in names or "avar" in names))


def long_layout(df: pd.DataFrame, path: Path, header_row: int = 1,
                 channels: list[str] | None = None) -> tuple[pd.DataFrame, np.ndarray, bool]:
    """(table in the long layout ``channel, tau_s, adev[, lci, uci]``, the file's 0-based data row
    of each of its rows, whether it came from the wide layout). Accepted: the long layout with
    header names as in :data:`_ALIASES` (any case), ``avar`` instead of ``adev`` (its square
    root is taken, and of ``lci``/``uci`` with it), and the wide layout ``tau_s, <channel>, …``
    (one ADEV column per channel, named with its unit like a log column, e.g. ``gyro_x_dps``).
    A long table without a channel column (``tau_s, adev``: one curve) is read as the one
    channel ``channels`` names, and refused with how to name it when it names none."""
    expected = ("channel, tau_s, adev[, lci, uci] (one row per channel and τ; avar instead of adev "
                "is read too), or tau_s and one ADEV column per channel named with its unit (gyro_x_dps, …)")
    names = {c: canonical(c) for c in df.columns}
    dup = [c for c in set(n for n in names.values() if n) if list(names.values()).count(c) > 1]
    if dup:
        raise InputError(f"two header names read as {dup[0]}", file=path, row=header_row, expected=expected)
    known = {c: n for c, n in names.items() if n}
    rest = [c for c, n in names.items() if not n]
    if set(known.values()) == {"tau_s"} and rest:  # wide: tau_s + one column per channel
        for c in rest:
            try:
                u.split_channel_column(str(c).strip())
            except ValueError as err:
                raise InputError(f"wide Allan table: column {c!r} is not a channel with its unit ({err})",
                                 file=path, row=header_row, expected=expected) from None
        tau_col = next(iter(known))
        rows = np.tile(np.arange(len(df)), len(rest))
        long = pd.DataFrame({"channel": np.repeat([str(c).strip() for c in rest], len(df)),
                             "tau_s": np.tile(df[tau_col].to_numpy(), len(rest)),
                             "adev": np.concatenate([df[c].to_numpy() for c in rest])})
        return long, rows, True
    df = df.rename(columns=known)
    value = "avar" if "avar" in df.columns else "adev"
    if "channel" not in df.columns and "tau_s" in df.columns and value in df.columns and not rest:
        df = df.assign(channel=_only_channel(channels, path, header_row))
    missing = [c for c in ("channel", "tau_s") if c not in df.columns] + ([] if value in df.columns else ["adev"])
    if missing or rest or ("avar" in df.columns and "adev" in df.columns):
        what = "; ".join(t for t in (missing and f"missing {missing}", rest and f"unknown {rest}",
                                     "avar" in df.columns and "adev" in df.columns and "both adev and avar")
                         if t)
        raise InputError(f"not an Allan table layout this tool reads: columns {what}", file=path, row=header_row,
                         expected=expected)
    if value == "avar":
        for col in ("avar", "lci", "uci"):
            if col in df.columns:
                v = pd.to_numeric(df[col], errors="coerce")
                df[col] = np.sqrt(v.where(v >= 0))  # a negative variance stays NaN: refused below
        df = df.rename(columns={"avar": "adev"})
    return df, np.arange(len(df)), False


def is_row_index(df: pd.DataFrame, col: str) -> bool:
    """True for the column pandas' ``to_csv`` writes first by default: no header name
    (``Unnamed: 0``) and the row numbers 0, 1, 2 … (allantools' curves saved with pandas)."""
    if not (col == "" or col.startswith("Unnamed:")):
        return False
    v = pd.to_numeric(df[col], errors="coerce").to_numpy(float)
    return bool(v.size) and np.array_equal(v, np.arange(v.size))


def _only_channel(channels: list[str] | None, path: Path, header_row: int) -> str:
    """The channel of a table with one curve and no channel column: the one ``channels`` names."""
    how = (f"name its channel: {CURVE_CHANNEL_WAY.cli}; or "
           "add a channel column (channel, tau_s, adev), or name the ADEV column after its channel "
           "and unit (tau_s, gyro_z_dps)")
    if not channels:
        raise InputError("the table has no channel column: whose curve it is is not said", file=path,
                         row=header_row, field="channel", expected=how)
    if len(channels) > 1:
        raise InputError(f"the table has no channel column, so it holds one curve, but {len(channels)} "
                         f"channels are named ({', '.join(channels)})", file=path, field="channels",
                         expected="one channel, e.g. --channels gyro_z")
    if channels[0] not in u.CHANNELS:
        raise InputError(f"unknown channel {channels[0]!r}", file=path, field="channels",
                         expected=f"one of {', '.join(u.CHANNELS)} (the unit goes in the ADEV column's "
                                  "header: adev [deg/h])")
    return channels[0]


def tau_to_seconds(columns, path: Path, header_row: int) -> float:
    """Factor to seconds of the τ column: from its name (``tau_ms``) or the unit in brackets after
    it (``tau [ms]``, :func:`budget.units.header_time_factor`); both given must agree."""
    col = next((c for c in columns if canonical(c) == "tau_s"), None)
    if col is None:
        return 1.0
    base, written = _split(col)
    named = _TAU_UNITS.get(_key(base))
    if written is None:
        return named or 1.0
    try:
        factor = u.header_time_factor(written, col)
    except ValueError as err:
        raise InputError(str(err), file=path, row=header_row, field=col,
                         expected="τ in a time unit: tau [s], tau [ms], tau_s") from None
    if named is not None and not math.isclose(named, factor):
        raise InputError(f"column {col!r} names two time units, in its name and {written!r} in brackets",
                         file=path, row=header_row, field=col, expected="one unit: tau [s] or tau_s")
    return factor


#: An Allan variance's unit as written in a header: the square of a rate unit, ``(deg/h)^2``.
_SQUARED = re.compile(r"\(\s*(.*?)\s*\)\s*(?:\^\s*2|²)")


def value_unit(columns, path: Path, header_row: int) -> tuple[str | None, str | None]:
    """(the unit written in brackets after the ADEV, AVAR, LCI and UCI columns — one for all, an
    AVAR's as a square ``avar [(deg/h)^2]`` — and the column it was read from), or (None, None);
    columns that write different units are refused."""
    found: dict[str, str] = {}
    variance = any(canonical(c) == "avar" for c in columns)  # lci, uci are variances then too
    for col in columns:
        name = canonical(col)
        written = _split(col)[1] if name in ("adev", "avar", "lci", "uci") else None
        if written is None:
            continue
        if variance:
            m = _SQUARED.fullmatch(written)
            if m is None:
                raise InputError(f"column {col!r}: an Allan variance's unit is a square", file=path,
                                 row=header_row, field=col, expected="avar [(deg/h)^2], or adev [deg/h]")
            written = m.group(1)
        found[col] = written
    keys = {k.strip().lower().replace(" ", "") for k in found.values()}
    if len(keys) > 1:
        shown = ", ".join(f"{c!r}" for c in found)
        raise InputError(f"columns {shown} write different units", file=path, row=header_row,
                         field=next(iter(found)), expected="one unit for the ADEV and its bounds")
    return next(iter(found.values()), None), next(iter(found), None)


def value_column(columns) -> str | None:
    """The header name of a table's Allan-deviation or Allan-variance column (``avar``,
    ``sigma (deg/h)``, ``allanvar``), as the file writes it; None in the wide layout."""
    return next((c for c in columns if canonical(c) in ("adev", "avar")), None)


def channel_unit(name, written: str | None, column: str | None, path: Path, row: int,
                  header_row: int, named: bool = False, value_col: str | None = None) -> tuple[str, str]:
    """(channel, unit tag) of a table's channel ``name`` — a cell of the channel column (file row
    ``row``), or the channel the caller ``named`` for a table without one — its unit from the name
    (``gyro_x_dps``) or the one ``written`` in the ``column`` header (``adev [deg/h]``, row
    ``header_row``); two that disagree are refused. ``value_col``: the table's ADEV or AVAR column
    as the file names it (:func:`value_column`), named when no unit is written anywhere — an
    ``avar`` column is asked for its unit as a square, ``avar [(deg/h)^2]``."""
    text = str(name).strip()
    bare = u.CHANNEL_NAME_ALIASES.get(text.lower(), text.lower())
    value_col = column or value_col or "adev"
    variance = canonical(value_col) == "avar"
    at, field = (header_row, value_col) if named else (row, "channel")
    if written is None:
        if bare in u.CHANNELS:
            kind = "gyro" if bare.startswith("gyro") else "accel"
            tags = "|".join(u.CHANNEL_UNIT_TAGS[kind])
            what = "Allan variance" if variance else "ADEV"
            base = _split(value_col)[0].strip() or value_col
            form = f"{base} [(unit)^2] (the square of a rate unit)" if variance else f"{base} [unit]"
            raise InputError(f"no unit for {bare}: the table writes it neither in the channel name "
                             f"({bare}_{tags}) nor in brackets after the {what} column's name "
                             f"({value_col!r})", file=path,
                             row=at, field=field, value=None if named else name,
                             expected=f"{form} with unit one of " + ", ".join(u.HEADER_CHANNEL_UNITS[kind])
                                      + (f", e.g. {base} [(deg/h)^2]" if variance and kind == "gyro" else ""))
        try:
            return u.split_channel_column(text)
        except ValueError as err:
            raise InputError(str(err), file=path, row=row, field="channel") from None
    if bare in u.CHANNELS:
        try:
            return bare, _adev_unit(bare, written, column)
        except ValueError as err:
            raise InputError(str(err), file=path, row=header_row, field=column,
                             expected=f"a unit of {bare} in the ADEV column's header") from None
    try:
        ch, tag = u.split_channel_column(text)
    except ValueError as err:
        raise InputError(str(err), file=path, row=row, field="channel") from None
    try:
        said = _adev_unit(ch, written, column)
    except ValueError as err:
        raise InputError(str(err), file=path, row=header_row, field=column,
                         expected=f"a unit of {ch} in the ADEV column's header") from None
    if said != tag:
        raise InputError(f"channel {text!r} is in {tag} but the column {column!r} says {written!r}: "
                         "the two units disagree", file=path, row=row, field="channel", value=name,
                         expected="one unit: in the channel name or in the ADEV column's header")
    return ch, tag


def _adev_unit(channel: str, written: str, column: str | None) -> str:
    """:func:`budget.units.header_channel_unit` for an ADEV column: a noise density written there
    (``mrad/s/√Hz``, ``deg/√h``) is refused as such — an Allan deviation is in the rate unit."""
    try:
        return u.header_channel_unit(channel, written, column)
    except ValueError:
        if not u.is_density_unit(written):
            raise
        rate = re.split(r"/\s*(?:√|sqrt|rt)", written, maxsplit=1, flags=re.I)[0].strip()
        rate = rate if "/" in rate else ("deg/h" if channel.startswith("gyro") else "µg")  # deg/√h: an ARW
        raise ValueError(f"column {column!r}: {written!r} is a noise density (ARW/VRW), but an Allan "
                         f"deviation is in the channel's rate unit ({rate}, …); the density N is what the "
                         f"fit gives from the curve — write adev [{rate}]") from None
