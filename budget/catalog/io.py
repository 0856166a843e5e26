"""Read, validate, merge and write the IMU catalog CSV files.

* The shipped catalog lives in ``catalog/`` at the repository root (installed as
  ``budget/_catalog``). A user catalog (``--catalog PATH`` or the environment variable
  ``SAR_BUDGET_CATALOG``) is merged over it: a user row with the same ``part_id`` replaces the
  shipped one, new ids are added. :func:`as_catalog` turns the ``catalog`` argument of the API
  (a mapping, a user CSV path or None) into the merged catalog, in one place.
* Validation is strict: unknown or duplicate columns, duplicate ids, non-numeric, negative,
  NaN/inf or out-of-range numbers, formula-looking text cells (OWASP: a text cell starting with
  ``= + - @``, tab or CR; plain numbers such as ``-2.5`` pass), control characters or escape
  sequences in text, cells over :data:`MAX_CELL_CHARS`, wrong encoding and empty files each
  raise :class:`~budget.errors.InputError` naming file, row (1-based data row; the header is
  row 1, so the first part is row 2 as in a spreadsheet), column, value and what was expected.
* Validation is vectorised per column (:func:`budget.catalog.validate.validate_parts_table`): a
  50 MB catalog checks in seconds; :func:`read_parts` then builds the :class:`PartSpec` models
  (pydantic re-checks each row, so the schema stays the single authority).
* Other header units: a column may carry an alternative unit named in :data:`ALT_UNIT_COLUMNS`
  (e.g. ``accel_vrw_ug_rt_hz`` instead of ``accel_vrw_m_s_rt_h``); it is converted to the
  canonical unit on reading. Giving both the canonical and an alternative column is an error.
* Writes are atomic (temporary file + rename): a failed update never leaves a half-written file.
  :func:`append_part` adds one row in the user's own column order and units, follows a
  symbolic link to its target and refuses a missing folder.
* What is written is what a later read accepts: the writers re-validate every part (a
  ``model_copy(update=…)`` skips pydantic's checks) and check the CSV text they produce with the
  reader's own validation before the file is touched; a bad part is an :class:`InputError`
  naming the part, the field and what was expected, and the file is left as it was.
* Part ids are compared case-insensitively where a mix-up is likely: :func:`append_part` refuses
  an id differing only in case from one already in the file (unless ``replace``) or from a
  shipped id, the reader refuses two ids of one file differing only in case (in the same words,
  naming both rows), and :func:`load_catalog` warns about user ids differing only in case from a
  shipped id.
"""

from __future__ import annotations

import csv
import io
import os
import warnings
from collections.abc import Mapping
from pathlib import Path

from pydantic import ValidationError

from ..errors import InputError, OutputError, from_validation_error
from ..fileio import atomic_write_text
from ..safe_text import csv_text
from .across_rows import case_twin_reason
from .schema import PART_COLUMNS, PART_NUMERIC_COLUMNS, PART_REQUIRED, GradeSpec, PartSpec, expected_text
from .validate import (ALT_UNIT_COLUMNS, MAX_BYTES, MAX_CELL_CHARS,  # noqa: F401
                       _map_header, _read_rows, _read_text, count_valid_parts, validate_parts_table)

ENV_VAR = "SAR_BUDGET_CATALOG"

GRADE_COLUMNS = tuple(GradeSpec.model_fields)


def shipped_catalog_dir() -> Path:
    """Directory of the shipped catalog (installed copy first, then the source tree)."""
    here = Path(__file__).resolve().parent.parent
    for cand in (here / "_catalog", here.parent / "catalog"):
        if (cand / "parts.csv").is_file():
            return cand
    raise InputError("shipped catalog not found", file=str(here.parent / "catalog" / "parts.csv"),
                     expected="catalog/parts.csv in the source tree or budget/_catalog when installed")


def read_parts(path: str | Path) -> dict[str, PartSpec]:
    """Validate a parts CSV; returns part_id → :class:`PartSpec` in file order."""
    return _parts_of(Path(path))


