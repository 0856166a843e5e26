"""``simulate_motion``: IMU errors → antenna-phase-centre error → range and phase error, per trial.

One path for free-inertial and aided navigation (seed 000 (2)–(10), seed 004 (3)–(4)):

1. true platform motion (:func:`budget.nav.platform.true_motion`) over the span simulated —
   the aperture, preceded by the aiding warm-up when the IMU is aided;
2. IMU errors for that motion (:func:`budget.imu.generator.generate_imu_errors`: noise, bias,
   scale factor and misalignment acting on the true rate and specific force);
3. optionally seed 000's ARMA-Kalman pre-filter on the sensor output
   (:class:`~budget.noise.prefilter.ImuPrefilter`);
4. flat-earth strapdown error propagation (:func:`budget.nav.strapdown.propagate_errors`);
5. optionally aiding: the filter's corrections in the chosen mode
   (:func:`budget.aiding.correct_free_inertial`, modes of :mod:`budget.aiding_spec`);
6. antenna phase centre through the lever arm, δp_APC = δp + (C·d) × φ (seed 000 (7));
   range error to every scene point, phase 4πΔr/λ, Legendre decomposition.

Free-inertial: the IMU is aligned at the aperture start (t = 0), as seed 004 assumes. Aided:
the navigation starts ``warmup_s`` before the aperture with initial errors drawn from the
filter's initial 1σ (or the caller's ``initial_errors``) and the APC error is reported relative
to its value at the aperture start (a constant offset only moves the image). With no aiding
sensor the aided path *is* the free-inertial path.

Limits stated or refused: the propagation is flat-earth, except that the Earth and transport
rate turn an initial attitude error (at the caller's latitude and heading, or the stated
defaults); the result's ``earth_model`` gives the estimated size of the Schuler, Earth-rate and
transport-rate terms it leaves out over Tc (:func:`budget.nav.earth.flat_earth_neglect`). One
rule, :func:`check_flat_earth`: a coast across the aperture (free-inertial, ``frozen``, or
``feedforward`` blending slower than Tc) whose estimate exceeds :data:`MAX_FLAT_EARTH_NEGLECT`
(Tc ≳ 790 s) is refused — the coast's estimate includes the heading error an aiding warm-up
leaves unobserved, turned by the Earth and transport rate across the aperture
(:func:`heading_term`); aiding that corrects inside the aperture bounds the neglect (measured,
:data:`AIDED_FLAT_EARTH_NOTE`) up to Tc = :data:`AIDED_FLAT_EARTH_MAX_TC_S`. A run whose working
memory (:func:`estimate_cost`) exceeds :data:`MAX_WORKING_BYTES` is refused. An aperture cut to
whole IMU intervals more than 1 % away from Tc, and an aided run in which no fix reaches the
filter in time (``frozen`` with a warm-up shorter than the first fix), are warned of and said in
the result.

Reproducibility: trials are processed in fixed blocks of :func:`block_trials` trials; the block
starting at trial i draws from ``trial_generator(seed, i, stream)`` with the streams of
:data:`budget.rng.STREAMS` (IMU, disturbance, initial errors, aiding). A block is always
generated whole, so trial i's numbers depend only on (seed, i, scenario, model, options) —
not on the number of trials, the chunk size (rounded up to whole blocks) or the worker threads.
"""

from __future__ import annotations

import math
import threading
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from pydantic import ValidationError

from ..aiding import (ImuErrorModel, InitialUncertainty, NominalTrajectory, build_system,
                      correct_free_inertial)
from ..aiding.flexure import antenna_flexure_error, simulate_flexure
from ..aiding.kalman import joseph_update
from ..aiding.measurements import measurement_from_config
from ..aiding_spec import AidingPlan
from ..errors import MOTION_MEMORY_WAY, InputError, from_validation_error, whole_number
from ..imu.generator import generate_imu_errors
from ..imu.noise_model import NoiseModel, NoiseModelSI, as_noise_model_si
from ..nav.earth import flat_earth_neglect, navigation_frame_rate
from ..nav.platform import Disturbance, true_motion
from ..nav.strapdown import InitialErrors, cross, propagate_errors
from ..rng import STREAMS, trial_generator
from ..scenario import Scenario
from ..units import G0, two_way_wavenumber_rad_m
from .geometry import range_error, scene_targets
from .phase import decompose_phase
from .result import METRICS, MotionResult

IMU_STREAM = STREAMS["motion_imu"]
DISTURBANCE_STREAM = STREAMS["motion_disturbance"]
INITIAL_STREAM = STREAMS["motion_initial"]
AIDING_STREAM = STREAMS["motion_aiding"]
#: Initial errors of an aided run when the caller gives none: the filter's default 1σ at the
#: start of the warm-up (a coarse alignment; the filter converges during the warm-up).
AIDED_INITIAL = InitialErrors(position_sigma_m=(1.0, 1.0, 1.0), velocity_sigma_m_s=(0.1, 0.1, 0.1),
                              attitude_sigma_rad=(1e-3, 1e-3, 1e-3))
