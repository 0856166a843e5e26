"""``sar-budget mc`` (Monte Carlo verdict of one part) and ``sar-budget sweep`` (trade study)."""

from __future__ import annotations

import sys

from ..catalog.io import get_part, load_catalog
from ..errors import InputError
from ..imu.noise_model import NoiseModel
from ..mc import McOptions, run_mc
from ..mc.options import PREFILTERS
from ..mc.sweep import cheapest_passing, sweep
from ..presets import get_preset
from ..scenario import Scenario
from .common import add_catalog_option, add_scenario_options, scenario_from_args
from .output import add_json_option, write_json


def _progress_bar(done: int, total: int) -> None:
    if not sys.stderr.isatty():
        return
    width = 30
    k = int(width * done / max(total, 1))
    sys.stderr.write(f"\r[{'#' * k}{'.' * (width - k)}] {done}/{total} trials")
    if done >= total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _model(args):
    if args.model:
        return NoiseModel.load(args.model)
    return get_part(args.part, load_catalog(args.catalog))


def _options(args) -> McOptions:
    upd = {}
    if getattr(args, "no_fast_phase", False):
        upd["max_residual_phase_rms_deg"] = None
    if getattr(args, "prefilter", "none") != "none":
        upd["prefilter"] = args.prefilter
    return McOptions(**upd)


def _positive(name, v):
    if v < 1:
        raise InputError(f"{name} must be ≥ 1", field=f"--{name}", value=v)


def add_parser(sub) -> None:
    p = sub.add_parser("mc", help="Monte Carlo verdict: does autofocus absorb what the IMU leaves?")
    add_scenario_options(p, required=True)
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--part", metavar="ID", help="catalog part")
    g.add_argument("--model", metavar="M.json", help="noise-model JSON")
    add_catalog_option(p)
    p.add_argument("--trials", type=int, default=256)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--workers", type=int, default=1, help="local processes (results do not depend on it)")
    p.add_argument("--no-fast-phase", action="store_true",
                   help="judge by the image alone (drop seed 004's 1° fast-phase criterion)")
    p.add_argument("--prefilter", choices=PREFILTERS, default="none",
                   help="seed 000's ARMA-Kalman filtering of the IMU output before navigation "
                        "(real-time filter or RTS smoother; ARMA fitted on a simulated static record)")
    add_json_option(p)
    p.set_defaults(func=run)

    s = sub.add_parser("sweep", help="trade study: parts × scenarios → CSV")
    s.add_argument("--scenario", nargs="+", metavar="S.json", help="scenario files")
    s.add_argument("--preset", nargs="+", metavar="NAME", help="preset scenarios")
    s.add_argument("--part", nargs="+", metavar="ID", help="parts (default: every catalog part with specs)")
    add_catalog_option(s)
    s.add_argument("--trials", type=int, default=128)
    s.add_argument("--seed", type=int, default=0)
    s.add_argument("--workers", type=int, default=1)
    s.add_argument("--target", type=float, default=0.9, help="P(pass after PGA) wanted")
    s.add_argument("--out", metavar="CSV", required=True, help="tidy result table (CSV)")
    s.set_defaults(func=run_sweep)


def run(args) -> int:
    _positive("trials", args.trials)
    _positive("workers", args.workers)
    if args.seed < 0:
        raise InputError("seed must be ≥ 0", field="--seed", value=args.seed)
    scen = scenario_from_args(args)
    res = run_mc(scen, _model(args), args.trials, args.seed, options=_options(args),
                 workers=args.workers, progress=_progress_bar)
    if args.json:
        write_json(res.to_json_dict(), args.json)
    else:
        print(res.summary())
    return 0


def run_sweep(args) -> int:
    _positive("trials", args.trials)
    scens = [Scenario.load(p) for p in (args.scenario or [])] + [get_preset(n) for n in (args.preset or [])]
    if not scens:
        raise InputError("no scenario given", field="--scenario/--preset")
    cat = load_catalog(args.catalog)
    parts = [get_part(pid, cat) for pid in args.part] if args.part else \
        [p for p in cat.values() if p.gyro_arw_deg_rt_h is not None or p.accel_vrw_m_s_rt_h is not None]
    table = sweep(parts, scens, args.trials, args.seed, workers=args.workers,
                  progress=lambda d, t: _progress_bar(d, t))
    from ..fileio import atomic_write_text
    atomic_write_text(args.out, table.to_csv(index=False))
    print(cheapest_passing(table, args.target).to_string(index=False))
    return 0
