"""``sar-budget check``: every catalog part against a scenario's bounds."""

from __future__ import annotations

from ..api import load_parts
from ..bounds.lever_arm import pga_limited_bounds
from ..catalog.io import load_catalog, load_grades
from ..check import check_parts, recommend_grade
from .common import add_catalog_option, add_scenario_options, scenario_from_args
from .output import add_json_option, write_json


def add_parser(sub) -> None:
    p = sub.add_parser("check", help="check catalog parts against a scenario",
                       description="Margins (bound/spec) of every catalog part for one scenario.")
    add_scenario_options(p, required=True)
    add_catalog_option(p)
    p.add_argument("--mode", choices=("paper", "derived", "no-autofocus"), default="paper")
    p.add_argument("--part", nargs="+", metavar="ID", help="only these parts")
    add_json_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    scen = scenario_from_args(args)
    catalog = load_catalog(args.catalog)
    parts = load_parts(args.part, catalog) if args.part else list(catalog.values())
    res = check_parts(parts, scen, mode=args.mode)
    if args.json:
        write_json(res.to_dict()["scenarios"][0]["parts"], args.json)
        return 0
    print(f"scenario {scen.name}: Tc = {scen.tc_s:.3g} s, δr = {scen.range_resolution_m:g} m, "
          f"λ = {scen.wavelength_m:.4g} m ({args.mode} bounds)")
    print(res.summary())
    rec = recommend_grade([scen.tc_s], scen.range_resolution_m, list(load_grades().values()), mode=args.mode,
                          wavelength_m=scen.wavelength_m)
    print(f"lowest sufficient grade (typical, bias + noise, {args.mode} bounds): {rec.grade[0] or 'none'}")
    limited, _ = pga_limited_bounds(scen)
    rec = recommend_grade([scen.tc_s], scen.range_resolution_m, list(load_grades().values()), bounds=limited)
    print(f"lowest sufficient grade (typical, bias + noise, PGA-limited bounds): {rec.grade[0] or 'none'}")
    return 0
