"""One Monte Carlo trial chain: IMU errors → APC motion error → image → PGA → metrics.

For each trial (DESIGN.md §3–4):

1. the motion-error engine draws the IMU errors of trial i and propagates them to the antenna
   phase-centre error e(t) = true − IMU-measured (:func:`budget.motion.simulate_motion`);
2. e(t) is interpolated to the pulse times; the echoes come from the nominal (true) track and
   the image is formed with the IMU-measured track, measured = true − e, so the residual enters
   the image exactly as in a real motion-compensated system (:mod:`budget.sar`);
3. image-quality metrics before PGA, PGA, metrics after PGA;
4. the verdict: the image acceptance after PGA, the range migration (peak LOS error in range
   cells — PGA cannot undo it) and the residual phase noise: ``residual_phase_rms_deg`` after
   PGA is the fast part of the true phase error, beyond a smooth Legendre fit of order 10 —
   seed 004 assumes PGA removes linear, quadratic, cubic and slow harmonic errors and limits
   the rest to 1° rms. Before PGA it is the whole phase error (constant and linear removed).
   ``pga_error_rms_deg`` (PGA estimate − truth beyond a cubic fit) is reported for information:
   on the default noise-free scene PGA's own estimation floor is ≈ 0.5–1.1°, and image metrics
   are insensitive to phase noise of a few degrees (σ² ≈ −35 dB of sidelobe energy at 1°). ``fast_phase_rms_deg`` (the true phase beyond a smooth order-10
   Legendre fit) is reported for information: PGA is non-parametric and removes part of it.

The echoes do not depend on the trial when the scene is noise-free (the default), so they are
simulated once per chunk; with ``snr_db`` set, each trial draws its receiver noise from its own
stream (``trial_generator(seed, i, SAR_STREAM)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.polynomial import legendre

from ..errors import InputError
from ..imu.noise_model import as_noise_model_si
from ..motion import simulate_motion
from ..noise.prefilter import calibrate_prefilter
from ..rng import trial_generator
from ..sar import (SarGeometry, Scene, evaluate, form_image, measure_targets, pga, phase_on_bins,
                   residual_phase_rad, simulate_echoes)
from ..sar.phase import normalised_time, remove_linear
from ..scenario import Scenario
from .options import McOptions

SAR_STREAM = 21
#: Azimuth search half-width (cells) for the metrics: linear phase only shifts a target.
AZ_SEARCH_CELLS = 20.0

#: Per-trial metrics reported before and after PGA (worst target).
TRIAL_METRICS = ("azimuth_broadening", "range_broadening", "pslr_db", "islr_db", "peak_loss_db",
                 "residual_phase_rms_deg", "pga_error_rms_deg")
#: Failure reasons in the order they are reported.
REASONS = ("range_migration", "residual_phase_noise", "broadening", "pslr", "islr", "peak_loss",
           "pga_failed")


@dataclass
class ChainSetup:
    """What every trial of one scenario shares: geometry, scene, the noise-free echoes."""

    scenario: Scenario
    geom: SarGeometry
    scene: Scene
    echoes: np.ndarray | None
    options: McOptions

    @classmethod
    def build(cls, scenario: Scenario, options: McOptions | None = None,
              scene: Scene | None = None) -> "ChainSetup":
        options = options or McOptions()
        geom = SarGeometry.from_scenario(scenario)
        scene = scene or Scene.default(geom, snr_db=options.snr_db)
        echoes = None
        if options.snr_db is None and scene.clutter_to_target_db is None:
            echoes = simulate_echoes(geom, scene, None, None)
        return cls(scenario, geom, scene, echoes, options)


@dataclass
class TrialOutcome:
    """Result of one trial (metrics: worst target; angles in degrees, ratios, dB)."""

    trial: int
    passed_before: bool
    passed_after: bool
    reasons: list[str]
    before: dict[str, float]
    after: dict[str, float]
    peak_range_cells: float
    pga_converged: bool
    pga_reason: str
    score: float = 0.0
    detail: dict = field(default_factory=dict)


def _worst(metrics) -> dict[str, float]:
    """Worst value over the targets (and over azimuth/range for PSLR and ISLR)."""
    ts = list(metrics)
    return {
        "azimuth_broadening": max(t.azimuth.broadening for t in ts),
        "range_broadening": max(t.range.broadening for t in ts),
        "pslr_db": max(max(t.azimuth.pslr_db, t.range.pslr_db) for t in ts),
        "islr_db": max(max(t.azimuth.islr_db, t.range.islr_db) for t in ts),
        "peak_loss_db": max(t.peak_loss_db for t in ts),
    }


#: Legendre order of the smooth phase autofocus removes ("linear, quadratic, cubic and slow
#: harmonic", seed 004): up to about five cycles over the aperture.
SMOOTH_ORDER = 10


def residual_noise_deg(diff_rad: np.ndarray, mask: np.ndarray, order: int = 3) -> float:
    """rms (deg) of the PGA estimate minus the true phase over ``mask``, after removing a Legendre
    fit of ``order`` (3): the noise-like part PGA left. The smooth part of the difference (the
    space variance between the scene-centre truth and PGA's average over the targets, a residual
    low-order term) shows in the image metrics (broadening, PSLR) instead."""
    m = mask & np.isfinite(diff_rad)
    if m.sum() <= order + 2:
        return math.nan
    u = np.linspace(-1.0, 1.0, diff_rad.size)[m]
    coef = legendre.legfit(u, diff_rad[m], order)
    return math.degrees(float(np.sqrt(np.mean((diff_rad[m] - legendre.legval(u, coef)) ** 2))))


def fast_phase_rms_deg(psi_pulses: np.ndarray, u: np.ndarray) -> float:
    """rms (deg) of the phase error beyond a Legendre fit of order :data:`SMOOTH_ORDER`: the fast
    part PGA cannot remove, to compare with seed 004's 1° rms limit."""
    coef = legendre.legfit(u, psi_pulses, SMOOTH_ORDER)
    return math.degrees(float(np.sqrt(np.mean((psi_pulses - legendre.legval(u, coef)) ** 2))))


