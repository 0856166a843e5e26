"""``sar-budget check``: every catalog part against a scenario's bounds."""

from __future__ import annotations

from .common import add_catalog_option, add_scenario_options, scenario_from_args
from .motion_options import add_platform_motion_options, platform_motion_from_args
from .output import add_json_option, write_json


def add_parser(sub) -> None:
    p = sub.add_parser("check", help="check catalog parts against a scenario",
                       description="Margins (bound/spec) of every catalog part for one scenario.")
    add_scenario_options(p, required=True)
    add_catalog_option(p)
    p.add_argument("--mode", choices=("paper", "derived", "no-autofocus"), default="paper")
    p.add_argument("--part", nargs="+", metavar="ID", help="only these parts")
    add_platform_motion_options(p, unset="unset (default: the bounds' own attitude change of 1 rad), straight "
                                         "(gyro scale factor and misalignment not exercised)")
    add_json_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    # the computation's modules when it runs, not for --help or an argument error (budget.cli.main)
    from ..api import load_parts
    from ..catalog.io import catalog_note, load_catalog, load_grades, user_catalog_path
    from ..check import check_parts, check_scenario_keys
    from ..check_text import check_record
    from ..recommend import lowest_sufficient_grades

    scen = scenario_from_args(args)
    catalog = load_catalog(args.catalog)
    parts = load_parts(args.part, catalog) if args.part else list(catalog.values())
    res = check_parts(parts, scen, mode=args.mode, platform_motion=platform_motion_from_args(args))
    grades = lowest_sufficient_grades(scen, args.mode, load_grades().values())
    keys = check_scenario_keys(args.mode, getattr(args, "platform_motion", None))
    origin = catalog_note(res.part_ids, args.catalog)  # '' with the shipped catalog alone
    if args.json:
        # the user catalog merged over the shipped one: --catalog, else $SAR_BUDGET_CATALOG
        user = user_catalog_path(args.catalog)
        # what the verdicts were computed with, beside the records
        write_json(check_record(res, scen, args.mode, grades, catalog=str(user) if user else "shipped",
                                catalog_note=origin, scenario_keys=keys), args.json)
        return 0
    print(f"scenario {scen.name}: Tc = {scen.tc_s:.3g} s, δr = {scen.range_resolution_m:g} m, "
          f"λ = {scen.wavelength_m:.4g} m ({args.mode} bounds)")
    print(res.summary())
    if origin:
        print(origin)
    print(f"lowest sufficient grade (typical, bias + noise, {args.mode} bounds): {grades.text(args.mode)}")
    print(f"lowest sufficient grade (typical, bias + noise, PGA-limited bounds): {grades.text('pga_limited')}")
    return 0
