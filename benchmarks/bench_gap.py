"""Benchmark of the model-gap workflow: speed, detection matrix, false positives, real logs.

Logs come from the independent generators of ``tests/gap_truth.py`` (written without any code
of ``budget.imu`` or ``budget.gap``): one hour at 100 Hz, six channels, a tactical-grade base
model, one hidden effect each, scaled so that the channel's Allan deviation is 3× the base
model's at the τ where the effect shows most (quantization: at τ = dt; heavy tails: Student t
ν = 4 at twice the white variance; outliers: 1 sample in 2000 at ±10 white σ; thermal lag: its
part beyond an instantaneous sensitivity, see ``gap_truth.calibrate``). Printed:

1. wall time of :func:`budget.gap.run_gap` on a one-hour, 100 Hz, six-channel log (target < 60 s);
2. detection matrix: for each hidden effect over ``--seeds`` seeds, what was named *first*
   (effect@channel counts), how often it was the right one, with its 95 % Wilson interval (ten
   seeds give 8/10 or fewer for a detector whose rate is 0.9 one time in four), the seeds on
   which it was not, and the median / worst relative error of each parameter when it was; for
   the rate random walk, the ramp and the temperature sensitivity also the most any detector
   could reach on these logs (``tests/gap_power.py``: the Neyman–Pearson power at α = 2 % with
   the magnitude known);
3. false positives: effects named on logs that follow the base model (``--fp-seeds``);
4. with ``--real``: cross-validation on the two shared ADIS16405 logs (fit on log 1, test on
   log 2) when ``../shared/data`` is present.

Run from the repository root: ``python3 benchmarks/bench_gap.py [--quick] [--jobs 2] [--real]
[--low-frequency] [--decorrelate] [--ratio R] [--effects a,b] [--no-timing] [--grade G]
[--rate-hz F] [--minutes T] [--flicker kasdin]`` (``--low-frequency`` and ``--decorrelate``: the options of
:func:`budget.gap.run_gap`; ``--ratio``: the Allan-deviation ratio the effects are sized to,
default 3 — heavy tails and outliers keep their own sizes; ``--grade``, ``--rate-hz``,
``--minutes``: another base-model grade of ``gap_truth.GRADES``, sample rate and log length than
the tactical, 100 Hz, one-hour logs the workflow was developed on — a check that it holds on
logs it was not tuned on); ``--flicker kasdin``: the base flicker from a second, differently
built generator (a fractional integrator started with the log, Kasdin & Walter 1992); ``--real --seeds 0 --fp-seeds 0``: the speed run and the real logs
only (≈ 5 min).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import gap_power as gp  # noqa: E402
import gap_truth as gt  # noqa: E402
from budget.gap import cross_validate, log_from_arrays, run_gap  # noqa: E402
from budget.imu import NoiseModel  # noqa: E402
from budget.mc.stats import wilson_interval  # noqa: E402

BASE = NoiseModel.model_validate(gt.base_model_dict())
SHARED_LOGS = ROOT.parent / "shared" / "data" / "logs"


def run_one(args) -> dict:
    name, n, seed, opts = args
    x, temp, truth = gt.make(name, n, 1000 + seed)
    t0, c0 = time.perf_counter(), time.process_time()
    rep = run_gap(log_from_arrays(x, gt.RATE, temp_c=temp), BASE, seed=seed, max_steps=4, **opts)
    out = {"name": name, "seed": seed, "n": n, "time": time.perf_counter() - t0,
           "cpu": time.process_time() - c0, "truth": truth,
           "steps": [(s.name, s.channel, dict(s.params)) for s in rep.steps],
           # the level each named step was tested at: α spread over every candidate tried
           "step_alpha": [float(stats.chi2.sf(s.penalty, s.n_params)) for s in rep.steps],
           "stop": rep.stop_reason}
    return out


def timing(n: int, opts: dict) -> None:
    r = run_one(("rate_random_walk", n, 0, opts))
    named = ", ".join(f"{a}@{b}" for a, b, _ in r["steps"]) or "none"
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    print(f"{n / gt.RATE / 60:.0f} min, {gt.RATE:g} Hz, 6 channels (hidden rate random walk): {r['time']:.1f} s "
          f"wall, {r['cpu']:.1f} s CPU (target < 60 s; load {load}); named {named}; {r['stop']}")


def _errors(truth: dict, params: dict) -> dict[str, float]:
    return {k: abs(params[k] / v - 1.0) for k, v in truth["params"].items() if k in params and v}


def detection(results: list[dict], seeds: int) -> None:
    print(f"\ndetection matrix ({seeds} seeds per effect; first named effect@channel, counts)")
    for name in gt.ALL:
        rows = [r for r in results if r["name"] == name]
        if not rows:
            continue
        truth = rows[0]["truth"]
        first = Counter(f"{r['steps'][0][0]}@{r['steps'][0][1]}" if r["steps"] else "nothing"
                        for r in rows)
        right = [r for r in rows if r["steps"] and r["steps"][0][:2] == (name, truth["channel"])]
        errs: dict[str, list[float]] = {}
        for r in right:
            for k, e in _errors(r["truth"], r["steps"][0][2]).items():
                errs.setdefault(k, []).append(e)
        err_txt = ", ".join(f"{k} {np.median(v):.0%}/{np.max(v):.0%}" for k, v in errs.items()) or "-"
        t = np.median([r["time"] for r in rows])
        lo, hi = wilson_interval(len(right), len(rows))
        print(f"  {name:24s} on {truth['channel']:8s} right first {len(right):2d}/{len(rows)} "
              f"(95 % Wilson [{lo:.2f}, {hi:.2f}])  param err median/worst: {err_txt}  ({t:.0f} s/run)")
        print("      first named: " + ", ".join(f"{k} ×{v}" for k, v in first.most_common()))
        missed = sorted(r["seed"] for r in rows if r not in right)
        if missed:
            print("      missed seeds: " + ", ".join(map(str, missed)))
        if len(rows) > 10:
            # the target is stated for ten seeds: how the count of ten varies from one set to the next
            hits = {r["seed"] for r in right}
            sets = [sum(s in hits for s in range(k, min(k + 10, len(rows)))) for k in range(0, len(rows), 10)]
            print("      per ten seeds (0–9, 10–19, …): " + ", ".join(map(str, sets)))
        if name in gp.BOUNDED and gt.FLICKER == "spectral":
            bound = gp.power_bound(name, gt.RATIO, n=rows[0]["n"])
            extra = ""
            if name == "temperature_sensitivity":
                b2 = gp.power_bound(name, gt.RATIO, n=rows[0]["n"], trend=True)
                extra = f"; {b2:.0%} with a linear trend unknown too"
            print(f"      best any detector can do (Neyman–Pearson, this magnitude known, α = 2 %): "
                  f"{bound:.0%} → {bound * len(rows):.1f}/{len(rows)} expected{extra}")
            levels = [r["step_alpha"][0] for r in right]
            if levels:
                # the workflow names an effect only past a penalty at α over all its candidate
                # tests; the same bound at that level is what its detection can be compared with
                a_eff = float(np.median(levels))
                b_eff = gp.power_bound(name, gt.RATIO, n=rows[0]["n"], alpha=a_eff)
                print(f"      the same at the level the workflow named it at (α = {a_eff:.1e}, "
                      f"median over the runs that named it): {b_eff:.0%} → "
                      f"{b_eff * len(rows):.1f}/{len(rows)} expected")
        stops = Counter(r["stop"].split(":")[0] for r in rows)
        print("      stop: " + "; ".join(f"{k} ×{v}" for k, v in stops.most_common()))


def false_positives(results: list[dict]) -> None:
    if not results:
        return
    named = [r for r in results if r["steps"]]
    lo, hi = wilson_interval(len(named), len(results))
    print(f"\nfalse positives: effects named on {len(named)}/{len(results)} model-following logs "
          f"({len(named) / max(len(results), 1):.1%}, 95 % Wilson [{lo:.1%}, {hi:.1%}])"
          + ("; " + "; ".join(f"seed {r['seed']}: " + ", ".join(f"{a}@{b}" for a, b, _ in r['steps'])
                              for r in named) if named else ""))


def real() -> None:
    logs = [SHARED_LOGS / f"adis16405_static_{i}.csv.gz" for i in (1, 2)]
    if not all(p.is_file() for p in logs):
        print("\nreal logs: ../shared/data/logs not found, skipped")
        return
    t0 = time.perf_counter()
    cv = cross_validate(logs[0], logs[1], "ADIS16405", seed=0, max_steps=30)
    print(f"\nreal ADIS16405 logs, fit on log 1, test on log 2 ({time.perf_counter() - t0:.0f} s):")
    print(cv.fit.summary())
    print(cv.summary())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="2 seeds, 4 FP seeds, 10-min logs")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--fp-seeds", type=int, default=50)
    ap.add_argument("--jobs", type=int, default=1, help="processes (the machine has 2 cores)")
    ap.add_argument("--effects", default=",".join(gt.ALL), help="comma-separated subset")
    ap.add_argument("--ratio", type=float, default=gt.RATIO,
                    help=f"Allan-deviation ratio (log / base model) the hidden effects are sized to "
                         f"(default {gt.RATIO:g}; the detection target is stated for 2–5)")
    ap.add_argument("--no-timing", action="store_true", help="skip the speed run")
    ap.add_argument("--grade", default="tactical", choices=sorted(gt.GRADES),
                    help="base-model grade of the generated logs (gap_truth.GRADES)")
    ap.add_argument("--rate-hz", type=float, default=100.0, help="sample rate of the generated logs")
    ap.add_argument("--minutes", type=float, default=60.0, help="length of the generated logs")
    ap.add_argument("--flicker", default="spectral", choices=("spectral", "kasdin"),
                    help="base flicker generator: spectral shaping over 8× the record (stationary) or "
                         "Kasdin & Walter's fractional integrator started with the log (gap_truth.FLICKER)")
    ap.add_argument("--real", action="store_true",
                    help="also cross-validate the real ADIS16405 logs (after the speed run and the "
                         "detection matrix; --real --seeds 0 --fp-seeds 0 for the real logs alone, "
                         "≈ 5 min)")
    ap.add_argument("--low-frequency", action="store_true",
                    help="run_gap(low_frequency=True): the record's low-frequency bands too")
    ap.add_argument("--decorrelate", action="store_true",
                    help="run_gap(decorrelate=True): spectral terms summed decorrelated")
    args = ap.parse_args()
    opts = {"low_frequency": args.low_frequency, "decorrelate": args.decorrelate}
    if not args.rate_hz > 0 or not args.minutes > 0:
        ap.error("--rate-hz and --minutes must be positive")
    gt.use(args.grade, args.rate_hz)  # the generators read it when they run (worker processes fork)
    global BASE
    BASE = NoiseModel.model_validate(gt.base_model_dict())
    n = int(round(args.minutes * 60.0 * args.rate_hz))
    if args.quick:
        args.seeds, args.fp_seeds, n = 2, 4, int(round(600.0 * args.rate_hz))
    if (args.grade, args.rate_hz, args.minutes) != ("tactical", 100.0, 60.0):
        print(f"base model: {args.grade} grade {gt.GRADES[args.grade]} (ARW deg/√h, deg/h, VRW m/s/√h, µg); "
              f"{args.rate_hz:g} Hz; {n / args.rate_hz / 60:g}-min logs")
    if not args.ratio > 1.0:
        ap.error("--ratio must be > 1 (the log's Allan deviation over the base model's)")
    gt.RATIO = args.ratio  # the generators read it when they size an effect (worker processes fork)
    gt.FLICKER = args.flicker
    if args.flicker != "spectral":
        print(f"base flicker: {args.flicker} (gap_truth.kasdin_flicker); the Neyman–Pearson bounds assume the "
              "spectral flicker and are not printed")
    if args.ratio != 3.0:
        print(f"hidden effects sized to {args.ratio:g}× the base model's Allan deviation")
    if not args.no_timing:
        timing(n, opts)
    tasks = [(name, n, s, opts) for name in args.effects.split(",") if name for s in range(args.seeds)]
    tasks += [(None, n, 5000 + s, opts) for s in range(args.fp_seeds)]
    with ProcessPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
        results = list(pool.map(run_one, tasks))
    detection([r for r in results if r["name"] is not None], args.seeds)
    false_positives([r for r in results if r["name"] is None])
    if args.real:
        real()


if __name__ == "__main__":
    main()
