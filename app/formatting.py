"""How numbers look in the dashboard's tables: 4 significant figures, "–" for an empty cell.

One rule for every page, so a fitted Allan term is not shown with 1 significant figure next to a
catalog value with 16, and an empty cell never reads "None" or "nan". No Streamlit here.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

SIG_FIGS = 4
EMPTY = "–"


def fmt_value(v, sig: int = SIG_FIGS) -> str:
    """A cell as text: floats to ``sig`` significant figures, None/NaN as "–", others as str."""
    if v is None or (isinstance(v, (float, np.floating)) and math.isnan(v)):
        return EMPTY
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return f"{float(v):.{sig}g}"
    if isinstance(v, (tuple, list)):
        return ", ".join(fmt_value(x, sig) for x in v)
    return str(v)


def tidy(frame: pd.DataFrame, sig: int = SIG_FIGS):
    """A Styler showing ``frame`` with :func:`fmt_value` in every cell (numbers stay numbers, so
    sorting keeps working; empty cells become "–"). Downloads use the frame itself.

    A column with an empty cell is shown as text throughout: Streamlit draws a null cell as
    "None" whatever the Styler says, and a column mixing numbers with "–" cannot be sent as an
    Arrow table (Streamlit would convert it to text itself, after logging a traceback)."""
    shown = frame.copy()
    for col in shown.columns:
        if shown[col].isna().any():
            shown[col] = shown[col].map(lambda v: fmt_value(v, sig)).astype(object)
    return shown.style.format(lambda v: fmt_value(v, sig))


def value_table(row: dict, sig: int = SIG_FIGS) -> pd.DataFrame:
    """``{column: value}`` → a two-column table of the set values, formatted as text."""
    items = [(k, v) for k, v in row.items() if v not in (None, "") and not
             (isinstance(v, float) and math.isnan(v))]
    return pd.DataFrame({"column": [k for k, _ in items], "value": [fmt_value(v, sig) for _, v in items]})


def grade_text(grades: dict, key: str) -> str:
    """A lowest sufficient grade as a page shows it: the grade; "none" where the library found no
    grade sufficient (a verdict); "–" where nothing was computed (``key`` absent: the bounds were
    refused — the page says why beside it)."""
    if key not in grades:
        return EMPTY
    return grades[key] or "none"