def _parts_of(path: Path, text: str | None = None) -> dict[str, PartSpec]:
    """:func:`read_parts` of the file, or of ``text`` (``path`` then only names it in messages)."""
    table, rows = validate_parts_table(path, text)
    names = list(table)
    cols = [table[c].tolist() if c in PART_NUMERIC_COLUMNS else table[c] for c in names]
    parts: dict[str, PartSpec] = {}
    for i, values in zip(rows, zip(*cols)):
        rec = {}
        for c, v in zip(names, values):
            if c in PART_NUMERIC_COLUMNS:
                rec[c] = None if v != v else v
            elif v != "" or c in PART_REQUIRED:
                rec[c] = v
        try:
            part = PartSpec.model_validate(rec)
        except ValidationError as err:  # a rule of the schema not mirrored above
            e = err.errors()[0]
            canon = str(e["loc"][0]) if e.get("loc") else None
            unit = PART_NUMERIC_COLUMNS.get(canon, ("",))[0]
            raise InputError(e["msg"].removeprefix("Value error, "), file=path, row=i, field=canon,
                             value=rec.get(canon), expected=expected_text(canon, unit)) from None
        parts[part.part_id] = part
    return parts


def read_grades(path: str | Path) -> dict[str, GradeSpec]:
    """Validate a grades CSV; returns grade → :class:`GradeSpec`."""
    path = Path(path)
    header, rows = _read_rows(path)
    required = tuple(c for c in GRADE_COLUMNS if c != "notes")
    mapping = _map_header(header, path, GRADE_COLUMNS, required, {})
    out: dict[str, GradeSpec] = {}
    for i, raw in rows:
        rec = {mapping[k]: v for k, v in raw.items()}
        try:
            g = GradeSpec.model_validate(rec)
        except ValidationError as err:
            e = err.errors()[0]
            col = str(e["loc"][0]) if e.get("loc") else None
            raise InputError(e["msg"], file=path, row=i, field=col, value=raw.get(col)) from None
        if g.grade in out:
            raise InputError("duplicate grade", file=path, row=i, field="grade", value=g.grade)
        out[g.grade] = g
    return out


def user_catalog_path(explicit: str | Path | None = None) -> Path | None:
    """The user catalog named by ``explicit`` or ``$SAR_BUDGET_CATALOG`` (None if neither);
    ``explicit`` that is not a path (``5``) is an :class:`InputError` naming ``user_csv``."""
    if explicit is not None and not isinstance(explicit, (str, os.PathLike)):
        raise InputError(f"the user catalog is not a path (type {type(explicit).__name__})", field="user_csv",
                         value=explicit, expected="a parts CSV path (str or pathlib.Path), or None")
    if explicit:
        return Path(explicit)
    env = os.environ.get(ENV_VAR, "").strip()
    return Path(env) if env else None


class Catalog(dict):
    """``part_id`` → :class:`PartSpec` as :func:`load_catalog` merged it, knowing the files it was
    read from (``files``: the shipped ``parts.csv``, then the user CSV if any), so that an unknown
    id can name the files searched. Otherwise a plain ``dict``."""

    def __init__(self, parts=(), files=()):
        super().__init__(parts)
        self.files: tuple[Path, ...] = tuple(Path(f) for f in files)

    @property
    def user_file(self) -> Path | None:
        """The user CSV merged over the shipped parts (None: the shipped catalog alone)."""
        return self.files[1] if len(self.files) > 1 else None


def load_catalog(user_csv: str | Path | None = None) -> Catalog:
    """Shipped parts merged with the user's (user rows replace shipped rows with the same id).

    A user id that differs from a shipped id only in letter case (``stim300`` vs ``STIM300``)
    stays a separate part (ids are case-sensitive, as in the CSV) but gives a ``UserWarning``
    naming the file and both ids: it is most likely meant to override the shipped row.
    """
    shipped_csv = shipped_catalog_dir() / "parts.csv"
    parts = Catalog(read_parts(shipped_csv), [shipped_csv])
    user = user_catalog_path(user_csv)
    if user is not None:
        mine = read_parts(user)
        for pid, shipped_id in _case_twins(mine, parts):
            warnings.warn(f"{user}: part_id {pid!r} differs only in case from the shipped part "
                          f"{shipped_id!r}; it is a separate part and does not replace the shipped "
                          f"row (name it {shipped_id!r} to do so)", UserWarning, stacklevel=2)
        parts.update(mine)
        parts.files = (shipped_csv, user)
    return parts


#: What a ``catalog`` argument of the API accepts (:func:`as_catalog`).
CATALOG_ARGUMENT = ("a mapping part_id → PartSpec (budget.load_catalog(...)), a path to a user parts CSV "
                    "(merged over the shipped parts) or None (the shipped catalog)")


