"""``sar-budget mc`` (Monte Carlo verdict of one part) and ``sar-budget sweep`` (trade study)."""

from __future__ import annotations

import sys

from ..aiding_spec import AidingPlan
from ..api import load_parts
from ..catalog.io import catalog_note, load_catalog
from ..errors import InputError
from ..mc import McOptions, run_mc
from ..mc.options import (DEFAULT_SEED, DEFAULT_TRIALS, PREFILTERS, UNSPECIFIED_DEFAULT, UNSPECIFIED_POLICIES,
                          acceptance_spec_options)
from ..mc.sweep import cheapest_passing, not_simulated, sweep
from ..noise.prefilter import prefilter_for
from ..presets import get_preset
from ..sar.residual import DEFAULT_PASS_SHARE
from ..scenario import Scenario
from .common import (add_catalog_option, add_part_or_model_options, add_scenario_options,
                     part_or_model_from_args, scenario_from_args)
from .motion_options import add_platform_motion_options, platform_motion_from_args  # noqa: F401 (check, report)
from .output import add_json_option, write_json
from .progress import add_quiet_option, progress


def _options(args) -> McOptions:
    upd = {}
    if getattr(args, "no_fast_phase", False):
        upd["max_residual_phase_rms_deg"] = None
    if getattr(args, "no_pga_second_pass", False):
        upd["pga_second_pass"] = False
    if getattr(args, "prefilter", "none") != "none":
        upd["prefilter"] = args.prefilter
    if getattr(args, "unspecified", None) is not None:
        upd["unspecified"] = args.unspecified
    for name in ("scene", "clutter_to_target_db", "snr_db", "window"):
        if getattr(args, name, None) is not None:
            upd[name] = getattr(args, name)
    if upd.get("clutter_to_target_db") is not None and upd.get("scene", McOptions().scene) == "points":
        raise InputError("the points scene has no clutter", field="--clutter-db", value=upd["clutter_to_target_db"],
                         expected="--scene realistic (or auto) with --clutter-db, or no --clutter-db")
    motion = platform_motion_from_args(args)
    if motion is not None:
        upd["platform_motion"] = motion
    if getattr(args, "acceptance", None):
        from ..structured import read_structured
        spec = read_structured(args.acceptance, "an acceptance spec")  # size, depth and duplicate-key limits
        if not isinstance(spec, dict):
            raise InputError("the acceptance spec must be a JSON object", file=args.acceptance)
        # the library's one merge: the spec over the verdict's defaults, its verdict limits as options
        merged = acceptance_spec_options(spec)
        verdict = [k for k in merged if k != "acceptance"]
        upd.update(merged)
        try:
            return McOptions.build(**upd)
        except InputError as err:  # a field of the spec: name its file
            if err.field and (err.field.startswith("acceptance") or err.field in verdict):
                raise err.rename_file(args.acceptance) from None
            raise
    return McOptions.build(**upd)


def _positive(name, v):
    if v < 1:
        raise InputError(f"{name} must be ≥ 1", field=f"--{name}", value=v)


def add_parser(sub) -> None:
    p = sub.add_parser("mc", help="Monte Carlo verdict: does autofocus absorb what the IMU leaves?")
    add_scenario_options(p, required=True)
    add_part_or_model_options(p, part_help="catalog part", model_help="noise-model JSON")
    p.add_argument("--trials", type=int, default=DEFAULT_TRIALS, help="Monte Carlo trials")
    p.add_argument("--seed", type=int, default=DEFAULT_SEED, help="random seed (same seed → same numbers)")
    p.add_argument("--workers", type=int, default=1, help="local processes (results do not depend on it)")
    _add_verdict_options(p)
    _add_unspecified_option(p)
    add_json_option(p)
    add_quiet_option(p)
    p.set_defaults(func=run)

    s = sub.add_parser("sweep", help="trade study: parts × scenarios → CSV")
    s.add_argument("--scenario", nargs="+", metavar="S.json", help="scenario files")
    s.add_argument("--preset", nargs="+", metavar="NAME", help="preset scenarios")
    s.add_argument("--part", nargs="+", metavar="ID", help="parts (default: every catalog part with specs)")
    add_catalog_option(s)
    s.add_argument("--trials", type=int, default=DEFAULT_TRIALS, help="trials per part × scenario")
    s.add_argument("--seed", type=int, default=DEFAULT_SEED, help="random seed (common to every cell)")
    s.add_argument("--workers", type=int, default=1, help="local processes (results do not depend on it)")
    s.add_argument("--target", type=float, default=DEFAULT_PASS_SHARE, help="P(pass after PGA) wanted")
    s.add_argument("--out", metavar="CSV", required=True, help="tidy result table (CSV; '-' for stdout)")
    _add_verdict_options(s)
    _add_unspecified_option(s)
    add_quiet_option(s)
    s.set_defaults(func=run_sweep)


