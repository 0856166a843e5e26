"""Argument helpers shared by the sub-commands: scenario and catalog selection, and the check of
output paths that runs *before* any computation."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from ..errors import InputError, OutputError
from ..fileio import read_only_reason
from ..presets import PRESETS, get_preset
from ..scenario import Scenario

#: Argument names (argparse ``dest``) that name an output file; ``-`` means stdout.
OUTPUT_FILE_OPTIONS = ("json", "out", "report", "out_model", "image", "csv_out", "html")
#: Argument names that name a file a row is appended to. One rule for every output file, these
#: included: its missing folders are created when it is written, and the command says so
#: (``created folder …``); the nearest existing folder must be writable, checked before the work.
APPEND_OPTIONS = ("append",)
#: Argument names that name an output folder (created if missing).
OUTPUT_DIR_OPTIONS = ("plots", "out_dir", "figures")


def add_scenario_options(parser, required: bool = False) -> None:
    g = parser.add_mutually_exclusive_group(required=required)
    g.add_argument("--scenario", metavar="S.json", help="scenario JSON/YAML file")
    g.add_argument("--preset", choices=sorted(PRESETS), help="a preset scenario")


def scenario_from_args(args, default_preset: str | None = None) -> Scenario:
    if getattr(args, "scenario", None):
        if args.scenario in PRESETS and not Path(args.scenario).exists():  # a preset's name, not a file
            raise InputError("file not found (this is the name of a preset)", file=args.scenario,
                             field="--scenario", expected=f"--preset {args.scenario}, or a scenario JSON/YAML file")
        return Scenario.load(args.scenario)
    if getattr(args, "preset", None):
        return get_preset(args.preset)
    if default_preset:
        return get_preset(default_preset)
    raise InputError("no scenario given", field="--scenario", expected="--scenario FILE or --preset NAME")


def add_catalog_option(parser) -> None:
    parser.add_argument("--catalog", metavar="CSV",
                        help="user catalog merged over the shipped one (default: $SAR_BUDGET_CATALOG)")


def add_part_or_model_options(parser, part_help: str = "catalog part id",
                               model_help: str = "noise-model JSON/YAML (catalog fields + effects)") -> None:
    """``--part ID`` | ``--model M.json`` (one of them required) and ``--catalog``."""
    src = parser.add_mutually_exclusive_group(required=True)
    src.add_argument("--part", metavar="ID", help=part_help)
    src.add_argument("--model", metavar="M.json", help=model_help)
    add_catalog_option(parser)


def part_or_model_from_args(args):
    """The IMU named by ``--part`` (in the catalog merged with ``--catalog``) or ``--model``
    (a noise-model file): :func:`budget.api.load_part`, whose errors name the part or the file."""
    from ..api import load_part

    model = getattr(args, "model", None)
    return load_part(Path(model) if model else args.part, getattr(args, "catalog", None))


def _probe_dir(folder: Path, option: str, target: Path) -> None:
    """Create and delete a temporary file in ``folder``: the only reliable writability test
    (``os.access`` says yes for root on /proc, read-only mounts, …)."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=".sar-budget-probe-", suffix=".tmp", dir=folder)
    except OSError as err:
        raise OutputError(f"cannot write in {folder} ({err.strerror or type(err).__name__})",
                          file=target, option=option) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def check_output_path(path: str | os.PathLike, option: str, *, must_exist_dir: bool = False,
                      directory: bool = False) -> Path | None:
    """Check that ``path`` can be written (``-`` = stdout passes); raise :class:`OutputError`.

    A symbolic link is judged by its target. ``must_exist_dir``: the folder must already exist
    (appends); otherwise the nearest existing parent must be writable (folders are created
    when the output is written). ``directory``: ``path`` is a folder to write files into.
    """
    if path is None or str(path) == "-":
        return None
    text = str(path)
    if text.strip() == "" or "\x00" in text:
        raise OutputError("empty or invalid path", file=repr(text), option=option)
    target = Path(os.path.realpath(text))
    if directory:
        if target.exists() and not target.is_dir():
            raise OutputError("exists and is not a folder", file=text, option=option)
    else:
        if target.is_dir():  # refused now, not after the computation
            raise OutputError("is a folder; give a file name", file=text, option=option)
        if target.exists() and not target.is_file():
            raise OutputError("is not a regular file", file=text, option=option)
    folder = target if directory else target.parent
    if not folder.is_dir():
        if must_exist_dir:
            raise OutputError(f"folder {folder} does not exist", file=text, option=option)
        while not folder.exists():
            folder = folder.parent
        if not folder.is_dir():
            raise OutputError(f"{folder} is not a folder", file=text, option=option)
    _probe_dir(folder, option, Path(text))
    locked = read_only_reason(target) if target.is_file() else None
    if locked:
        raise OutputError(locked, file=text, option=option)
    return target


