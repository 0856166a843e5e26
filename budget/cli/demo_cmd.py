"""``sar-budget demo``: bounds and the check table for a preset scenario (the quick-start job)."""

from __future__ import annotations

from ..presets import PRESETS, get_preset


#: The aperture times and range resolution of seed 004's grade conclusion (its table, printed for
#: comparison under the preset's own grades).
SEED004_TC_S = (1.0, 10.0, 25.0, 50.0, 100.0)
SEED004_RANGE_RESOLUTION_M = 0.1


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="print bounds and the part check for a preset scenario")
    p.add_argument("--preset", choices=sorted(PRESETS), default="airborne_xband", help="preset scenario")
    p.set_defaults(func=run)


def run(args) -> int:
    # the computation's modules when it runs, not for --help or an argument error (budget.cli.main)
    from ..bounds import compute_bounds, fast_phase_limits
    from ..catalog.io import load_catalog, load_grades
    from ..check import check_parts
    from ..recommend import lowest_sufficient_grades, recommend_grade
    from ..sar.windows import verdict_window

    s = get_preset(args.preset)
    print(f"Scenario {s.name}: {s.medium}, f0 = {s.carrier_frequency_hz:.4g} Hz, "
          f"λ = {s.wavelength_m:.4g} m, R = {s.slant_range_m:g} m, V = {s.platform_speed_m_s:g} m/s, "
          f"δℓ = {s.azimuth_resolution_m:g} m, δr = {s.range_resolution_m:g} m")
    print(f"Aperture time Tc = {s.tc_s:.3f} s (seed 004 (5)), aperture length {s.aperture_length_m:.1f} m\n")
    for mode in ("paper", "derived", "no-autofocus"):
        print(compute_bounds([s.tc_s], s.range_resolution_m, mode, wavelength_m=s.wavelength_m).summary())
        print()
    print(fast_phase_limits(s.wavelength_m, aperture_window=verdict_window(s).kind).summary(), "\n")
    res = check_parts(load_catalog().values(), s)
    print("Catalog check (paper bounds; margin = bound / spec):")
    print(res.summary())
    flags = [r for r in res.to_dict()["scenarios"][0]["parts"] if r.get("flag")]
    if flags:
        print("\nFlagged — seed 004's bounds pass but what PGA cannot remove (fast phase, lever arm) "
              "fails; the Monte Carlo (`sar-budget mc`) simulates it:")
        for r in flags:
            print(f"  ! {r['part_id']}: {r['flag_reason']}")
    grades = list(load_grades().values())
    # this preset's own grades, from the call `sar-budget check` makes (lowest_sufficient_grades)
    own = lowest_sufficient_grades(s, "paper", grades)
    print()
    print(f"lowest sufficient grade for {s.name} (typical, bias + noise, paper bounds): {own.text('paper')}")
    print(f"lowest sufficient grade for {s.name} (typical, bias + noise, PGA-limited bounds): "
          f"{own.text('pga_limited')}")
    print()
    print(f"For comparison, seed 004's table (δr = 0.1 m, Tc = 1 … 100 s; not {s.name}'s geometry):")
    print(recommend_grade(list(SEED004_TC_S), SEED004_RANGE_RESOLUTION_M, grades).summary())
    return 0
