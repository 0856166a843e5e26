"""sar-imu-budget: IMU grade selection and error budgets for synthetic-aperture radar and sonar.

Top-level API (imported on first use, so ``import budget`` stays fast)::

    import budget
    s = budget.load_scenario("airborne_xband")          # preset name, JSON/YAML path or Scenario
    budget.check_parts(["ADIS16405", "STIM300"], s)      # analytic check → CheckResult
    budget.run_mc(s, "STIM300", trials=64, seed=1)       # Monte Carlo verdict → McResult
    table = budget.sweep(["ADIS16405", "STIM300"], ["airborne_xband", "automotive_77ghz"])
    budget.cheapest_passing(table)                       # per scenario

Names accepted wherever an object is expected: preset names for scenarios, ``part_id`` for
parts (:mod:`budget.api`). Everything else lives in the sub-packages (``budget.bounds``,
``budget.mc``, ``budget.noise``, ``budget.gap`` …).
"""

from __future__ import annotations

__version__ = "0.1.0"

#: Names served by :mod:`budget.api` (lazily, PEP 562).
_API = ("load_scenario", "load_scenarios", "load_catalog", "load_part", "load_parts", "check_parts",
        "run_mc", "sweep", "sweep_over", "vary_scenario", "cheapest_passing", "compute_bounds",
        "DEFAULT_TRIALS", "DEFAULT_SEED")
_OTHER = {"Scenario": ("budget.scenario", "Scenario"), "McOptions": ("budget.mc.options", "McOptions"),
          "InputError": ("budget.errors", "InputError"), "PRESETS": ("budget.presets", "PRESETS"),
          "build_report": ("budget.report", "build_report")}

__all__ = ["__version__", *_API, *_OTHER]


def __getattr__(name: str):
    import importlib

    if name in _API:
        return getattr(importlib.import_module("budget.api"), name)
    if name in _OTHER:
        mod, attr = _OTHER[name]
        return getattr(importlib.import_module(mod), attr)
    raise AttributeError(f"module 'budget' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
