"""Benchmark: Monte Carlo trials per second on the reference airborne X-band scenario (STIM300,
full chain with PGA), its FFT-bound rate, memory against the number of trials, and a streaming
sweep through the Dask backend on a local cluster.

Rates. Both scenes are timed (the realistic scene, the verdict's default: clutter −25 dB, SNR
30 dB, 16 scatterers, PGA on it, metrics on five clutter-free points; the five noise-free points), with
1 and 2 worker processes: wall-clock trials/s, and trials per CPU-second of all processes (parent
and workers, ``time.process_time`` and ``RUSAGE_CHILDREN``), which a loaded machine does not
distort. Targets on 2 cores: ≥ 60 trials/s and ≥ 20 trials/s (realistic), on the default scene. The load average
is printed beside every figure.

FFT-bound rate (how fast the chain would run if it did nothing but its FFTs). Definition: one
64-trial chunk of the chain is run with every FFT recorded where it arrives — scipy's pocketfft
binding (c2c, r2c, c2r: what ``scipy.fft``'s functions call, and what PGA's line transforms call
directly) and ``numpy.fft``'s functions — with function, array shape and dtype, axes, length —
so the list is exactly what the chain needs: the motion engine's noise synthesis, image formation
(batched as the chain batches it), PGA's iterations as many times as PGA really iterated on these
trials, the phase corrections and the metric cuts' 16× upsampling. The recorded calls are then
replayed on arrays of the same shapes, timed alone (CPU time of this one process, one thread, the
same SciPy/NumPy transforms); FFT-bound rate per core = trials / replay CPU seconds, and on
``w`` cores w times that (the chain's workers are independent processes). The ratio printed is
the measured rate ÷ the FFT-bound rate on the same number of cores, wall-clock and CPU-based.

Memory: the default scene run serially in a fresh process for 64, 256 and 1024 trials: peak
traced Python/NumPy heap (``tracemalloc``) and peak RSS; flat means chunk-bounded.

Usage: ``python benchmarks/bench_mc.py [--trials N] [--sweep-trials M] [--no-sweep] [--no-memory]``.
Prints figures only.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import tracemalloc

import numpy as np
import numpy.fft

from budget.catalog.fill import resolve_unspecified
from budget.catalog.io import get_part
from budget.mc import McOptions, run_mc
from budget.mc.chain import ChainSetup, chain_plan, run_chunk
from budget.mc.runner import single_threaded_blas
from budget.presets import get_preset

_FFT_NAMES = ("fft", "ifft", "fft2", "ifft2", "fftn", "ifftn", "rfft", "irfft")


def rss_mb() -> float:
    """Peak RSS of this process (MB): VmHWM of /proc/self/status (per address space, so a child
    started by exec does not inherit its parent's peak, as ru_maxrss does), else ru_maxrss."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def cpu_s() -> float:
    """CPU seconds of this process and of its reaped children (the pool's workers)."""
    ch = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + ch.ru_utime + ch.ru_stime


def load() -> str:
    return "load average {:.1f}/{:.1f}/{:.1f}".format(*os.getloadavg())


def time_run(scen, part, opt, trials: int, workers: int) -> dict:
    l0 = os.getloadavg()[0]
    t0, c0 = time.perf_counter(), cpu_s()
    r = run_mc(scen, part, trials, 1, workers=workers, options=opt)
    dt, dc = time.perf_counter() - t0, cpu_s() - c0
    return {"wall_rate": trials / dt, "cpu_rate": trials / dc, "wall_s": dt, "cpu_s": dc, "p": r.p_pass_after,
            "load": (l0 + os.getloadavg()[0]) / 2.0}


def record_ffts(scen, part, opt, trials: int = 64) -> list[tuple]:
    """Every FFT of one chunk of ``trials`` trials: (function, array shape, dtype, arguments).

    Recorded where every transform of the chain arrives, whichever way it was called: scipy's
    pocketfft binding (``c2c``, ``r2c``, ``c2r``; what ``scipy.fft``'s public functions call, and
    what PGA's line transforms call directly, without the dispatch layers) and NumPy's public FFT
    functions (their own pocketfft). Real-to-real transforms (DCTs) are not counted."""
    import budget.sar.pga_lines as pga_lines
    from scipy.fft._pocketfft import pypocketfft as pfft

    calls = []
    saved = []

    def wrap(owner, name, binding: bool):
        orig = getattr(owner, name)
        if orig is None:
            return
        saved.append((owner, name, orig))

        def wrapped(x, *args, _orig=orig, **kw):
            a = np.asarray(x)
            if binding:  # (axes, forward, norm, out, workers) or, for c2r, (axes, n, forward, …):
                # replayed into a new array (out=None) on one thread (workers=1)
                rec = tuple(None if isinstance(v, np.ndarray) else v for v in args[:-1]) + (1,)
                calls.append((_orig, a.shape, a.dtype, rec, {}))
            else:
                calls.append((_orig, a.shape, a.dtype, args, {k: v for k, v in kw.items() if k != "overwrite_x"}))
            return _orig(x, *args, **kw)

        setattr(owner, name, wrapped)

    for name in ("c2c", "r2c", "c2r"):
        wrap(pfft, name, True)
    wrap(pga_lines, "_c2c", True)
    for name in _FFT_NAMES:
        wrap(numpy.fft, name, False)
    try:
        setup = ChainSetup.build(scen, opt)
        chain_plan(setup)
        calls.clear()  # the setup (echoes, plans) is built once per process, not per trial
        model = resolve_unspecified(part, opt.unspecified).model
        with single_threaded_blas():
            run_chunk(setup, model, 1, 0, trials)
    finally:
        for owner, name, orig in saved:
            setattr(owner, name, orig)
    return calls


def replay_cpu_s(calls: list[tuple], repeats: int = 3) -> float:
    """CPU seconds of the recorded FFT calls alone (best of ``repeats``), on arrays of the recorded
    shapes and dtypes, one thread, results in new arrays."""
    rng = np.random.default_rng(0)
    arrays = {}
    for _, shape, dtype, _, _ in calls:
        key = (shape, np.dtype(dtype).str)
        if key not in arrays:
            a = rng.standard_normal(shape)
            arrays[key] = (a + 1j * rng.standard_normal(shape)).astype(dtype) if np.iscomplexobj(np.empty(0, dtype)) \
                else a.astype(dtype)

    jobs = [(f, arrays[(shape, np.dtype(dtype).str)], args, kw) for f, shape, dtype, args, kw in calls]
    best = float("inf")
    with single_threaded_blas():
        for _ in range(repeats):
            c0 = time.process_time()
            for f, x, args, kw in jobs:
                f(x, *args, **kw)
            best = min(best, time.process_time() - c0)
    return best


def memory_run(trials: int) -> None:
    """Child mode: one serial run of ``trials`` trials on the default scene; prints JSON."""
    scen, part = get_preset("airborne_xband"), get_part("STIM300")
    rss0 = rss_mb()
    tracemalloc.start()
    run_mc(scen, part, trials, 2)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(json.dumps({"trials": trials, "traced_peak_mb": peak / 1e6, "max_rss_mb": rss_mb(), "rss_before_mb": rss0}))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=256)
    ap.add_argument("--sweep-trials", type=int, default=512)
    ap.add_argument("--no-sweep", action="store_true")
    ap.add_argument("--no-memory", action="store_true")
    ap.add_argument("--memory-run", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.memory_run:
        memory_run(args.memory_run)
        return
    scen, part = get_preset("airborne_xband"), get_part("STIM300")
    print(f"airborne_xband, STIM300, {args.trials} trials per figure; {os.cpu_count()} CPUs; {load()}")
    for scene in ("realistic", "points"):  # the default scene first
        opt = McOptions(scene=scene)
        t0 = time.perf_counter()
        run_mc(scen, part, 64, 0, options=opt)  # warm-up (geometry, echoes once per setup, imports)
        print(f"[{scene}] setup + first 64 trials: {time.perf_counter() - t0:.2f} s")
        rates = {}
        for workers in (1, 2):
            r = rates[workers] = time_run(scen, part, opt, args.trials, workers)
            print(f"[{scene}] {workers} worker(s): {r['wall_s']:.2f} s = {r['wall_rate']:.1f} trials/s wall; "
                  f"{r['cpu_rate']:.1f} trials per CPU-second (all processes); P(pass after PGA) = {r['p']:.3f}; "
                  f"load average {r['load']:.1f}")
        calls = record_ffts(scen, part, opt)
        fft_s = replay_cpu_s(calls) / 64
        bound1 = 1.0 / fft_s
        shapes = {}
        for f, shape, _, _, _ in calls:
            name = getattr(f, "__name__", str(f))
            shapes[(name, shape)] = shapes.get((name, shape), 0) + 1
        top = sorted(shapes.items(), key=lambda kv: -kv[1] * int(np.prod(kv[0][1])))[:4]
        print(f"[{scene}] FFTs per trial: {len(calls) / 64:.0f} calls, {fft_s * 1e3:.2f} ms CPU → FFT-bound "
              f"rate {bound1:.0f} trials/s per core, {2 * bound1:.0f} on 2 cores (largest: "
              + ", ".join(f"{n}{list(s)}×{c / 64:.1f}" for (n, s), c in top) + ")")
        print(f"[{scene}] ratio to the FFT bound: 1 worker {rates[1]['wall_rate'] / bound1:.2f} wall, "
              f"{rates[1]['cpu_rate'] / bound1:.2f} CPU-based; 2 workers {rates[2]['wall_rate'] / (2 * bound1):.2f} "
              f"wall, {rates[2]['cpu_rate'] / bound1:.2f} CPU-based (target ≥ 0.7); {load()}")
    if not args.no_memory:
        mem = {}
        for n in (64, 256, 1024):
            out = subprocess.run([sys.executable, __file__, "--memory-run", str(n)], capture_output=True,
                                 text=True, check=True)
            m = mem[n] = json.loads(out.stdout.strip().splitlines()[-1])
            print(f"[{McOptions().scene}] memory, {n} trials (serial, fresh process): peak traced heap {m['traced_peak_mb']:.1f} MB, "
                  f"max RSS {m['max_rss_mb']:.0f} MB ({m['rss_before_mb']:.0f} MB after the imports); {load()}")
        # per trial: the growth with the number of trials (≈ 0 when chunk-bounded), and what one
        # chunk in flight holds per trial of it (its peak over the imports, ÷ the chunk size)
        grow = (mem[1024]["traced_peak_mb"] - mem[64]["traced_peak_mb"]) / (1024 - 64) * 1e3
        chunk = McOptions().chunk_trials
        held = (mem[64]["max_rss_mb"] - mem[64]["rss_before_mb"]) / chunk * 1e3
        print(f"[{McOptions().scene}] memory per trial: growth {grow:.2f} kB per added trial (64 → 1024); a chunk of {chunk} "
              f"trials in flight holds ≈ {held:.0f} kB of RSS per trial")
    if args.no_sweep:
        return

    from budget.mc.sweep import sweep
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