def as_catalog(catalog: Mapping[str, PartSpec] | str | os.PathLike | None = None,
               field: str = "catalog") -> Mapping[str, PartSpec]:
    """The catalog a ``catalog`` argument names — the one conversion for the API, the CLI and the
    part resolution: a mapping (e.g. from :func:`load_catalog`) as is, a path to a user CSV merged
    over the shipped parts (as ``--catalog``), ``None`` the shipped catalog (and
    ``$SAR_BUDGET_CATALOG``). Anything else, or a mapping holding something other than parts,
    is an :class:`InputError` naming ``field``; a missing or bad CSV is the reader's
    :class:`InputError` naming the file, row and column."""
    if isinstance(catalog, Catalog):  # read and checked by load_catalog
        return catalog
    if isinstance(catalog, Mapping):
        for pid, part in catalog.items():
            if not isinstance(part, PartSpec):
                raise InputError(f"the catalog entry {pid!r} is not a part (a {type(part).__name__})",
                                 field=field, expected=CATALOG_ARGUMENT)
        return catalog
    if catalog is not None and (isinstance(catalog, bool) or not isinstance(catalog, (str, os.PathLike))):
        raise InputError(f"cannot use a {type(catalog).__name__} as a catalog", field=field, value=catalog,
                         expected=CATALOG_ARGUMENT)
    if isinstance(catalog, str) and not catalog.strip():
        raise InputError("empty catalog path", field=field, value=catalog, expected=CATALOG_ARGUMENT)
    return load_catalog(catalog)


#: Where a merged catalog row comes from (:func:`part_origins`).
ORIGIN_SHIPPED, ORIGIN_USER, ORIGIN_REPLACED = "shipped", "user", "user, replaces shipped"


def part_origins(user_csv: str | Path | None = None) -> dict[str, str]:
    """For every part of :func:`load_catalog` (same order), where its row comes from: "shipped",
    "user" (a part only the user catalog has) or "user, replaces shipped" (a user row that
    overrides the shipped row with the same id: its numbers are not the shipped datasheet's)."""
    shipped = read_parts(shipped_catalog_dir() / "parts.csv")
    user = user_catalog_path(user_csv)
    mine = read_parts(user) if user is not None else {}
    origins = {pid: ORIGIN_SHIPPED for pid in shipped}
    for pid in mine:
        origins[pid] = ORIGIN_REPLACED if pid in shipped else ORIGIN_USER
    return origins


def catalog_note(part_ids, user_csv: str | Path | None = None) -> str:
    """One line naming the user catalog in use (``user_csv`` or ``$SAR_BUDGET_CATALOG``) and which
    of ``part_ids`` come from it — those replacing a shipped row first, since their numbers are not
    the shipped datasheet's though their id is; '' when no user catalog is in use."""
    user = user_catalog_path(user_csv)
    if user is None:
        return ""
    origins = part_origins(user)
    replaced = [p for p in part_ids if origins.get(p) == ORIGIN_REPLACED]
    own = [p for p in part_ids if origins.get(p) == ORIGIN_USER]
    via = "" if user_csv else f" (from ${ENV_VAR})"
    text = f"catalog: the shipped parts with the user catalog {user}{via} merged over them"
    if replaced:
        text += f"; the user's row replaces the shipped one of: {', '.join(replaced)}"
    if own:
        text += f"; from the user catalog only: {', '.join(own)}"
    return text


def _case_twins(ids, others) -> list[tuple[str, str]]:
    """(id, other id) for each id of ``ids`` equal to an id of ``others`` up to letter case only."""
    lower = {o.lower(): o for o in others}
    return [(i, lower[i.lower()]) for i in ids if i.lower() in lower and lower[i.lower()] != i
            and i not in others]


def load_grades() -> dict[str, GradeSpec]:
    return read_grades(shipped_catalog_dir() / "grades.csv")


def close_part_ids(part_id: str, catalog: Mapping[str, PartSpec], most: int = 8) -> list[str]:
    """Catalog ids closest to a mistyped ``part_id`` (case-insensitive similarity, then a
    shared 4-character prefix), best first, at most ``most``."""
    import difflib

    by_lower = {p.lower(): p for p in catalog}
    key = str(part_id).lower()
    close = [by_lower[p] for p in difflib.get_close_matches(key, list(by_lower), n=most, cutoff=0.6)]
    close += [p for p in catalog if p.lower().startswith(key[:4]) and p not in close]
    return close[:most]


def get_part(part_id: str, catalog: Mapping[str, PartSpec] | None = None,
             user_csv: str | Path | None = None) -> PartSpec:
    """The catalog row ``part_id`` (of ``catalog``, else of the shipped catalog merged with
    ``user_csv``); an unknown id is an :class:`InputError` listing the closest ids."""
    catalog = catalog if catalog is not None else load_catalog(user_csv)
    try:
        return catalog[part_id]
    except KeyError:
        close = close_part_ids(part_id, catalog)
        files = getattr(catalog, "files", ())  # a Catalog names the files searched
        user = catalog.user_file if isinstance(catalog, Catalog) else None
        raise InputError(f"unknown part {part_id!r}" + (" (neither in this user catalog nor in the shipped "
                                                         f"one, {files[0]})" if user else ""),
                         file=user or (files[0] if files else None), field="part_id",
                         expected="a part_id of the catalog" + (f"; closest: {', '.join(close)}" if close else
                                                                 " (see `sar-budget catalog list`)")) from None


