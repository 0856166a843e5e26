"""``sar-budget focus``: form a ground image from recorded phase-history files (AFRL format),
autofocus it (PGA, the recorded solution, or none) and report what the data are (band, aperture,
closed-form resolutions beside the pixel spacing: :mod:`budget.sar.acquisition`), the per-pulse
phase estimate, entropy before/after and the rms difference from the recorded autofocus solution.

With ``--part ID`` (or ``--model M.json``): the part's verdict on the recorded scene
(:func:`budget.mc.real_scene.real_scene_verdict`: its motion error injected into the phase history
``--trials`` times, focused, PGA, judged; P(pass) with its Wilson interval)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..mc.real_scene import DEFAULT_EXTENT_M, DEFAULT_SPEED_M_S, RealSceneOptions
from ..sar.afrl import read_afrl
from ..sar.focus import FocusOptions
from ..sar.focus_pga import AUTOFOCUS_MODES, focus
from .common import add_catalog_option, part_or_model_from_args
from .output import add_json_option, write_json


def add_parser(sub) -> None:
    p = sub.add_parser("focus", help="focus recorded SAR phase-history files and autofocus the image",
                       description="Backproject recorded phase histories (several files are concatenated "
                                   "along the aperture) onto a ground grid, autofocus, and report the phase "
                                   "error per pulse (the correction applied is its negative), the image entropy "
                                   "before/after and the rms difference from the recorded autofocus solution "
                                   "beyond a linear term.")
    p.add_argument("files", nargs="+", metavar="FILE.mat", help="phase-history files, in aperture order")
    p.add_argument("--format", choices=("afrl",), default="afrl", help="file format (AFRL Gotcha .mat)")
    p.add_argument("--autofocus", choices=AUTOFOCUS_MODES, default="pga")
    p.add_argument("--kernel", choices=("ml", "lumv"), default="ml", help="PGA phase-gradient kernel")
    p.add_argument("--spacing-m", type=float, default=None, help="pixel spacing (default 0.25 m)")
    p.add_argument("--range-extent-m", type=float, default=None, help="ground-range size (default 100 m; 60 m with --part / --model)")
    p.add_argument("--azimuth-extent-m", type=float, default=None, help="cross-range size (default 100 m; 60 m with --part / --model)")
    p.add_argument("--range-centre-m", type=float, default=None, help="window centre in ground range (default 0)")
    p.add_argument("--azimuth-centre-m", type=float, default=None, help="window centre in cross range (default 0)")
    p.add_argument("--window", default=None, help="range and azimuth window: rect | taylor | taylor-35-4 (default)")
    p.add_argument("--workers", type=int, default=None, help="threads for backprojection (default 2)")
    p.add_argument("--inject", metavar="Q,C,S,N", default=None,
                   help="multiply a known error into the phase history first: Q u² + C u³ + S sin(Nπu) rad, "
                        "u from −1 to 1 over the pulses (a test of the autofocus on real clutter)")
    p.add_argument("--image", metavar="OUT.png", default=None,
                   help="write the image before | after side by side (40 dB, greyscale PNG)")
    v = p.add_argument_group("verdict of an IMU on this scene (--part or --model)")
    src = v.add_mutually_exclusive_group()
    src.add_argument("--part", metavar="ID", default=None,
                     help="catalog part: inject its motion error into the phase history per trial, focus, PGA, "
                          "and judge what PGA leaves (P(pass) with its 95 %% Wilson interval)")
    src.add_argument("--model", metavar="M.json", default=None, help="noise-model JSON/YAML instead of --part")
    add_catalog_option(v)
    v.add_argument("--trials", type=int, default=8, help="trials (default 8; ≈ 1.5 s each on the default patch)")
    v.add_argument("--seed", type=int, default=1, help="seed of the IMU draws (default 1)")
    v.add_argument("--speed-m-s", type=float, default=None,
                   help=f"platform speed, assumed: the files carry no pulse times (default {DEFAULT_SPEED_M_S:g} "
                        "m/s); sets the aperture time = track length / speed")
    v.add_argument("--imu-rate-hz", type=float, default=None, help="IMU sample rate (default 200 Hz)")
    add_json_option(p)
    p.set_defaults(func=run)


#: Fields of a focusing error that come from the files (not from an option): named with the files.
_DATA_FIELDS = ("antenna_m", "scene_range_m", "pulses", "samples", "frequency_hz")


def _injected(spec: str) -> tuple[float, float, float, float]:
    try:
        q, c, s, n = (float(x) for x in spec.split(","))
    except ValueError:
        raise InputError("expected four numbers", field="--inject", value=spec,
                         expected="Q,C,S,N in rad (and cycles for N), e.g. 4,2,1.5,1.5") from None
    if not all(np.isfinite([q, c, s, n])):
        raise InputError("must be finite", field="--inject", value=spec)
    return q, c, s, n


def _named_with_files(err: InputError, files) -> InputError:
    """A geometry or size the data cannot be imaged with: the error names the files it comes from."""
    if err.file is None and (err.field or "").startswith(_DATA_FIELDS):
        return err.rename_file(files[0] if len(files) == 1 else ", ".join(files))
    return err


def _verdict(args, ph, options: FocusOptions) -> int:
    """``--part`` / ``--model``: the part's verdict on the recorded scene (thin: the library judges)."""
    from ..mc.real_scene import real_scene_verdict
    if args.autofocus != "pga":
        raise InputError("the verdict judges what PGA leaves", field="--autofocus", value=args.autofocus,
                         expected="pga (the default) with --part / --model")
    if args.image:
        raise InputError("--image shows one focus, not a verdict's trials", field="--image",
                         expected="no --image with --part / --model")
    if args.trials is None or args.trials < 1:
        raise InputError("must be ≥ 1", field="--trials", value=args.trials, expected="a whole number of trials")
    if args.seed is None or args.seed < 0:
        raise InputError("must be ≥ 0", field="--seed", value=args.seed, expected="a whole number")
    try:
        opt = RealSceneOptions.build(platform_speed_m_s=args.speed_m_s, imu_rate_hz=args.imu_rate_hz, focus=options,
                                     pga_kernel=args.kernel)
    except InputError as err:  # name the option the user wrote
        names = {"platform_speed_m_s": "--speed-m-s", "imu_rate_hz": "--imu-rate-hz"}
        if err.field in names:
            raise InputError(err.reason, field=names[err.field], value=err.value,
                             expected=err.expected) from None
        raise
    model = part_or_model_from_args(args)
    try:
        verdict = real_scene_verdict(ph, model, args.trials, args.seed, opt)
    except InputError as err:
        raise _named_with_files(err, args.files) from None
    if args.json:
        write_json(verdict.to_dict(), args.json)
        return 0
    print(verdict.acquisition.summary())
    print(verdict.summary())
    return 0


