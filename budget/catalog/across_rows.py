"""Catalog checks across rows and columns of a parts table: repeated and case-twin part ids,
and a repeatability column given with a constant-bias convention (:func:`row_problems`), in the
words :func:`budget.catalog.io.append_part` uses too (:func:`case_twin_reason`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from .schema import CONSTANT_BIAS_CONVENTIONS, expected_text

#: The columns :func:`row_problems` looks at.
ACROSS_ROWS = ("part_id", "bias_instability_convention", "gyro_bias_repeatability_deg_h",
               "accel_bias_repeatability_ug")


def check_rows(table: dict, rows: list[int], path: Path, header_of: dict[str, str]) -> None:
    """Checks across columns and rows (:func:`row_problems`): the first problem raises."""
    problems = row_problems(table, rows, path, header_of, first_only=True)
    if problems:
        raise problems[0]


def case_twin_reason(other: str, row: int | None = None) -> str:
    """Why a part_id differing only in letter case from ``other`` (at ``row`` of the same file,
    if given) is refused — the words of :func:`budget.catalog.io.append_part` and of the reader."""
    return f"part_id differs only in case from {other!r}" + (f" (row {row})" if row is not None else "") \
        + ", already in the catalog"


def row_problems(table: dict, rows: list[int], path: Path, header_of: dict[str, str],
                 first_only: bool = False) -> list[InputError]:
    """Problems across columns and rows, in row order: a repeated part_id (naming the row that
    has it first), a part_id differing only in letter case from an earlier one (refused as
    :func:`~budget.catalog.io.append_part` refuses it: ids are case-sensitive, so it would be a
    separate part, which is never what two spellings of one id mean), a repeatability column
    given with a constant-bias convention. An empty part_id is skipped (a cell error of its own).
    ``first_only``: stop at the first row with a problem."""
    import pandas as pd

    found: list[tuple[int, InputError]] = []
    ids = pd.Series(table["part_id"], dtype=object)
    given = (ids != "").to_numpy()
    lower = ids.str.lower()
    dup = ids.duplicated().to_numpy() & given
    twin = lower.duplicated().to_numpy() & given & ~dup
    bad = np.flatnonzero(dup | twin)
    # the row where each id comes first, as written and in any case
    first_exact = {v: j for j, v in reversed(list(enumerate(ids))) if given[j]} if bad.size else {}
    first_any = {v: j for j, v in reversed(list(enumerate(lower))) if given[j]} if bad.size else {}
    for k in bad[:1] if first_only else bad:
        j = first_exact[ids.iat[k]] if dup[k] else first_any[lower.iat[k]]
        if dup[k]:
            err = InputError(f"duplicate part_id (also at row {rows[j]})", file=path, row=rows[k],
                             field=header_of.get("part_id", "part_id"), value=ids.iat[k],
                             expected="each part_id once per file")
        else:
            err = InputError(case_twin_reason(ids.iat[j], rows[j]), file=path, row=rows[k],
                             field=header_of.get("part_id", "part_id"), value=ids.iat[k],
                             expected=f"each part_id once per file, letter case ignored (rename or "
                                      f"delete one of rows {rows[j]} and {rows[k]})")
        found.append((k, err))
    conv = table.get("bias_instability_convention")
    if conv is not None:
        const = pd.Series(conv, dtype=object).isin(CONSTANT_BIAS_CONVENTIONS).to_numpy()
        for rep in ("gyro_bias_repeatability_deg_h", "accel_bias_repeatability_ug"):
            if rep not in table:
                continue
            for k in np.flatnonzero(const & np.isfinite(table[rep])):
                found.append((k, InputError(
                    f"{conv[k]} says the bias columns already hold the turn-on bias, but {rep} is "
                    "also given; leave it empty or use adev_min / ieee_b for an in-run figure",
                    file=path, row=rows[k], field=header_of.get("bias_instability_convention"),
                    value=conv[k], expected=expected_text("bias_instability_convention", ""))))
                if first_only:
                    break
    found.sort(key=lambda ke: ke[0])
    return [e for _, e in (found[:1] if first_only else found)]
