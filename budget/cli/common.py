"""Argument helpers shared by the sub-commands (scenario and catalog selection)."""

from __future__ import annotations

from ..errors import InputError
from ..presets import PRESETS, get_preset
from ..scenario import Scenario


def add_scenario_options(parser, required: bool = False) -> None:
    g = parser.add_mutually_exclusive_group(required=required)
    g.add_argument("--scenario", metavar="S.json", help="scenario JSON/YAML file")
    g.add_argument("--preset", choices=sorted(PRESETS), help="a preset scenario")


def scenario_from_args(args, default_preset: str | None = None) -> Scenario:
    if getattr(args, "scenario", None):
        return Scenario.load(args.scenario)
    if getattr(args, "preset", None):
        return get_preset(args.preset)
    if default_preset:
        return get_preset(default_preset)
    raise InputError("no scenario given", field="--scenario", expected="--scenario FILE or --preset NAME")


def add_catalog_option(parser) -> None:
    parser.add_argument("--catalog", metavar="CSV",
                        help="user catalog merged over the shipped one (default: $SAR_BUDGET_CATALOG)")
