"""``sar-budget motion``: Monte Carlo of IMU errors → antenna motion error → phase error."""

from __future__ import annotations

import sys

from ..aiding_spec import AidingPlan
from ..catalog.fill import DEFAULT_POLICY, POLICIES
from ..errors import InputError
from ..mc.options import DEFAULT_SEED
from ..mc.runner import MAX_TRIALS
from ..motion.cost import estimate_cost
from ..motion.engine import simulate_motion
from ..nav.platform import Disturbance
from .common import add_part_or_model_options, add_scenario_options, part_or_model_from_args, scenario_from_args
from .output import add_json_option, write_json
from .progress import add_quiet_option, progress



def add_parser(sub) -> None:
    p = sub.add_parser("motion", help="simulate motion and phase errors of an IMU over the aperture",
                       description="Monte Carlo of the antenna-phase-centre error over the synthetic "
                                   "aperture and its phase error, decomposed by Legendre polynomials.")
    add_scenario_options(p, required=True)
    add_part_or_model_options(p)
    p.add_argument("--trials", type=int, default=1000, help="number of trials (default 1000)")
    p.add_argument("--seed", type=int, default=DEFAULT_SEED, help=f"random seed (default {DEFAULT_SEED}, as mc's)")
    p.add_argument("--unspecified", choices=POLICIES, default=DEFAULT_POLICY,
                   help="empty datasheet terms: fill_grade_typical (grade typical values, recorded; "
                        f"default {DEFAULT_POLICY}, as mc's), refuse (error naming them) or zero (stated zero)")
    p.add_argument("--disturbance", metavar="D.json", help="platform disturbance JSON")
    p.add_argument("--workers", type=int, default=1, help="worker threads (results do not depend on it)")
    add_json_option(p)
    add_quiet_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    if not 1 <= args.trials <= MAX_TRIALS:
        raise InputError("--trials out of range", field="--trials", value=args.trials,
                         expected=f"1 … {MAX_TRIALS:,}")
    if args.seed < 0:
        raise InputError("--seed must be ≥ 0", field="--seed", value=args.seed)
    scen = scenario_from_args(args)
    model = part_or_model_from_args(args)
    dist = Disturbance.load(args.disturbance) if args.disturbance else None
    quiet = getattr(args, "quiet", False)
    cost = estimate_cost(scen, args.trials, AidingPlan.from_scenario(scen), args.workers)
    if not quiet and cost["cpu_s"] > 10.0:  # say what a large run costs before it starts
        print(f"motion: {cost['samples']:,} IMU samples per trial, ≈ {cost['cpu_s']:.0f} s CPU and "
              f"≈ {cost['bytes'] / 1e9:.2g} GB", file=sys.stderr, flush=True)
    with progress(f"motion {getattr(model, 'part_id', None) or 'model'}", quiet=quiet) as bar:
        res = simulate_motion(scen, model, args.trials, args.seed, disturbance=dist,
                              workers=args.workers, keep_series=False, progress=bar,
                              unspecified=args.unspecified)
    if args.json:
        write_json(res.to_dict(), args.json)
    else:
        print(res.summary())
    return 0
