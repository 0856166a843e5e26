"""Platform motion in the Monte Carlo (``McOptions.platform_motion``, budget.nav.manoeuvre): the
gyro scale factor acts as the closed form of a roll manoeuvre says, the verdict sees it when the
platform rotates and not in straight flight, and bad manoeuvres are refused by name."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from budget.errors import InputError
from budget.imu import NoiseModel
from budget.imu.generator import generate_imu_errors
from budget.imu.noise_model import as_noise_model_si
from budget.mc import McOptions, run_mc
from budget.mc.consistency import consistency_table
from budget.motion import simulate_motion
from budget.nav.manoeuvre import PlatformMotion
from budget.nav.platform import Disturbance, true_motion
from budget.presets import get_preset
from budget.rng import STREAMS, trial_generator
from budget.units import G0

XBAND = get_preset("airborne_xband")


def _drawn_gyro_scale_factor(scen, model, dist, seed, n):
    """The per-trial gyro scale factors the motion engine draws for trials 0 … 63 (its IMU stream)."""
    t = np.arange(n) / scen.imu_rate_hz
    mot = true_motion(scen.platform_speed_m_s, t, dist)
    errs = generate_imu_errors(as_noise_model_si(model), 64, n, scen.imu_rate_hz,
                               trial_generator(seed, 0, STREAMS["motion_imu"]),
                               true_rate_rad_s=mot.rate_b_rad_s, true_force_m_s2=mot.force_b_m_s2)
    return errs.gyro_scale_factor


@pytest.mark.parametrize("rate_hz, tol", [(200.0, 0.015), (800.0, 0.004)])
def test_roll_through_theta_gives_the_closed_form_cross_track_error(rate_hz, tol):
    """Gyro scale factor γ on a roll roll(t) = −(Θ/2)cos(πt/Tc): the roll error γ(roll(t) − roll(0))
    tilts the computed frame, gravity leaks into cross-track y, and
    δy(t) = g·γ·(Θ/2)·(t²/2 − (Tc/π)²(1 − cos πt/Tc)) (double integral; true − measured has this
    sign for the engine's frame). Lever arm zero so only the position error counts. The
    tolerance is the strapdown integration's O(dt) lag: 4× smaller at 4× the rate."""
    scen = XBAND.model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0), "imu_rate_hz": rate_hz})
    motion = PlatformMotion(kind="attitude_change")
    dist = motion.disturbance_for(scen)
    model = NoiseModel(gyro_scale_factor_ppm=1000.0)
    res = simulate_motion(scen, model, 16, seed=3, disturbance=dist)
    t, tc = res.time_s, scen.tc_s
    gamma_x = _drawn_gyro_scale_factor(scen, model, dist, 3, t.size)[:16, 0]
    pred = G0 * 0.5 * (t**2 / 2 - (tc / math.pi) ** 2 * (1 - np.cos(math.pi * t / tc)))
    for k in (t.size // 4, t.size // 2, t.size - 1):
        ratio = res.position_error_m[:, k, 1] / (gamma_x * pred[k])
        assert np.all(np.abs(ratio - 1.0) < tol), (k, ratio)
    # roll only: no error along-track or vertical at first order
    assert np.max(np.abs(res.position_error_m[:, :, [0, 2]])) < 1e-6 * np.max(np.abs(res.position_error_m[:, :, 1]))


def test_roll_oscillation_gives_the_closed_form_and_a_bounded_error():
    """A custom roll sinusoid A·sin(ωt): δy(t) = g·γ·A·(t/ω − sin(ωt)/ω²) — a drift (a linear
    phase: an image shift) plus an oscillation of only g·γ·A/ω²."""
    scen = XBAND.model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0), "imu_rate_hz": 800.0})
    a, period = math.radians(2.0), 5.0
    w = 2 * math.pi / period
    dist = Disturbance(sinusoids=[{"axis": "roll", "frequency_hz": 1 / period, "amplitude_rad": a}])
    motion = PlatformMotion(kind="custom", disturbance=dist)
    assert motion.rotates and "roll" in motion.describe(scen)
    model = NoiseModel(gyro_scale_factor_ppm=1000.0)
    res = simulate_motion(scen, model, 8, seed=4, disturbance=motion.disturbance_for(scen))
    t = res.time_s
    gamma_x = _drawn_gyro_scale_factor(scen, model, dist, 4, t.size)[:8, 0]
    pred = G0 * a * (t / w - np.sin(w * t) / w**2)
    k = t.size - 1
    assert np.all(np.abs(res.position_error_m[:, k, 1] / (gamma_x * pred[k]) - 1.0) < 0.005)


