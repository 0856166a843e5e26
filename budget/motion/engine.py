"""``simulate_motion``: IMU errors → antenna-phase-centre error → range and phase error, per trial.

Pipeline per block of trials (DESIGN.md §3–4, seed 000 (2)–(10)):

1. true platform motion over the aperture (:func:`budget.nav.platform.true_motion`);
2. IMU errors for that motion (:func:`budget.imu.generator.generate_imu_errors`);
3. flat-earth strapdown error propagation with lever arm (:func:`budget.nav.strapdown.propagate_errors`);
4. range error to every scene point and phase 4πΔr/λ; Legendre decomposition.

Reproducibility: trials are processed in fixed blocks of :func:`block_trials` trials; the block
starting at trial i draws from ``trial_generator(seed, i, stream)`` with one stream each for the
IMU (``IMU_STREAM``), random disturbances and initial errors. A block is always generated
whole, so trial i's numbers depend only on (seed, i, scenario, model) — not on the number of
trials, the chunk size (rounded up to whole blocks) or the number of worker threads.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from pydantic import ValidationError

from ..errors import InputError, from_validation_error
from ..imu.generator import generate_imu_errors
from ..imu.noise_model import NoiseModel, NoiseModelSI, as_noise_model_si
from ..nav.platform import Disturbance, true_motion
from ..nav.strapdown import InitialErrors, propagate_errors
from ..rng import trial_generator
from ..scenario import Scenario
from .geometry import range_error, scene_targets
from .phase import decompose_phase
from .result import METRICS, MotionResult

IMU_STREAM, DISTURBANCE_STREAM, INITIAL_STREAM = 11, 12, 13
#: Default chunk (unit of work for a worker thread), in trials.
DEFAULT_CHUNK = 1024
#: Refuse to keep series larger than this (bytes); use keep_series=False.
MAX_SERIES_BYTES = 3_000_000_000
MAX_SAMPLES = 2_000_000


def block_trials(n_samples: int) -> int:
    """Trials per random-stream block: 64, fewer (even, ≥ 2) for long apertures to bound memory."""
    if n_samples <= 16_384:
        return 64
    return max(2, 2 * ((32 * 16_384) // n_samples))


def aperture_samples(scenario: Scenario) -> int:
    """IMU samples spanning the aperture: round(Tc·rate) + 1 (sample 0 at the aperture start)."""
    return int(round(scenario.tc_s * scenario.imu_rate_hz)) + 1


def _label(model) -> str:
    if isinstance(model, NoiseModelSI):
        return "noise model"
    return getattr(model, "part_id", None) or "noise model"


def _positive_int(name: str, value, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{name} must be an integer ≥ {minimum}", field=name, value=value)
    return int(value)


class _Context:
    """Everything a block needs, computed once."""

    def __init__(self, scenario, model_si, seed, disturbance, targets, initial_errors, keep_series,
                 prefilter=None):
        self.scenario, self.si, self.seed = scenario, model_si, seed
        self.prefilter = prefilter
        self.rate = scenario.imu_rate_hz
        self.dt = 1.0 / self.rate
        self.n = aperture_samples(scenario)
        self.block = block_trials(self.n)
        self.time_s = np.arange(self.n) * self.dt
        self.disturbance = disturbance
        self.targets = targets
        self.initial = initial_errors
        self.keep = keep_series
        self.lever = np.asarray(scenario.lever_arm_m, dtype=float)
        self.wavelength = scenario.wavelength_m
        self.motion = None if (disturbance is not None and disturbance.is_random) else \
            true_motion(scenario.platform_speed_m_s, self.time_s, disturbance)

    def motion_for(self, start: int):
        if self.motion is not None:
            return self.motion
        rng = trial_generator(self.seed, start, DISTURBANCE_STREAM)
        return true_motion(self.scenario.platform_speed_m_s, self.time_s, self.disturbance,
                           n_trials=self.block, rng=rng)


def _run_block(ctx: _Context, start: int, stop: int, out: dict, offset: int = 0) -> None:
    """Simulate the whole block starting at ``start``; store trials start … stop−1 at rows
    start−offset … stop−offset−1 of ``out``."""
    motion = ctx.motion_for(start)
    moving = ctx.disturbance is not None
    rate_b = motion.rate_b_rad_s if (moving and np.any(motion.rate_b_rad_s)) else None
    errs = generate_imu_errors(ctx.si, ctx.block, ctx.n, ctx.rate,
                               trial_generator(ctx.seed, start, IMU_STREAM),
                               true_rate_rad_s=rate_b, true_force_m_s2=motion.force_b_m_s2)
    init = ctx.initial.draw(ctx.block, trial_generator(ctx.seed, start, INITIAL_STREAM)) \
        if ctx.initial is not None else {}
    gyro, accel = errs.gyro_rad_s, errs.accel_m_s2
    if ctx.prefilter is not None:  # filter what the sensor outputs (true + error), keep the error
        gyro, accel = ctx.prefilter.apply(gyro, accel, rate_b, motion.force_b_m_s2)
    nav = propagate_errors(gyro, accel, ctx.dt,
                           force_n_m_s2=motion.force_n_m_s2 if moving else None,
                           c_b_n=motion.c_b_n, lever_arm_b_m=ctx.lever, **init)
    del errs
    err = nav.apc_position_m
    np.negative(err, out=err)  # computed − true → true − measured (seed 000 (7))
    apc_true = motion.position_m
    if np.any(ctx.lever):
        apc_true = apc_true + (ctx.lever if motion.c_b_n is None else np.matmul(motion.c_b_n, ctx.lever))
    m = stop - start
    phase_scale = 4.0 * math.pi / ctx.wavelength
    for k, target in enumerate(ctx.targets):
        dr = range_error(apc_true, err, target)
        dec = decompose_phase(dr * phase_scale)
        peak = np.max(np.abs(dr), axis=1)
        vals = {"constant_rad": dec.constant_rad, "linear_edge_rad": dec.linear_edge_rad,
                "quadratic_edge_rad": dec.quadratic_edge_rad, "cubic_edge_rad": dec.cubic_edge_rad,
                "residual_rms_deg": dec.residual_rms_deg, "peak_range_error_m": peak,
                "peak_range_cells": peak / ctx.scenario.range_resolution_m}
        for name in METRICS:
            out[name][start - offset:stop - offset, k] = vals[name][:m]
        if ctx.keep:
            out["range_error_m"][start - offset:stop - offset, k] = dr[:m]
    if ctx.keep:
        out["position_error_m"][start - offset:stop - offset] = err[:m]


def simulate_motion(scenario: Scenario, model, n_trials: int, seed: int, *, chunk_size: int | None = None,
                    disturbance: Disturbance | dict | None = None, targets=None,
                    initial_errors: InitialErrors | dict | None = None, workers: int = 1,
                    keep_series: bool = True, first_trial: int = 0, prefilter=None) -> MotionResult:
    """Monte Carlo of the motion error of ``n_trials`` apertures of ``scenario`` with IMU ``model``.

    ``model``: :class:`~budget.imu.noise_model.NoiseModel`, catalog ``PartSpec`` or
    ``NoiseModelSI``. ``disturbance``: platform motion (:class:`~budget.nav.platform.Disturbance`);
    ``targets``: scene points (K, 3) in m (default: the scene centre at slant range along the
    LOS); ``initial_errors``: 1σ initial position/velocity/attitude errors (default none, as in
    seed 004). The IMU is aligned at the aperture start (t = 0) and the scenario's lever arm
    (body frame, IMU → APC) applies. ``keep_series`` keeps the APC error (T, N, 3) and range
    error (T, K, N) series. ``workers`` > 1 runs chunks on threads; results are identical.
    ``first_trial`` (a multiple of :func:`block_trials`) simulates trials ``first_trial …
    first_trial + n_trials − 1`` of the same seed, so a Monte Carlo can be cut into chunks.
    ``prefilter``: an :class:`~budget.noise.prefilter.ImuPrefilter` applied to the IMU output
    before navigation (seed 000's ARMA-Kalman filtering), default none.
    """
    if not isinstance(scenario, Scenario):
        scenario = Scenario.from_dict(scenario) if isinstance(scenario, dict) else scenario
        if not isinstance(scenario, Scenario):
            raise InputError("scenario must be a Scenario", field="scenario")
    if isinstance(model, dict):
        model = NoiseModel.from_dict(model)
    si = as_noise_model_si(model)
    n_trials = _positive_int("n_trials", n_trials)
    seed = _positive_int("seed", seed, minimum=0)
    workers = _positive_int("workers", workers)
    try:
        if isinstance(disturbance, dict):
            disturbance = Disturbance.model_validate(disturbance)
        if isinstance(initial_errors, dict):
            initial_errors = InitialErrors.model_validate(initial_errors)
    except ValidationError as err:
        raise from_validation_error(err) from None
    n = aperture_samples(scenario)
    if n < 5:
        raise InputError(f"the aperture spans only {n} IMU samples (Tc = {scenario.tc_s:.3g} s at "
                         f"{scenario.imu_rate_hz:g} Hz)", field="imu_rate_hz", expected="at least 5 samples")
    if n > MAX_SAMPLES:
        raise InputError(f"the aperture spans {n} IMU samples", field="imu_rate_hz",
                         expected=f"at most {MAX_SAMPLES:,} (lower the IMU rate)")
    if disturbance is not None and 2.0 * disturbance.max_frequency_hz() >= scenario.imu_rate_hz:
        raise InputError(f"disturbance content up to {disturbance.max_frequency_hz():g} Hz needs an IMU rate "
                         f"above {2 * disturbance.max_frequency_hz():g} Hz", field="imu_rate_hz",
                         value=scenario.imu_rate_hz)
    pts = scene_targets(scenario, targets)
    if keep_series and 8 * n_trials * n * (3 + pts.shape[0]) > MAX_SERIES_BYTES:
        raise InputError(f"keeping the series of {n_trials} trials × {n} samples needs more than "
                         f"{MAX_SERIES_BYTES / 1e9:g} GB", field="n_trials",
                         expected="fewer trials or keep_series=False")

    ctx = _Context(scenario, si, seed, disturbance, pts, initial_errors, keep_series, prefilter)
    first = _positive_int("first_trial", first_trial, minimum=0)
    if first % ctx.block:
        raise InputError(f"first_trial must be a multiple of the {ctx.block}-trial random-stream block",
                         field="first_trial", value=first_trial)
    chunk = DEFAULT_CHUNK if chunk_size is None else _positive_int("chunk_size", chunk_size)
    chunk = -(-chunk // ctx.block) * ctx.block
    k = pts.shape[0]
    out = {name: np.empty((n_trials, k)) for name in METRICS}
    if keep_series:
        out["position_error_m"] = np.empty((n_trials, n, 3))
        out["range_error_m"] = np.empty((n_trials, k, n))

    def run_chunk(c0: int) -> None:
        for b0 in range(c0, min(c0 + chunk, first + n_trials), ctx.block):
            _run_block(ctx, b0, min(b0 + ctx.block, first + n_trials), out, first)

    starts = range(first, first + n_trials, chunk)
    if workers == 1 or len(starts) == 1:
        for c0 in starts:
            run_chunk(c0)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            list(pool.map(run_chunk, starts))
    return MotionResult(scenario=scenario, model_label=_label(model), seed=seed, time_s=ctx.time_s,
                        targets_m=pts, position_error_m=out.pop("position_error_m", None),
                        range_error_m=out.pop("range_error_m", None), **out)
