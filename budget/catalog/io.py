"""Read, validate, merge and write the IMU catalog CSV files.

* The shipped catalog lives in ``catalog/`` at the repository root (installed as
  ``budget/_catalog``). A user catalog (``--catalog PATH`` or the environment variable
  ``SAR_BUDGET_CATALOG``) is merged over it: a user row with the same ``part_id`` replaces the
  shipped one, new ids are added.
* Validation is strict: unknown or duplicate columns, duplicate ids, non-numeric, negative,
  NaN/inf or out-of-range numbers, formula-looking text cells, wrong encoding and empty files
  each raise :class:`~budget.errors.InputError` naming file, row (1-based data row; the header
  is row 1, so the first part is row 2 as in a spreadsheet), column, value and what was expected.
* Other header units: a column may carry an alternative unit named in :data:`ALT_UNIT_COLUMNS`
  (e.g. ``accel_vrw_ug_rt_hz`` instead of ``accel_vrw_m_s_rt_h``); it is converted to the
  canonical unit on reading. Giving both the canonical and an alternative column is an error.
* Writes are atomic (temporary file + rename): a failed update never leaves a half-written file.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Mapping
from pathlib import Path

from pydantic import ValidationError

from .. import units as u
from ..errors import InputError
from ..fileio import atomic_write_text
from .schema import (GRADES, PART_COLUMNS, PART_NUMERIC_COLUMNS, PART_REQUIRED, GradeSpec,
                     PartSpec)

ENV_VAR = "SAR_BUDGET_CATALOG"
MAX_BYTES = 20_000_000

#: Alternative header → (canonical column, conversion to the canonical unit).
ALT_UNIT_COLUMNS: dict[str, tuple[str, callable]] = {
    "gyro_bias_instability_deg_s": ("gyro_bias_instability_deg_h", lambda v: v * 3600.0),
    "gyro_bias_repeatability_deg_s": ("gyro_bias_repeatability_deg_h", lambda v: v * 3600.0),
    "gyro_arw_deg_s_rt_hz": ("gyro_arw_deg_rt_h", lambda v: v * 60.0),
    "gyro_arw_rad_s_rt_hz": ("gyro_arw_deg_rt_h", u.rad_s_rt_hz_to_deg_rt_h),
    "gyro_scale_factor_pct": ("gyro_scale_factor_ppm", lambda v: v * 1e4),
    "gyro_misalignment_deg": ("gyro_misalignment_mrad", lambda v: u.rad_to_mrad(u.deg_to_rad(v))),
    "accel_bias_instability_mg": ("accel_bias_instability_ug", lambda v: v * 1e3),
    "accel_bias_repeatability_mg": ("accel_bias_repeatability_ug", lambda v: v * 1e3),
    "accel_vrw_ug_rt_hz": ("accel_vrw_m_s_rt_h", u.ug_rt_hz_to_m_s_rt_h),
    "accel_vrw_m_s2_rt_hz": ("accel_vrw_m_s_rt_h", u.m_s2_rt_hz_to_m_s_rt_h),
    "accel_scale_factor_pct": ("accel_scale_factor_ppm", lambda v: v * 1e4),
    "accel_misalignment_deg": ("accel_misalignment_mrad", lambda v: u.rad_to_mrad(u.deg_to_rad(v))),
}

GRADE_COLUMNS = tuple(GradeSpec.model_fields)


def shipped_catalog_dir() -> Path:
    """Directory of the shipped catalog (installed copy first, then the source tree)."""
    here = Path(__file__).resolve().parent.parent
    for cand in (here / "_catalog", here.parent / "catalog"):
        if (cand / "parts.csv").is_file():
            return cand
    raise InputError("shipped catalog not found", file=str(here.parent / "catalog" / "parts.csv"),
                     expected="catalog/parts.csv in the source tree or budget/_catalog when installed")


def _read_rows(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    if not path.is_file():
        raise InputError("file not found", file=path, expected="a catalog CSV file")
    size = path.stat().st_size
    if size == 0:
        raise InputError("file is empty", file=path, expected="a header row and at least one part")
    if size > MAX_BYTES:
        raise InputError(f"file is {size} bytes", file=path, expected=f"at most {MAX_BYTES} bytes")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(f"not UTF-8 text (byte {err.start})", file=path,
                         expected="a UTF-8 encoded CSV") from None
    if "\x00" in text:
        raise InputError("contains NUL bytes (binary file?)", file=path, expected="a UTF-8 CSV")
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        rows = [r for r in reader]
    except csv.Error as err:
        raise InputError(f"malformed CSV: {err}", file=path) from None
    rows = [r for r in rows if any(c.strip() for c in r)]
    if not rows:
        raise InputError("file has no header", file=path, expected="a header row")
    header = [h.strip() for h in rows[0]]
    out = []
    for i, r in enumerate(rows[1:], start=2):
        if len(r) != len(header):
            raise InputError(f"has {len(r)} cells but the header has {len(header)}", file=path, row=i,
                             expected="one cell per header column (quote cells that contain commas)")
        out.append(dict(zip(header, (c.strip() for c in r))))
    return header, out


def _parse_number(text: str, *, path, row, col, unit: str) -> float | None:
    if text == "":
        return None
    try:
        v = float(text)
    except ValueError:
        raise InputError("not a number", file=path, row=row, field=col, value=text,
                         expected=f"a number in {unit} (or an empty cell if unknown)") from None
    if not math.isfinite(v):
        raise InputError("not a finite number", file=path, row=row, field=col, value=text,
                         expected=f"a finite number in {unit}")
    return v


def _map_header(header: list[str], path: Path, allowed: tuple[str, ...], required: tuple[str, ...],
                alt: Mapping[str, tuple[str, callable]]) -> dict[str, str]:
    """Header column → canonical column; raises on unknown, duplicate or missing columns."""
    mapping: dict[str, str] = {}
    seen: dict[str, str] = {}
    for col in header:
        if col == "":
            raise InputError("empty column name in the header", file=path, row=1)
        if col in allowed:
            canon = col
        elif col in alt:
            canon = alt[col][0]
        else:
            raise InputError("unknown column", file=path, row=1, field=col,
                             expected=f"one of {', '.join(allowed)}"
                             + (f" or an alternative-unit column ({', '.join(alt)})" if alt else ""))
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


def read_parts(path: str | Path) -> dict[str, PartSpec]:
    """Validate a parts CSV; returns part_id → :class:`PartSpec` in file order."""
    path = Path(path)
    header, rows = _read_rows(path)
    mapping = _map_header(header, path, PART_COLUMNS, PART_REQUIRED, ALT_UNIT_COLUMNS)
    if not rows:
        raise InputError("has a header but no parts", file=path, expected="at least one data row")
    parts: dict[str, PartSpec] = {}
    for i, raw in enumerate(rows, start=2):
        rec: dict[str, object] = {}
        for col, text in raw.items():
            canon = mapping[col]
            if canon in PART_NUMERIC_COLUMNS:
                unit = PART_NUMERIC_COLUMNS[canon][0] if col == canon else col.rsplit("_", 1)[-1]
                v = _parse_number(text, path=path, row=i, col=col, unit=unit)
                if v is not None and col != canon:
                    v = ALT_UNIT_COLUMNS[col][1](v)
                rec[canon] = v
            elif text != "" or canon in PART_REQUIRED:
                rec[canon] = text
        try:
            part = PartSpec.model_validate(rec)
        except ValidationError as err:
            e = err.errors()[0]
            canon = str(e["loc"][0]) if e.get("loc") else None
            col = next((h for h, c in mapping.items() if c == canon), canon)
            unit = PART_NUMERIC_COLUMNS.get(canon, ("",))[0]
            expected = _expected_text(canon, e, unit)
            raise InputError(e["msg"], file=path, row=i, field=col, value=raw.get(col, None),
                             expected=expected) from None
        if part.part_id in parts:
            raise InputError("duplicate part_id", file=path, row=i, field="part_id",
                             value=part.part_id, expected="each part_id once per file")
        parts[part.part_id] = part
    return parts


def _expected_text(canon: str | None, err: dict, unit: str) -> str | None:
    if canon == "grade":
        return "one of " + ", ".join(GRADES)
    if canon == "part_id":
        return "letters, digits, '.', '_' or '-' (1-64 characters, starting with a letter or digit)"
    if canon in PART_NUMERIC_COLUMNS:
        lim = PART_NUMERIC_COLUMNS[canon][1]
        return f"a number in {unit}, 0 … {lim:g}" + (" (> 0)" if canon == "rate_hz" else "")
    if canon == "bias_instability_convention":
        return "adev_min or ieee_b"
    if canon == "source":
        return "the datasheet (with revision) the numbers come from"
    return None


def read_grades(path: str | Path) -> dict[str, GradeSpec]:
    """Validate a grades CSV; returns grade → :class:`GradeSpec`."""
    path = Path(path)
    header, rows = _read_rows(path)
    required = tuple(c for c in GRADE_COLUMNS if c != "notes")
    mapping = _map_header(header, path, GRADE_COLUMNS, required, {})
    out: dict[str, GradeSpec] = {}
    for i, raw in enumerate(rows, start=2):
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
    """The user catalog named by ``explicit`` or ``$SAR_BUDGET_CATALOG`` (None if neither)."""
    if explicit:
        return Path(explicit)
    env = os.environ.get(ENV_VAR, "").strip()
    return Path(env) if env else None


def load_catalog(user_csv: str | Path | None = None) -> dict[str, PartSpec]:
    """Shipped parts merged with the user's (user rows replace shipped rows with the same id)."""
    parts = dict(read_parts(shipped_catalog_dir() / "parts.csv"))
    user = user_catalog_path(user_csv)
    if user is not None:
        parts.update(read_parts(user))
    return parts