def test_gyro_scale_factor_fails_the_verdict_only_when_the_platform_rotates():
    """One term, the gyro scale factor, at 0.1× and 30× seed 004's bound (6) on airborne X-band:
    with the bound's roll through 1 rad it passes at 0.1× and fails at 30× (range migration among
    the reasons: the error reaches ≈ 0.13 δr·scale cross-track); in straight flight 30× passes."""
    bound_ppm = 0.1 * XBAND.range_resolution_m / XBAND.tc_s**2 * 1e6
    roll = McOptions(platform_motion={"kind": "attitude_change"}, scene="points")
    small = run_mc(XBAND, NoiseModel(part_id="sf", gyro_scale_factor_ppm=0.1 * bound_ppm), 64, 1, options=roll)
    big = run_mc(XBAND, NoiseModel(part_id="sf", gyro_scale_factor_ppm=30 * bound_ppm), 64, 1, options=roll)
    straight = run_mc(XBAND, NoiseModel(part_id="sf", gyro_scale_factor_ppm=30 * bound_ppm), 64, 1,
                      options=McOptions(scene="points"))
    assert small.p_pass_after == 1.0
    assert big.ci_after[1] < 0.5 and big.agg.failure_reasons()["range_migration"] > 0
    assert straight.p_pass_after == 1.0
    assert "rolling through 57.3°" in big.judged_on["platform_motion"]
    assert big.options.platform_motion.kind == "attitude_change"
    assert "rolling through" in big.summary()


@pytest.mark.slow
def test_oscillation_verdict_is_the_same_with_two_workers():
    opt = McOptions(platform_motion={"kind": "oscillation", "period_s": 4.0}, scene="points")
    part = NoiseModel(part_id="m", gyro_misalignment_mrad=50.0, gyro_arw_deg_rt_h=0.5)
    a = run_mc(XBAND, part, 128, 2, options=opt)
    b = run_mc(XBAND, part, 128, 2, options=opt, workers=2)
    ta, tb = a.agg.trial_metrics, b.agg.trial_metrics
    for key in ta:
        assert np.array_equal(np.asarray(ta[key], float), np.asarray(tb[key], float), equal_nan=True), key
    assert "±0.637° at a period of 4 s, peak rate 1 deg/s" in a.judged_on["platform_motion"]


def test_gyro_misalignment_moves_the_error_only_with_rotation():
    scen = XBAND.model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    model = NoiseModel(gyro_misalignment_mrad=5.0)
    still = simulate_motion(scen, model, 4, seed=0)
    moving = simulate_motion(scen, model, 4, seed=0,
                             disturbance=PlatformMotion(kind="oscillation").disturbance_for(scen))
    assert np.max(np.abs(still.position_error_m)) == 0.0
    assert np.max(np.abs(moving.position_error_m)) > 1e-6


def test_bad_platform_motions_are_refused_by_name():
    with pytest.raises(InputError, match="period_s does not apply"):
        McOptions.build(platform_motion={"kind": "attitude_change", "period_s": 3.0})
    with pytest.raises(InputError, match="needs a disturbance"):
        McOptions.build(platform_motion={"kind": "custom"})
    with pytest.raises(InputError) as e:
        McOptions.build(platform_motion={"kind": "oscillation", "period_s": -1.0})
    assert "period_s" in str(e.value)
    still = XBAND.model_copy(update={"platform_rate_deg_s": 0.0})
    with pytest.raises(InputError) as e:
        run_mc(still, NoiseModel(), 64, 0, options=McOptions(platform_motion={"kind": "oscillation"}, scene="points"))
    assert e.value.field == "platform_motion.peak_rate_deg_s"
    with pytest.raises(InputError) as e:
        PlatformMotion(kind="oscillation", peak_rate_deg_s=30.0, period_s=60.0).disturbance_for(XBAND)
    assert e.value.field == "platform_motion.period_s" and "±286°" in str(e.value)