#: Feed-forward blend time when the scenario gives none, in apertures (5·Tc).
BLEND_APERTURES = 5.0
#: Default chunk (unit of work for a worker thread), in trials.
DEFAULT_CHUNK = 1024
#: Refuse to keep series larger than this (bytes); use keep_series=False.
MAX_SERIES_BYTES = 3_000_000_000
MAX_SAMPLES = 2_000_000
#: Largest relative effect (dimensionless) of the Schuler, Earth-rate and transport-rate terms
#: the flat-earth propagation leaves out (:func:`budget.nav.earth.flat_earth_neglect`) over a
#: free-inertial coast of Tc: 10 %, reached at Tc ≈ 790 s. Beyond it the flat model's t³ growth
#: overstates the Schuler-bounded error (2× at Tc = 3000 s), so the run is refused.
MAX_FLAT_EARTH_NEGLECT = 0.10
#: Aided runs that correct inside the aperture (``realtime``, ``smoothed``, and ``feedforward``
#: with a blend time below Tc): the aiding bounds what the flat-earth neglect does, measured
#: against a truth *and* filter with the Schuler, Earth-rate and transport-rate terms (GNSS 1 Hz
#: σ 5 cm, 60 s warm-up, 50 m/s, 45°): the aided error changes by ≤ 0.6 % (realtime) / 1.2 %
#: (smoothed) at Tc = 3000 s with a 1 deg/h gyro and by ≤ 2.3 % / 5.2 % with 10 deg/h (GNSS
#: 0.1 Hz: 1.4 % / 4.5 %), growing with Tc; not measured beyond, so longer apertures are refused.
#: A long warm-up (3000 s, 10 deg/h, Tc = 30 s: the heading error of :data:`HEADING_TERM_NOTE`)
#: stays inside it: 0.6 % realtime, 2.2 % smoothed, 1.7 % feedforward with a 10 s blend (worst of
#: 4 trials; 1 deg/h: 0.3 % / 1.0 % / 0.15 %).
AIDED_FLAT_EARTH_MAX_TC_S = 3000.0
AIDED_FLAT_EARTH_NOTE = ("bounded by the aiding here: measured ≤ 1.2 % of the aided error at Tc = "
                         "3000 s with a 1 deg/h gyro, ≤ 5.2 % with 10 deg/h")
#: Aided coasts (``frozen``, ``feedforward`` blending slower than Tc) after a warm-up: a heading
#: error the filter leaves unobserved grows over the warm-up (gyro bias × warm-up; position fixes
#: do not see heading in straight level flight) and is then turned by the Earth and transport rate
#: into a tilt rate |ω_in × ẑ|·ψ across the aperture — which the flat model leaves out (it turns
#: only the *initial* attitude error). :func:`heading_term` sizes it before the run from the
#: flat filter's covariance at the aperture start: g·|ω_in × ẑ|·σ_ψ·Tc³/6 against the coast's 1σ
#: error (start covariance + process noise over Tc); the rule adds it to the coast estimate and
#: refuses beyond :data:`MAX_FLAT_EARTH_NEGLECT`. Measured against a truth and filter with the Earth
#: terms (tests/test_hardening_motion9.py; GNSS 1 Hz, Tc = 30 s, 45°, 50 m/s, RMS over trials):
#: frozen, 10 deg/h, 3000 s warm-up: the flat model 6.7 % off (11.9 % the worst of 4 trials), the
#: estimate 29 %; 1000 s: 8.9 % / 12 %; 1 deg/h, 3000 s: 2.7 % / 3.1 %.
HEADING_TERM_NOTE = "heading error unobserved during the warm-up, turned by the Earth and transport rate"
#: Aperture simulated over (N − 1)/rate s; a departure from Tc above this fraction is warned of.
APERTURE_ROUNDING_NOTE = 0.01
#: Working memory of a run (bytes, every block in flight together; the kept series are limited
#: apart, :data:`MAX_SERIES_BYTES`): a run whose :func:`estimate_cost` exceeds it is refused
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
#: Latitude and heading (deg; heading from north, of the along-track axis) at which the Earth and
#: transport rate turn an initial attitude error (:func:`budget.nav.strapdown.propagate_errors`,
#: ``frame_rate_n_rad_s``) when the caller gives none — the scenario carries neither. 45° is
#: the latitude :func:`budget.nav.earth.flat_earth_neglect` is stated at; the result says so.
DEFAULT_LATITUDE_DEG, DEFAULT_HEADING_DEG = 45.0, 0.0


def coasts_over_aperture(plan: AidingPlan | None, tc_s: float) -> bool:
    """True when the antenna track coasts free-inertial across the aperture, so the flat-earth
    neglect is that of a Tc coast (:func:`budget.nav.earth.flat_earth_neglect`): no aiding,
    ``frozen``, or ``feedforward`` with a blend time ≥ Tc (the default 5·Tc: its corrections lag
    by more than the aperture; measured against the Earth model at Tc = 1000 s: 12.8 %, the
    estimate 15.5 %). ``realtime``, ``smoothed`` and a faster blend correct inside the aperture
    (:data:`AIDED_FLAT_EARTH_NOTE`)."""
    if plan is None or not plan.aiding or plan.mode == "frozen":
        return True
    if plan.mode == "feedforward":
        return (plan.blend_time_s or BLEND_APERTURES * tc_s) >= tc_s
    return False


