"""Benchmark: the vectorised check of 1,000 parts × 1,000 scenarios (target: well under 1 s).

Prints the wall time of ``check_arrays`` (bounds for every scenario, margins of every part on
every parameter, verdict and minimum margin) and the size of the margin array.
"""

from __future__ import annotations

import time

import numpy as np

from budget.check import PARAM_NAMES, check_arrays


def main() -> None:
    rng = np.random.default_rng(0)
    n_parts, n_scen = 1000, 1000
    # SI specs spread over the grades (log-uniform), some unspecified
    lo = np.array([1e-7, 1e-7, 1e-5, 1e-5, 1e-6, 1e-9, 1e-5, 1e-7])
    hi = np.array([1e-1, 1e-1, 1e-2, 1e-2, 1e-2, 1e-3, 1e-2, 1e-3])
    specs = np.exp(rng.uniform(np.log(lo), np.log(hi), size=(n_parts, len(PARAM_NAMES))))
    specs[rng.random(specs.shape) < 0.1] = np.nan
    tc = rng.uniform(0.1, 100, n_scen)
    dr = rng.uniform(0.05, 3, n_scen)
    check_arrays(specs[:10], tc[:10], dr[:10])  # warm-up
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        ok, mm = check_arrays(specs, tc, dr)
        best = min(best, time.perf_counter() - t0)
    print(f"check 1000 parts x 1000 scenarios x {len(PARAM_NAMES)} parameters: "
          f"{best * 1e3:.1f} ms (best of 5); pass fraction {ok.mean():.3f}; "
          f"margin array {n_parts * n_scen * len(PARAM_NAMES) * 8 / 1e6:.0f} MB")


if __name__ == "__main__":
    main()
