"""``sar-budget sar``: image the default scene of a scenario with an injected smooth phase error,
then autofocus it, printing the impulse-response metrics before and after PGA."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..sar import (Acceptance, SarGeometry, Scene, evaluate, form_image, los_offset_for_phase, measure_targets,
                   pga, phase_on_bins, residual_phase_rad, residual_rms_rad, simulate_echoes,
                   smooth_phase_error)
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
    scenario = scenario_from_args(args, default_preset="airborne_xband")
    for name in ("quadratic_rad", "cubic_rad", "sinusoid_rad", "sinusoid_cycles", "snr_db"):
        if not np.isfinite(getattr(args, name)):
            raise InputError("must be a finite number", field="--" + name.replace("_", "-"))
    if args.seed < 0:
        raise InputError("seed must be ≥ 0", field="--seed", value=args.seed)
    geom = SarGeometry.from_scenario(scenario, window=args.window)
    scene = Scene.build(**Scene.default(geom).model_dump(exclude={"snr_db"}), snr_db=args.snr_db)
    u = 2.0 * geom.pulse_times_s / geom.aperture_time_s
    psi = smooth_phase_error(u, quadratic_rad=args.quadratic_rad, cubic_rad=args.cubic_rad,
                             sinusoid_rad=args.sinusoid_rad, sinusoid_cycles=args.sinusoid_cycles)
    offset = los_offset_for_phase(geom, psi)
    data = simulate_echoes(geom, scene, offset, np.random.default_rng(args.seed))
    image = form_image(geom, data, None, method=args.method)
    before = measure_targets(image, geom, scene)
    result = pga(image.data, kernel=args.kernel)
    after = measure_targets(image.with_data(result.image), geom, scene)
    truth = phase_on_bins(image, geom, residual_phase_rad(geom, offset))
    mask = image.aperture_mask() & result.estimated_bins
    resid = residual_rms_rad(result.phase_error_rad, truth, mask) if result.converged else float("nan")
    acc = Acceptance()
    ev_before, ev_after = evaluate(before, acc), evaluate(after, acc)
    if args.json:
        write_json({"geometry": geom.summary(), "pga": result.summary(), "residual_rms_rad": resid,
                    "before": before.to_frame().reset_index().to_dict(orient="records"),
                    "after": after.to_frame().reset_index().to_dict(orient="records"),
                    "passed_before": ev_before.passed, "passed_after": ev_after.passed}, args.json)
        return 0
    g = geom.summary()
    print(f"{scenario.name}: {g['n_pulses']} pulses × {g['n_range']} range bins, PRF {g['prf_hz']:.4g} Hz, "
          f"T = {g['aperture_time_s']:.3g} s, cells {g['azimuth_cell_m']:.3g} m × {g['range_cell_m']:.3g} m, "
          f"window {g['window_azimuth']}")
    print(f"injected phase error: {args.quadratic_rad:g} u² + {args.cubic_rad:g} u³ + "
          f"{args.sinusoid_rad:g} sin({args.sinusoid_cycles:g}πu) rad along the line of sight")
    with np.printoptions(precision=3, suppress=True):
        print("\nbefore PGA:")
        print(before.to_frame()[_COLS].round(3).to_string())
        print(f"acceptance: {'PASS' if ev_before.passed else 'FAIL'} ({len(ev_before.reasons)} failed checks)")
        print(f"\nPGA ({args.kernel}): {result.reason}; {result.usable_lines} range lines; "
              f"residual vs truth {resid:.3g} rad rms")
        print("\nafter PGA:")
        print(after.to_frame()[_COLS].round(3).to_string())
        print(f"acceptance: {'PASS' if ev_after.passed else 'FAIL'} ({len(ev_after.reasons)} failed checks)")
        for r in ev_after.reasons[:10]:
            print("  " + r)
    return 0
