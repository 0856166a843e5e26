"""Output helpers shared by the sub-commands: JSON to a file or stdout, tables for humans."""

from __future__ import annotations

import sys
from pathlib import Path


from ..fileio import atomic_write_text, json_text


def write_json(obj, dest: str) -> None:
    """Write ``obj`` as JSON to ``dest`` (a path, or ``-`` for stdout; files written atomically)."""
    text = json_text(obj)
    if dest == "-":
        sys.stdout.write(text)
    else:
        atomic_write_text(Path(dest), text)


def add_json_option(parser) -> None:
    parser.add_argument("--json", metavar="FILE", default=None,
                        help="write JSON to FILE ('-' for stdout) instead of a table")
