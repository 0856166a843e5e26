"""The flat-earth rule of the motion engine: where its flat-earth error propagation holds.

The engine propagates the navigation error flat-earth (:func:`budget.nav.strapdown.propagate_errors`),
except that the Earth and transport rate turn an initial attitude error (:func:`earth_frame`). What it
leaves out — the Schuler, Earth-rate and transport-rate terms over the aperture — is estimated by
:func:`budget.nav.earth.flat_earth_neglect` for a free-inertial coast of Tc, plus, for an aided coast,
the heading error the warm-up leaves unobserved (:func:`heading_term`). One rule,
:func:`check_flat_earth`, refuses a run beyond :data:`MAX_FLAT_EARTH_NEGLECT`; :func:`earth_model_note`
says in the result what was left out and how large it is.
"""

from __future__ import annotations

import math

import numpy as np

from ..aiding import ImuErrorModel, InitialUncertainty, NominalTrajectory, build_system
from ..aiding.kalman import joseph_update
from ..aiding_spec import AidingPlan
from ..errors import InputError
from ..imu.noise_model import NoiseModelSI
from ..nav.earth import (AIDED_FLAT_EARTH_MAX_TC_S, MAX_FLAT_EARTH_NEGLECT, flat_earth_neglect,
                         navigation_frame_rate)
from ..nav.strapdown import COARSE_ALIGNMENT, InitialErrors, cross
from ..scenario import Scenario
from ..units import G0

#: Largest relative effect (dimensionless) of the Schuler, Earth-rate and transport-rate terms
#: the flat-earth propagation leaves out (:func:`budget.nav.earth.flat_earth_neglect`) over a
#: free-inertial coast of Tc: 10 %, reached at Tc ≈ 790 s. Beyond it the flat model's t³ growth
#: overstates the Schuler-bounded error (2× at Tc = 3000 s), so the run is refused.
#: (Defined in :mod:`budget.nav.earth`, where the analytic bounds and the scenario's notes read it.)
#: Aided runs that correct inside the aperture (``realtime``, ``smoothed``, and ``feedforward``
#: with a blend time below Tc): the aiding bounds what the flat-earth neglect does, measured
#: against a truth *and* filter with the Schuler, Earth-rate and transport-rate terms (GNSS 1 Hz
#: σ 5 cm, 60 s warm-up, 50 m/s, 45°): the aided error changes by ≤ 0.6 % (realtime) / 1.2 %
#: (smoothed) at Tc = 3000 s with a 1 deg/h gyro and by ≤ 2.3 % / 5.2 % with 10 deg/h (GNSS
#: 0.1 Hz: 1.4 % / 4.5 %), growing with Tc; not measured beyond, so longer apertures are refused.
#: A long warm-up (3000 s, 10 deg/h, Tc = 30 s: the heading error of :data:`HEADING_TERM_NOTE`)
#: stays inside it: 0.6 % realtime, 2.2 % smoothed, 1.7 % feedforward with a 10 s blend (worst of
#: 4 trials; 1 deg/h: 0.3 % / 1.0 % / 0.15 %). (Defined in :mod:`budget.nav.earth`: the analytic
#: bounds refuse a Tc beyond it too, :func:`budget.bounds.check_bounds_tc`.)
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
        return plan.blend_time_for(tc_s) >= tc_s
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


def earth_frame(scenario: Scenario, latitude_deg, heading_deg) -> dict:
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
    does (DVL through V·ψ across track, master INS, star tracker). Over the aperture the Earth
    and transport rate turn it into the tilt rate
    |ω_in × ẑ|·σ_ψ, a position error g·|ω_in × ẑ|·σ_ψ·Tc³/6 (``term_m``); ``budget_m`` is the 1σ
    (3-D) of the flat coast's error over Tc relative to its start, from the same covariance
    propagated with the process noise; ``neglect`` = term / budget. Measured against the Earth
    model it is of the size of the change it makes (RMS over trials), larger where the Earth
    filter itself observes part of the heading (≥ 20 %: 29 % estimated for 6.7 % measured)."""
    if plan is None or not plan.aiding or not coasts_over_aperture(plan, scenario.tc_s):
        return None
    ini = initial or COARSE_ALIGNMENT
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
    """Longest coast (s) whose :func:`~budget.nav.earth.flat_earth_neglect` stays within MAX_FLAT_EARTH_NEGLECT."""
    lo, hi = 0.0, 1e5
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if flat_earth_neglect(mid, speed_m_s) <= MAX_FLAT_EARTH_NEGLECT else (lo, mid)
    return lo


def earth_model(scenario: Scenario, plan: AidingPlan | None, model_si: NoiseModelSI,
                initial: InitialErrors | None = None, latitude_deg=None, heading_deg=None, *,
                say_frame: bool | None = None) -> tuple[dict, str]:
    """The flat-earth rule applied to a run (:func:`check_flat_earth`, refusing beyond it) and the
    note its result carries (:func:`earth_model_note`): ``(frame, note)`` with ``frame`` of
    :func:`earth_frame`. The frame's sentence is said only when the run has an initial attitude
    error for the Earth and transport rate to turn — the caller's ``initial``, else an aided
    run's :data:`~budget.nav.strapdown.COARSE_ALIGNMENT`; a free-inertial run aligned at the
    aperture start has none (``say_frame`` True says it whatever the run: a verdict states the
    defaults it was judged with). The motion engine and the Monte Carlo's verdict both say this note."""
    frame = earth_frame(scenario, latitude_deg, heading_deg)
    head = check_flat_earth(scenario, plan, model_si, initial, frame["rate"])
    start = initial if initial is not None else (COARSE_ALIGNMENT if plan is not None and plan.aiding else None)
    if say_frame is None:
        say_frame = start is not None and any(start.attitude_sigma_rad)
    said = frame if say_frame else None
    return frame, earth_model_note(scenario, coasts_over_aperture(plan, scenario.tc_s), said, head)