def test_consistency_table_refuses_rotation_terms_in_straight_flight():
    with pytest.raises(InputError) as e:
        consistency_table(XBAND, terms=["gyro_scale_factor"], scales=(1.0,), trials=64)
    assert e.value.field == "platform_motion"
    with pytest.raises(InputError, match="unknown error term"):
        consistency_table(XBAND, terms=["gyro_flux"], scales=(1.0,), trials=64)


@pytest.mark.slow
def test_cli_platform_motion_options(tmp_path):
    def run(*args):
        return subprocess.run([sys.executable, "-m", "budget.cli.main", "mc", "--preset", "airborne_xband",
                               "--part", "STIM300", "--trials", "64", "--quiet", "--scene", "points", *args],
                              capture_output=True, text=True)
    r = run("--manoeuvre-period", "3")
    assert r.returncode != 0 and "need --platform-motion" in r.stderr and "Traceback" not in r.stderr
    r = run("--platform-motion", "custom")
    assert r.returncode != 0 and "--disturbance" in r.stderr and "Traceback" not in r.stderr
    dist = tmp_path / "d.json"
    dist.write_text('{"sinusoids": [{"axis": "pitch", "frequency_hz": 0.2, "amplitude_rad": 0.05}]}')
    r = run("--platform-motion", "custom", "--disturbance", str(dist))
    assert r.returncode == 0, r.stderr
    assert "platform disturbance (custom): pitch 0.05 rad at 0.2 Hz" in r.stdout


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_report_states_the_platform_motion_it_was_judged_with(tmp_path):
    from budget.cli.main import main
    out = tmp_path / "r.html"
    assert main(["report", "--preset", "airborne_xband", "--part", "STIM300", "--mc-part", "STIM300",
                 "--trials", "64", "--platform-motion", "attitude_change", "--manoeuvre-angle", "30",
                 "--out", str(out), "--quiet"]) == 0
    text = out.read_text()
    assert "data-key='platform_motion'><small>platform rolling through 30°" in text


def test_sweep_rows_name_the_platform_motion():
    from budget.mc.sweep import sweep
    table = sweep([NoiseModel(part_id="m", gyro_arw_deg_rt_h=0.1)], [XBAND], 64, 1,
                  options=McOptions(platform_motion={"kind": "oscillation"}, scene="points"))
    assert table["platform_motion"].str.startswith("platform oscillating").all()


def test_a_disturbance_must_fly_something_within_bounds():
    for bad, word in (({}, "at least one component"),
                      ({"sinusoids": [{"axis": "sway", "frequency_hz": 1.0, "amplitude_m": 1e9}]}, "1000"),
                      ({"random": [{"axis": "yaw", "frequency_hz": [0.1, 50.0],
                                    "psd_rad2_per_hz": [0.1, 0.1]}]}, "rad rms")):
        with pytest.raises(InputError, match=word):
            McOptions.build(platform_motion={"kind": "custom", "disturbance": bad})


def test_a_disturbance_faster_than_a_tenth_of_the_imu_rate_is_refused():
    """At the interval midpoints the motion error of a scale factor on a component at f is right
    to ≈ (πf/rate)²/6; a 5 Hz roll at 200 Hz gives the closed form within 0.5 % (sampled at the
    interval starts it came out 4.8×), and content above rate/10 is refused."""
    scen = XBAND.model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    a, f = 0.01, 5.0
    w = 2 * math.pi * f
    dist = Disturbance(sinusoids=[{"axis": "roll", "frequency_hz": f, "amplitude_rad": a}])
    model = NoiseModel(gyro_scale_factor_ppm=1000.0)
    res = simulate_motion(scen, model, 8, seed=3, disturbance=dist)
    t = res.time_s
    gamma_x = _drawn_gyro_scale_factor(scen, model, dist, 3, t.size)[:8, 0]
    pred = G0 * a * (t / w - np.sin(w * t) / w**2)
    assert np.all(np.abs(res.position_error_m[:, -1, 1] / (gamma_x * pred[-1]) - 1.0) < 0.005)
    fast = Disturbance(sinusoids=[{"axis": "roll", "frequency_hz": 25.0, "amplitude_rad": a}])
    with pytest.raises(InputError) as e:
        simulate_motion(scen, model, 8, seed=3, disturbance=fast)
    assert e.value.field == "imu_rate_hz" and "250 Hz" in str(e.value)