def earth_model_note(scenario: Scenario, coasting: bool, frame: dict | None = None,
                     heading: dict | None = None) -> str:
    """What the navigation model leaves out, for results: the flat-earth error propagation and
    the relative size of its neglected terms over the aperture (a free-inertial coast of Tc when
    ``coasting``, :func:`coasts_over_aperture`; otherwise bounded by the aiding, as measured in
    :data:`AIDED_FLAT_EARTH_NOTE`).
    ``frame`` (``{"latitude_deg", "heading_deg", "latitude_default", "heading_default"}``): the
    initial attitude error is turned by the Earth and transport rate at that latitude and
    heading — said, with which of them are defaults. ``heading`` (:func:`heading_term`): the
    size of the heading term an aided coast leaves out, said with its figures."""
    neglect = flat_earth_neglect(scenario.tc_s, scenario.platform_speed_m_s)
    where = f"over the {scenario.tc_s:.3g} s free-inertial coast" if coasting else \
        f"over a {scenario.tc_s:.3g} s coast; {AIDED_FLAT_EARTH_NOTE}"
    text = (f"flat earth (Schuler, Earth-rate and transport-rate terms neglected: "
            f"≈ {100 * neglect:.2g} % of the error {where})")
    if frame is not None:
        dflt = lambda key: " (default: the scenario carries none)" if frame[f"{key}_default"] else ""  # noqa: E731
        text += (f"; the Earth and transport rate turning the initial attitude error are included, "
                 f"at latitude {frame['latitude_deg']:g}°{dflt('latitude')} and heading "
                 f"{frame['heading_deg']:g}° from north{dflt('heading')}")
    if heading is not None:
        text += (f"; not included: the {HEADING_TERM_NOTE} over the aperture (heading 1σ "
                 f"{1e3 * heading['sigma_psi_rad']:.3g} mrad at the aperture start, {heading['term_m']:.3g} m "
                 f"over Tc): ≈ {100 * heading['neglect']:.2g} % of the aperture's {heading['budget_m']:.3g} m "
                 f"error (1σ, from the filter's covariance)")
    return text


def first_fix_note(plan: AidingPlan, n_warm: int, n_total: int, rate_hz: float) -> str | None:
    """None if some aiding measurement reaches the filter in time; otherwise why none does —
    in ``frozen`` mode by the aperture start (sample ``n_warm``: validity + latency, the epochs of
    :meth:`budget.aiding.measurements.Measurement.epochs`), in the other modes within the
    ``n_total`` samples of the record. The aperture is then free-inertial from the initial errors."""
    dt = 1.0 / rate_hz
    frozen = plan.mode == "frozen"
    for i, cfg in enumerate(plan.aiding):
        m = measurement_from_config(cfg, i)
        ep = m.epochs(n_total, dt)
        if ep.size and (not frozen or ep[0] + m.latency_steps(dt) <= n_warm):
            return None
    first = min(1.0 / cfg.rate_hz + cfg.latency_s for cfg in plan.aiding)
    if frozen:
        return (f"no aiding fix reaches the filter by the aperture start (first after {first:.3g} s, "
                f"warm-up {plan.warmup_s:g} s): the aperture is free-inertial from the initial errors")
    return (f"no aiding fix falls within the {n_total * dt:.3g} s record (first after {first:.3g} s): "
            "the aperture is free-inertial from the initial errors")


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


def _label(model) -> str:
    if isinstance(model, NoiseModelSI):
        return "noise model"
    return getattr(model, "part_id", None) or "noise model"


class _Context:
    """Everything a block needs, computed once."""

    def __init__(self, scenario, model_si, seed, disturbance, targets, initial_errors, keep_series,
                 prefilter=None, plan: AidingPlan | None = None, frame_rate=None):
        self.scenario, self.si, self.seed = scenario, model_si, seed
        #: ω_in (nav frame, rad/s) turning the initial attitude error; None: not applied
        self.frame_rate = frame_rate
        self.prefilter = prefilter
        self.plan = plan if (plan is not None and plan.aiding) else None
        self.rate = scenario.imu_rate_hz
        self.dt = 1.0 / self.rate
        self.n = aperture_samples(scenario)
        self.n_warm = int(round(self.plan.warmup_s * self.rate)) if self.plan else 0
        self.n_total = self.n_warm + self.n
        self.block = block_trials(self.n_total, aided=self.plan is not None) if self.plan \
            else block_trials(self.n)
        self.time_s = np.arange(self.n) * self.dt
        #: sample times of the whole span; 0 = aperture start
        self.span_time_s = (np.arange(self.n_total) - self.n_warm) * self.dt
        self.disturbance = disturbance
        self.targets = targets
        self.initial = initial_errors
        if self.plan is not None and initial_errors is None:
            self.initial = AIDED_INITIAL
        #: keep the APC error series; the range error series too unless only "position" is asked
        self.keep = bool(keep_series)
        self.keep_range = keep_series is True
        self.lever = np.asarray(scenario.lever_arm_m, dtype=float)
        self.wavelength = scenario.wavelength_m
        self.motion = None if (disturbance is not None and disturbance.is_random) else \
            true_motion(scenario.platform_speed_m_s, self.span_time_s, disturbance, imu_dt_s=self.dt)
        if self.plan is not None:
            self.blend_time_s = self.plan.blend_time_s or BLEND_APERTURES * scenario.tc_s
            self.filter_initial = InitialUncertainty(
                position_m=np.asarray(self.initial.position_sigma_m),
                velocity_m_s=np.asarray(self.initial.velocity_sigma_m_s),
                attitude_rad=np.asarray(self.initial.attitude_sigma_rad))

    def motion_for(self, start: int):
        if self.motion is not None:
            return self.motion
        rng = trial_generator(self.seed, start, DISTURBANCE_STREAM)
        return true_motion(self.scenario.platform_speed_m_s, self.span_time_s, self.disturbance,
                           n_trials=self.block, rng=rng, imu_dt_s=self.dt)