# --- writing -----------------------------------------------------------------------------------

def _cell(part: PartSpec, column: str):
    """The value of ``part`` for a header ``column`` (canonical or alternative unit). A converted
    value is written with the fewest digits (15 to 17) that the reader converts back to exactly
    the canonical value: 50 µg/√Hz held as 0.02942 m/s/√h is written as 50, not 50.00000000000001."""
    d = part.model_dump()
    if column in ALT_UNIT_COLUMNS:
        canon, conv = ALT_UNIT_COLUMNS[column]
        v = d[canon]
        if v is None:
            return None
        x = float(v) / float(conv(1.0))  # conversions are linear
        return next((w for w in (float(f"{x:.{n}g}") for n in (15, 16, 17)) if float(conv(w)) == float(v)), x)
    return d[column]


def _as_part(part: PartSpec | Mapping[str, object], file: str | Path | None = None) -> PartSpec:
    """``part`` (a :class:`PartSpec` or a mapping of its fields) validated again by the schema:
    ``model_copy(update=…)`` and ``model_construct`` skip pydantic's checks, so a model is not
    trusted as it stands. A bad value is an :class:`InputError` naming the part and the field."""
    if isinstance(part, PartSpec):
        data = dict(vars(part))  # what the model holds, unknown keys set by model_copy included
    elif isinstance(part, Mapping):
        data = dict(part)
    else:
        raise InputError(f"not a catalog part: a {type(part).__name__}", file=file,
                         expected="a PartSpec or a mapping of its fields")
    try:
        return PartSpec.model_validate(data)
    except ValidationError as err:
        e = from_validation_error(err)
        pid = data.get("part_id")
        canon = e.field if e.field in PartSpec.model_fields else None
        unit = PART_NUMERIC_COLUMNS.get(canon, ("",))[0]
        raise InputError((f"part {pid!r}: " if isinstance(pid, str) else "") + e.reason, file=file,
                         field=e.field, value=e.value, expected=expected_text(canon, unit)) from None


def _checked(path: str | Path, text: str, part_id: str | None = None) -> str:
    """``text`` (a whole parts CSV, or a header and the rows to be added) if the reader accepts
    it (:func:`read_parts`'s checks, models included); otherwise the reader's
    :class:`InputError`, saying nothing was written (and naming ``part_id`` if given)."""
    try:
        _parts_of(Path(path), text)
    except InputError as err:
        what = f"part {part_id!r} not written" if part_id else "not written"
        raise InputError(f"{what}: {err.reason}", file=path, row=None if part_id else err.row,
                         field=err.field, value=err.value, expected=err.expected) from None
    return text


def parts_to_csv_text(parts: Mapping[str, PartSpec] | list[PartSpec]) -> str:
    """Canonical CSV text (header + rows in canonical column order and units); text cells
    spreadsheet-safe (:func:`budget.safe_text.safe_csv_text`). A part may be a mapping of its
    fields (validated; a bad one is an :class:`InputError`); a :class:`PartSpec` is written as
    it stands (the text only: :func:`write_parts` and :func:`append_part` validate again)."""
    items = list(parts.values()) if isinstance(parts, Mapping) else list(parts)
    items = [p if isinstance(p, PartSpec) else _as_part(p) for p in items]
    return csv_text(([p.model_dump()[c] for c in PART_COLUMNS] for p in items), PART_COLUMNS)


def write_parts(path: str | Path, parts: Mapping[str, PartSpec] | list[PartSpec]) -> None:
    """Write a parts CSV atomically. Every part is validated again and the text is checked by
    the reader before writing (duplicate ids included), so the file is always one
    :func:`read_parts` accepts; otherwise :class:`InputError` and the file is left as it was."""
    items = list(parts.values()) if isinstance(parts, Mapping) else list(parts)
    items = [_as_part(p, file=path) for p in items]
    pid = items[0].part_id if len(items) == 1 else None
    atomic_write_text(path, _checked(path, parts_to_csv_text(items), pid))


