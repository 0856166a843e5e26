"""``sar-budget`` entry point.

Each sub-command lives in its own module of this package with two functions:
``add_parser(subparsers)`` (registers arguments and sets ``func=run``) and ``run(args) -> int``.
Bad input exits with status 2 and one line on stderr, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from ..errors import InputError

#: Modules of this package that provide sub-commands, in help order.
COMMAND_MODULES = (
    "dashboard_cmd",
    "demo_cmd",
    "bounds_cmd",
    "check_cmd",
    "catalog_cmd",
    "motion_cmd",
    "sar_cmd",
    "noise_cmd",
    "mc_cmd",
    "gap_cmd",
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="sar-budget",
        description="IMU grade selection and error budgets for synthetic-aperture radar and sonar.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        try:
            mod = importlib.import_module(f"{__package__}.{name}")
        except ModuleNotFoundError as err:
            if err.name == f"{__package__}.{name}":
                continue  # command not built yet
            raise
        mod.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except InputError as err:
        print(f"sar-budget {args.command}: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"sar-budget {args.command}: cancelled", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