def _add_verdict_options(p) -> None:
    """What the verdict is judged on (scene, window, acceptance, pre-filter): the same options
    for ``mc`` and ``sweep``."""
    p.add_argument("--no-fast-phase", action="store_true",
                   help="judge by the image alone (drop the 1° limit on what PGA cannot remove)")
    p.add_argument("--no-pga-second-pass", action="store_true",
                   help="one PGA pass (default: after a correction of more than π rad rms from a clutter-limited "
                        "start PGA runs again on the image it corrected, kept when the image is sharper)")
    p.add_argument("--scene", choices=("auto", "realistic", "points"), default=None,
                   help="realistic (the default): clutter + noise + many scatterers, judged against a "
                        "perfect IMU on the same scene; points: five noise-free points (PGA's best case); "
                        "auto: realistic")
    p.add_argument("--clutter-db", dest="clutter_to_target_db", type=float, default=None,
                   help="realistic scene: clutter-to-target ratio in dB (default −25)")
    p.add_argument("--snr-db", dest="snr_db", type=float, default=None,
                   help="receiver SNR in dB (default: 30 on the realistic scene, none on the points)")
    p.add_argument("--window", choices=("auto", "rect", "taylor"), default=None,
                   help="image weighting (default auto: Taylor −35 dB for radar, the scenario's own for sonar)")
    p.add_argument("--acceptance", metavar="A.json",
                   help="acceptance spec: max_broadening, max_pslr_db, max_islr_db, "
                        "max_peak_loss_db, max_range_migration_cells, max_residual_phase_rms_deg …")
    add_platform_motion_options(p)
    p.add_argument("--prefilter", choices=PREFILTERS, default="none",
                   help="seed 000's ARMA-Kalman filtering of the IMU output before navigation "
                        "(real-time filter or RTS smoother; ARMA fitted on a simulated static record)")


def _add_unspecified_option(p) -> None:
    p.add_argument("--unspecified", choices=UNSPECIFIED_POLICIES, default=None,
                   help="empty datasheet terms: fill_grade_typical (grade typical values, recorded; "
                        f"default {UNSPECIFIED_DEFAULT}), refuse (error naming them) or zero (stated zero)")


def run(args) -> int:
    _positive("trials", args.trials)
    _positive("workers", args.workers)
    if args.seed < 0:
        raise InputError("seed must be ≥ 0", field="--seed", value=args.seed)
    scen = scenario_from_args(args)
    model = part_or_model_from_args(args)
    with progress(f"mc {getattr(model, 'part_id', None) or 'model'}", quiet=args.quiet) as bar:
        res = run_mc(scen, model, args.trials, args.seed, options=_options(args),
                     workers=args.workers, progress=bar)
    opts = _options(args)
    gains = None
    if opts.prefilter != "none":  # the run refused a filter that rescales motion; report what passed
        gains = prefilter_for(model, scen.imu_rate_hz, kind=opts.prefilter,
                              samples=opts.prefilter_calibration_samples,
                              seed=args.seed).dc_gains(scen.imu_rate_hz)
    versus = _check_vs_mc(scen, model, res)
    # a part id read from a user catalog (--catalog or $SAR_BUDGET_CATALOG): say so, above all
    # when the user's row replaces a shipped part of the same id
    origin = catalog_note([model.part_id], args.catalog) if args.part else ""
    if args.json:
        out = res.to_dict()
        out["aiding"] = AidingPlan.from_scenario(scen).label()
        out["catalog_note"] = origin or None
        if gains is not None:
            out["prefilter_dc_gain"] = gains
        if versus is not None:
            out["check_vs_mc"] = versus
        write_json(out, args.json)
    else:
        print(res.summary())
        print(f"aiding: {AidingPlan.from_scenario(scen).label()}")
        if origin:
            print(origin)
        if gains is not None:
            print("pre-filter DC gain: " + ", ".join(f"{ch} {g:.4f}" for ch, g in gains.items()))
        if versus is not None:  # names the check compared: the PGA-limited one
            from ..report import check_vs_mc_text
            print(check_vs_mc_text(versus))
    return 0


def _check_vs_mc(scen, model, res):
    """The analytic check of a catalog part beside its Monte Carlo verdict (None for a noise model:
    a NoiseModel is a PartSpec too, but its effects are not in the analytic check)."""
    from ..catalog.schema import PartSpec
    from ..check import check_parts
    from ..imu import NoiseModel
    from ..report import check_vs_mc

    if not isinstance(model, PartSpec) or isinstance(model, NoiseModel):
        return None
    return check_vs_mc(check_parts([model], scen).to_dict()["scenarios"][0]["parts"][0], res)


def run_sweep(args) -> int:
    _positive("trials", args.trials)
    if not 0.0 < args.target <= 1.0:  # before the study, not after it (NaN fails the test too)
        raise InputError("target probability out of range", field="--target", value=args.target,
                         expected="0 < target ≤ 1")
    scens = [Scenario.load(p) for p in (args.scenario or [])] + [get_preset(n) for n in (args.preset or [])]
    if not scens:
        raise InputError("no scenario given", field="--scenario/--preset")
    cat = load_catalog(args.catalog)
    parts = load_parts(args.part, cat)  # None: every part with a noise figure
    with progress(f"sweep {len(parts)} parts × {len(scens)} scenarios", "cells",
                  quiet=args.quiet) as bar:
        table = sweep(parts, scens, args.trials, args.seed, options=_options(args), workers=args.workers,
                      progress=bar, sources=list(args.scenario or []) + [None] * len(args.preset or []))
    from .output import warn, write_frame_csv  # text cells (scenario names …) spreadsheet-safe
    write_frame_csv(table, args.out)
    for scen, status in not_simulated(table).items():
        warn(args, f"scenario {scen!r} {status}")
    # '-' where no part passes (the basis column says why), not Python's None
    best = cheapest_passing(table, args.target)
    # with --out - stdout carries the CSV alone; the cheapest-part table then goes to stderr
    print(best.astype(object).where(best.notna(), "-").to_string(index=False),
          file=sys.stderr if args.out == "-" else sys.stdout)
    if origin := catalog_note([p.part_id for p in parts], args.catalog):
        print(origin, file=sys.stderr if args.out == "-" else sys.stdout)
    return 0
