"""Seed 001 (4): PRF slaved to forward speed (f_PR = k·V) versus a fixed PRF.

Full-size run of :mod:`budget.seeds.prf_slaving` on the ``missile_borne`` preset: the
missile accelerates (2 m/s²) and its speed oscillates (±0.5 m/s at 1 Hz). Prints the
along-track sampling non-uniformity and the point-target metrics for targets at −1, 0, +1
aperture lengths from the reference time.

    python3 examples/seed001_prf_slaving.py [--trials 50] [--seed 4] [--accel 2.0]
"""

from __future__ import annotations

import numpy as np

from _seed_run import seed_run_parser  # puts the checkout on sys.path
from budget.seeds.prf_slaving import PrfParams, run_prf_slaving


def main() -> None:
    ap = seed_run_parser(__doc__, trials=50, seed=4)
    ap.add_argument("--accel", type=float, default=2.0, help="along-track acceleration, m/s²")
    args = ap.parse_args()
    res = run_prf_slaving(PrfParams(trials=args.trials, accel_m_s2=args.accel),
                          rng=np.random.default_rng(args.seed))
    print("seed 001 (4): PRF slaving, missile_borne preset")
    print(res.table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    print(res.summary())


if __name__ == "__main__":
    main()
