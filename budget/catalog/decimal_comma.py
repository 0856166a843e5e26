"""An unquoted decimal comma in a catalog row (``…,0,42,…``: one cell too many): which adjacent
cells, joined as one decimal, make the row fit its header — named in the reader's error."""

from __future__ import annotations

import itertools
import re
from collections.abc import Callable

_INT_CELL = re.compile(r"[+-]?\d+")
_DIGITS_CELL = re.compile(r"\d+")


def decimal_comma_split(r: list[str], header: list[str], cell_fits: Callable[[str, str], bool]):
    """For a row with more cells than the header: the adjacent whole-number cells that, joined as
    one decimal (``0`` and ``42`` → 0.42: an unquoted decimal comma), make it fit — ``cell_fits(cell, column)`` true for
    every cell (the reader's own number and choice checks). Returns (reason,
    field, value, what to write) naming the two cells and the column, or None. Several fits are
    ranked (an integer part of 0 is a decimal comma rather than a thousands separator) and up to
    three of the best are named."""
    extra = len(r) - len(header)
    pairs = [j for j in range(len(r) - 1) if _INT_CELL.fullmatch(r[j]) and _DIGITS_CELL.fullmatch(r[j + 1])]
    if not 1 <= extra <= 3 or len(pairs) > 40:
        return None
    fits = []
    for combo in itertools.combinations(pairs, extra):
        if any(b - a < 2 for a, b in zip(combo, combo[1:])):
            continue  # overlapping pairs
        merged, k = [], 0
        while k < len(r):
            if k in combo:
                merged.append(f"{r[k]}.{r[k + 1]}")
                k += 2
            else:
                merged.append(r[k])
                k += 1
        if all(cell_fits(c, col) for c, col in zip(merged, header)):
            # where each joined cell lands in the merged row: its index minus the pairs before it
            at = [j - n for n, j in enumerate(combo)]
            rank = (sum(_INT_CELL.fullmatch(r[j]) and int(r[j]) == 0 for j in combo) * -1,
                    sum(len(r[j + 1]) == 3 for j in combo))
            fits.append((rank, combo, at))
    if not fits:
        return None
    fits.sort(key=lambda f: f[0])
    best = [f for f in fits if f[0] == fits[0][0]][:3]

    def said(combo, at) -> str:
        return " and ".join(f"cells {j + 1} and {j + 2} ('{r[j]}' and '{r[j + 1]}') as {r[j]}.{r[j + 1]} "
                            f"in {header[a]}" for j, a in zip(combo, at))

    what = "an unquoted decimal comma" if extra == 1 else "unquoted decimal commas"
    joined = "joining " + ", or ".join(said(c, a) for _, c, a in best) + f" makes it fit: {what}?"
    if len(best) > 1:
        return joined, None, None, "write a decimal"
    _, combo, at = best[0]
    return (joined, header[at[0]] if extra == 1 else None, ", ".join(f"{r[j]},{r[j + 1]}" for j in combo),
            "write " + " and ".join(f"{r[j]}.{r[j + 1]}" for j in combo))