def run(args) -> int:
    if args.image and not str(args.image).lower().endswith(".png"):
        # the file is a PNG whatever its name (out.txt held one)
        raise InputError("the image is written as PNG", field="--image", value=args.image,
                         expected="a file name ending in .png")
    verdict = bool(getattr(args, "part", None) or getattr(args, "model", None))
    extent = DEFAULT_EXTENT_M if verdict else None  # the verdict's smaller default patch: one image per trial
    options = FocusOptions.build(spacing_m=args.spacing_m,
                                 range_extent_m=args.range_extent_m if args.range_extent_m is not None else extent,
                                 azimuth_extent_m=(args.azimuth_extent_m if args.azimuth_extent_m is not None
                                                   else extent),
                                 range_centre_m=args.range_centre_m, azimuth_centre_m=args.azimuth_centre_m,
                                 range_window=args.window, azimuth_window=args.window, workers=args.workers)
    ph = read_afrl(args.files)
    if args.inject:
        ph = ph.with_smooth_phase_error(*_injected(args.inject))
    if verdict:
        return _verdict(args, ph, options)
    try:
        result = focus(ph, options, args.autofocus, kernel=args.kernel)
    except InputError as err:
        raise _named_with_files(err, args.files) from None
    if args.image:
        from ..plots.focus import write_before_after_png
        write_before_after_png(result, args.image)
    if args.json:
        write_json(result.to_dict(), args.json)
        return 0
    s, c = result.scalars(), result.comparison
    g = result.before.grid
    print(result.acquisition.summary())
    if (widths := _window_widths(options, result.acquisition)):
        print(widths)
    print(f"{ph.n_pulses} pulses × {ph.n_frequencies} frequencies from {len(args.files)} file(s); "
          f"image {g.v_m.size} × {g.u_m.size} at {g.spacing_m:g} m "
          f"({', '.join(f'{k} {v:.2f} s' for k, v in result.timings_s.items())})")
    print(f"autofocus {args.autofocus}: entropy {s['entropy_before']:.5g} → {s['entropy_after']:.5g}, "
          f"contrast {s['contrast_before']:.4g} → {s['contrast_after']:.4g}")
    if result.pga:
        print(f"PGA: {result.pga.get('reason')}; {result.pga.get('usable_lines')} usable lines")
    if "recorded_beyond_linear_rms_rad" in c:
        print(f"recorded solution beyond linear: {c['recorded_beyond_linear_rms_rad']:.3g} rad rms; "
              f"estimate {c['estimate_beyond_linear_rms_rad']:.3g} rad rms; difference {c['rms_diff_rad']:.3g} rad rms")
        if "rms_diff_slow_rad" in c:
            print(f"PGA's bandwidth {c['pga_bandwidth_cycles']:.3g} cycles/aperture: recorded within it "
                  f"{c['recorded_slow_rms_rad']:.3g} rad rms, above it {c['recorded_fast_rms_rad']:.3g} rad rms; "
                  f"estimate − recorded low-passed {c['rms_diff_slow_rad']:.3g} rad rms; the difference's part "
                  f"within the bandwidth {c['rms_diff_in_band_rad']:.3g} rad rms")
    known = c.get("known")
    if known:
        line = (f"against the known error ({known['reference']}), {known['recorded_beyond_linear_rms_rad']:.3g} rad "
                f"rms beyond linear: difference {known['rms_diff_rad']:.3g} rad rms")
        if "rms_diff_slow_rad" in known:
            line += (f"; estimate − known low-passed to PGA's bandwidth {known['rms_diff_slow_rad']:.3g} rad rms, "
                     f"the difference's part within the bandwidth {known['rms_diff_in_band_rad']:.3g} rad rms")
        print(line)
    for note in result.notes:
        print("note: " + note)
    return 0


def _window_widths(options, acq) -> str:
    """The closed-form resolutions c/(2B cos ψ) and λ/(2Δθ) are one cell of the band and the
    aperture; an image's 3 dB width is 0.886 cell unweighted and more with a window (Taylor
    −35 dB, n̄ = 4: 1.184 cells, :func:`budget.sar.windows.ideal_irf`): the widths the image has."""
    from ..sar.windows import Window, ideal_irf

    wr, wa = Window.parse(options.range_window), Window.parse(options.azimuth_window)
    fr, fa = ideal_irf(wr).width_3db_cells, ideal_irf(wa).width_3db_cells
    return (f"3 dB widths of this image ({wr.label} range, {wa.label} azimuth window): {fr:.4g} / {fa:.4g} of "
            f"those resolutions, {fr * acq.ground_range_resolution_m:.4g} m ground range, "
            f"{fa * acq.cross_range_resolution_m:.4g} m cross range")
