"""The analytic PGA-limited verdict beside the Monte Carlo's decision, for every catalog part on
every preset.

    python examples/check_vs_monte_carlo.py [--trials 64] [--seed 1] [--presets NAME ...] [--out table.csv]

For each part × preset: the check's PGA-limited verdict and margin (seed 004's bounds tightened by
what PGA cannot remove, the fast phase asked of 0.9 of apertures), its predicted share of
apertures within the fast-phase limit, and the Monte Carlo's P(pass after PGA) with its 95 %
Wilson interval and decision (lower bound ≥ 0.9, as ``cheapest_passing`` decides). A row agrees
when both say pass or both say fail; where they do not, the table says which side is stricter.
The two verdicts do not see the same part where the datasheet leaves terms empty: the check
judges the specified terms only, the Monte Carlo fills the empty ones from the grade (its
``unspecified_terms`` column lists them) — the usual reason for a Monte Carlo that fails a part
the check passes. So the check is also run on the part as the Monte Carlo simulates it (its empty
terms filled from the grade, ``resolve_unspecified``: columns ``*_as_simulated``), and agreement
is counted both ways.
"""

from __future__ import annotations

import argparse

import pandas as pd

import budget
from budget.catalog.fill import resolve_unspecified
from budget.mc.options import UNSPECIFIED_DEFAULT
from budget.sar.residual import DEFAULT_PASS_SHARE


def main(argv: list[str] | None = None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=budget.DEFAULT_TRIALS)
    ap.add_argument("--seed", type=int, default=budget.DEFAULT_SEED)
    ap.add_argument("--presets", nargs="+", default=None, help="default: every preset")
    ap.add_argument("--out", default=None, help="write the table as CSV")
    args = ap.parse_args(argv)

    from budget.mc.runner import check_run_counts
    from budget.presets import PRESETS, get_preset
    check_run_counts(args.trials, args.seed)  # before any work: a bad count is said at once
    presets = [get_preset(name).name for name in (args.presets or list(PRESETS))]
    check = budget.check_parts(None, presets).to_frame()
    check = check[check["pga_limited_verdict"] != "unknown"]
    ids = list(check["part_id"].unique())
    filled = [resolve_unspecified(p, UNSPECIFIED_DEFAULT).model for p in budget.load_parts(ids)]
    as_simulated = budget.check_parts(filled, presets).to_frame()[
        ["scenario", "part_id", "pga_limited_verdict", "pga_limited_min_margin"]].rename(
        columns={"pga_limited_verdict": "verdict_as_simulated", "pga_limited_min_margin": "margin_as_simulated"})
    check = check.merge(as_simulated, on=["scenario", "part_id"])
    table = budget.sweep(ids, presets, args.trials, args.seed)
    mc = table[["scenario", "part_id", "p_pass_after", "ci_after_lo", "ci_after_hi", "unspecified_terms"]]
    both = check[["scenario", "part_id", "grade", "pga_limited_verdict", "pga_limited_min_margin",
                  "verdict_as_simulated", "margin_as_simulated",
                  "fast_phase_p_within_limit"]].merge(mc, on=["scenario", "part_id"])
    both["mc_decision"] = (both["ci_after_lo"] >= DEFAULT_PASS_SHARE).map({True: "pass", False: "fail"})
    agree = both["mc_decision"] == both["pga_limited_verdict"]
    both["agreement"] = agree.map({True: "agree", False: ""})
    both.loc[~agree & (both["pga_limited_verdict"] == "pass"), "agreement"] = "Monte Carlo stricter"
    both.loc[~agree & (both["pga_limited_verdict"] == "fail"), "agreement"] = "check stricter"
    # where the point estimate and the lower bound straddle the target, the trials cannot decide
    undecided = (both["p_pass_after"] >= DEFAULT_PASS_SHARE) & (both["ci_after_lo"] < DEFAULT_PASS_SHARE)
    both.loc[~agree & undecided, "agreement"] += " (p̂ ≥ target: more trials would decide)"
    pd.set_option("display.width", 250)
    print(both.drop(columns=["unspecified_terms"]).to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print(f"\n{int(agree.sum())} of {len(both)} part × preset pairs agree ({args.trials} trials, seed {args.seed}); "
          + ", ".join(f"{k}: {v}" for k, v in both.loc[~agree, "agreement"].value_counts().items()))
    same = both["mc_decision"] == both["verdict_as_simulated"]
    lenient = ~same & (both["verdict_as_simulated"] == "pass")
    print(f"checked as simulated (empty terms filled from the grade): {int(same.sum())} of {len(both)} agree; "
          f"Monte Carlo stricter {int(lenient.sum())} ({int((lenient & undecided).sum())} of them with p̂ ≥ target), "
          f"check stricter {int((~same & ~lenient).sum())}")
    if args.out:
        both.to_csv(args.out, index=False)
    return both


if __name__ == "__main__":
    from budget.errors import InputError
    try:
        main()
    except InputError as err:  # a bad preset name or trial count: the error, not a traceback
        raise SystemExit(f"error: {err}") from None
