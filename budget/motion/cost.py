"""Cost of a motion run before it starts: samples, random-stream blocks, working memory, CPU.

Trials run in blocks of :func:`block_trials` (the random-stream unit, :mod:`budget.motion.engine`);
memory is that of the blocks in flight together, so it does not grow with the number of trials.
:func:`check_cost` refuses a run beyond :data:`MAX_WORKING_BYTES` before anything is simulated.
"""

from __future__ import annotations

import math

from ..aiding_spec import AidingPlan
from ..errors import MOTION_MEMORY_WAY, InputError
from ..scenario import Scenario

#: Default chunk (unit of work for a worker thread), in trials.
DEFAULT_CHUNK = 1024
#: Working memory of a run (bytes, every block in flight together; the kept series are limited
#: apart, :data:`budget.motion.engine.MAX_SERIES_BYTES`): a run whose :func:`estimate_cost` exceeds it is refused
#: with the figure, before anything is simulated.
MAX_WORKING_BYTES = 3_000_000_000
#: Cost per IMU sample of one block in flight: (bytes shared by the block, bytes per trial,
#: CPU µs shared by the block, CPU µs per trial). Memory measured (traced heap, 200 Hz, 64 trials
#: × 12 401 samples and 8 × 120 401; tactical IMU with bias instability, GNSS 10 Hz) and rounded
#: up ≈ 10 %: free-inertial 112 + 128·T B, aided realtime/frozen 512 + 274·T B, smoothed and
#: feedforward 512 + 346·T B. CPU: the Kalman covariance recursion, per sample and block,
#: dominates aided runs (≈ 20–25 µs per sample for a 15–21-state filter, 2 µs per trial and
#: sample; the smoother about doubles it) — a rough figure for the progress line, not a limit.
COST_PER_SAMPLE = {"none": (128.0, 144.0, 0.0, 0.35), "realtime": (576.0, 304.0, 25.0, 2.0),
                   "frozen": (576.0, 304.0, 25.0, 2.0), "feedforward": (576.0, 384.0, 35.0, 2.5),
                   "smoothed": (576.0, 384.0, 50.0, 3.0)}


def estimate_cost(scenario: Scenario, n_trials: int, plan: AidingPlan | None = None,
                  workers: int = 1) -> dict:
    """Working memory and CPU time of a run before it starts, from samples × trials
    (:data:`COST_PER_SAMPLE`): ``{"samples", "block", "blocks", "bytes", "cpu_s"}`` — ``bytes``
    for the blocks in flight together (one per worker thread), ``cpu_s`` summed over all blocks.
    Memory does not grow with the number of trials: trials run in blocks of :func:`block_trials`
    (the random-stream unit, so a smaller block would change the numbers)."""
    aided = plan is not None and bool(plan.aiding)
    n = aperture_samples(scenario)
    n_total = n + (int(round(plan.warmup_s * scenario.imu_rate_hz)) if aided else 0)
    block = block_trials(n_total, aided=True) if aided else block_trials(n)
    blocks = -(-int(n_trials) // block)
    chunks = -(-int(n_trials) // (-(-DEFAULT_CHUNK // block) * block))
    b_shared, b_trial, c_shared, c_trial = COST_PER_SAMPLE[plan.mode if aided else "none"]
    per_block = n_total * (b_shared + block * b_trial)  # a block is generated whole
    return {"samples": n_total, "block": block, "blocks": blocks,
            "bytes": per_block * max(1, min(int(workers), chunks)),
            "cpu_s": blocks * n_total * (c_shared + block * c_trial) * 1e-6}


def block_trials(n_samples: int, aided: bool = False) -> int:
    """Trials per random-stream block: 64, fewer for long spans to bound memory — even and
    ≥ 2 (free-inertial), a power of two so that it divides 64-trial chunks (aided)."""
    if n_samples <= 16_384:
        return 64
    if aided:
        return max(2, 1 << int(math.log2(max(1, (64 * 16_384) // n_samples))))
    return max(2, 2 * ((32 * 16_384) // n_samples))


def aperture_samples(scenario: Scenario) -> int:
    """IMU samples spanning the aperture: round(Tc·rate) + 1 (sample 0 at the aperture start)."""
    return int(round(scenario.tc_s * scenario.imu_rate_hz)) + 1


def check_cost(scenario: Scenario, n_trials: int, plan: AidingPlan | None = None, workers: int = 1) -> dict:
    """:func:`estimate_cost`, refusing a run whose working memory exceeds :data:`MAX_WORKING_BYTES`
    (with the figures and what a user can change)."""
    cost = estimate_cost(scenario, n_trials, plan, workers)
    if cost["bytes"] > MAX_WORKING_BYTES:
        aided = plan is not None and bool(plan.aiding)
        raise InputError(
            f"this run would hold ≈ {cost['bytes'] / 1e9:.2g} GB at once ({cost['samples']:,} IMU samples "
            f"× {cost['block']}-trial blocks × {min(workers, cost['blocks'])} worker(s); ≈ "
            f"{cost['cpu_s']:.0f} s CPU), more than the {MAX_WORKING_BYTES / 1e9:g} GB a motion run may use",
            field="imu_rate_hz" if not aided else "aiding_warmup_s",
            expected=MOTION_MEMORY_WAY.cli + (", a shorter aiding_warmup_s" if aided else "")
                     + " or a shorter aperture (memory does not depend on the number of trials)")
    return cost
