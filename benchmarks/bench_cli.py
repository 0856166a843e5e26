"""Benchmark of the command line's start-up: how long a user waits for ``--help`` or for the
one-line error of a mistyped option, each in a fresh process (the package's imports included).

Printed per command: the wall time of ``sar-budget --help``, of ``sar-budget CMD --help`` for every
sub-command, and of one argument error (``sar-budget check --bogus``), median of ``--repeat`` runs.
Target: ``sar-budget --help`` and an argument error of a light command under 1 s (the parser loads
only the module of the command typed, ``budget/cli/main.py``); the heavy commands' help loads the
option constants of their engines (the Monte Carlo, the noise lab, the model gap).

Run from the repository root: ``python3 benchmarks/bench_cli.py [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from budget.cli.main import COMMANDS  # noqa: E402  (light: the command table only)

CLI = [sys.executable, "-m", "budget.cli.main"]


def wall(args: list[str], repeat: int) -> tuple[float, int]:
    """(median wall time in s, exit code) of the CLI with ``args`` in a fresh process."""
    times, code = [], 0
    for _ in range(repeat):
        t0 = time.perf_counter()
        code = subprocess.run(CLI + args, cwd=ROOT, capture_output=True).returncode
        times.append(time.perf_counter() - t0)
    times.sort()
    return times[len(times) // 2], code


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="runs per command (median printed)")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat must be ≥ 1")
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    print(f"CLI start-up, wall time in a fresh process, median of {args.repeat} (load {load}):")
    rows = [("--help", ["--help"]), ("check --bogus (argument error)", ["check", "--bogus"])]
    rows += [(f"{name} --help", [name, "--help"]) for name in COMMANDS]
    for label, argv in rows:
        t, code = wall(argv, args.repeat)
        print(f"  sar-budget {label:<34}{t:6.2f} s  (exit {code})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
