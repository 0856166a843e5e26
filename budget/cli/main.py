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

#: Sub-commands in help order: name → (module of this package that defines it, its one-line help).
#: ``sar-budget --help`` and a wrong command name are answered from this table alone; only the
#: module of the command given is imported (:func:`build_parser` with ``argv``), so the help and
#: argument errors do not wait for every command's dependencies (scipy, pandas, plotly, numba …).
#: ``tests/test_cli_review_fixes.py`` checks each help here is the one its module registers.
COMMANDS: dict[str, tuple[str, str]] = {
    "dashboard": ("dashboard_cmd", "start the interactive dashboard and print its URL"),
    "demo": ("demo_cmd", "print bounds and the part check for a preset scenario"),
    "bounds": ("bounds_cmd", "maximum allowed IMU errors for given aperture times"),
    "check": ("check_cmd", "check catalog parts against a scenario"),
    "catalog": ("catalog_cmd", "validate, list or show catalog parts"),
    "motion": ("motion_cmd", "simulate motion and phase errors of an IMU over the aperture"),
    "sar": ("sar_cmd", "simulate, image and autofocus the default point-target scene"),
    "focus": ("focus_cmd", "focus recorded SAR phase-history files and autofocus the image"),
    "noise": ("noise_cmd", "noise lab: Allan characterisation, ARMA + Kalman filter"),
    "mc": ("mc_cmd", "Monte Carlo verdict: does autofocus absorb what the IMU leaves?"),
    "sweep": ("mc_cmd", "trade study: parts × scenarios → CSV"),
    "gap": ("gap_cmd", "model gap: compare a log with its noise model, name missing effects"),
    "scenario": ("scenario_cmd", "show, write or validate a scenario (JSON/YAML)"),
    "report": ("report_cmd", "HTML report: scenario, bounds, check, Monte Carlo, figures"),
}

#: Modules of this package that provide sub-commands, in help order.
COMMAND_MODULES = tuple(dict.fromkeys(module for module, _ in COMMANDS.values()))

DEBUG_ENV = "SAR_BUDGET_DEBUG"


def command_in(argv: list[str]) -> str | None:
    """The sub-command ``argv`` names (its first word that is not a top-level option), or None."""
    for word in argv:
        if not word.startswith("-"):
            return word
        if word == "--":
            return None
    return None


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The ``sar-budget`` parser. Without ``argv``: every sub-command's full parser (each module
    imported). With ``argv``: only the module of the command it names is imported and its parser
    built; the other commands are listed with their help (:data:`COMMANDS`) and nothing else."""
    from .help_format import DefaultsParser  # every sub-command's --help shows its defaults

    parser = DefaultsParser(
        prog="sar-budget",
        description="IMU grade selection and error budgets for synthetic-aperture radar and sonar.")
    parser.add_argument("--debug", action="store_true",
                        help=f"show the traceback of unexpected errors (or set {DEBUG_ENV}=1)")

    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=DefaultsParser)
    if argv is None:
        modules = COMMAND_MODULES
    else:
        chosen = command_in(argv)
        modules = (COMMANDS[chosen][0],) if chosen in COMMANDS else ()
    for name in modules:
        importlib.import_module(f"{__package__}.{name}").add_parser(sub)
    built = dict(sub.choices)
    for name, (_, help_) in COMMANDS.items():  # the others: listed, in help order
        if name not in built:
            sub.add_parser(name, help=help_)
    order = list(COMMANDS)  # help order whichever module was imported first
    sub._choices_actions.sort(key=lambda a: order.index(a.dest) if a.dest in order else len(order))
    sub.choices = dict(sorted(sub.choices.items(),
                              key=lambda kv: order.index(kv[0]) if kv[0] in order else len(order)))
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


def _name_option(err: BaseException, parser, args) -> BaseException:
    """A library error about one of its fields names the option the user typed instead
    (``option --manoeuvre-period``, not ``field period_s``: :mod:`.option_names`)."""
    from pydantic import ValidationError

    from ..errors import from_validation_error
    from .option_names import name_option

    if isinstance(err, ValidationError):
        err = from_validation_error(err)
    return name_option(err, parser, args)


def _one_line_warning(label: str):
    """``warnings.showwarning`` for the CLI: ``<label>: warning: <message>`` on one line (the
    default also prints the file, line and source line of the code that warned)."""
    def show(message, category, filename, lineno, file=None, line=None):
        from .output import warning_line
        print(warning_line(label, str(message)), file=file or sys.stderr)
    return show


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(argv)  # the command's own module only: help and argument errors are fast
    args = parser.parse_args(argv)
    if getattr(args, "command", None) and not getattr(args, "func", None):
        parser = build_parser()  # a command the quick look did not find (never expected): the full parser
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
        err = _name_option(err, parser, args)
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
