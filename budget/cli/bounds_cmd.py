"""``sar-budget bounds``: the Tc-driven sensor-error bounds (seed 004 (6)–(11))."""

from __future__ import annotations

import numpy as np

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
                   help="wavelength in m (with --tc; needed by --mode no-autofocus and lever-arm, and for "
                        "the fast-phase VRW/ARW limits)")
    add_scenario_options(p)
    p.add_argument("--mode", choices=("paper", "derived", "no-autofocus", "lever-arm"), default="paper",
                   help="lever-arm: seed 004's bounds with attitude error × lever arm (which binds)")
    p.add_argument("--lever-arm", type=float, nargs=3, metavar=("X", "Y", "Z"),
                   help="lever arm IMU → antenna in m (with --tc and --mode lever-arm; a scenario "
                        "gives its own)")
    p.add_argument("--platform-rate", type=float, metavar="DEG_S",
                   help="platform turn rate during the aperture (with --tc and --mode lever-arm; "
                        "default 0)")
    add_json_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    # the bounds (and the SAR modules behind their fast-phase limits) when the command runs, not
    # for --help or an argument error (budget.cli.main)
    from ..bounds import (LeverArmAssumptions, compute_bounds, fast_phase_limits, for_scenario, lever_arm_terms,
                          scenario_assumptions, scenario_keys)

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
        for option, value in (("--range-resolution", args.range_resolution), ("--wavelength", args.wavelength)):
            if value is not None:
                raise InputError("is used only with --tc (a scenario gives its own; edit the scenario "
                                 "to change it)", field=option, value=value, expected=f"--tc … {option}, or no {option}")
        s = scenario_from_args(args)
        tc, dr, lam = np.array([s.tc_s]), s.range_resolution_m, s.wavelength_m
    if not np.all(np.isfinite(tc)) or np.any(tc <= 0):
        raise InputError("Tc must be finite and > 0", field="--tc", value=list(args.tc or []))
    from ..scenario import PLAUSIBLE, PLAUSIBLE_TC_S  # the scenario's plausibility limits
    if np.any(tc < PLAUSIBLE_TC_S[0]) or np.any(tc > PLAUSIBLE_TC_S[1]):
        raise InputError("aperture time outside the physically plausible range", field="--tc",
                         value=list(args.tc or []), expected=f"{PLAUSIBLE_TC_S[0]:g} … {PLAUSIBLE_TC_S[1]:g} s")
    from ..bounds import check_bounds_tc
    check_bounds_tc(tc, field="--tc" if args.tc else "tc_s (derived)")
    lo, hi, why = PLAUSIBLE["range_resolution_m"]
    if np.isfinite(dr) and not lo <= dr <= hi:
        raise InputError("range resolution outside the physically plausible range",
                         field="--range-resolution", value=dr, expected=f"{lo:g} … {hi:g} m ({why})")
    if not (np.isfinite(dr) and dr > 0):
        raise InputError("range resolution must be finite and > 0", field="--range-resolution",
                         value=dr, expected="metres > 0")
    if args.wavelength is not None and not (np.isfinite(args.wavelength) and args.wavelength > 0):
        raise InputError("wavelength must be finite and > 0", field="--wavelength",
                         value=args.wavelength, expected="λ in m, e.g. 0.03")
    if args.wavelength is not None:
        from ..scenario import PLAUSIBLE_WAVELENGTH_M
        lo, hi = PLAUSIBLE_WAVELENGTH_M
        if not lo <= args.wavelength <= hi:
            raise InputError("wavelength outside the physically plausible range", field="--wavelength",
                             value=args.wavelength, expected=f"{lo:g} … {hi:g} m (radar 1 MHz … 10 THz, "
                             "sonar 10 Hz … 5 MHz)")
        if args.range_resolution is not None and args.range_resolution <= 0.25 * args.wavelength:
            raise InputError(f"range resolution {args.range_resolution:g} m needs a bandwidth above twice "
                             f"the carrier of a {args.wavelength:g}-m wave", field="--range-resolution",
                             value=args.range_resolution, expected=f"> λ/4 = {0.25 * args.wavelength:g} m "
                             "(as a scenario requires), or check the units of --wavelength")
    if args.mode in ("no-autofocus", "lever-arm") and lam is None:
        raise InputError(f"{args.mode} bounds need the wavelength", field="--wavelength",
                         expected="λ in m, or a scenario")
    for option, value in (("--lever-arm", args.lever_arm), ("--platform-rate", args.platform_rate)):
        if value is not None and not (args.tc and args.mode == "lever-arm"):
            raise InputError("is used only with --tc and --mode lever-arm (a scenario gives its own)",
                             field=option, value=value, expected="--tc … --mode lever-arm, or no "
                             f"{option}")
    lever = None
    if args.mode == "lever-arm":
        if args.tc:
            arm = tuple(args.lever_arm or (0.0, 0.0, 0.0))
            if not all(np.isfinite(v) and abs(v) <= 1e3 for v in arm):
                raise InputError("lever arm components must be finite and within 1 km", field="--lever-arm",
                                 value=list(arm), expected="X Y Z in m, |component| ≤ 1000 m")
            rate = 0.0 if args.platform_rate is None else args.platform_rate
            if not (np.isfinite(rate) and rate >= 0):
                raise InputError("platform turn rate must be finite and ≥ 0", field="--platform-rate",
                                 value=rate, expected="deg/s, ≥ 0")
            lever = LeverArmAssumptions(lever_arm_m=arm, platform_rate_deg_s=rate)
        else:
            lever = LeverArmAssumptions.from_scenario(s)
    assumed = lever if args.tc or lever is not None else scenario_assumptions(args.mode, s)
    table = compute_bounds(tc, dr, args.mode, wavelength_m=lam, assumptions=assumed)
    if not args.tc:  # the table says which scenario it is for, its defaults and what it does not use,
        table = for_scenario(table, s, args.mode)  # as budget.compute_bounds does
    # fast-phase limits at these Tc, weighted by the window the verdict images with (a scenario's:
    # Taylor on radar) or unweighted, the conservative side, for bare --tc
    window = LeverArmAssumptions.from_scenario(s).aperture_window if not args.tc else "rect"
    fast = fast_phase_limits(lam, tc, aperture_window=window) if lam is not None else None
    if args.json:
        out = {"mode": args.mode, "scenario": None if args.tc else s.model_dump(mode="json"),
               "tc_s": np.atleast_1d(tc).tolist(),
               # no-autofocus bounds do not use δr: none given with --tc is null, not the 1.0 filled above
               "range_resolution_m": None if args.tc and args.range_resolution is None else float(dr),
               "wavelength_m": None if lam is None else float(lam), "bounds": table.to_dict(),
               "fast_phase": None if fast is None else fast.to_dict(),
               "scenario_defaults": None if args.tc else s.defaults_taken(scenario_keys(args.mode))}
        if lever is not None:
            terms = {f"{t:.6g}": lever_arm_terms(float(t), dr, lam, lever) for t in np.atleast_1d(tc)}
            out["lever_arm"] = {"assumptions": lever.model_dump(mode="json"),
                                "terms": {t: f.to_dict(orient="records") for t, f in terms.items()},
                                "notes": [n for f in terms.values() for n in f.attrs.get("notes", [])]}
        write_json(out, args.json)
        return 0
    print(table.summary())
    if lever is not None:
        for t in np.atleast_1d(tc):
            print(f"lever arm at Tc = {t:.4g} s (|d| = {lever.lever_m:.3g} m):")
            terms = lever_arm_terms(float(t), dr, lam, lever)
            print(terms.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
            for note in terms.attrs.get("notes", []):
                print(note)
    if fast is not None:
        print(fast.summary())
    return 0