def _image_reasons(evaluation) -> set[str]:
    out = set()
    for r in evaluation.reasons:
        for key, name in (("broadening", "broadening"), ("pslr", "pslr"), ("islr", "islr"),
                          ("peak_loss", "peak_loss")):
            if key in r:
                out.add(name)
    return out


def _to_pulses(time_s: np.ndarray, series: np.ndarray, pulse_times_s: np.ndarray) -> np.ndarray:
    """APC error (N, 3) at IMU times 0…Tc → (n_pulses, 3) at pulse times −T/2…T/2 (linear)."""
    t = pulse_times_s + 0.5 * (time_s[-1] - time_s[0]) + time_s[0]
    t = np.clip(t, time_s[0], time_s[-1])
    return np.stack([np.interp(t, time_s, series[:, k]) for k in range(3)], axis=1)


def run_trial_errors(setup: ChainSetup, error_m: np.ndarray, trial: int, seed: int,
                     peak_range_cells: float, keep_detail: bool = False) -> TrialOutcome:
    """Steps 2–4 for one trial whose APC error at the pulse times is ``error_m`` (n_pulses, 3)."""
    g, opt = setup.geom, setup.options
    measured = -error_m  # true track is nominal; the IMU believes true − error
    data = setup.echoes
    if data is None:
        data = simulate_echoes(g, setup.scene, None, trial_generator(seed, trial, SAR_STREAM))
    img = form_image(g, data, measured, method=opt.image_method)
    psi = residual_phase_rad(g, None, measured)
    truth = phase_on_bins(img, g, psi)
    mask = img.aperture_mask()
    m_before = measure_targets(img, g, setup.scene, azimuth_search_cells=AZ_SEARCH_CELLS)
    ev_before = evaluate(m_before, opt.acceptance)
    before = _worst(m_before)
    before["residual_phase_rms_deg"] = math.degrees(float(np.sqrt(np.nanmean(remove_linear(truth, mask) ** 2))))

    res = pga(img.data, kernel=opt.pga_kernel, max_iter=opt.pga_max_iter, tol_rad=opt.pga_tol_rad)
    after_img = img.with_data(res.image)
    m_after = measure_targets(after_img, g, setup.scene, azimuth_search_cells=AZ_SEARCH_CELLS)
    ev_after = evaluate(m_after, opt.acceptance)
    after = _worst(m_after)
    # PGA that found no scatterers returns the image unchanged: its estimate is zero everywhere
    est_mask = mask & res.estimated_bins if res.usable_lines else mask
    estimate = res.phase_error_rad if res.usable_lines else np.zeros_like(truth)
    after["pga_error_rms_deg"] = residual_noise_deg(estimate - truth, est_mask)
    fast_deg = fast_phase_rms_deg(psi, normalised_time(g))

    reasons = set(_image_reasons(ev_after))
    if opt.max_range_migration_cells is not None and peak_range_cells > opt.max_range_migration_cells:
        reasons.add("range_migration")
    if (opt.max_residual_phase_rms_deg is not None
            and fast_deg > opt.max_residual_phase_rms_deg):
        reasons.add("residual_phase_noise")
    if res.usable_lines == 0:
        reasons.add("pga_failed")
    passed_before = ev_before.passed and not (
        opt.max_range_migration_cells is not None and peak_range_cells > opt.max_range_migration_cells)
    ordered = [r for r in REASONS if r in reasons]
    after["residual_phase_rms_deg"] = fast_deg
    before["pga_error_rms_deg"] = math.nan
    score = max(after["azimuth_broadening"], 0.0) + max(after["residual_phase_rms_deg"], 0.0) / 10.0 \
        + peak_range_cells / 10.0
    detail = {}
    if keep_detail:
        detail = {"image_before_db": img.magnitude_db(), "image_after_db": after_img.magnitude_db(),
                  "azimuth_m": img.azimuth_m, "slant_range_m": img.slant_range_m,
                  "phase_truth_rad": truth, "phase_estimate_rad": estimate,
                  "evaluation_after": ev_after.reasons}
    return TrialOutcome(trial=trial, passed_before=bool(passed_before), passed_after=not ordered,
                        reasons=ordered, before=before, after=after,
                        peak_range_cells=float(peak_range_cells), pga_converged=bool(res.converged),
                        pga_reason=res.reason, score=float(score), detail=detail)


