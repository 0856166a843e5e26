"""Output helpers shared by the sub-commands: JSON to a file or stdout, CSV, printable text."""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

from ..fileio import atomic_write_text, json_text  # noqa: F401
from ..safe_text import frame_csv_text, printable  # noqa: F401


def warning_line(label: str, text: str) -> str:
    """The one form of a command-line warning: ``<label>: warning: <text>`` on one line, with no
    terminal escapes from file contents (``label`` is ``sar-budget <command>``)."""
    return f"{label}: warning: {printable(' '.join(str(text).split()))}"


def warn(args, text: str) -> None:
    """Print ``text`` as a warning of the command ``args`` runs (:func:`warning_line`, stderr)."""
    print(warning_line(f"sar-budget {args.command}", text), file=sys.stderr)


def write_json(obj, dest: str) -> None:
    """Write ``obj`` as JSON to ``dest`` (a path, or ``-`` for stdout; files written atomically)."""
    text = json_text(obj)
    if dest == "-":
        sys.stdout.write(text)
    else:
        atomic_write_text(Path(dest), text)


def write_frame_csv(frame, dest: str) -> None:
    """Write a table as CSV, every text cell spreadsheet-safe (see ``budget.safe_text.safe_csv_text``)."""
    text = frame_csv_text(frame)
    if dest == "-":
        sys.stdout.write(text)
    else:
        atomic_write_text(Path(dest), text)


def add_json_option(parser) -> None:
    parser.add_argument("--json", metavar="FILE", default=None,
                        help="write JSON to FILE ('-' for stdout) instead of a table")


def make_output_folder(dest: str) -> None:
    """Create the missing folders of the output file ``dest`` and say so, as every output's writer
    does (:func:`budget.fileio.atomic_write_text`): the one rule of the command line's outputs
    (``--json``, ``--out``, ``--report``, ``--append`` …). ``-`` (stdout) and existing folders: nothing."""
    if str(dest) == "-":
        return
    folder = Path(os.path.realpath(dest)).parent
    if folder.is_dir():
        return
    created = [d for d in (folder, *folder.parents) if not d.exists()]
    folder.mkdir(parents=True, exist_ok=True)
    many = len(created) > 1
    warnings.warn(f"created folder{'s' if many else ''} {', '.join(str(d) for d in reversed(created))} "
                  f"({'they' if many else 'it'} did not exist) to write {dest}", UserWarning, stacklevel=2)
