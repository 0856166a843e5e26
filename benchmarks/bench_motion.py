"""Benchmark: the motion-error engine on 10,000 trials of a 4 s aperture at 200 Hz (801 samples).

Target: 10,000 trials × 800 samples propagated in under 2 s on the 2-core machine.
Prints trial-samples per second and wall/CPU seconds (best of ``REPEATS``) for

1. strapdown error propagation alone (errors given, with lever arm);
2. IMU error generation alone (ARW/VRW + turn-on bias + scale factor + misalignment);
3. ``simulate_motion`` end to end with that model (keep_series False and True);
4. ``simulate_motion`` with bias instability added (flicker bank, circulant synthesis);
5. the same on 2 worker threads.

Run from the repository root: ``PYTHONPATH=. python3 benchmarks/bench_motion.py`` (or after ``pip install -e .``).
"""

from __future__ import annotations

import time

import numpy as np

from budget.imu.generator import generate_imu_errors
from budget.imu.noise_model import NoiseModel
from budget.motion.cost import block_trials
from budget.motion.engine import simulate_motion
from budget.nav.strapdown import propagate_errors
from budget.scenario import Scenario
from budget.units import G0

TRIALS, RATE, TC = 10_000, 200.0, 4.0
REPEATS = 3

WHITE = NoiseModel(gyro_arw_deg_rt_h=0.15, accel_vrw_m_s_rt_h=0.03, gyro_bias_repeatability_deg_h=1.0,
                   accel_bias_repeatability_ug=100.0, gyro_scale_factor_ppm=300.0, accel_scale_factor_ppm=300.0,
                   gyro_misalignment_mrad=0.5, accel_misalignment_mrad=0.5)
TACTICAL = NoiseModel.model_validate({**WHITE.model_dump(), "gyro_bias_instability_deg_h": 0.5,
                                      "accel_bias_instability_ug": 50.0})


def scenario() -> Scenario:
    """Airborne X band with R chosen so that Tc = 4 s exactly (λR/(2·δℓ·V) = 4 s)."""
    lam = 299_792_458.0 / 9.6e9
    r = TC * 2 * 0.5 * 50.0 / lam
    return Scenario(name="bench_4s", carrier_frequency_hz=9.6e9, slant_range_m=r, azimuth_resolution_m=0.5,
                    range_resolution_m=0.5, platform_speed_m_s=50.0, lever_arm_m=(0.5, 0.0, 0.3),
                    imu_rate_hz=RATE)


def timed(fn) -> tuple[float, float]:
    """Best wall and CPU seconds over REPEATS runs."""
    wall, cpu = np.inf, np.inf
    for _ in range(REPEATS):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall, cpu = min(wall, time.perf_counter() - w0), min(cpu, time.process_time() - c0)
    return wall, cpu


def report(label: str, n_samples: int, wall: float, cpu: float) -> None:
    rate = TRIALS * n_samples / wall
    print(f"{label:<58} {wall:6.2f} s wall {cpu:6.2f} s CPU  {rate / 1e6:6.1f} M trial-samples/s")


def main() -> None:
    scen = scenario()
    n = int(round(scen.tc_s * RATE)) + 1
    block = block_trials(n)
    print(f"{TRIALS} trials x {n} samples (Tc = {scen.tc_s:.3f} s at {RATE:g} Hz) = "
          f"{TRIALS * n / 1e6:.1f} M trial-samples; blocks of {block} trials")
    rng = np.random.default_rng(0)
    gyro = rng.normal(0, 1e-4, (block, n, 3))
    accel = rng.normal(0, 1e-3, (block, n, 3))
    blocks = -(-TRIALS // block)

    def propagate():
        for _ in range(blocks):
            propagate_errors(gyro, accel, 1.0 / RATE, lever_arm_b_m=scen.lever_arm_m)

    report("1. strapdown propagation only", n, *timed(propagate))

    force = np.tile([0.0, 0.0, G0], (n, 1))

    def generate():
        for b in range(blocks):
            generate_imu_errors(WHITE, block, n, RATE, np.random.default_rng(b), true_force_m_s2=force)

    report("2. IMU error generation only (white + constants)", n, *timed(generate))
    report("3a. simulate_motion, white + constants, no series",
           n, *timed(lambda: simulate_motion(scen, WHITE, TRIALS, 1, keep_series=False)))
    report("3b. simulate_motion, white + constants, keep series",
           n, *timed(lambda: simulate_motion(scen, WHITE, TRIALS, 1, keep_series=True)))
    report("4. simulate_motion, + bias instability, no series",
           n, *timed(lambda: simulate_motion(scen, TACTICAL, TRIALS, 1, keep_series=False)))
    report("5. as 4 on 2 worker threads",
           n, *timed(lambda: simulate_motion(scen, TACTICAL, TRIALS, 1, keep_series=False, workers=2)))


if __name__ == "__main__":
    main()