def _apc_error(ctx: _Context, start: int, motion, gyro, accel, init) -> np.ndarray:
    """APC position error, computed − true, (T, N_aperture, 3)."""
    moving = ctx.disturbance is not None
    if ctx.plan is None:
        nav = propagate_errors(gyro, accel, ctx.dt, force_n_m_s2=motion.force_n_m_s2 if moving else None,
                               c_b_n=motion.c_b_n, lever_arm_b_m=ctx.lever,
                               frame_rate_n_rad_s=ctx.frame_rate, **init)
        return nav.apc_position_m
    nav = propagate_errors(gyro, accel, ctx.dt, force_n_m_s2=motion.force_n_m_s2 if moving else None,
                           c_b_n=motion.c_b_n, keep_states=True, frame_rate_n_rad_s=ctx.frame_rate, **init)
    rng = trial_generator(ctx.seed, start, AIDING_STREAM)
    pos, att = correct_free_inertial(
        nav.position_m, nav.velocity_m_s, nav.attitude_rad, ctx.si.errors, ctx.plan.aiding, ctx.dt,
        rng, mode=ctx.plan.mode, aperture_start=ctx.n_warm, blend_time_s=ctx.blend_time_s,
        initial=ctx.filter_initial, imu_rate_hz=ctx.rate,
        velocity_n_m_s=(ctx.scenario.platform_speed_m_s, 0.0, 0.0))
    del nav
    w = ctx.n_warm
    apc = pos[:, w:].copy()
    if np.any(ctx.lever):
        c = motion.c_b_n
        arm = ctx.lever if c is None else np.matmul(c[..., w:, :, :], ctx.lever)
        apc += cross(arm, att[:, w:])
    if ctx.plan.antenna_flexure is not None:
        c = None if motion.c_b_n is None else motion.c_b_n[..., w:, :, :]
        apc += antenna_flexure_error(simulate_flexure(ctx.plan.antenna_flexure, ctx.dt, ctx.n,
                                                      apc.shape[0], rng).displacement_m, c)
    apc -= apc[:, :1]  # relative to the aperture start: a constant offset only moves the image
    return apc


def _run_block(ctx: _Context, start: int, stop: int, out: dict, offset: int = 0) -> None:
    """Simulate the whole block starting at ``start``; store trials start … stop−1 at rows
    start−offset … stop−offset−1 of ``out``."""
    motion = ctx.motion_for(start)
    moving = ctx.disturbance is not None
    rate_b = motion.rate_b_rad_s if (moving and np.any(motion.rate_b_rad_s)) else None
    errs = generate_imu_errors(ctx.si, ctx.block, ctx.n_total, ctx.rate,
                               trial_generator(ctx.seed, start, IMU_STREAM),
                               true_rate_rad_s=rate_b, true_force_m_s2=motion.force_b_m_s2)
    init = ctx.initial.draw(ctx.block, trial_generator(ctx.seed, start, INITIAL_STREAM)) \
        if ctx.initial is not None else {}
    gyro, accel = errs.gyro_rad_s, errs.accel_m_s2
    if ctx.prefilter is not None:  # filter what the sensor outputs (true + error), keep the error
        gyro, accel = ctx.prefilter.apply(gyro, accel, rate_b, motion.force_b_m_s2)
    del errs
    err = _apc_error(ctx, start, motion, gyro, accel, init)
    del gyro, accel
    np.negative(err, out=err)  # computed − true → true − measured (seed 000 (7))
    w = ctx.n_warm
    apc_true = motion.position_m[..., w:, :]
    if w:  # re-centre the nominal along-track position on the aperture centre
        apc_true = apc_true.copy()
        apc_true[..., 0] += 0.5 * ctx.scenario.platform_speed_m_s * ctx.span_time_s[0]
    if np.any(ctx.lever):
        c = motion.c_b_n
        apc_true = apc_true + (ctx.lever if c is None else np.matmul(c[..., w:, :, :], ctx.lever))
    m = stop - start
    phase_scale = two_way_wavenumber_rad_m(ctx.wavelength)
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
        if ctx.keep_range:
            out["range_error_m"][start - offset:stop - offset, k] = dr[:m]
    if ctx.keep:
        out["position_error_m"][start - offset:stop - offset] = err[:m]


