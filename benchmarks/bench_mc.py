"""Benchmark: Monte Carlo trials per second on the reference airborne X-band scenario (full chain
with PGA), memory per trial, and a streaming sweep through the Dask backend on a local cluster.

Both scenes are timed: the five noise-free points and the realistic scene (clutter −25 dB, SNR
30 dB, 16 scatterers; PGA on it, metrics on five clutter-free points; target ≥ 20 trials/s on 2
cores). Usage: ``python benchmarks/bench_mc.py [--trials N] [--sweep-trials M] [--no-sweep]``.
Prints figures only.
"""

from __future__ import annotations

import argparse
import os
import resource
import time
import tracemalloc

from budget.catalog.io import get_part
from budget.mc import McOptions, run_mc
from budget.mc.sweep import sweep
from budget.presets import get_preset


def rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=256)
    ap.add_argument("--sweep-trials", type=int, default=512)
    ap.add_argument("--no-sweep", action="store_true")
    args = ap.parse_args()
    scen, part = get_preset("airborne_xband"), get_part("STIM300")
    for scene in ("points", "realistic"):
        opt = McOptions(scene=scene)
        t0 = time.perf_counter()
        run_mc(scen, part, 64, 0, options=opt)  # warm-up (geometry, echoes once per setup, imports)
        print(f"[{scene}] setup + first 64 trials: {time.perf_counter() - t0:.2f} s")
        for workers in (1, 2):
            t0, c0 = time.perf_counter(), time.process_time()
            r = run_mc(scen, part, args.trials, 1, workers=workers, options=opt)
            dt, dc = time.perf_counter() - t0, time.process_time() - c0
            cpu = f"; {args.trials / dc:.1f} trials per CPU-second of this process" if workers == 1 else ""
            print(f"[{scene}] airborne_xband, STIM300, {args.trials} trials, {workers} worker(s): {dt:.2f} s = "
                  f"{args.trials / dt:.1f} trials/s wall{cpu} (P(pass after PGA) = {r.p_pass_after:.3f}); "
                  f"load average {os.getloadavg()[0]:.1f}")
        tracemalloc.start()
        run_mc(scen, part, 64, 2, options=opt.model_copy(update={"keep_trial_metrics": False}))
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        print(f"[{scene}] peak Python-heap memory of a 64-trial chunk: {peak / 1e6:.1f} MB = "
              f"{peak / 64 / 1e6:.2f} MB per trial (chunk-bounded: memory does not grow with trials); "
              f"process max RSS {rss_mb():.0f} MB")
    if args.no_sweep:
        return

    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        print("dask[distributed] not installed: sweep benchmark skipped")
        return
    parts = [get_part(p) for p in ("ADIS16405", "ADIS16465-1", "STIM300", "HG1700AG58", "HG4930")]
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        rss0 = rss_mb()
        t0 = time.perf_counter()
        table = sweep(parts, [get_preset("automotive_77ghz")], args.sweep_trials, 3, backend="dask",
                      client=client, workers=2)
        dt = time.perf_counter() - t0
    n = args.sweep_trials * len(parts)
    print(f"sweep through Dask LocalCluster (2 workers): {len(parts)} parts × {args.sweep_trials} trials = {n} "
          f"trials in {dt:.1f} s ({n / dt:.1f} trials/s); client max RSS {rss0:.0f} → {rss_mb():.0f} MB")
    print(table[["part_id", "p_pass_after", "ci_after_lo", "ci_after_hi"]].to_string(index=False))


if __name__ == "__main__":
    main()
