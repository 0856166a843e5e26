"""The rotation a gyro scale factor and misalignment see (budget.bounds.rotation) and the check
judged on it: closed forms, an independent numerical double integral of the tilt, an independent
random-phase generator for the random part, and the Monte Carlo flying the same manoeuvre."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from budget.bounds import paper_bounds
from budget.bounds.rotation import axis_envelopes, motion_excursion, rotation_excursion
from budget.catalog.io import load_catalog
from budget.check import PARAM_NAMES, check_parts
from budget.errors import InputError
from budget.nav.manoeuvre import PlatformMotion
from budget.nav.platform import Disturbance
from budget.presets import get_preset

J_SF, J_GM = PARAM_NAMES.index("gyro_scale_factor_ppm"), PARAM_NAMES.index("gyro_misalignment_mrad")


def _double_integral(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """∫₀ᵗ∫₀ˢ (θ(u) − θ(0)) du ds by two cumulative trapezoids (independent of the closed form)."""
    first = cumulative_trapezoid(theta - theta[0], t, initial=0.0)
    return cumulative_trapezoid(first, t, initial=0.0)


@pytest.mark.parametrize("theta_rad, tc_s", [(1.0, 3.12), (0.3, 0.49), (1.5, 40.0)])
def test_roll_through_theta_closed_form(theta_rad, tc_s):
    # roll(t) = −(Θ/2)cos(πt/Tc): E(Tc) = Θ·Tc²·(1/4 − 1/π²), so Θ_eq = 2(1/4 − 1/π²)·Θ = 0.297·Θ
    dist = Disturbance(sinusoids=({"axis": "roll", "frequency_hz": 1 / (2 * tc_s), "amplitude_rad": theta_rad / 2,
                                   "phase_rad": -math.pi / 2},))
    exc = rotation_excursion(dist, tc_s)
    assert exc.scale_factor_rad == pytest.approx(2 * (0.25 - 1 / math.pi ** 2) * theta_rad, rel=1e-6)
    assert exc.peak_tilt_rad == pytest.approx(theta_rad, rel=1e-6)
    # a roll alone leaks into the pitch and yaw readings only: no range error from misalignment
    assert exc.misalignment_rad == 0.0 and math.isinf(exc.factor("gyro_misalignment"))
    assert exc.factor("gyro_scale_factor") == pytest.approx(1.0 / exc.scale_factor_rad)


def test_attitude_change_manoeuvre_is_the_closed_form():
    scen = get_preset("missile_borne")
    exc = motion_excursion(PlatformMotion(kind="attitude_change", angle_deg=40.0), scen)
    assert exc.scale_factor_rad == pytest.approx(2 * (0.25 - 1 / math.pi ** 2) * math.radians(40.0), rel=1e-6)
    assert "rolling through 40°" in exc.motion and exc.tc_s == scen.tc_s


@pytest.mark.parametrize("freq_hz, phase_rad, tc_s", [(0.1, 0.0, 3.0), (0.7, 1.1, 2.0), (2.5, -2.0, 0.8)])
def test_sinusoid_against_numerical_double_integral(freq_hz, phase_rad, tc_s):
    amp = 0.02
    dist = Disturbance(sinusoids=({"axis": "roll", "frequency_hz": freq_hz, "amplitude_rad": amp,
                                   "phase_rad": phase_rad},))
    t = np.linspace(0.0, tc_s, 200_001)
    e = _double_integral(t, amp * np.sin(2 * np.pi * freq_hz * t + phase_rad))
    expected = 2.0 * np.max(np.abs(e)) / tc_s ** 2
    exc = rotation_excursion(dist, tc_s)
    assert exc.scale_factor_rad == pytest.approx(expected, rel=2e-3)  # the time grid's max: 1025 points
    tilt = np.abs(amp * (np.sin(2 * np.pi * freq_hz * t + phase_rad) - np.sin(phase_rad)))
    assert exc.peak_tilt_rad == pytest.approx(tilt.max(), rel=2e-3)


def test_random_part_against_an_independent_random_phase_generator():
    # a band of roll noise, 0.2–2 Hz, S = 1e-5 rad²/Hz (≈ 4.2 mrad rms); realisations drawn here as
    # sums of random-phase cosines on a fine grid, double-integrated numerically
    table = {"axis": "roll", "frequency_hz": (0.2, 2.0), "psd_rad2_per_hz": (1e-5, 1e-5)}
    dist = Disturbance(random=(table,))
    tc = 3.0
    _, env = axis_envelopes(dist, tc, k_sigma=1.0, n_time=5)
    sigma_e = env["roll"][-1]
    _, tilt_env = axis_envelopes(dist, tc, k_sigma=1.0, n_time=5, tilt=True)
    sigma_tilt = tilt_env["roll"][-1]
    rng = np.random.default_rng(7)
    f = np.linspace(0.2, 2.0, 600)
    df = f[1] - f[0]
    w = np.full(f.size, df)
    w[[0, -1]] *= 0.5  # trapezoid weights of the band
    amp = np.sqrt(2.0 * 1e-5 * w)
    t = np.linspace(0.0, tc, 3001)
    draws = 1500
    phase = rng.uniform(0, 2 * np.pi, (f.size, draws))
    arg = 2 * np.pi * np.outer(t, f)  # cos(a + φ) = cos a·cos φ − sin a·sin φ, all draws at once
    theta = np.cos(arg) @ (amp[:, None] * np.cos(phase)) - np.sin(arg) @ (amp[:, None] * np.sin(phase))
    first = cumulative_trapezoid(theta - theta[0], t, axis=0, initial=0.0)
    ends = cumulative_trapezoid(first, t, axis=0)[-1]
    tilts = theta[-1] - theta[0]
    # 1500 draws: the sample std is within ≈ 2 × 1.8 % of the truth
    assert np.std(ends) == pytest.approx(sigma_e, rel=0.05)
    assert np.std(tilts) == pytest.approx(sigma_tilt, rel=0.05)


def test_yaw_rotation_exercises_misalignment_only():
    dist = Disturbance(sinusoids=({"axis": "yaw", "frequency_hz": 0.1, "amplitude_rad": 0.05},))
    exc = rotation_excursion(dist, 3.0)
    assert exc.scale_factor_rad == 0.0 and math.isinf(exc.factor("gyro_scale_factor"))
    assert exc.misalignment_rad == pytest.approx(exc.per_axis_rad["yaw"], rel=1e-12)
    assert exc.misalignment_rad > 0


def test_straight_flight_exercises_neither_and_the_check_says_so():
    scen = get_preset("airborne_xband")
    parts = [load_catalog()["MPU-6050"]]
    plain = check_parts(parts, scen)
    straight = check_parts(parts, scen, platform_motion={"kind": "straight"})
    assert np.isfinite(plain.margins[0, 0, J_SF]) and plain.binding_index[0, 0] == J_SF
    assert math.isinf(straight.margins[0, 0, J_SF]) and math.isinf(straight.margins[0, 0, J_GM])
    assert straight.binding_index[0, 0] != J_SF
    others = [j for j in range(len(PARAM_NAMES)) if j not in (J_SF, J_GM)]
    np.testing.assert_array_equal(straight.margins[..., others], plain.margins[..., others])
    text = straight.summary()
    assert "not exercised" in text and "straight" in text
    rot = straight.to_dict()["scenarios"][0]["rotation"]
    assert rot["scale_factor_excursion_rad"] == 0.0
    assert plain.to_dict()["scenarios"][0]["rotation"] is None


@pytest.mark.parametrize("mode", ["paper", "derived"])
def test_check_scales_the_rotation_bounds_by_the_excursion(mode):
    scen = get_preset("airborne_xband")
    parts = list(load_catalog().values())
    motion = PlatformMotion(kind="oscillation")
    base = check_parts(parts, scen, mode=mode)
    moved = check_parts(parts, scen, mode=mode, platform_motion=motion)
    exc = motion_excursion(motion, scen)
    gamma = paper_bounds(scen.tc_s, scen.range_resolution_m).gyro_scale_factor[0]
    if mode == "derived":  # the derived γ bound with the scenario's own assumptions
        from budget.bounds import compute_bounds, scenario_assumptions
        gamma = compute_bounds(scen.tc_s, scen.range_resolution_m, mode,
                               assumptions=scenario_assumptions(mode, scen)).gyro_scale_factor[0]
    for i, p in enumerate(parts):
        if p.gyro_scale_factor_ppm:
            assert moved.margins[i, 0, J_SF] == pytest.approx(
                base.margins[i, 0, J_SF] * exc.factor("gyro_scale_factor"), rel=1e-9)
        if p.gyro_misalignment_mrad:
            assert moved.margins[i, 0, J_GM] == pytest.approx(
                gamma * exc.factor("gyro_misalignment") / (p.gyro_misalignment_mrad * 1e-3), rel=1e-9)
    # the line states what each bound of the check moved by: the misalignment's own bound (seed 004
    # (7), a full cell) becomes the γ bound (half a cell) × Θ_ref/Θ_eq, so it moves by less
    rot = moved.rotation[0]
    j = next(i for i, p in enumerate(parts) if p.gyro_misalignment_mrad)
    assert rot["gyro_misalignment_bound_change"] == pytest.approx(
        moved.margins[j, 0, J_GM] / base.margins[j, 0, J_GM], rel=1e-9)
    assert rot["gyro_scale_factor_bound_change"] == pytest.approx(exc.factor("gyro_scale_factor"), rel=1e-9)
    assert f"gyro misalignment bound × {rot['gyro_misalignment_bound_change']:.3g}" in moved.summary()


def test_bad_motion_and_aperture_are_refused():
    scen = get_preset("airborne_xband")
    with pytest.raises(InputError, match="kind"):
        check_parts([load_catalog()["STIM300"]], scen, platform_motion={"kind": "wobble"})
    with pytest.raises(InputError, match="angle_deg"):
        check_parts([load_catalog()["STIM300"]], scen, platform_motion={"kind": "attitude_change",
                                                                          "angle_deg": -3})
    with pytest.raises(InputError, match="tc_s"):
        rotation_excursion(None, float("nan"))
    with pytest.raises(InputError, match="k_sigma"):
        rotation_excursion(None, 1.0, k_sigma=0.0)


def test_cli_check_with_platform_motion(capsys):
    from budget.cli.main import main
    assert main(["check", "--preset", "airborne_xband", "--part", "MPU-6050", "--platform-motion",
                 "attitude_change"]) == 0
    out = capsys.readouterr().out
    assert "rotation: gyro scale factor and misalignment judged against the motion flown" in out
    assert "gyro SF bound × 3.36" in out
    assert main(["check", "--preset", "airborne_xband", "--manoeuvre-angle", "30"]) == 2
    assert "--platform-motion" in capsys.readouterr().err


def _p_pass(scen, term: str, aware_multiple: float, kind: str) -> float:
    """P(pass after PGA) with ``term`` alone at ``aware_multiple`` × the bound the check judges it
    against under ``kind`` (the γ bound × Θ_ref/Θ_eq for both terms); the single-term model is
    sized in multiples of the straight-flight check's bound of the term (γ, or seed 004 (7))."""
    from budget.mc import McOptions, run_mc
    from budget.mc.consistency import single_term_model
    motion = PlatformMotion(kind=kind)
    pb = paper_bounds(scen.tc_s, scen.range_resolution_m)
    gamma = float(pb.gyro_scale_factor[0])
    own = gamma if term == "gyro_scale_factor" else float(pb.misalignment_rad[0])
    paper_multiple = aware_multiple * motion_excursion(motion, scen).bounds(gamma)[term] / own
    # the points scene, as the measurement record (docs/check.md) states
    opt = McOptions(platform_motion={"kind": kind}, keep_trial_metrics=False, unspecified="zero", scene="points")
    return run_mc(scen, single_term_model(scen, term, paper_multiple), 64, 1, options=opt).p_pass_after


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_monte_carlo_agrees_with_the_motion_aware_gyro_scale_factor_bound():
    """Airborne X-band, the MC flying the manoeuvre the check is judged on (64 trials, seed 1; the
    scale factor drawn per trial with 1σ = the value): a roll through 1 rad passes at 0.25× the
    motion-aware bound (0.84× seed 004's) and fails at 3× (10× seed 004's); the oscillation passes
    at 0.25× its motion-aware bound, which is 17× seed 004's (the 1-rad bound would fail it)."""
    scen = get_preset("airborne_xband")
    assert _p_pass(scen, "gyro_scale_factor", 0.25, "attitude_change") >= 0.95
    assert _p_pass(scen, "gyro_scale_factor", 3.0, "attitude_change") <= 0.4
    assert _p_pass(scen, "gyro_scale_factor", 0.25, "oscillation") >= 0.95


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_monte_carlo_agrees_with_the_motion_aware_gyro_misalignment_bound():
    """The oscillation's gyro misalignment (64 trials, seed 1; six entries drawn per trial with
    1σ = the value): P(pass after PGA) ≥ 0.95 at 0.25× the check's motion-aware bound and ≥ 0.5 at
    1× (measured 1.00 and 0.69; the 50 % crossing 1.60×). Sized on seed 004 (7)'s full cell
    instead of γ's half, the bound would sit at 2× here, where P(pass) = 0.38."""
    scen = get_preset("airborne_xband")
    assert _p_pass(scen, "gyro_misalignment", 0.25, "oscillation") >= 0.95
    assert _p_pass(scen, "gyro_misalignment", 1.0, "oscillation") >= 0.5


@pytest.mark.slow  # CI's second step: 41 s on a fresh clone (fast suite under 10 min on 2 cores)
def test_report_judges_the_check_on_the_monte_carlo_rotation():
    from budget.mc import McOptions
    from budget.report import build_report
    scen = get_preset("airborne_xband")
    rolled = build_report(scen, ["STIM300"], mc_parts=["STIM300"], trials=4,
                          options=McOptions(platform_motion={"kind": "attitude_change"}, scene="points"))
    assert rolled.check.rotation and rolled.check.rotation[0]["scale_factor_excursion_rad"] > 0
    assert "data-key='rotation'" in rolled.html() and "gyro SF bound × 3.36" in rolled.html()
    plain = build_report(scen, ["STIM300"])  # no Monte Carlo: the bounds' own assumption
    assert not plain.check.rotation and "data-key='rotation'" not in plain.html()
