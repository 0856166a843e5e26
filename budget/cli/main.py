"""``sar-budget`` entry point and the CLI's error boundary.

Each sub-command lives in its own module of this package with two functions:
``add_parser(subparsers)`` (registers arguments and sets ``func=run``) and ``run(args) -> int``.

Before a command runs, every output path it was given (``--json``, ``--out``, ``--report``,
``--append``, ``--image`` …, see :func:`.common.check_output_args`) is checked, so an
unwritable output fails in a second, not after the computation. Every failure ends as one line
on stderr (:func:`budget.errors.describe_error`): exit status 2 for bad input, 1 for an
environment problem (unwritable output, out of memory) or an unexpected error, 130 when
cancelled. ``--debug`` (or ``SAR_BUDGET_DEBUG=1``) prints the traceback of unexpected errors.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import traceback
import warnings

from ..errors import describe_error

#: Modules of this package that provide sub-commands, in help order.
COMMAND_MODULES = (
    "dashboard_cmd",
    "demo_cmd",
    "bounds_cmd",
    "check_cmd",
    "catalog_cmd",
    "motion_cmd",
    "sar_cmd",
    "focus_cmd",
    "noise_cmd",
    "mc_cmd",
    "gap_cmd",
    "scenario_cmd",
    "report_cmd",
)

DEBUG_ENV = "SAR_BUDGET_DEBUG"


def build_parser() -> argparse.ArgumentParser:
    from .help_format import DefaultsParser  # every sub-command's --help shows its defaults

    parser = DefaultsParser(
        prog="sar-budget",
        description="IMU grade selection and error budgets for synthetic-aperture radar and sonar.")
    parser.add_argument("--debug", action="store_true",
                        help=f"show the traceback of unexpected errors (or set {DEBUG_ENV}=1)")

    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=DefaultsParser)
    for name in COMMAND_MODULES:
        importlib.import_module(f"{__package__}.{name}").add_parser(sub)
    return parser


def _terminate(signum, frame):
    # SIGTERM as an exception: `finally` blocks run, so temporary files are removed
    raise KeyboardInterrupt


def _debug_wanted(args) -> bool:
    return bool(getattr(args, "debug", False)) or os.environ.get(DEBUG_ENV, "") not in ("", "0")


def _name_scenario_file(err: BaseException, args) -> None:
    """An error about a scenario key raised after ``--scenario FILE`` was loaded (the simulator's
    or the motion engine's limits) names FILE (:func:`budget.scenario.name_scenario_file`). With
    several scenario files, or files and presets, only the command knows which one was running
    (``sweep`` names it itself, :func:`budget.mc.sweep.sweep` ``sources``); nothing is named here."""
    from ..errors import InputError
    from ..scenario import name_scenario_file

    given = getattr(args, "scenario", None)
    if isinstance(given, (list, tuple)):
        given = given[0] if len(given) == 1 and not getattr(args, "preset", None) else None
    if isinstance(err, InputError) and given:
        name_scenario_file(err, given)


def _one_line_warning(label: str):
    """``warnings.showwarning`` for the CLI: ``<label>: warning: <message>`` on one line (the
    default also prints the file, line and source line of the code that warned)."""
    def show(message, category, filename, lineno, file=None, line=None):
        from .output import warning_line
        print(warning_line(label, str(message)), file=file or sys.stderr)
    return show


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    label = f"sar-budget {args.command}"
    try:
        previous = signal.signal(signal.SIGTERM, _terminate)
    except ValueError:  # not the main thread: leave signals alone
        previous = None
    try:
        from .common import check_output_args
        check_output_args(args)
        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warning(label)  # never the source line of the code
            return int(args.func(args) or 0)
    except BrokenPipeError:
        return 0
    except SystemExit:
        raise
    except BaseException as err:  # noqa: BLE001 — the error boundary: one line, never a traceback
        _name_scenario_file(err, args)
        msg = describe_error(err)
        if msg.kind == "cancelled":
            print(f"{label}: cancelled", file=sys.stderr)
        else:
            if msg.kind == "unexpected" and _debug_wanted(args):
                traceback.print_exc()
            from ..safe_text import printable  # no terminal escapes from file contents
            print(f"{label}: error: {printable(msg.text)}", file=sys.stderr)
        return msg.exit_code
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