def simulate_motion(scenario: Scenario, model, n_trials: int, seed: int, *, chunk_size: int | None = None,
                    disturbance: Disturbance | dict | None = None, targets=None,
                    initial_errors: InitialErrors | dict | None = None, workers: int = 1,
                    keep_series: bool | str = True, first_trial: int = 0, prefilter=None,
                    aiding: AidingPlan | dict | str | None = "scenario",
                    latitude_deg: float | None = None, heading_deg: float | None = None,
                    progress=None) -> MotionResult:
    """Monte Carlo of the motion error of ``n_trials`` apertures of ``scenario`` with IMU ``model``.

    ``model``: :class:`~budget.imu.noise_model.NoiseModel`, catalog ``PartSpec`` or
    ``NoiseModelSI``. ``disturbance``: platform motion (:class:`~budget.nav.platform.Disturbance`);
    ``targets``: scene points (K, 3) in m (default: the scene centre at slant range along the
    LOS); ``initial_errors``: 1σ initial position/velocity/attitude errors (free-inertial:
    default none, the IMU aligned at the aperture start t = 0, as in seed 004; aided: at the
    warm-up start, default :data:`AIDED_INITIAL`, also the filter's initial 1σ). The
    scenario's lever arm (body frame, IMU → APC) applies. ``keep_series``: True keeps the APC
    error (T, N, 3) and range error (T, K, N) series, ``"position"`` the APC error only, False
    neither. ``workers`` > 1 runs chunks on threads; results are identical.
    ``first_trial`` (a multiple of :func:`block_trials`) simulates trials ``first_trial …
    first_trial + n_trials − 1`` of the same seed, so a Monte Carlo can be cut into chunks.
    ``prefilter``: an :class:`~budget.noise.prefilter.ImuPrefilter` applied to the IMU output
    before navigation (seed 000's ARMA-Kalman filtering), default none; it must keep real
    motion (DC gain within 1 %, :meth:`~budget.noise.prefilter.ImuPrefilter.check_dc_gain`).
    ``aiding``: ``"scenario"`` (default) uses the scenario's aiding section
    (:meth:`AidingPlan.from_scenario`); an :class:`~budget.aiding_spec.AidingPlan` (or its dict)
    overrides it; ``None`` is free-inertial. An aided run simulates the warm-up before the
    aperture and applies the corrections in the plan's mode (module docstring); with no sensor
    it is the free-inertial run. ``latitude_deg`` (|L| < 89°) and ``heading_deg`` (of the
    along-track axis, from north): where the Earth and transport rate turn the initial attitude
    error (first order, :func:`budget.nav.strapdown.propagate_errors`); default
    :data:`DEFAULT_LATITUDE_DEG`, :data:`DEFAULT_HEADING_DEG`, said in ``earth_model``. They act
    only when there is an initial attitude error (``initial_errors``; an aided run's default).
    ``progress(done, total)`` (trials) is called after each block (:func:`estimate_cost` gives
    the cost before the run; one beyond :data:`MAX_WORKING_BYTES` is refused).
    """
    if not isinstance(scenario, Scenario):
        scenario = Scenario.from_dict(scenario) if isinstance(scenario, dict) else scenario
        if not isinstance(scenario, Scenario):
            raise InputError("scenario must be a Scenario", field="scenario")
    if isinstance(model, dict):
        model = NoiseModel.from_dict(model)
    si = as_noise_model_si(model)
    n_trials = whole_number("n_trials", n_trials, 1)
    seed = whole_number("seed", seed, 0)
    workers = whole_number("workers", workers, 1)
    try:
        if isinstance(disturbance, dict):
            disturbance = Disturbance.model_validate(disturbance)
        if isinstance(initial_errors, dict):
            initial_errors = InitialErrors.model_validate(initial_errors)
        if isinstance(aiding, str):
            if aiding != "scenario":
                raise InputError("unknown aiding option", field="aiding", value=aiding,
                                 expected="'scenario', an AidingPlan or None")
            aiding = AidingPlan.from_scenario(scenario)
        elif isinstance(aiding, dict):
            aiding = AidingPlan.model_validate(aiding)
    except ValidationError as err:
        raise from_validation_error(err) from None
    if aiding is not None and not isinstance(aiding, AidingPlan):
        raise InputError("aiding must be an AidingPlan, its dict, 'scenario' or None", field="aiding")
    if prefilter is not None:
        prefilter.check_dc_gain(scenario.imu_rate_hz)
    n = aperture_samples(scenario)
    if n < 5:
        raise InputError(f"the aperture spans only {n} IMU samples (Tc = {scenario.tc_s:.3g} s at "
                         f"{scenario.imu_rate_hz:g} Hz)", field="imu_rate_hz", expected="at least 5 samples")
    if n > MAX_SAMPLES:
        raise InputError(f"the aperture spans {n} IMU samples", field="imu_rate_hz",
                         expected=f"at most {MAX_SAMPLES:,} (lower the IMU rate)")
    if disturbance is not None:
        disturbance.check_imu_rate(scenario.imu_rate_hz)
    pts = scene_targets(scenario, targets)
    if keep_series not in (True, False, "position"):
        raise InputError("keep_series must be True, False or 'position'", field="keep_series", value=keep_series)
    if keep_series and 8 * n_trials * n * (3 + (pts.shape[0] if keep_series is True else 0)) > MAX_SERIES_BYTES:
        raise InputError(f"keeping the series of {n_trials} trials × {n} samples needs more than "
                         f"{MAX_SERIES_BYTES / 1e9:g} GB", field="n_trials",
                         expected="fewer trials or keep_series=False")

    aided = aiding is not None and bool(aiding.aiding)
    coasting = coasts_over_aperture(aiding, scenario.tc_s)
    frame = _frame(scenario, latitude_deg, heading_deg)
    heading = check_flat_earth(scenario, aiding, si, initial_errors, frame["rate"])
    span = (n - 1) / scenario.imu_rate_hz
    if abs(span - scenario.tc_s) > APERTURE_ROUNDING_NOTE * scenario.tc_s:
        warnings.warn(f"{scenario.name}: the aperture is simulated over {n - 1} IMU intervals = "
                      f"{span:.4g} s, {100 * (span / scenario.tc_s - 1):+.1f} % of Tc = {scenario.tc_s:.4g} s "
                      "(a bias's quadratic phase scales with its square): raise imu_rate_hz",
                      UserWarning, stacklevel=2)
    warm = round(aiding.warmup_s * scenario.imu_rate_hz) if aided else 0
    if n + warm > MAX_SAMPLES:
        raise InputError(f"the warm-up and aperture span more than {MAX_SAMPLES:,} IMU samples",
                         field="aiding_warmup_s", value=aiding.warmup_s, expected="a shorter warm-up")
    cost = estimate_cost(scenario, n_trials, aiding, workers)
    if cost["bytes"] > MAX_WORKING_BYTES:
        raise InputError(
            f"this run would hold ≈ {cost['bytes'] / 1e9:.2g} GB at once ({cost['samples']:,} IMU samples "
            f"× {cost['block']}-trial blocks × {min(workers, cost['blocks'])} worker(s); ≈ "
            f"{cost['cpu_s']:.0f} s CPU), more than the {MAX_WORKING_BYTES / 1e9:g} GB a motion run may use",
            field="imu_rate_hz" if not aided else "aiding_warmup_s",
            expected=MOTION_MEMORY_WAY.cli + (", a shorter aiding_warmup_s" if aided else "")
                     + " or a shorter aperture (memory does not depend on the number of trials)")
    ctx = _Context(scenario, si, seed, disturbance, pts, initial_errors, keep_series, prefilter, aiding,
                   frame_rate=frame["rate"])
    if ctx.initial is None or not any(ctx.initial.attitude_sigma_rad):
        frame = None
    aiding_label = ctx.plan.label() if ctx.plan else "none"
    if ctx.plan is not None:
        no_fix = first_fix_note(ctx.plan, ctx.n_warm, ctx.n_total, ctx.rate)
        if no_fix is not None:
            aiding_label += f"; {no_fix}"
            warnings.warn(f"{scenario.name}: {no_fix}", UserWarning, stacklevel=2)
    first = whole_number("first_trial", first_trial, 0)
    if first % ctx.block:
        raise InputError(f"first_trial must be a multiple of the {ctx.block}-trial random-stream block",
                         field="first_trial", value=first_trial)
    chunk = DEFAULT_CHUNK if chunk_size is None else whole_number("chunk_size", chunk_size, 1)
    chunk = -(-chunk // ctx.block) * ctx.block
    k = pts.shape[0]
    out = {name: np.empty((n_trials, k)) for name in METRICS}
    if keep_series:
        out["position_error_m"] = np.empty((n_trials, n, 3))
    if keep_series is True:
        out["range_error_m"] = np.empty((n_trials, k, n))

    lock, done = threading.Lock(), [0]

    def run_chunk(c0: int) -> None:
        for b0 in range(c0, min(c0 + chunk, first + n_trials), ctx.block):
            b1 = min(b0 + ctx.block, first + n_trials)
            _run_block(ctx, b0, b1, out, first)
            if progress is not None:
                with lock:
                    done[0] += b1 - b0
                    progress(done[0], n_trials)

    starts = range(first, first + n_trials, chunk)
    if workers == 1 or len(starts) == 1:
        for c0 in starts:
            run_chunk(c0)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            list(pool.map(run_chunk, starts))
    return MotionResult(scenario=scenario, model_label=_label(model), seed=seed, time_s=ctx.time_s,
                        targets_m=pts, position_error_m=out.pop("position_error_m", None),
                        range_error_m=out.pop("range_error_m", None),
                        aiding=aiding_label, earth_model=earth_model_note(scenario, coasting, frame, heading),
                        prefilter=prefilter.kind if prefilter is not None else "none",
                        options={"disturbance": _dump(disturbance), "initial_errors": _dump(initial_errors),
                                 "aiding_plan": _dump(aiding), "first_trial": first, "keep_series": keep_series,
                                 "latitude_deg": latitude_deg, "heading_deg": heading_deg},
                        **out)


def _frame(scenario: Scenario, latitude_deg, heading_deg) -> dict:
    """Latitude, heading (the defaults where None) and the nav frame's rate ω_in there."""
    lat = DEFAULT_LATITUDE_DEG if latitude_deg is None else latitude_deg
    hdg = DEFAULT_HEADING_DEG if heading_deg is None else heading_deg
    for name, v, lim in (("latitude_deg", lat, 89.0), ("heading_deg", hdg, 360.0)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or abs(v) > lim:
            raise InputError(f"{name} must be a finite number of degrees", field=name, value=v,
                             expected=f"−{lim:g} … {lim:g}")
    rate = navigation_frame_rate(scenario.platform_speed_m_s, math.radians(lat), math.radians(hdg))
    return {"latitude_deg": float(lat), "heading_deg": float(hdg), "rate": rate,
            "latitude_default": latitude_deg is None, "heading_default": heading_deg is None}


def heading_term(scenario: Scenario, plan: AidingPlan | None, model_si: NoiseModelSI,
                 initial: InitialErrors | None, frame_rate_n_rad_s) -> dict | None:
    """Size of the heading term an aided coast leaves out (:data:`HEADING_TERM_NOTE`), before the
    run: ``{"sigma_psi_rad", "term_m", "budget_m", "neglect"}`` or None (no aiding, or aiding that
    corrects inside the aperture, :func:`coasts_over_aperture`).

    The flat filter (the engine's own: the IMU's catalog errors, straight level flight at the
    scenario's speed, the plan's sensors) is run as a covariance alone over the warm-up, on a grid
    of the fastest sensor's period (latency ignored): σ_ψ is its heading 1σ at the aperture start —
    the a-priori growth √(σ_ψ0² + (b·W)² + N²·W …) where no sensor observes heading (GNSS, with
    or without a lever arm: in straight flight l × ψ grows like a velocity error), less where one
    does (DVL through V·ψ across track, master INS, star tracker). Over the aperture the Earth and transport rate turn it into the tilt rate
    |ω_in × ẑ|·σ_ψ, a position error g·|ω_in × ẑ|·σ_ψ·Tc³/6 (``term_m``); ``budget_m`` is the 1σ
    (3-D) of the flat coast's error over Tc relative to its start, from the same covariance
    propagated with the process noise; ``neglect`` = term / budget. Measured against the Earth
    model it is of the size of the change it makes (RMS over trials), larger where the Earth
    filter itself observes part of the heading (≥ 20 %: 29 % estimated for 6.7 % measured)."""
    if plan is None or not plan.aiding or not coasts_over_aperture(plan, scenario.tc_s):
        return None
    ini = initial or AIDED_INITIAL
    imu = ImuErrorModel.from_imu_errors(model_si.errors, gm_tau_s=100.0)
    rate = max(a.rate_hz for a in plan.aiding)
    dt = 1.0 / rate
    n_w = int(round(plan.warmup_s * rate))
    n_grid = max(n_w + 1, 2)
    traj = NominalTrajectory(dt_s=dt, f_n=np.broadcast_to(np.array([0.0, 0.0, G0]), (n_grid, 3)),
                             c_bn=np.broadcast_to(np.eye(3), (n_grid, 3, 3)),
                             v_n=np.broadcast_to(np.array([scenario.platform_speed_m_s, 0.0, 0.0]), (n_grid, 3)),
                             constant=True)
    system = build_system(traj, imu, plan.aiding, InitialUncertainty(
        position_m=np.asarray(ini.position_sigma_m), velocity_m_s=np.asarray(ini.velocity_sigma_m_s),
        attitude_rad=np.asarray(ini.attitude_sigma_rad)))
    lay = system.layout["filter"]
    phi, qd = (a[0] for a in system.transitions("filter", 0, 1))
    events: dict[int, list] = {}
    for m in system.measurements:
        for k in system.epochs[m.name]:
            events.setdefault(int(k), []).append(m)
    P = system.P0("filter")
    for k in range(1, n_w + 1):
        P = phi @ P @ phi.T + qd
        for m in events.get(k, ()):
            P = joseph_update(P, system.H("filter", m, k), system.R_filter(m, k))[2]
    att, pos = lay.slice("att"), lay.slice("pos")
    sigma_psi = math.sqrt(max(P[att.start + 2, att.start + 2], 0.0))
    # the coast over Tc: Φ(Tc) and the noise it collects, by doubling
    n_a = max(1, int(round(scenario.tc_s * rate)))
    big, acc = np.eye(lay.n), np.zeros((lay.n, lay.n))
    step, step_q = phi, qd
    while n_a:
        if n_a & 1:
            big, acc = step @ big, step @ acc @ step.T + step_q
        step, step_q = step @ step, step @ step_q @ step.T + step_q
        n_a >>= 1
    d = big[pos] - np.eye(lay.n)[pos]
    budget = math.sqrt(max(np.trace(d @ P @ d.T + acc[pos, pos]), 0.0))
    w_h = float(np.linalg.norm(cross(np.asarray(frame_rate_n_rad_s, dtype=float), np.array([0.0, 0.0, 1.0]))))
    term = G0 * w_h * sigma_psi * scenario.tc_s ** 3 / 6.0
    return {"sigma_psi_rad": sigma_psi, "term_m": term, "budget_m": budget,
            "neglect": 0.0 if term == 0 else (term / budget if budget > 0 else math.inf)}


def check_flat_earth(scenario: Scenario, plan: AidingPlan | None, model_si: NoiseModelSI | None = None,
                     initial: InitialErrors | None = None, frame_rate_n_rad_s=None) -> dict | None:
    """The flat-earth rule (the one place it is applied): a coast across the aperture
    (:func:`coasts_over_aperture`) whose :func:`~budget.nav.earth.flat_earth_neglect` exceeds
    :data:`MAX_FLAT_EARTH_NEGLECT` is refused (Tc ≳ 790 s), and so is an aided run correcting
    inside the aperture with Tc above :data:`AIDED_FLAT_EARTH_MAX_TC_S` (not measured beyond).
    An aided coast (``frozen``, slow ``feedforward``) with ``model_si`` and ``frame_rate_n_rad_s``
    given also counts the heading term of the warm-up (:func:`heading_term`): the coast estimate
    plus its neglect beyond :data:`MAX_FLAT_EARTH_NEGLECT` is refused. Returns the heading term
    (for the result's note) or None."""
    tc = scenario.tc_s
    if coasts_over_aperture(plan, tc):
        neglect = flat_earth_neglect(tc, scenario.platform_speed_m_s)
        if neglect > MAX_FLAT_EARTH_NEGLECT:
            how = "a free-inertial coast" if plan is None or not plan.aiding else \
                f"a coast ({plan.mode} aiding) over the aperture"
            raise InputError(
                f"{how} of Tc = {tc:.4g} s is beyond the flat-earth navigation model: the Schuler, "
                f"Earth-rate and transport-rate terms it neglects change the error by ≈ {100 * neglect:.0f} %",
                field="tc_s (derived)",
                expected=f"Tc ≤ {_max_coast_s(scenario.platform_speed_m_s):.0f} s free-inertial, with "
                         "aiding_mode frozen, or feedforward with aiding_blend_time_s ≥ Tc (smoothed / "
                         "realtime aiding, or feedforward with a blend time below Tc, corrects inside "
                         f"the aperture, up to Tc = {AIDED_FLAT_EARTH_MAX_TC_S:g} s)")
        if model_si is None or frame_rate_n_rad_s is None:
            return None
        head = heading_term(scenario, plan, model_si, initial, frame_rate_n_rad_s)
        if head is not None and neglect + head["neglect"] > MAX_FLAT_EARTH_NEGLECT:
            raise InputError(
                f"a coast ({plan.mode} aiding) of Tc = {tc:.4g} s after a {plan.warmup_s:g} s warm-up is "
                f"beyond the flat-earth navigation model: the {HEADING_TERM_NOTE} (heading 1σ "
                f"{1e3 * head['sigma_psi_rad']:.3g} mrad at the aperture start, {head['term_m']:.3g} m over Tc) "
                f"is ≈ {100 * head['neglect']:.2g} % of the aperture's {head['budget_m']:.3g} m error, which "
                f"the flat model leaves out", field="aiding_warmup_s", value=plan.warmup_s,
                expected=f"neglect ≤ {100 * MAX_FLAT_EARTH_NEGLECT:g} %: a shorter aiding_warmup_s, aiding "
                         "that observes heading (DVL, master INS, star tracker), or realtime / smoothed "
                         "aiding (corrects inside the aperture)")
        return head
    if tc > AIDED_FLAT_EARTH_MAX_TC_S:
        raise InputError(
            f"an aided aperture of Tc = {tc:.4g} s ({plan.mode}) is beyond what the flat-earth "
            f"navigation model was checked for: {AIDED_FLAT_EARTH_NOTE}, growing with Tc",
            field="tc_s (derived)", expected=f"Tc ≤ {AIDED_FLAT_EARTH_MAX_TC_S:g} s with aiding")
    return None


def _max_coast_s(speed_m_s: float) -> float:
    """Longest coast (s) whose :func:`flat_earth_neglect` stays within MAX_FLAT_EARTH_NEGLECT."""
    lo, hi = 0.0, 1e5
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if flat_earth_neglect(mid, speed_m_s) <= MAX_FLAT_EARTH_NEGLECT else (lo, mid)
    return lo


def _dump(options) -> dict | None:
    """JSON-ready dict of a pydantic options model (None stays None)."""
    return None if options is None else options.model_dump(mode="json")
