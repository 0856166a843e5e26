"""Output helpers shared by the sub-commands: JSON to a file or stdout, tables for humans."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from ..fileio import atomic_write_text


def _clean(obj):
    """Make ``obj`` JSON-safe: numpy scalars/arrays to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def write_json(obj, dest: str) -> None:
    """Write ``obj`` as JSON to ``dest`` (a path, or ``-`` for stdout; files written atomically)."""
    text = json.dumps(_clean(obj), indent=2, ensure_ascii=False) + "\n"
    if dest == "-":
        sys.stdout.write(text)
    else:
        atomic_write_text(Path(dest), text)


def add_json_option(parser) -> None:
    parser.add_argument("--json", metavar="FILE", default=None,
                        help="write JSON to FILE ('-' for stdout) instead of a table")