def _input_files(args) -> dict[Path, str]:
    """Real path → option of every existing file among ``args`` that is not an output (the
    scenario, catalog, model, log, phase histories, …), and the user catalog of
    ``$SAR_BUDGET_CATALOG``."""
    outputs = set(OUTPUT_FILE_OPTIONS) | set(APPEND_OPTIONS) | set(OUTPUT_DIR_OPTIONS)
    found: dict[Path, str] = {}
    for name, value in vars(args).items():
        if name in outputs or name == "func":
            continue
        for v in value if isinstance(value, (list, tuple)) else (value,):
            if isinstance(v, (str, os.PathLike)) and str(v).strip() and "\x00" not in str(v):
                with contextlib.suppress(OSError, ValueError):
                    if Path(v).is_file():
                        found.setdefault(Path(os.path.realpath(v)), "--" + name.replace("_", "-"))
    env = os.environ.get("SAR_BUDGET_CATALOG", "").strip()
    if env and Path(env).is_file():
        found.setdefault(Path(os.path.realpath(env)), "$SAR_BUDGET_CATALOG")
    return found


def _shipped_catalog() -> Path | None:
    from ..catalog.io import shipped_catalog_dir

    try:
        return Path(os.path.realpath(shipped_catalog_dir()))
    except InputError:
        return None


def check_output_args(args) -> None:
    """Check every output path among ``args`` (see :data:`OUTPUT_FILE_OPTIONS` …) before the
    command runs; the CLI entry point calls this for every command. An output that is one of
    the command's input files, another output of it, or a file of the shipped catalog is refused
    (``check --catalog mine.csv --json mine.csv`` overwrote the user catalog with the JSON)."""
    inputs = _input_files(args)
    shipped = _shipped_catalog()
    written: dict[Path, str] = {}

    def guard(target: Path | None, option: str, *, append: bool = False) -> None:
        if target is None:
            return
        if shipped is not None and shipped in target.parents:
            raise OutputError(f"is in the shipped catalog ({shipped}), which is never written; a user "
                              "catalog is a file of its own (--catalog, $SAR_BUDGET_CATALOG)",
                              file=str(target), option=option)
        if target in inputs and not append:  # appending a row to the catalog read is the intent
            raise OutputError(f"is also the input {inputs[target]}: writing it would destroy the input",
                              file=str(target), option=option)
        if target in written:
            raise OutputError(f"is also the output {written[target]}: one would overwrite the other",
                              file=str(target), option=option)
        written[target] = option

    for name in OUTPUT_FILE_OPTIONS:
        value = getattr(args, name, None)
        if isinstance(value, (str, os.PathLike)):
            option = "--" + name.replace("_", "-")
            guard(check_output_path(value, option), option)
    for name in APPEND_OPTIONS:
        value = getattr(args, name, None)
        if isinstance(value, (str, os.PathLike)):
            guard(check_output_path(value, "--" + name), "--" + name, append=True)
    for name in OUTPUT_DIR_OPTIONS:
        value = getattr(args, name, None)
        if isinstance(value, (str, os.PathLike)):
            check_output_path(value, "--" + name.replace("_", "-"), directory=True)
