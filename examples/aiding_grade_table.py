"""Cheapest passing IMU for the airborne X-band preset: unaided vs GNSS-aided vs RTS-smoothed.

Runs the Monte Carlo verdict (budget.mc) for catalog parts spanning the grades, with the
scenario's aiding set three ways, and prints P(pass after PGA) per part and the cheapest part
(lowest grade; no catalog prices are published) with P(pass) ≥ the target.

Usage: python examples/aiding_grade_table.py [--trials 64] [--seed 1] [--target 0.9]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from budget.catalog.io import get_part  # noqa: E402
from budget.mc.sweep import cheapest_passing, sweep  # noqa: E402
from budget.presets import get_preset  # noqa: E402
from budget.scenario import Scenario  # noqa: E402

PARTS = ("MPU-6050", "ADIS16405", "ADIS16465-1", "STIM300", "HG1700AG58", "HG9900")
GNSS = {"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02}  # RTK-grade position fixes


def configs() -> dict[str, Scenario]:
    base = get_preset("airborne_xband").model_dump()
    return {
        "unaided": Scenario.model_validate(base | {"name": "unaided"}),
        "gnss_kf": Scenario.model_validate(base | {"name": "gnss_kf", "aiding": [GNSS]}),
        "gnss_rts": Scenario.model_validate(base | {"name": "gnss_rts", "aiding": [GNSS],
                                                    "aiding_smoother": "rts"}),
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=64)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--target", type=float, default=0.9)
    args = ap.parse_args()
    parts = [get_part(p) for p in PARTS]
    table = sweep(parts, list(configs().values()), args.trials, args.seed)
    wide = table.pivot(index="part_id", columns="scenario", values="p_pass_after").loc[list(PARTS)]
    print(f"P(pass after PGA), airborne_xband, {args.trials} trials, seed {args.seed}")
    print(wide[list(configs())].to_string(float_format=lambda v: f"{v:.2f}"))
    print(f"\ncheapest part with P(pass) ≥ {args.target}:")
    print(cheapest_passing(table, args.target).to_string(index=False))


if __name__ == "__main__":
    main()
