"""``sar-budget sar``: image the default scene of a scenario with an injected smooth phase error,
then autofocus it, printing the impulse-response metrics before and after PGA."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .common import add_scenario_options, scenario_from_args
from .output import add_json_option, write_json

_COLS = ["peak_loss_db", "azimuth_broadening", "azimuth_pslr_db", "azimuth_islr_db", "azimuth_peak_shift_m",
         "range_broadening", "range_pslr_db", "range_islr_db"]


def add_parser(sub) -> None:
    p = sub.add_parser("sar", help="simulate, image and autofocus the default point-target scene",
                       description="Point-target SAR/SAS demo: inject a smooth phase error (quadratic + "
                                   "cubic + slow sinusoid, along the line of sight), form the image, run "
                                   "PGA and print the IRF metrics before and after.")
    add_scenario_options(p)
    p.add_argument("--quadratic-rad", type=float, default=6.0, help="quadratic phase at the aperture edge")
    p.add_argument("--cubic-rad", type=float, default=3.0, help="cubic phase at the aperture edge")
    p.add_argument("--sinusoid-rad", type=float, default=2.0, help="sinusoid amplitude (rad)")
    p.add_argument("--sinusoid-cycles", type=float, default=1.5, help="sinusoid cycles over the aperture")
    p.add_argument("--window", default=None, help="rect | taylor | taylor-35-4 (default from the scenario)")
    p.add_argument("--method", choices=("rda", "backprojection"), default="rda")
    p.add_argument("--kernel", choices=("ml", "lumv"), default="ml")
    p.add_argument("--snr-db", type=float, default=50.0, help="image-domain SNR of a unit target")
    p.add_argument("--seed", type=int, default=0)
    add_json_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    # the simulator when the command runs, not for --help or an argument error (budget.cli.main)
    from ..sar import SarGeometry, Scene, smooth_phase_error
    from ..sar.geometry import IMAGE_MARGIN_CELLS
    from ..sar.injected import run_injected_phase_trial
    from ..sar.phase import check_phase_sampled, normalised_time

    scenario = scenario_from_args(args, default_preset="airborne_xband")
    for name in ("quadratic_rad", "cubic_rad", "sinusoid_rad", "sinusoid_cycles", "snr_db"):
        if not np.isfinite(getattr(args, name)):
            raise InputError("must be a finite number", field="--" + name.replace("_", "-"))
    if args.seed < 0:
        raise InputError("seed must be ≥ 0", field="--seed", value=args.seed)
    geom = SarGeometry.from_scenario(scenario, window=args.window)
    nyquist = geom.n_pulses / 2.0  # cycles over the aperture that its pulses can still sample
    if abs(args.sinusoid_cycles) > nyquist:
        raise InputError(f"the {geom.n_pulses} pulses of the aperture cannot sample this sinusoid "
                         "(it would alias to a slower one)", field="--sinusoid-cycles",
                         value=args.sinusoid_cycles, expected=f"|cycles| ≤ {nyquist:g}")
    scene = Scene.build(**Scene.default(geom).model_dump(exclude={"snr_db"}), snr_db=args.snr_db)
    def injected(g: SarGeometry) -> np.ndarray:  # the error on g's pulses
        return smooth_phase_error(normalised_time(g), quadratic_rad=args.quadratic_rad, cubic_rad=args.cubic_rad,
                                  sinusoid_rad=args.sinusoid_rad, sinusoid_cycles=args.sinusoid_cycles)

    psi = check_phase_sampled(injected(geom), "--quadratic-rad, --cubic-rad, --sinusoid-rad")
    # the injected error moves a response by (dψ/du)/π azimuth cells (a phase slope of σ rad per
    # pulse shifts it σN/2π cells, u = −1 … 1 over the N pulses): the image gets that room, as the
    # Monte Carlo's defocus_room_cells, so a large error defocuses inside it instead of aliasing
    slope = 2 * abs(args.quadratic_rad) + 3 * abs(args.cubic_rad) + abs(args.sinusoid_rad * args.sinusoid_cycles) * math.pi
    room = slope / math.pi
    if room > 1024:
        raise InputError(f"the injected error spreads a response over ±{room:.0f} azimuth cells",
                         field="--quadratic-rad, --cubic-rad, --sinusoid-rad",
                         expected="an error whose slope 2|q| + 3|c| + π|s·N| stays below 1024π rad "
                                  "(±1024 cells of defocus)")
    if room > IMAGE_MARGIN_CELLS:  # the image's own margin already holds a smaller defocus
        geom = SarGeometry.from_scenario(scenario, window=args.window, defocus_room_cells=room)
        psi = injected(geom)
    trial = run_injected_phase_trial(geom, scene, psi, np.random.default_rng(args.seed), method=args.method,
                                     kernel=args.kernel)
    if args.json:
        write_json(trial.to_dict(), args.json)
        return 0
    g = geom.to_dict()
    print(f"{scenario.name}: {g['n_pulses']} pulses × {g['n_range']} range bins, PRF {g['prf_hz']:.4g} Hz, "
          f"T = {g['aperture_time_s']:.3g} s, cells {g['azimuth_cell_m']:.3g} m × {g['range_cell_m']:.3g} m, "
          f"window {g['window_azimuth']}")
    if geom.squint_note:
        print(geom.squint_note)
    print(f"injected phase error: {args.quadratic_rad:g} u² + {args.cubic_rad:g} u³ + "
          f"{args.sinusoid_rad:g} sin({args.sinusoid_cycles:g}πu) rad along the line of sight")
    with np.printoptions(precision=3, suppress=True):
        print()
        print(trial.summary(_COLS))
    return 0
