"""``sar-budget demo``: bounds and the check table for a preset scenario (the quick-start job)."""

from __future__ import annotations

from ..bounds import compute_bounds, fast_phase_limits
from ..catalog.io import load_catalog, load_grades
from ..check import check_parts
from ..recommend import recommend_grade
from ..presets import PRESETS, get_preset
from ..sar.windows import verdict_window


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="print bounds and the part check for a preset scenario")
    p.add_argument("--preset", choices=sorted(PRESETS), default="airborne_xband", help="preset scenario")
    p.set_defaults(func=run)


def run(args) -> int:
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
    print()
    print(recommend_grade([1, 10, 25, 50, 100], 0.1, grades).summary())
    return 0
