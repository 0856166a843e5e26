"""``sar-budget bounds``: the Tc-driven sensor-error bounds (seed 004 (6)–(11))."""

from __future__ import annotations

import numpy as np

from ..bounds import compute_bounds, fast_phase_limits
from ..errors import InputError
from .common import add_scenario_options, scenario_from_args
from .output import add_json_option, write_json


def add_parser(sub) -> None:
    p = sub.add_parser("bounds", help="maximum allowed IMU errors for given aperture times",
                       description="Maximum allowed IMU errors per synthetic-aperture time Tc.")
    p.add_argument("--tc", type=float, nargs="+", metavar="S", help="aperture times Tc in s")
    p.add_argument("--range-resolution", type=float, metavar="M",
                   help="range resolution δr in m (with --tc)")
    p.add_argument("--wavelength", type=float, metavar="M",
                   help="wavelength in m (with --tc; needed by --mode no-autofocus)")
    add_scenario_options(p)
    p.add_argument("--mode", choices=("paper", "derived", "no-autofocus"), default="paper")
    add_json_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    if args.tc:
        if args.scenario or args.preset:
            raise InputError("give either --tc or a scenario, not both", field="--tc")
        if args.range_resolution is None and args.mode != "no-autofocus":
            raise InputError("--tc needs --range-resolution", field="--range-resolution",
                             expected="δr in m, e.g. 0.1")
        tc = np.asarray(args.tc, float)
        dr = args.range_resolution if args.range_resolution is not None else 1.0
        lam = args.wavelength
    else:
        s = scenario_from_args(args)
        tc, dr, lam = np.array([s.tc_s]), s.range_resolution_m, s.wavelength_m
    if not np.all(np.isfinite(tc)) or np.any(tc <= 0):
        raise InputError("Tc must be finite and > 0", field="--tc", value=list(args.tc or []))
    if not (np.isfinite(dr) and dr > 0):
        raise InputError("range resolution must be finite and > 0", field="--range-resolution",
                         value=dr, expected="metres > 0")
    if args.mode == "no-autofocus" and not lam:
        raise InputError("no-autofocus bounds need the wavelength", field="--wavelength",
                         expected="λ in m, or a scenario")
    table = compute_bounds(tc, dr, args.mode, wavelength_m=lam)
    if args.json:
        write_json(table.records(), args.json)
        return 0
    print(table.summary())
    if lam:
        print(fast_phase_limits(lam).summary())
    return 0