def load_grades() -> dict[str, GradeSpec]:
    return read_grades(shipped_catalog_dir() / "grades.csv")


def get_part(part_id: str, catalog: Mapping[str, PartSpec] | None = None,
             user_csv: str | Path | None = None) -> PartSpec:
    catalog = catalog if catalog is not None else load_catalog(user_csv)
    try:
        return catalog[part_id]
    except KeyError:
        close = [p for p in catalog if p.lower().startswith(part_id.lower()[:4])][:8]
        raise InputError(f"unknown part {part_id!r}", field="part_id",
                         expected="a part_id of the catalog" + (f", e.g. {', '.join(close)}" if close else
                                                                 " (see `sar-budget catalog list`)")) from None


def parts_to_csv_text(parts: Mapping[str, PartSpec] | list[PartSpec]) -> str:
    """Canonical CSV text (header + rows in canonical column order and units)."""
    items = list(parts.values()) if isinstance(parts, Mapping) else list(parts)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(PART_COLUMNS)
    for p in items:
        d = p.model_dump()
        w.writerow(["" if d[c] is None else (repr(d[c]) if isinstance(d[c], float) else d[c])
                    for c in PART_COLUMNS])
    return buf.getvalue()


def write_parts(path: str | Path, parts: Mapping[str, PartSpec] | list[PartSpec]) -> None:
    """Write a parts CSV atomically (validated models only, so the file is always valid)."""
    atomic_write_text(path, parts_to_csv_text(parts))


def append_part(path: str | Path, part: PartSpec, *, replace: bool = False) -> None:
    """Add ``part`` to the user catalog at ``path`` (created if absent), atomically.

    An existing file is validated first; a duplicate id is an error unless ``replace``.
    The shipped catalog cannot be the target.
    """
    path = Path(path)
    try:
        shipped = shipped_catalog_dir().resolve()
    except InputError:
        shipped = None
    if shipped is not None and path.resolve().parent == shipped:
        raise InputError("refusing to modify the shipped catalog", file=path,
                         expected="a user catalog path (e.g. my_catalog.csv)")
    parts = read_parts(path) if path.exists() and path.stat().st_size > 0 else {}
    if part.part_id in parts and not replace:
        raise InputError("part_id already in the catalog", file=path, field="part_id",
                         value=part.part_id, expected="a new id (or replace=True)")
    parts[part.part_id] = part
    write_parts(path, parts)
