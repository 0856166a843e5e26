"""Benchmark of the noise lab against its peers, in one run.

Targets:
* five-model ARMA selection on 10⁵ samples ≥ 100× faster than a statsmodels
  ``ARIMA(...).fit()`` sweep, parameters within 2 %;
* overlapping Allan deviation of 10⁷ samples no slower than ``allantools.oadev``;
* Kalman filtering of 10⁶ samples ≥ 30× faster than filterpy's ``KalmanFilter`` loop.

filterpy is a benchmark-only peer, never a project dependency: run this script with a Python
that has it, e.g. ``python3 -m venv --system-site-packages /tmp/bench && /tmp/bench/bin/pip
install filterpy && /tmp/bench/bin/python benchmarks/bench_noise.py`` (without it that part is
skipped). Run from the repository root. ``--quick`` uses 10× smaller sizes.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from budget.noise import ArmaKalman, allan_deviation, select_arma  # noqa: E402
from budget.noise.arma import DEFAULT_ORDERS  # noqa: E402
from budget.noise.synth import simulate_arma  # noqa: E402

PHI, THETA, S2 = [0.8397, 0.1288], [0.9596], 0.007778


def best_of(fn, repeat: int):
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def bench_arma(n: int) -> None:
    from statsmodels.tsa.arima.model import ARIMA
    x = simulate_arma(PHI, THETA, S2, n, np.random.default_rng(0))
    x = x - x.mean()
    ours_t, sel = best_of(lambda: select_arma(x, demean=False), 3)

    def sweep():
        out = []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for p, q in DEFAULT_ORDERS:
                out.append(ARIMA(x, order=(p, 0, q), trend="n").fit().params)
        return out
    ref_t, ref = best_of(sweep, 1)
    worst = 0.0
    for fit, params in zip(sel.candidates, ref):
        mine = np.r_[fit.phi, fit.theta, fit.sigma2]
        worst = max(worst, float(np.max(np.abs(mine / params - 1))))
    print(f"ARMA selection, 5 models, n = {n:.0e}: ours {ours_t * 1e3:.0f} ms (best of 3), "
          f"statsmodels ARIMA sweep {ref_t:.2f} s → {ref_t / ours_t:.0f}× "
          f"(target ≥ 100×); max relative parameter difference {100 * worst:.3f} % (target ≤ 2 %); "
          f"selected {sel.selected.name}")


def bench_allan(n: int) -> None:
    import allantools
    y = np.random.default_rng(1).normal(size=n)
    ours_t, r = best_of(lambda: allan_deviation(y, 100.0), 3)
    ref_t, ref = best_of(lambda: allantools.oadev(y, rate=100.0, data_type="freq", taus="octave"), 3)
    dev = float(np.max(np.abs(r.adev / ref[1] - 1)))
    print(f"Allan deviation, octave τ, n = {n:.0e}: ours {ours_t:.2f} s, allantools.oadev "
          f"{ref_t:.2f} s → {ref_t / ours_t:.2f}× (target ≥ 1×); max relative difference {dev:.1e}; "
          f"ours includes EDF and χ² intervals")


def bench_kalman(n: int) -> None:
    x = simulate_arma(PHI, THETA, S2, n, np.random.default_rng(2))
    from budget.noise.arma import ArmaFit
    fit = ArmaFit(2, 1, np.array(PHI), np.array(THETA), S2, n, "paper", float(np.var(x)), np.zeros(3))
    ours_t, res = best_of(lambda: ArmaKalman(fit).filter(x, center=False), 3)
    try:
        from filterpy.kalman import KalmanFilter
    except ImportError:
        print(f"Kalman filter, n = {n:.0e}: ours {ours_t * 1e3:.0f} ms; filterpy not installed — "
              "peer comparison skipped (see the module docstring)")
        return
    kf = ArmaKalman(fit)
    ref = KalmanFilter(dim_x=kf.n_states, dim_z=1)
    ref.F, ref.H, ref.Q = kf.F.copy(), kf.H[None, :].copy(), kf.Q.copy()
    ref.R, ref.P, ref.x = np.array([[kf.R]]), np.eye(kf.n_states), np.zeros((kf.n_states, 1))
    out = np.empty(n)
    t0 = time.perf_counter()
    for k, z in enumerate(x):
        ref.predict()
        ref.update(z)
        out[k] = ref.x[0, 0]
    ref_t = time.perf_counter() - t0
    dev = float(np.max(np.abs(out - res.signal)) / np.std(x))
    print(f"Kalman filter ARMA(2,1), n = {n:.0e}: ours {ours_t * 1e3:.0f} ms (best of 3), filterpy "
          f"loop {ref_t:.1f} s → {ref_t / ours_t:.0f}× (target ≥ 30×); max difference "
          f"{dev:.1e} of the signal σ (filterpy updates P in Joseph form too)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="10× smaller sizes")
    scale = 10 if ap.parse_args().quick else 1
    bench_arma(100_000 // scale)
    bench_allan(10_000_000 // scale)
    bench_kalman(1_000_000 // scale)


if __name__ == "__main__":
    main()
