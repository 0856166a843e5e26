"""One result protocol (``budget/__init__.py``): every result object has ``summary() -> str``,
``to_frame() -> pandas.DataFrame`` and ``to_dict() -> dict`` (JSON-serialisable), and the dict
carries the options and inputs the result was computed with.

The classes are discovered by scanning ``budget/`` for classes that define ``summary``; each one
is built here from a small real computation. A class found without a builder fails the test, so
a new result class cannot skip the protocol unseen.
"""

from __future__ import annotations

import ast
import functools
import importlib
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "budget"
SCENARIO = "automotive_24ghz"
PART = "MPU-6050"
RATE_HZ = 100.0

#: Classes with ``summary`` that are not results (models and filters applied to data; their
#: outputs are the results below).
_NOT_RESULTS = {
    "budget.noise.kalman:ArmaKalman": "a Kalman filter built from an ARMA fit; its output is KalmanResult",
    "budget.noise.prefilter:ImuPrefilter": "a set of per-channel filters; its responses are FrequencyResponse",
}

#: Result classes allowed to break the protocol for a stated reason (skipped, the reason shown);
#: empty: every result follows it.
_PENDING: dict[str, str] = {}


def _discover() -> list[str]:
    """``module:Class`` of every class in ``budget/`` that defines a ``summary`` method."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        module = ".".join(("budget",) + path.relative_to(PACKAGE).with_suffix("").parts)
        module = module.removesuffix(".__init__")
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef) and any(
                    isinstance(m, ast.FunctionDef) and m.name == "summary" for m in node.body):
                found.append(f"{module}:{node.name}")
    return found


def _get(d: dict, dotted: str):
    """``d["a"]["b"]`` … for ``"a.b"`` (list items by index)."""
    for key in dotted.split("."):
        d = d[int(key)] if isinstance(d, list) else d[key]
    return d


# ---- small real computations (cached: several results come from one run) ------------------

@functools.cache
def _series() -> np.ndarray:
    """White + flicker + random-walk noise, 20 000 samples at 100 Hz (a gyro-like channel, rad/s)."""
    from budget.noise.synth import imu_noise
    return imu_noise(20_000, RATE_HZ, np.random.default_rng(11), N=1e-3, B=2e-5, K=1e-6)


@functools.cache
def _allan():
    from budget.noise import allan_deviation
    return allan_deviation(_series(), RATE_HZ, channel="gyro_x", unit="rad/s")


@functools.cache
def _arma():
    from budget.noise.pipeline import ArmaOptions, analyse_arma
    return analyse_arma(_series()[:4000], RATE_HZ, channel="gyro_x", options=ArmaOptions(pauta_k=3.5))


@functools.cache
def _aided():
    """A 5 s straight-and-level trajectory with GNSS fixes, 6 trials: truth, filter, smoother."""
    from budget.aiding.ins_error_model import ImuErrorModel, NominalTrajectory
    from budget.aiding.kalman import run_kalman
    from budget.aiding.rts import run_rts
    from budget.aiding.system import InitialUncertainty, build_system, simulate_measurements, simulate_truth
    from budget.aiding_spec import GnssAiding

    traj = NominalTrajectory.straight_level(10.0, 0.1, 51)
    system = build_system(traj, ImuErrorModel(gyro_arw_rad_s_rt_hz=1e-4, accel_vrw_m_s2_rt_hz=5e-3),
                          [GnssAiding(rate_hz=2, sigma_m=1.5)], InitialUncertainty(3.0, 0.1, 1e-3))
    rng = np.random.default_rng(5)
    truth = simulate_truth(system, 6, rng)
    filt = run_kalman(system, simulate_measurements(system, truth, rng))
    return system, truth, filt, run_rts(system, filt)


@functools.cache
def _sar():
    from budget.presets import get_preset
    from budget.sar import SarGeometry, Scene, form_image, simulate_echoes
    g = SarGeometry.from_scenario(get_preset(SCENARIO))
    scene = Scene.default(g, snr_db=None)
    return g, scene, form_image(g, simulate_echoes(g, scene, None))


@functools.cache
def _phase_history():
    """Two point targets seen from a 2° circular pass (S(n, f) evaluated directly)."""
    from budget.sar.phase_history import C_M_S, PhaseHistory
    th = np.radians(np.linspace(-1.0, 1.0, 96))
    ant = np.stack([7090.0 * np.cos(th), 7090.0 * np.sin(th), np.full(th.size, 7276.0)], axis=1)
    f = 9.6e9 + 3e6 * np.arange(64)
    r0 = np.linalg.norm(ant, axis=1)
    s = np.zeros((ant.shape[0], f.size), complex)
    for p in (np.zeros(3), np.array([2.0, -3.0, 0.0])):
        s += np.exp(-4j * np.pi * f[None, :] / C_M_S * (np.linalg.norm(ant - p, axis=1) - r0)[:, None])
    return PhaseHistory(samples=s.astype(np.complex64), frequency_hz=f, antenna_m=ant, scene_range_m=r0,
                        pulse_source=np.array(["synthetic"] * ant.shape[0]))


def _focus_options():
    from budget.sar.focus import FocusOptions
    return FocusOptions(range_extent_m=16, azimuth_extent_m=16, spacing_m=0.5, workers=1)


@functools.cache
def _gap_log():
    import gap_truth as gt
    from budget.gap import log_from_arrays
    rng = np.random.default_rng(21)
    return log_from_arrays({"gyro_z": gt.base_channel("gyro_z", 8192, rng)}, gt.RATE, source="synthetic")


def _gap_model():
    import gap_truth as gt
    from budget.imu import NoiseModel
    return NoiseModel.model_validate(gt.base_model_dict())


def _seed(name):
    return importlib.import_module(f"budget.seeds.{name}")


# builder → (result, {dotted key in to_dict(): the input it must carry})
def _build_bounds():
    from budget.bounds import compute_bounds
    from budget.bounds.derived import DerivedAssumptions
    return compute_bounds([1.0, 10.0], 0.1, "derived", assumptions=DerivedAssumptions(k_sigma=3.0)), \
        {"mode": "derived", "assumptions.k_sigma": 3.0}


def _build_fast_phase():
    from budget.bounds.fast_phase import fast_phase_limits
    return fast_phase_limits(0.0125, [1.0, 10.0], noise_rms_deg=2.0), {"wavelength_m": 0.0125, "noise_rms_deg": 2.0}


def _build_fast_phase_residual():
    from budget.bounds import fast_phase_residual
    from budget.catalog.io import get_part
    from budget.presets import get_preset
    si = get_part("ADIS16405").to_si()
    return fast_phase_residual(get_preset("automotive_77ghz"), si, pga_bandwidth_cycles=2.05, aperture_window="rect"), \
        {"scenario": "automotive_77ghz", "pga_bandwidth_cycles": 2.05, "aperture_window": "rect", "limit_deg": 1.0}


def _build_rotation():
    from budget.bounds.rotation import motion_excursion
    from budget.nav.manoeuvre import PlatformMotion
    from budget.presets import get_preset
    scen = get_preset(SCENARIO)
    return (motion_excursion(PlatformMotion(kind="oscillation"), scen),
            {"tc_s": scen.tc_s, "k_sigma": 2.0, "reference_excursion_rad": 1.0})


def _build_check():
    from budget.catalog.io import load_catalog
    from budget.check import check_parts
    from budget.presets import get_preset
    parts = list(load_catalog().values())[:4]
    return check_parts(parts, get_preset(SCENARIO), mode="derived"), \
        {"mode": "derived", "scenarios.0.name": SCENARIO, "scenarios.0.parts.0.part_id": parts[0].part_id}


def _build_grade():
    from budget.catalog.io import load_grades
    from budget.recommend import recommend_grade
    return recommend_grade([1.0, 10.0], 0.1, list(load_grades().values()), use="typical"), \
        {"use": "typical", "mode": "paper", "rows.1.tc_s": 10.0}


def _build_resolution():
    from budget.catalog.fill import resolve_unspecified
    from budget.catalog.io import get_part
    return resolve_unspecified(get_part("ADIS16465-1"), "fill_grade_typical"), {"policy": "fill_grade_typical"}


def _build_mc():
    from budget.catalog.io import get_part
    from budget.mc import McOptions, run_mc
    from budget.presets import get_preset
    opts = McOptions(pga_max_iter=7)
    return run_mc(get_preset(SCENARIO), get_part(PART), 4, 3, options=opts), \
        {"trials": 4, "seed": 3, "scenario": SCENARIO, "model": PART, "options.pga_max_iter": 7}


def _build_motion():
    from budget.catalog.io import get_part
    from budget.motion import simulate_motion
    from budget.presets import get_preset
    return simulate_motion(get_preset(SCENARIO), get_part(PART), 4, 5, keep_series=False), \
        {"trials": 4, "seed": 5, "scenario_spec.name": SCENARIO, "options.keep_series": False}


def _build_allan():
    return _allan(), {"rate_hz": RATE_HZ, "samples": _series().size, "channel": "gyro_x"}


def _build_terms():
    from budget.noise import fit_noise_terms
    return fit_noise_terms(_allan()), {"channel": "gyro_x", "unit": "rad/s"}


def _build_characterization():
    from budget.noise import characterize
    return characterize({"gyro_x": _allan()}, grade="tactical", model_error=0.1), \
        {"options.model_error": 0.1, "options.grade": "tactical", "options.taus": "octave"}


def _build_psd():
    from budget.noise import welch_psd
    return welch_psd(_series(), RATE_HZ, channel="gyro_x", unit="rad/s"), {"rate_hz": RATE_HZ, "channel": "gyro_x"}


def _build_preprocessed():
    return _arma().pre, {"samples": 4000}


def _build_checks():
    return _arma().checks, {"alpha": 0.05}


def _build_arma_fit():
    return _arma().selection.selected, {"method": "ls"}


def _build_arma_selection():
    return _arma().selection, {}


def _build_kalman_result():
    return _arma().smoothed, {"smoothed": True, "samples": 4000}


def _build_response():
    return _arma().response, {"rate_hz": RATE_HZ}


def _build_arma_analysis():
    return _arma(), {"rate_hz": RATE_HZ, "channel": "gyro_x", "options.pauta_k": 3.5}


def _build_model_adequacy():
    a = _arma().adequacy
    return a, {"model": a.model_name, "model_innovations.lags": a.model.lags}


def _build_innovation_test():
    t = _arma().adequacy.filter
    return t, {"samples": t.samples, "ljung_box_q": t.q}


@functools.cache
def _imu_log(tmp: str):
    from budget.noise import read_log
    t = np.arange(2000) / RATE_HZ
    rng = np.random.default_rng(4)
    cols = {"time_s": t, **{f"gyro_{a}_rps": 1e-3 * rng.standard_normal(t.size) for a in "xyz"}}
    cols["gyro_y_rps"][700] = np.nan  # one empty cell: the checks report it (LogReport has a row)
    path = Path(tmp) / "static.csv"
    pd.DataFrame(cols).to_csv(path, index=False)
    return read_log(path, repair=True)


def _build_imu_log(tmp):
    log = _imu_log(tmp)
    return log, {"rate_hz": pytest.approx(RATE_HZ), "n_samples": 2000, "channels": ["gyro_x", "gyro_y", "gyro_z"]}


def _build_log_report(tmp):
    return _imu_log(tmp).issues, {}


def _build_report():
    from budget.catalog.io import load_catalog
    from budget.presets import get_preset
    from budget.report import build_report
    parts = [p.part_id for p in list(load_catalog().values())[:3]]
    return build_report(get_preset(SCENARIO), parts, mode="derived"), {"mode": "derived", "scenario.name": SCENARIO}


def _build_filter():
    return _aided()[2], {"trials": 6, "samples": 51}


def _build_smoother():
    return _aided()[3], {"trials": 6, "samples": 51}


def _build_aided():
    from budget.aiding.chain import run_aided
    system, truth, _, _ = _aided()
    return run_aided(system, truth, np.random.default_rng(8), smoother=True), {"trials": 6}


def _build_consistency():
    from budget.aiding.consistency import nees_report
    _, truth, filt, _ = _aided()
    return nees_report(truth[:, filt.checkpoints] - filt.x_post, filt.p_post, alpha=0.1), {"alpha": 0.1, "trials": 6}


def _build_flexure():
    from budget.aiding.flexure import simulate_flexure
    from budget.aiding_spec import FlexureConfig
    mode = FlexureConfig(frequency_hz=2.0, damping_ratio=0.1, amplitude_m=(1e-3, 1e-3, 5e-4))
    return simulate_flexure(mode, 0.01, 300, 3, np.random.default_rng(2)), {"dt_s": 0.01, "trials": 3, "samples": 300}


def _build_geometry():
    return _sar()[0], {"scenario": SCENARIO}


def _build_irf():
    from budget.sar.point_target import azimuth_irf_metrics
    return azimuth_irf_metrics(np.zeros((3, 128)), "rect"), {"window": "rect"}


def _build_phase_history():
    return _phase_history(), {"pulses": 96, "frequencies": 64}


def _build_ground_image():
    from budget.sar.focus import form_ground_image
    return form_ground_image(_phase_history(), _focus_options(), label="synthetic"), {"label": "synthetic"}


def _build_focus():
    from budget.sar.focus_pga import focus
    return focus(_phase_history(), _focus_options(), "pga"), {"autofocus": "pga", "options.spacing_m": 0.5}


def _build_real_scene_verdict():
    from budget.mc.real_scene import RealSceneOptions, real_scene_verdict
    opt = RealSceneOptions(focus=_focus_options())
    return real_scene_verdict(_phase_history(), PART, trials=1, seed=3, options=opt), \
        {"trials": 1, "seed": 3, "options.platform_speed_m_s": 100.0, "options.focus.spacing_m": 0.5}


def _build_acquisition():
    from budget.sar.acquisition import describe_acquisition
    from budget.sar.focus import ground_grid
    ph = _phase_history()
    return describe_acquisition(ph, ground_grid(ph, _focus_options())), \
        {"pulses": 96, "frequency_samples": 64, "pixel_spacing_m": 0.5}


def _build_sar_image():
    return _sar()[2], {"method": "rda"}


def _build_target_metrics():
    from budget.sar import measure_targets
    g, scene, img = _sar()
    return measure_targets(img, g, scene), {}


def _build_evaluation():
    from budget.sar import evaluate, measure_targets
    g, scene, img = _sar()
    return evaluate(measure_targets(img, g, scene)), {"acceptance.max_broadening": 0.1}


def _build_target_metric_arrays():
    from budget.sar.metrics import TargetMeter
    g, scene, img = _sar()
    return TargetMeter(g, scene, img.azimuth_m, img.slant_range_m).measure(img.data[None]), {}


def _build_scene_reference():
    from budget.mc import McOptions
    from budget.mc.chain import ChainSetup, scene_reference
    from budget.mc.reference import REFERENCE_DRAWS
    from budget.presets import get_preset
    setup = ChainSetup.build(get_preset(SCENARIO), McOptions(scene="realistic", pga_max_iter=7))
    return scene_reference(setup), {"draws": REFERENCE_DRAWS}


def _build_pga():
    from budget.sar import pga
    return pga(_sar()[2].data), {}


def _build_scene():
    return _sar()[1], {}


def _build_injected():
    from budget.sar import smooth_phase_error
    from budget.sar.injected import run_injected_phase_trial
    from budget.sar.phase import normalised_time
    g, scene, _ = _sar()
    psi = smooth_phase_error(normalised_time(g), quadratic_rad=3.0, cubic_rad=1.0)
    return run_injected_phase_trial(g, scene, psi, None, kernel="ml"), {"geometry.scenario": SCENARIO}


def _build_gap():
    from budget.gap import run_gap
    # one channel: the workflow raises S to 48 (≥ 48 leave-one-out gaps); ask for what it uses
    return run_gap(_gap_log(), _gap_model(), seed=2, realizations=48, max_steps=1, check_tau_range=False), \
        {"seed": 2, "realizations": 48}


def _build_crossval():
    import gap_truth as gt
    from budget.gap import cross_validate, log_from_arrays
    other = log_from_arrays({"gyro_z": gt.base_channel("gyro_z", 8192, np.random.default_rng(22))}, gt.RATE,
                            source="synthetic 2")
    return cross_validate(_gap_log(), other, _gap_model(), seed=2, realizations=4, max_steps=1,
                          check_tau_range=False), {}


def _build_master_slave():
    m = _seed("master_slave")
    p = m.MasterSlaveParams(trials=2, imaging_periods_s=(1.0,))
    return m.run_master_slave(p, rng=np.random.default_rng(1)), {"params.trials": 2, "trials": 2}


def _build_transfer():
    m = _seed("transfer_alignment")
    p = m.TransferParams(trials=2, rate_hz=20.0, duration_s=80.0, imaging_s=20.0)
    return m.run_transfer_alignment(p, rng=np.random.default_rng(2)), {"params.trials": 2, "params.duration_s": 80.0}


def _build_prf():
    m = _seed("prf_slaving")
    return m.run_prf_slaving(m.PrfParams(trials=2), rng=np.random.default_rng(3)), {"params.trials": 2}


def _build_sonar():
    m = _seed("sonar_fusion")
    p = m.SonarParams(trials=2, warmup_s=20.0)
    return m.run_sonar_fusion(p, rng=np.random.default_rng(4)), {"params.trials": 2, "params.warmup_s": 20.0}


def _build_misalignment():
    m = _seed("large_misalignment")
    p = m.MisalignmentParams(heading_sigma_deg=(0.5, 10.0), trials=2, duration_s=80.0, imaging_s=20.0)
    return m.run_large_misalignment(p, rng=np.random.default_rng(5)), \
        {"params.trials": 2, "params.heading_sigma_deg": [0.5, 10.0]}


BUILDERS = {
    "budget.bounds.table:BoundsTable": _build_bounds,
    "budget.bounds.fast_phase:FastPhaseLimits": _build_fast_phase,
    "budget.bounds.fast_phase:FastPhaseResidual": _build_fast_phase_residual,
    "budget.bounds.rotation:RotationExcursion": _build_rotation,
    "budget.check:CheckResult": _build_check,
    "budget.recommend:GradeRecommendation": _build_grade,
    "budget.catalog.fill:Resolution": _build_resolution,
    "budget.mc.result:McResult": _build_mc,
    "budget.motion.result:MotionResult": _build_motion,
    "budget.noise.allan:AllanResult": _build_allan,
    "budget.noise.terms:NoiseTerms": _build_terms,
    "budget.noise.characterize:Characterization": _build_characterization,
    "budget.noise.psd:PsdResult": _build_psd,
    "budget.noise.preprocess:Preprocessed": _build_preprocessed,
    "budget.noise.checks:CheckReport": _build_checks,
    "budget.noise.arma:ArmaFit": _build_arma_fit,
    "budget.noise.arma:ArmaSelection": _build_arma_selection,
    "budget.noise.kalman:KalmanResult": _build_kalman_result,
    "budget.noise.kalman_response:FrequencyResponse": _build_response,
    "budget.noise.pipeline:ArmaAnalysis": _build_arma_analysis,
    "budget.noise.adequacy:ModelAdequacy": _build_model_adequacy,
    "budget.noise.adequacy:InnovationTest": _build_innovation_test,
    "budget.noise.logs:ImuLog": _build_imu_log,
    "budget.noise.log_checks:LogReport": _build_log_report,
    "budget.report.content:Report": _build_report,
    "budget.aiding.kalman:FilterOutput": _build_filter,
    "budget.aiding.rts:SmootherOutput": _build_smoother,
    "budget.aiding.chain:AidedResult": _build_aided,
    "budget.aiding.consistency:ConsistencyReport": _build_consistency,
    "budget.aiding.flexure:FlexureHistory": _build_flexure,
    "budget.sar.geometry:SarGeometry": _build_geometry,
    "budget.sar.point_target:IrfMetrics": _build_irf,
    "budget.sar.phase_history:PhaseHistory": _build_phase_history,
    "budget.sar.focus:GroundImage": _build_ground_image,
    "budget.sar.focus_pga:FocusResult": _build_focus,
    "budget.mc.real_scene:RealSceneVerdict": _build_real_scene_verdict,
    "budget.sar.acquisition:Acquisition": _build_acquisition,
    "budget.sar.image:SarImage": _build_sar_image,
    "budget.sar.metrics:TargetMetricsTable": _build_target_metrics,
    "budget.sar.acceptance:Evaluation": _build_evaluation,
    "budget.sar.pga:PgaResult": _build_pga,
    "budget.mc.reference:SceneReference": _build_scene_reference,
    "budget.sar.metrics:TargetMetricArrays": _build_target_metric_arrays,
    "budget.sar.scene:Scene": _build_scene,
    "budget.sar.injected:InjectedPhaseTrial": _build_injected,
    "budget.gap.report:GapReport": _build_gap,
    "budget.gap.crossval:CrossValidation": _build_crossval,
    "budget.seeds.master_slave:MasterSlaveResult": _build_master_slave,
    "budget.seeds.transfer_alignment:TransferResult": _build_transfer,
    "budget.seeds.prf_slaving:PrfResult": _build_prf,
    "budget.seeds.sonar_fusion:SonarResult": _build_sonar,
    "budget.seeds.large_misalignment:MisalignmentResult": _build_misalignment,
}

DISCOVERED = _discover()


def test_every_result_class_has_a_builder():
    missing = [c for c in DISCOVERED if c not in BUILDERS and c not in _NOT_RESULTS]
    assert not missing, f"result classes with no builder here (add one): {missing}"
    stale = [c for c in list(BUILDERS) + list(_PENDING) + list(_NOT_RESULTS) if c not in DISCOVERED]
    assert not stale, f"listed here but no longer in budget/: {stale}"


@pytest.mark.parametrize("name", [c for c in DISCOVERED if c not in _NOT_RESULTS])
def test_result_protocol(name, tmp_path_factory):
    if name in _PENDING:
        pytest.skip(f"pending: {_PENDING[name]}")
    build = BUILDERS[name]
    module, cls_name = name.split(":")
    cls = getattr(importlib.import_module(module), cls_name)
    for legacy in ("records", "to_json", "to_json_dict", "summary_text"):
        assert not hasattr(cls, legacy), f"{cls_name}.{legacy}: the protocol has one name, to_dict"
    if build in (_build_imu_log, _build_log_report):
        result, carried = build(str(tmp_path_factory.getbasetemp()))
    else:
        result, carried = build()
    assert isinstance(result, cls)

    text = result.summary()
    assert isinstance(text, str) and text.strip(), f"{cls_name}.summary() must be a non-empty str"

    frame = result.to_frame()
    assert isinstance(frame, pd.DataFrame) and not frame.empty, f"{cls_name}.to_frame() is empty"

    d = result.to_dict()
    assert isinstance(d, dict) and d, f"{cls_name}.to_dict() must be a non-empty dict"
    back = json.loads(json.dumps(d))  # plain JSON types only (numpy scalars/arrays fail here)
    for key, value in carried.items():
        got = _get(back, key)
        if isinstance(value, float) and not isinstance(value, bool):
            assert math.isclose(got, value, rel_tol=1e-12), f"{cls_name}.to_dict()[{key!r}] = {got!r}"
        else:
            assert got == value, f"{cls_name}.to_dict()[{key!r}] = {got!r}, computed with {value!r}"
