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
rule, :func:`~budget.motion.flat_earth.check_flat_earth`: a coast across the aperture (free-inertial, ``frozen``, or
``feedforward`` blending slower than Tc) whose estimate exceeds :data:`~budget.motion.flat_earth.MAX_FLAT_EARTH_NEGLECT`
(Tc ≳ 790 s) is refused — the coast's estimate includes the heading error an aiding warm-up
leaves unobserved, turned by the Earth and transport rate across the aperture
(:func:`~budget.motion.flat_earth.heading_term`); aiding that corrects inside the aperture bounds the neglect (measured,
:data:`~budget.motion.flat_earth.AIDED_FLAT_EARTH_NOTE`) up to Tc =
:data:`~budget.motion.flat_earth.AIDED_FLAT_EARTH_MAX_TC_S`. A run whose working
memory (:func:`budget.motion.cost.estimate_cost`) exceeds
:data:`~budget.motion.cost.MAX_WORKING_BYTES` is refused. An aperture cut to
whole IMU intervals more than 1 % away from Tc, and an aided run in which no fix reaches the
filter in time (``frozen`` with a warm-up shorter than the first fix), are warned of and said in
the result.

Reproducibility: trials are processed in fixed blocks of :func:`~budget.motion.cost.block_trials` trials; the block
starting at trial i draws from ``trial_generator(seed, i, stream)`` with the streams of
:data:`budget.rng.STREAMS` (IMU, disturbance, initial errors, aiding). A block is always
generated whole, so trial i's numbers depend only on (seed, i, scenario, model, options) —
not on the number of trials, the chunk size (rounded up to whole blocks) or the worker threads.
"""

from __future__ import annotations

import threading
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from pydantic import ValidationError

from ..aiding import InitialUncertainty, correct_free_inertial
from ..aiding.flexure import antenna_flexure_error, simulate_flexure
from ..aiding.measurements import measurement_from_config
from ..aiding_spec import AidingPlan
from ..catalog.fill import resolve_unspecified
from ..errors import InputError, from_validation_error, whole_number
from ..imu.generator import generate_imu_errors
from ..imu.noise_model import NoiseModel, NoiseModelSI, as_noise_model_si
from ..nav.platform import Disturbance, true_motion
from ..nav.strapdown import COARSE_ALIGNMENT, InitialErrors, cross, propagate_errors
from ..rng import STREAMS, trial_generator
from ..scenario import Scenario
from ..units import two_way_wavenumber_rad_m
from .cost import DEFAULT_CHUNK, aperture_samples, block_trials, check_cost
from .flat_earth import earth_model
from .geometry import range_error, scene_targets
from .notes import imu_rate_note, lever_arm_note, platform_note
from .phase import decompose_phase
from .result import METRICS, MotionResult

IMU_STREAM = STREAMS["motion_imu"]
DISTURBANCE_STREAM = STREAMS["motion_disturbance"]
INITIAL_STREAM = STREAMS["motion_initial"]
AIDING_STREAM = STREAMS["motion_aiding"]
#: Refuse to keep series larger than this (bytes); use keep_series=False.
MAX_SERIES_BYTES = 3_000_000_000
MAX_SAMPLES = 2_000_000
#: Aperture simulated over (N − 1)/rate s; a departure from Tc above this fraction is warned of.
APERTURE_ROUNDING_NOTE = 0.01


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


def aperture_span_note(scenario: Scenario) -> str | None:
    """None, or the warning that the aperture is simulated over whole IMU intervals, (N − 1)/rate s,
    more than :data:`APERTURE_ROUNDING_NOTE` away from Tc (a bias's quadratic phase scales with
    its square)."""
    n = aperture_samples(scenario)
    span = (n - 1) / scenario.imu_rate_hz
    if abs(span - scenario.tc_s) <= APERTURE_ROUNDING_NOTE * scenario.tc_s:
        return None
    off = 100 * (span / scenario.tc_s - 1)
    return (f"{scenario.name}: the aperture is simulated over {n - 1} IMU intervals = "
            f"{span:.4g} s, {abs(off):.1f} % {'shorter' if off < 0 else 'longer'} than Tc = "
            f"{scenario.tc_s:.4g} s (a bias's quadratic phase scales with its square): raise "
            "imu_rate_hz")


def engine_notes(scenario: Scenario, aiding: AidingPlan | None = None) -> list[str]:
    """The warnings :func:`simulate_motion` gives for ``scenario`` flown with ``aiding`` (a plan, or
    None: free inertial): the aperture cut to whole IMU intervals (:func:`aperture_span_note`) and an
    aided run with no fix in time (:func:`first_fix_note`). A caller that runs the engine several
    times for one result (the Monte Carlo: its pilot and every chunk) states them once itself and
    passes ``warn_notes=False``. Empty when the engine refuses the aperture's sampling (fewer
    than 5 or more than :data:`MAX_SAMPLES` samples): its error says it then."""
    if not 5 <= aperture_samples(scenario) <= MAX_SAMPLES:
        return []
    out = [note] if (note := aperture_span_note(scenario)) else []
    if aiding is not None and aiding.aiding:
        rate = scenario.imu_rate_hz
        n_warm = int(round(aiding.warmup_s * rate))
        no_fix = first_fix_note(aiding, n_warm, n_warm + aperture_samples(scenario), rate)
        if no_fix is not None:
            out.append(f"{scenario.name}: {no_fix}")
    return out


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
            self.initial = COARSE_ALIGNMENT
        #: keep the APC error series; the range error series too unless only "position" is asked
        self.keep = bool(keep_series)
        self.keep_range = keep_series is True
        self.lever = np.asarray(scenario.lever_arm_m, dtype=float)
        self.wavelength = scenario.wavelength_m
        self.motion = None if (disturbance is not None and disturbance.is_random) else \
            true_motion(scenario.platform_speed_m_s, self.span_time_s, disturbance, imu_dt_s=self.dt)
        if self.plan is not None:
            self.blend_time_s = self.plan.blend_time_for(scenario.tc_s)
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
                    progress=None, unspecified: str = "zero", warn_notes: bool = True) -> MotionResult:
    """Monte Carlo of the motion error of ``n_trials`` apertures of ``scenario`` with IMU ``model``.

    ``model``: :class:`~budget.imu.noise_model.NoiseModel`, catalog ``PartSpec`` or
    ``NoiseModelSI``. ``disturbance``: platform motion (:class:`~budget.nav.platform.Disturbance`);
    ``targets``: scene points (K, 3) in m (default: the scene centre at slant range along the
    LOS); ``initial_errors``: 1σ initial position/velocity/attitude errors (free-inertial:
    default none, the IMU aligned at the aperture start t = 0, as in seed 004; aided: at the
    warm-up start, default :data:`~budget.nav.strapdown.COARSE_ALIGNMENT`, also the filter's initial 1σ). The
    scenario's lever arm (body frame, IMU → APC) applies. ``keep_series``: True keeps the APC
    error (T, N, 3) and range error (T, K, N) series, ``"position"`` the APC error only, False
    neither. ``workers`` > 1 runs chunks on threads; results are identical.
    ``first_trial`` (a multiple of :func:`~budget.motion.cost.block_trials`) simulates trials ``first_trial …
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
    :data:`~budget.motion.flat_earth.DEFAULT_LATITUDE_DEG`, ``DEFAULT_HEADING_DEG``, said in ``earth_model``. They act
    only when there is an initial attitude error (``initial_errors``; an aided run's default).
    ``unspecified``: what to do with a catalog part's empty datasheet terms
    (:func:`budget.catalog.fill.resolve_unspecified`): ``"zero"`` (default: the engine flies the
    terms given, so a one-term model is that term alone; the Monte Carlo passes the model it has
    resolved), ``"fill_grade_typical"`` (the Monte Carlo's and ``sar-budget motion``'s default:
    the grade's typical values, recorded) or ``"refuse"``. The result's ``notes["unspecified"]``
    says what was done, so an empty term is never a silent zero (``sar-budget motion`` ran a
    navigation-grade part's empty VRW as 0, 55× quieter than ``mc``, and said nothing).
    ``progress(done, total)`` (trials) is called after each block (:func:`~budget.motion.cost.estimate_cost`
    gives the cost before the run; one beyond ``MAX_WORKING_BYTES`` is refused).
    ``warn_notes``: give :func:`engine_notes` as :class:`UserWarning` (default); False for a caller
    that states them once for several runs (the Monte Carlo).
    """
    if not isinstance(scenario, Scenario):
        scenario = Scenario.from_dict(scenario) if isinstance(scenario, dict) else scenario
        if not isinstance(scenario, Scenario):
            raise InputError("scenario must be a Scenario", field="scenario")
    if isinstance(model, dict):
        model = NoiseModel.from_dict(model)
    resolution = resolve_unspecified(model, unspecified)
    model = resolution.model
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
    frame, earth_note = earth_model(scenario, aiding, si, initial_errors, latitude_deg, heading_deg)
    span_note = aperture_span_note(scenario)
    if span_note is not None and warn_notes:
        warnings.warn(span_note, UserWarning, stacklevel=2)
    warm = round(aiding.warmup_s * scenario.imu_rate_hz) if aided else 0
    if n + warm > MAX_SAMPLES:
        raise InputError(f"the warm-up and aperture span more than {MAX_SAMPLES:,} IMU samples",
                         field="aiding_warmup_s", value=aiding.warmup_s, expected="a shorter warm-up")
    check_cost(scenario, n_trials, aiding, workers)
    ctx = _Context(scenario, si, seed, disturbance, pts, initial_errors, keep_series, prefilter, aiding,
                   frame_rate=frame["rate"])
    aiding_label = ctx.plan.label() if ctx.plan else "none"
    if ctx.plan is not None:
        no_fix = first_fix_note(ctx.plan, ctx.n_warm, ctx.n_total, ctx.rate)
        if no_fix is not None:
            aiding_label += f"; {no_fix}"
            if warn_notes:
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
                        aiding=aiding_label, earth_model=earth_note,
                        prefilter=prefilter.kind if prefilter is not None else "none",
                        options={"disturbance": _dump(disturbance), "initial_errors": _dump(initial_errors),
                                 "aiding_plan": _dump(aiding), "first_trial": first, "keep_series": keep_series,
                                 "latitude_deg": latitude_deg, "heading_deg": heading_deg,
                                 "unspecified": resolution.to_dict()},
                        notes={"imu_rate": imu_rate_note(scenario, getattr(model, "rate_hz", None)),
                               "lever_arm": lever_arm_note(scenario), "platform": platform_note(disturbance),
                               "unspecified": resolution.summary()},
                        **out)


def _dump(options) -> dict | None:
    """JSON-ready dict of a pydantic options model (None stays None)."""
    return None if options is None else options.model_dump(mode="json")
