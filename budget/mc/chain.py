"""One Monte Carlo trial chain: IMU errors → APC motion error → image → PGA → metrics → verdict.

For each trial:

1. the motion-error engine draws the IMU errors of trial i and propagates them to the antenna
   phase-centre error e(t) = true − IMU-measured (:func:`budget.motion.simulate_motion`);
2. e(t) is interpolated to the pulse times; the echoes come from the nominal (true) track and
   the image is formed with the IMU-measured track, measured = true − e, so the residual enters
   the image exactly as in a real motion-compensated system (:mod:`budget.sar`);
3. PGA runs on the image of the scene. On the **realistic** scene (clutter at
   ``clutter_to_target_db``, receiver noise at ``snr_db``, many dominant scatterers) PGA sees the
   cluttered, noisy image; the point-target metrics are measured on a clutter-free copy of the
   scene, formed with the same measured track and corrected with PGA's estimate — a real system
   sees exactly that correction, and sidelobe integrals stay free of clutter energy. On the
   **points** scene (five noise-free points) PGA and the metrics see the same image;
4. the verdict, what a real system sees after PGA:

   * the image acceptance (broadening, PSLR, ISLR, peak loss; ``McOptions.acceptance``);
   * range migration: the peak LOS error in range cells (PGA cannot undo it);
   * what PGA cannot remove (:mod:`budget.sar.residual`, the definition the analytic bounds
     share): (estimate − truth) beyond PGA's settled window, energy-weighted rms
     (``residual_phase_rms_deg`` after PGA; before PGA the whole phase error, constant and linear
     removed) ≤ ``max_residual_phase_rms_deg``;
   * PGA's own outcome: "no usable scatterers" → ``pga_failed``, a stall ("did not converge") →
     ``pga_not_converged``. Either is a failure of the trial, never scored as focused (the image
     metrics are still measured on the image corrected with what PGA accumulated).

``pga_error_rms_deg`` (every component of estimate − truth, constant and linear removed,
energy-weighted) and ``fast_phase_rms_deg`` (the TRUE phase beyond PGA's window: what the
analytic bounds assume is left, PGA credited with nothing there) are reported for information. The echoes from the nominal track do not depend on
the trial except the receiver noise, so they are simulated once per setup; each trial draws its
noise from its own stream (``trial_generator(seed, i, SAR_STREAM)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft

from ..errors import InputError
from ..motion import simulate_motion
from ..noise.prefilter import prefilter_for
from ..rng import STREAMS, trial_generator
from ..sar import (SarGeometry, Scene, evaluate, form_image, measure_targets, pga, phase_on_bins,
                   residual_phase_rad, simulate_echoes)
from ..sar.residual import pga_bandwidth_cycles, pga_residual_rms_rad, phase_history_energy
from ..scenario import Scenario
from .options import REALISTIC_SNR_DB, McOptions

SAR_STREAM = STREAMS["sar_receiver_noise"]
#: Random stream of the realistic scene's layout and clutter (keyed by ``McOptions.scene_seed``).
SCENE_STREAM = STREAMS["sar_scene"]
#: Azimuth search half-width (cells) for the metrics: linear phase only shifts a target.
AZ_SEARCH_CELLS = 20.0
#: PGA's smallest window (samples): the settled window when a PGA result does not report one.
PGA_MIN_WINDOW = 8

#: Per-trial metrics reported before and after PGA (worst target).
TRIAL_METRICS = ("azimuth_broadening", "range_broadening", "pslr_db", "islr_db", "peak_loss_db",
                 "residual_phase_rms_deg", "pga_error_rms_deg", "fast_phase_rms_deg")
#: Failure reasons in the order they are reported.
REASONS = ("range_migration", "residual_phase_noise", "broadening", "pslr", "islr", "peak_loss",
           "pga_failed", "pga_not_converged")


def realistic_scene_available() -> bool:
    """True when :meth:`budget.sar.Scene.realistic` (clutter + many scatterers) exists."""
    return callable(getattr(Scene, "realistic", None))


@dataclass
class ChainSetup:
    """What every trial of one scenario shares: geometry, scenes, the noise-free echoes.

    ``scene`` is what PGA sees; ``clean_scene`` the clutter-free, noise-free copy the metrics
    are measured on (the same object on the points scene). ``echoes`` holds the echoes of
    ``scene`` without receiver noise, ``clean_echoes`` those of ``clean_scene``.
    """

    scenario: Scenario
    geom: SarGeometry
    scene: Scene
    echoes: np.ndarray
    options: McOptions
    clean_scene: Scene | None = None
    clean_echoes: np.ndarray | None = None
    scene_kind: str = "points"
    snr_db: float | None = None

    @classmethod
    def build(cls, scenario: Scenario, options: McOptions | None = None,
              scene: Scene | None = None) -> "ChainSetup":
        options = options or McOptions()
        geom = SarGeometry.from_scenario(scenario, window=options.window_for(scenario))
        kind = options.scene
        if kind == "auto":
            kind = "realistic" if realistic_scene_available() else "points"
        if scene is not None:
            kind = "custom"
        if kind == "realistic" and not realistic_scene_available():
            raise InputError("the realistic scene builder is not available in this version",
                             field="scene", value="realistic", expected="points")
        if kind == "realistic":
            snr = REALISTIC_SNR_DB if options.snr_db is None else options.snr_db
            scene = Scene.realistic(geom, clutter_to_target_db=options.clutter_to_target_db,
                                    snr_db=snr, n_scatterers=options.n_scatterers,
                                    rng=trial_generator(options.scene_seed, 0, SCENE_STREAM))
        elif kind == "points":
            scene = Scene.default(geom, snr_db=options.snr_db)
        snr = scene.snr_db
        quiet = scene.model_copy(update={"snr_db": None})  # noise is drawn per trial
        clean = scene.model_copy(update={"snr_db": None, "clutter_to_target_db": None})
        if kind == "realistic":
            # PGA's correction is one azimuth phase for the whole image, so it acts on any point
            # the same way: the metrics are measured on the well-separated five-point pattern
            # (its cuts clear of other targets), formed with the same track and corrected with
            # the estimate from the realistic image. The realistic scatterers, 2 cells apart in
            # range at random azimuths, would put their neighbours' main lobes into each cut.
            clean = Scene.default(geom, snr_db=None)
        clutter_rng = trial_generator(options.scene_seed, 1, SCENE_STREAM)
        echoes = simulate_echoes(geom, quiet, None, clutter_rng if quiet.clutter_to_target_db is not None else None)
        if clean == quiet:
            clean_echoes = echoes
        elif clean.targets:
            clean_echoes = simulate_echoes(geom, clean, None, None)
        else:
            raise InputError("the scene has clutter but no point targets to measure",
                             field="scene", expected="at least one point target")
        return cls(scenario, geom, scene, echoes, options, clean, clean_echoes, kind, snr)

    def describe(self) -> dict:
        """What the verdict was judged on (for results: the user could not know it otherwise)."""
        return {"scene": self.scene_kind, "n_targets": len(self.scene.targets),
                "clutter_to_target_db": self.scene.clutter_to_target_db, "snr_db": self.snr_db,
                "window": self.geom.window_azimuth.label, "image_method": self.options.image_method,
                "n_pulses": int(self.geom.n_pulses), "metrics_on": "five clutter-free points focused with "
                "PGA's estimate from the realistic image" if self.scene_kind == "realistic" else "the PGA image"}


def receiver_noise_echoes(geom: SarGeometry, snr_db: float, rng: np.random.Generator) -> np.ndarray:
    """Range-compressed receiver noise (n_pulses, n_range) at ``snr_db`` — the noise term of
    :func:`budget.sar.simulate_echoes` alone (same level and range window), so the noise-free
    echoes of a scene can be computed once and each trial adds only its own noise."""
    w_r = geom.window_range.samples(geom.band_bins)
    w_a = geom.window_azimuth.samples(geom.n_pulses)
    var_rc = (w_a.sum() ** 2 / (w_a ** 2).sum()) / 10.0 ** (snr_db / 10.0)
    s2 = var_rc * w_r.sum() ** 2 / (w_r ** 2).sum()
    noise = rng.standard_normal((geom.n_pulses, geom.band_bins, 2)) @ np.array([1.0, 1j])
    full = np.zeros((geom.n_pulses, geom.n_range), dtype=complex)
    full[:, geom.range_band_index] = np.sqrt(s2 / 2.0) * noise * w_r[None, :]
    return sfft.ifft(full, axis=1) * (geom.n_range / w_r.sum())


def apply_phase_estimate(image_data: np.ndarray, phase_rad: np.ndarray) -> np.ndarray:
    """The image corrected with a PGA phase estimate (centred azimuth-frequency bins): the phase
    history multiplied by e^{−jφ̂} (Wahl et al. 1994, step 5)."""
    hist = sfft.ifft(image_data, axis=0)
    return sfft.fft(hist * np.exp(-1j * np.fft.ifftshift(phase_rad))[:, None], axis=0)


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


def _weighted_rms_deg(phase_rad: np.ndarray, weight: np.ndarray) -> float:
    ok = np.isfinite(phase_rad)
    if ok.sum() < 3:
        return math.nan
    w = weight[ok] if np.any(weight[ok] > 0) else np.ones(ok.sum())
    x = phase_rad[ok]
    u = np.linspace(-1.0, 1.0, x.size)
    basis = np.stack([np.ones_like(u), u], axis=1)
    coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
    r = x - basis @ coef  # constant and linear only move the image
    return math.degrees(math.sqrt(float(np.sum(w * r * r) / np.sum(w))))


def _pga_kwargs(opt: McOptions) -> dict:
    kw = {"kernel": opt.pga_kernel, "max_iter": opt.pga_max_iter}
    if opt.pga_tol_rad is not None:
        kw["tol_rad"] = opt.pga_tol_rad
    return kw


def run_trial_errors(setup: ChainSetup, error_m: np.ndarray, trial: int, seed: int,
                     peak_range_cells: float, keep_detail: bool = False) -> TrialOutcome:
    """Steps 2–4 for one trial whose APC error at the pulse times is ``error_m`` (n_pulses, 3)."""
    g, opt = setup.geom, setup.options
    measured = -error_m  # true track is nominal; the IMU believes true − error
    img_clean = form_image(g, setup.clean_echoes, measured, method=opt.image_method)
    if setup.snr_db is None and setup.clean_echoes is setup.echoes:
        img_pga = img_clean
    else:
        separate = setup.clean_echoes is not setup.echoes
        extra = None
        if setup.snr_db is not None:
            noise = receiver_noise_echoes(g, setup.snr_db, trial_generator(seed, trial, SAR_STREAM))
            extra = noise if extra is None else extra + noise
        if separate:  # the PGA scene (clutter, scatterers) and the metric points are different scenes
            data = setup.echoes if extra is None else setup.echoes + extra
            img_pga = form_image(g, data, measured, method=opt.image_method)
        else:  # image formation is linear: the noisy image = clean image + image of the noise
            img_pga = img_clean.with_data(img_clean.data + form_image(g, extra, measured, method=opt.image_method).data)
    psi = residual_phase_rad(g, None, measured)
    truth = phase_on_bins(img_clean, g, psi)
    mask = img_clean.aperture_mask()
    energy = phase_history_energy(img_clean.data)
    m_before = measure_targets(img_clean, g, setup.clean_scene, azimuth_search_cells=AZ_SEARCH_CELLS)
    ev_before = evaluate(m_before, opt.acceptance)
    before = _worst(m_before)
    before["residual_phase_rms_deg"] = _weighted_rms_deg(truth[mask], energy[mask])
    before["pga_error_rms_deg"] = math.nan

    res = pga(img_pga.data, **_pga_kwargs(opt))
    failed = res.usable_lines == 0
    estimate = np.zeros_like(truth) if failed else np.asarray(res.phase_error_rad, float)
    after_img = img_clean.with_data(apply_phase_estimate(img_clean.data, estimate))
    m_after = measure_targets(after_img, g, setup.clean_scene, azimuth_search_cells=AZ_SEARCH_CELLS)
    ev_after = evaluate(m_after, opt.acceptance)
    after = _worst(m_after)
    window = getattr(res, "final_window", 0)
    if not window:
        window = res.history[-1]["window"] if res.history else PGA_MIN_WINDOW
    cutoff = pga_bandwidth_cycles(window, mask.size, int(mask.sum()))
    after["residual_phase_rms_deg"] = math.degrees(pga_residual_rms_rad(estimate, truth, mask, energy, cutoff))
    after["pga_error_rms_deg"] = _weighted_rms_deg((estimate - truth)[mask], energy[mask])
    # the analytic bounds' counterpart: the TRUE phase beyond PGA's window (PGA credited with nothing)
    after["fast_phase_rms_deg"] = math.degrees(pga_residual_rms_rad(np.zeros_like(truth), truth, mask, energy, cutoff))
    before["fast_phase_rms_deg"] = after["fast_phase_rms_deg"]

    migrated = opt.max_range_migration_cells is not None and peak_range_cells > opt.max_range_migration_cells
    reasons = set(_image_reasons(ev_after))
    if migrated:
        reasons.add("range_migration")
    if (opt.max_residual_phase_rms_deg is not None
            and not after["residual_phase_rms_deg"] <= opt.max_residual_phase_rms_deg):
        reasons.add("residual_phase_noise")
    if failed:
        reasons.add("pga_failed")
    elif not res.converged:
        reasons.add("pga_not_converged")
    passed_before = ev_before.passed and not migrated
    ordered = [r for r in REASONS if r in reasons]
    resid = after["residual_phase_rms_deg"] if math.isfinite(after["residual_phase_rms_deg"]) else 100.0
    score = max(after["azimuth_broadening"], 0.0) + resid / 10.0 + peak_range_cells / 10.0
    detail = {}
    if keep_detail:
        detail = {"image_before_db": img_clean.magnitude_db(), "image_after_db": after_img.magnitude_db(),
                  "image_pga_input_db": img_pga.magnitude_db(),
                  "azimuth_m": img_clean.azimuth_m, "slant_range_m": img_clean.slant_range_m,
                  "phase_truth_rad": truth, "phase_estimate_rad": estimate,
                  "pga_bandwidth_cycles": cutoff, "evaluation_after": ev_after.reasons}
    return TrialOutcome(trial=trial, passed_before=bool(passed_before), passed_after=not ordered,
                        reasons=ordered, before=before, after=after,
                        peak_range_cells=float(peak_range_cells), pga_converged=bool(res.converged),
                        pga_reason=res.reason, score=float(score), detail=detail)


def _prefilter(model, rate_hz: float, kind: str, samples: int, seed: int):
    """The part's pre-filter (fitted once per process), refused unless its DC gain is within
    1 % of unity on every channel (:meth:`~budget.noise.prefilter.ImuPrefilter.check_dc_gain`)."""
    pre = prefilter_for(model, rate_hz, kind=kind, samples=samples, seed=seed)
    pre.check_dc_gain(rate_hz)
    return pre


def run_chunk(setup: ChainSetup, model, seed: int, start: int, stop: int,
              keep_detail: bool = False) -> list[TrialOutcome]:
    """Trials ``start … stop−1`` (``start`` a multiple of the chunk size) of ``model``. The motion
    engine gives the APC error of the scenario's navigation — free-inertial, or aided in the
    scenario's correction mode (:func:`budget.motion.simulate_motion`, one path for both) —
    after the optional IMU pre-filter."""
    opts = setup.options
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
