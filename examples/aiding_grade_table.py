"""P(pass after PGA) unaided and GNSS-aided in every correction mode, per part and scenario.

Runs the Monte Carlo verdict (budget.mc) for catalog parts on the presets, with the scenario's
aiding section set five ways — unaided, then GNSS (10 Hz, σ = 2 cm, 60 s warm-up) in the modes
realtime, frozen, feedforward and smoothed — and prints P(pass after PGA) with its 95 % Wilson
interval, and the cheapest part (lowest grade; no catalog prices are published) with P(pass)
≥ the target per configuration.

Usage: python examples/aiding_grade_table.py [--trials 64] [--seed 1] [--target 0.9]
       [--preset airborne_xband automotive_77ghz] [--part STIM300 ADIS16465-1 HG1700AG58]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from budget.aiding_spec import CORRECTION_MODES  # noqa: E402
from budget.catalog.io import get_part  # noqa: E402
from budget.mc.sweep import cheapest_passing, sweep  # noqa: E402
from budget.presets import get_preset  # noqa: E402
from budget.scenario import Scenario  # noqa: E402

PARTS = ("MPU-6050", "ADIS16405", "ADIS16465-1", "STIM300", "HG1700AG58", "HG9900")
GNSS = {"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02}  # RTK-grade position fixes


def configs(preset: str) -> dict[str, Scenario]:
    """Unaided and GNSS-aided in each correction mode (scenario names carry the mode)."""
    base = get_preset(preset).model_dump()
    out = {"unaided": Scenario.model_validate(base | {"name": f"{preset}/unaided"})}
    for mode in CORRECTION_MODES:
        out[mode] = Scenario.model_validate(base | {"name": f"{preset}/{mode}", "aiding": [GNSS],
                                                    "aiding_mode": mode})
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=64)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--target", type=float, default=0.9)
    ap.add_argument("--preset", nargs="+", default=["airborne_xband"])
    ap.add_argument("--part", nargs="+", default=list(PARTS))
    args = ap.parse_args()
    parts = [get_part(p) for p in args.part]
    for preset in args.preset:
        cfg = configs(preset)
        table = sweep(parts, list(cfg.values()), args.trials, args.seed)
        table["config"] = table["scenario"].str.split("/").str[1]
        table["cell"] = [f"{p:.2f} [{lo:.2f}, {hi:.2f}]" for p, lo, hi in
                         zip(table.p_pass_after, table.ci_after_lo, table.ci_after_hi)]
        wide = table.pivot(index="part_id", columns="config", values="cell").loc[args.part]
        print(f"\nP(pass after PGA) [95 % Wilson], {preset}, {args.trials} trials, seed {args.seed}, "
              f"GNSS 10 Hz σ = 2 cm, 60 s warm-up")
        print(wide[list(cfg)].to_string())
        print(f"cheapest part with P(pass) ≥ {args.target}:")
        print(cheapest_passing(table, args.target)[["scenario", "part_id", "grade", "p_pass_after"]]
              .to_string(index=False))


if __name__ == "__main__":
    main()