_PREFILTERS: dict = {}


def _prefilter(model, rate_hz: float, kind: str, samples: int, seed: int):
    """The part's pre-filter, calibrated once per (model, rate, kind, samples, seed) and process."""
    si = as_noise_model_si(model)
    key = (repr(si), rate_hz, kind, samples, seed)
    if key not in _PREFILTERS:
        if len(_PREFILTERS) > 32:
            _PREFILTERS.clear()
        _PREFILTERS[key] = calibrate_prefilter(si, rate_hz, kind=kind, samples=samples, seed=seed)
    return _PREFILTERS[key]


def run_chunk(setup: ChainSetup, model, seed: int, start: int, stop: int,
              keep_detail: bool = False) -> list[TrialOutcome]:
    """Trials ``start … stop−1`` (``start`` a multiple of the chunk size) of ``model``; with the
    scenario's ``aiding``, the aided/smoothed solution (:mod:`budget.mc.aided`) replaces the
    free-inertial one."""
    opts = setup.options
    if setup.scenario.aiding and opts.prefilter != "none":
        raise InputError("the ARMA-Kalman pre-filter applies to the free-inertial chain, not with "
                         "aiding", field="prefilter", value=opts.prefilter,
                         expected="prefilter = none when the scenario has aiding")
    if setup.scenario.aiding:
        from .aided import aided_motion
        time_s, series, cells = aided_motion(setup.scenario, model, seed, start, stop)
    else:
        pre = None
        if opts.prefilter != "none":
            pre = _prefilter(model, setup.scenario.imu_rate_hz, opts.prefilter,
                             opts.prefilter_calibration_samples, seed)
        motion = simulate_motion(setup.scenario, model, stop - start, seed, first_trial=start,
                                 keep_series=True, prefilter=pre)
        time_s, series, cells = motion.time_s, motion.position_error_m, motion.peak_range_cells.max(axis=1)
    out = []
    for k in range(stop - start):
        err = _to_pulses(time_s, series[k], setup.geom.pulse_times_s)
        out.append(run_trial_errors(setup, err, start + k, seed, float(cells[k]), keep_detail))
    return out