def append_part(path: str | Path, part: PartSpec | Mapping[str, object], *,
                replace: bool = False) -> None:
    """Add ``part`` to the user catalog at ``path`` (created if absent), atomically.

    ``part`` is a :class:`PartSpec` or a mapping of its fields; it is validated again (a
    ``model_copy(update=…)`` skips validation) and its row, as it will be written, is checked by
    the reader's own validation, before anything is written: a bad value is an
    :class:`InputError` naming the file, the part id, the field and what was expected, and the
    file stays byte-identical. The existing file is validated first; a duplicate id is an error
    unless ``replace`` (the row is then replaced where it stands). The user's columns, their
    order, units and other rows are kept as they are: the new row is written in the file's own
    header (columns the header lacks but the part fills are added at the end). A symbolic link
    is followed (the target is updated); the folder must exist. The shipped catalog cannot be
    the target.

    Letter case: an id differing only in case from one in the file (``stim300`` vs ``STIM300``)
    is handled like the same id — refused unless ``replace``, which replaces that row. An id new
    to the file that differs only in case from a *shipped* id is refused (``replace`` does not
    help): it would be a separate part that does not override the shipped row, which is never
    what a user typing ``stim300`` means; the message names the shipped id to use instead.
    """
    given = Path(path)
    part = _as_part(part, file=given)
    target = Path(os.path.realpath(given))
    try:
        shipped = shipped_catalog_dir().resolve()
    except InputError:
        shipped = None
    if shipped is not None and target.parent == shipped:
        raise InputError("refusing to modify the shipped catalog", file=given,
                         expected="a user catalog path (e.g. my_catalog.csv)")
    if not target.parent.is_dir():
        raise OutputError(f"folder {target.parent} does not exist", file=given, option="--append")
    if target.exists() and not target.is_file():
        raise OutputError("is not a regular file", file=given, option="--append")
    fresh = not target.exists() or target.stat().st_size == 0
    parts = {} if fresh else read_parts(target)
    twin = next((other for _, other in _case_twins([part.part_id], parts)), None)
    if part.part_id in parts or twin is not None:
        if not replace:
            same = "part_id already in the catalog" if twin is None else case_twin_reason(twin)
            raise InputError(same, file=given, field="part_id", value=part.part_id,
                             expected="a new id (or replace=True, --replace, to replace that row)")
    elif shipped is not None:
        twin_shipped = next((o for _, o in _case_twins([part.part_id],
                                                       read_parts(shipped / "parts.csv"))), None)
        if twin_shipped is not None:
            raise InputError(f"part_id differs only in case from the shipped part {twin_shipped!r}: "
                             "it would be a separate part, not an override", file=given,
                             field="part_id", value=part.part_id,
                             expected=f"{twin_shipped!r} exactly (to override the shipped row) "
                                      "or an id that differs by more than letter case")
    if fresh:
        atomic_write_text(target, _checked(given, parts_to_csv_text([part]), part.part_id),
                          create_dirs=False)
        return
    old_id = part.part_id if part.part_id in parts else twin
    text = _read_text(target)
    with open(target, "rb") as fh:  # a byte-order mark (Excel's UTF-8 CSV) is kept: the reader
        bom = "\ufeff" if fh.read(3) == b"\xef\xbb\xbf" else ""  # drops it from ``text``
    newline = "\r\n" if "\r\n" in text[:65536] else "\n"
    records = list(csv.reader(io.StringIO(text, newline="")))
    header = [h.strip() for h in records[0]]
    canon_in_header = {ALT_UNIT_COLUMNS[h][0] if h in ALT_UNIT_COLUMNS else h for h in header}
    extra = [c for c in PART_COLUMNS if c not in canon_in_header     # a default needs no column
             and _cell(part, c) not in (None, "", PartSpec.model_fields[c].default)]
    new_row = [_cell(part, c) for c in header + extra]
    # the row exactly as it will be written, read back as a one-row file of the same header
    _checked(given, csv_text([new_row], header + extra, lineterminator=newline), part.part_id)
    if old_id is None and not extra:
        # plain append: the user's bytes stay as they are, one line is added
        sep = "" if text.endswith(("\n", "\r")) else newline
        atomic_write_text(target, bom + text + sep + csv_text([new_row], lineterminator=newline),
                          create_dirs=False)
        return
    body = []
    replaced = False
    pid = header.index("part_id")
    for r in records[1:]:
        if not any(c.strip() for c in r):
            continue  # blank lines are not rows (read_parts skips them too)
        if r[pid].strip() == old_id:
            body.append(new_row)
            replaced = True
        else:
            body.append(r + [""] * len(extra))
    if not replaced:
        body.append(new_row)
    out = csv_text(body, header + extra, lineterminator=newline)
    atomic_write_text(target, bom + out, create_dirs=False)
