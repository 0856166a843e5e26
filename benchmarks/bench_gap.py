"""Benchmark of the model-gap workflow: speed, detection rates and false-positive rate.

Target (issue 7): a one-hour, 100 Hz, six-channel log processed in under 60 s on the project's
2-core machine. Printed figures:

1. wall time of :func:`budget.gap.run_gap` on a synthetic 1 h log (base model + a sinusoid and
   a rate random walk hidden on two channels), and on the first hour of the real ADIS16405
   log when ``../shared/data`` is present;
2. detection matrix: for each vocabulary effect, obvious and near-limit magnitudes
   (``tests/test_gap_detection.py``), over ``--seeds`` seeds: how often the right effect on the
   right channel is named first, median parameter error and channel-gap ratio after/before;
3. false-positive rate: logs that follow the base model (``--fp-seeds`` seeds, 16 384 samples).

Run from the repository root: ``python3 benchmarks/bench_gap.py [--quick]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from budget.gap import log_from_arrays, run_gap  # noqa: E402
from budget.imu import simulate_static_log  # noqa: E402
from test_gap_detection import BASE, CASES, N_LOG, RATE, make_log  # noqa: E402

SHARED_LOG = ROOT.parent / "shared" / "data" / "logs" / "adis16405_static_1.csv.gz"


def timing() -> None:
    n = 360_000
    model = BASE.with_effect({"name": "sinusoid", "channel": "accel_x",
                              "params": {"frequency_hz": 2.2, "amplitude": 1e-3}})
    model = model.with_effect({"name": "rate_random_walk", "channel": "gyro_x", "params": {"K": 2e-5}})
    x = simulate_static_log(model, n, RATE, np.random.default_rng(1))
    t0 = time.perf_counter()
    rep = run_gap(log_from_arrays(x, RATE), BASE, seed=0)
    dt = time.perf_counter() - t0
    named = ", ".join(f"{s.name}@{s.channel}" for s in rep.steps) or "none"
    print(f"synthetic 1 h, 100 Hz, 6 channels: {dt:.1f} s (target < 60 s); named {named}; "
          f"gap {rep.gap_before:.3g} → {rep.gap_after:.3g}")
    if SHARED_LOG.is_file():
        t0 = time.perf_counter()
        rep = run_gap(SHARED_LOG, "ADIS16405", seed=0, max_rows=n)
        dt = time.perf_counter() - t0
        print(f"real ADIS16405 log, first hour (360 000 rows incl. reading): {dt:.1f} s; "
              f"{len(rep.steps)} effects; gap {rep.gap_before:.3g} → {rep.gap_after:.3g}")


def detection(seeds: int) -> None:
    print(f"\ndetection over {seeds} seeds, {N_LOG} samples per log "
          "(named-first rate, median |param error|, median channel-gap ratio after/before)")
    for effect, cases in CASES.items():
        for level, channel, params, _tol in cases:
            ok, errs, ratios, t_run = 0, [], [], 0.0
            for seed in range(seeds):
                t0 = time.perf_counter()
                rep = run_gap(make_log(effect, channel, params, N_LOG, 1000 + seed), BASE, seed=seed)
                t_run += time.perf_counter() - t0
                if rep.steps and (rep.steps[0].name, rep.steps[0].channel) == (effect, channel):
                    ok += 1
                    s = rep.steps[0]
                    errs.append(max(abs(s.params[k] - v) if k == "frequency_hz" else abs(s.params[k] / v - 1)
                                    for k, v in params.items()))
                    ratios.append(s.gap_after / s.gap_before)
            err = f"{np.median(errs):.2f}" if errs else "-"
            ratio = f"{np.median(ratios):.2f}" if ratios else "-"
            print(f"  {effect:24s} {level:7s} {channel:8s} named first {ok}/{seeds}  "
                  f"param err {err:>5s}  gap ratio {ratio:>5s}  ({t_run / seeds:.1f} s/run)")


def false_positives(seeds: int) -> None:
    named, over = 0, 0
    for seed in range(seeds):
        rep = run_gap(make_log(None, None, None, 16_384, 5000 + seed), BASE, seed=seed)
        named += bool(rep.steps)
        over += sum(c.gap_before > rep.null_before.channel_threshold(ch) for ch, c in rep.channels.items())
    print(f"\nfalse positives: effects named on {named}/{seeds} model-following logs "
          f"({named / seeds:.1%}); channels above threshold {over}/{6 * seeds}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="2 seeds, 10 FP seeds, no timing run")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--fp-seeds", type=int, default=60)
    args = ap.parse_args()
    if args.quick:
        args.seeds, args.fp_seeds = 2, 10
    else:
        timing()
    detection(args.seeds)
    false_positives(args.fp_seeds)


if __name__ == "__main__":
    main()
