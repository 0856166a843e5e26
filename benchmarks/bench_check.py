"""Benchmark: the vectorised check of 1,000 parts × 1,000 scenarios (target: well under 1 s), and
the full check of the shipped catalog on every preset (target: under 2 s, a dashboard page).

Prints the wall time of ``check_arrays`` (bounds for every scenario, margins of every part on
every parameter, verdict and minimum margin) and the size of the margin array; then the wall
time of ``check_parts`` on the catalog × presets, which adds per part and scenario the PGA-limited
verdict: the bounds with the lever arm and the fast phase, and the per-aperture distribution of
what PGA cannot remove (Imhof's inversion, one or two evaluations per part × scenario).
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
    _catalog_on_presets()


def _catalog_on_presets() -> None:
    from budget.catalog.io import load_catalog
    from budget.check import check_parts
    from budget.presets import PRESETS, get_preset

    parts = list(load_catalog(None).values())
    scen = [get_preset(n) for n in PRESETS]
    check_parts(parts[:2], scen[:1])  # warm-up: the walks' eigenvalues are cached per process
    t0 = time.perf_counter()
    check_parts(parts, scen)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    check_parts(parts, scen)
    again = time.perf_counter() - t0
    print(f"check_parts, {len(parts)} catalog parts x {len(scen)} presets: {first:.2f} s "
          f"(again, eigenvalues cached: {again:.2f} s)")


if __name__ == "__main__":
    main()
