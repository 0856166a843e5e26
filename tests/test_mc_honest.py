"""An honest verdict: what PGA leaves, the lever arm, the user's acceptance, decisions
on confidence. Fast tests check the definitions against closed forms / independent sampling;
the ``slow`` ones run the Monte Carlo on the presets."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from budget.bounds import (LeverArmAssumptions, compute_bounds, fast_phase_limits, lever_arm_terms,
                           paper_bounds)
from budget.catalog.io import get_part, load_catalog
from budget.errors import InputError
from budget.imu.noise_model import NoiseModel
from budget.mc import McOptions, run_mc
from budget.mc.chain import ChainSetup, run_chunk, run_trial_errors
from budget.mc.receiver_noise import receiver_noise_echoes
from budget.mc.consistency import fast_phase_share, probit_crossing, single_term_model
from budget.mc.sweep import cheapest_passing
from budget.presets import get_preset
from budget.sar import Scene, simulate_echoes
from budget.sar.phase import los_offset_for_phase
from budget.sar.residual import (DEFAULT_PGA_BANDWIDTH_CYCLES, highpass_phase, pga_bandwidth_cycles,
                                 pga_residual_rms_rad, random_walk_highpass_rms, random_walk_rms_quantile)

POINTS = McOptions(scene="points")


def _zero_lever(name: str):
    return get_preset(name).model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})


# --- one definition of "what PGA cannot remove" -------------------------------------------

def test_highpass_splits_sinusoids_at_the_cutoff():
    """A cosine of j/2 cycles (DCT index j) is kept iff j > 2K (its rms amplitude/√2, less the
    2 % of it the cubic also fits); trends up to the cubic are removed whatever their size."""
    n = 400
    t = (np.arange(n) + 0.5) / n
    slow = 0.3 * np.cos(np.pi * 4 * t)     # 2 cycles: inside K = 2.5
    fast = 0.02 * np.cos(np.pi * 12 * t)   # 6 cycles: beyond
    r = highpass_phase(slow + fast + 0.7 + 0.1 * t + 40.0 * t ** 2 - 9.0 * t ** 3, 2.5)
    assert np.sqrt(np.mean(r ** 2)) == pytest.approx(0.98 * 0.02 / math.sqrt(2), rel=0.005)
    assert np.sqrt(np.mean(highpass_phase(slow + 40.0 * t ** 2, 2.5) ** 2)) < 1e-9
    # the MC measure sees only estimate − truth: a perfect estimate leaves nothing
    mask = np.ones(n, bool)
    assert pga_residual_rms_rad(slow + fast, slow + fast, mask, np.ones(n), 2.5) == pytest.approx(0, abs=1e-12)
    assert pga_residual_rms_rad(slow, slow + fast, mask, np.ones(n), 2.5) == pytest.approx(0.98 * 0.02 / math.sqrt(2), rel=0.005)


def test_weighted_highpass_ignores_bins_without_signal():
    """The energy-weighted fit (highpass_phase(..., weight)): uniform weights give the unweighted
    projector; zero-weight bins holding arbitrary values do not change the result on the others;
    a bad weight is refused."""
    n = 200
    u = np.linspace(-1.0, 1.0, n)
    x = 3.0 * u ** 2 + 0.4 * np.cos(np.pi * 2 * (np.arange(n) + 0.5) / n) + 0.05 * np.sin(2 * np.pi * 20 * u)
    assert np.allclose(highpass_phase(x, 2.5, np.ones(n)), highpass_phase(x, 2.5), atol=1e-10)
    w = np.ones(n)
    w[:20] = 0.0
    y = x.copy()
    y[:20] = np.random.default_rng(0).normal(0.0, 50.0, 20)  # junk where there is no signal
    assert np.allclose(highpass_phase(y, 2.5, w)[20:], highpass_phase(x, 2.5, w)[20:], atol=1e-10)
    for bad in (np.zeros(n), -np.ones(n), np.full(n, np.nan), np.ones(n - 1)):
        with pytest.raises(ValueError):
            highpass_phase(x, 2.5, bad)


def test_bandwidth_from_the_window():
    # 8 samples of 462, 313 inside the aperture: 8·313/(2·462) = 2.71 cycles
    assert pga_bandwidth_cycles(8, 462, 313) == pytest.approx(2.7100, rel=1e-4)


@pytest.mark.parametrize("kind,power", [("rw", 0), ("vrw", 1), ("arw", 2)])
def test_random_walk_highpass_exact_against_sampling(kind, power):
    """The exact covariance result against 2,000 sampled random walks (seeded; 5 % ≈ 3σ of the
    sampled mean square)."""
    rng = np.random.default_rng(7)
    n = 300
    dw = rng.standard_normal((2000, n)) * math.sqrt(1.0 / n)
    e = np.cumsum(dw, axis=1)
    for _ in range(power):
        e = np.cumsum(e, axis=1) / n
    r = np.array([highpass_phase(x, 2.5) for x in e])
    assert math.sqrt(np.mean(r ** 2)) == pytest.approx(random_walk_highpass_rms(kind, 2.5), rel=0.05)


def test_fast_phase_limits_use_the_shared_definition():
    lam, tc = 0.03, 3.0
    f = fast_phase_limits(lam, [tc], pga_bandwidth_cycles=2.5, share=None)  # the rms over apertures
    phase_m = math.radians(1.0) * lam / (4 * math.pi)
    assert f.vrw_m_s2_rt_hz[0] * random_walk_highpass_rms("vrw", 2.5) * tc ** 1.5 == pytest.approx(phase_m)
    # the default asks 0.9 of apertures to meet the limit: the rms that far below it
    q = fast_phase_limits(lam, [tc], pga_bandwidth_cycles=2.5)
    assert q.share == 0.9
    assert q.vrw_m_s2_rt_hz[0] * random_walk_rms_quantile("vrw", 0.9, 2.5) == pytest.approx(f.vrw_m_s2_rt_hz[0])
    assert q.arw_rad_s_rt_hz[0] * random_walk_rms_quantile("arw", 0.9, 2.5) == pytest.approx(f.arw_rad_s_rt_hz[0])
    # a wider PGA bandwidth leaves less: the limit relaxes
    assert fast_phase_limits(lam, [tc], pga_bandwidth_cycles=10).vrw_m_s2_rt_hz[0] > f.vrw_m_s2_rt_hz[0]


# --- lever arm ------------------------------------------------------------------------------

def test_lever_arm_bounds_closed_forms():
    tc, dr, lam, d = 3.0, 0.5, 0.03, 0.6
    a = LeverArmAssumptions(lever_arm_m=(d, 0.0, 0.0), platform_rate_deg_s=2.0)
    t = lever_arm_terms(tc, dr, lam, a).set_index("lever_arm_rule")
    mig = t.loc["range migration k·N·√Tc·|d| ≤ δr", "lever_arm_limit"]
    assert math.radians(mig / 60.0) * 2.0 * math.sqrt(tc) * d == pytest.approx(dr)  # deg/√h → rad/√s
    fast = t.loc["PGA residual of N·√t·|d| ≤ 1° on 0.9 of apertures", "lever_arm_limit"]
    assert (math.radians(fast / 60.0) * random_walk_highpass_rms("rw", DEFAULT_PGA_BANDWIDTH_CYCLES)
            * random_walk_rms_quantile("rw", 0.9, DEFAULT_PGA_BANDWIDTH_CYCLES) * math.sqrt(tc) * d
            == pytest.approx(math.radians(1.0) * lam / (4 * math.pi)))
    rms = lever_arm_terms(tc, dr, lam, a.model_copy(update={"fast_residual_share": None})).set_index("lever_arm_rule")
    fast_rms = rms.loc["PGA residual of N·√t·|d| ≤ 1° rms", "lever_arm_limit"]
    assert (math.radians(fast_rms / 60.0) * random_walk_highpass_rms("rw", DEFAULT_PGA_BANDWIDTH_CYCLES) * math.sqrt(tc) * d
            == pytest.approx(math.radians(1.0) * lam / (4 * math.pi)))
    bias = t.loc["b·Tc·|d| ≤ δr", "lever_arm_limit"]
    assert math.radians(bias / 3600.0) * tc * d == pytest.approx(dr)
    # δr/(|d|·Θ) = 0.5/(0.6·6°) = 7.96 rad is beyond 90°: capped there, as seed 004 (7)'s
    # arcsin is, and said beside the table
    mis = t.loc["φm·|d|·Θ ≤ δr", "lever_arm_limit"]
    assert dr / (d * math.radians(2.0 * tc)) > math.pi / 2
    assert mis * 1e-3 == pytest.approx(math.pi / 2)
    assert any("capped at 90°" in n for n in t.attrs["notes"])
    # a faster turn (20 deg/s: Θ = 60°, 796 mrad) keeps the closed form
    fast_turn = lever_arm_terms(tc, dr, lam, a.model_copy(update={"platform_rate_deg_s": 20.0})).set_index("lever_arm_rule")
    assert fast_turn.loc["φm·|d|·Θ ≤ δr", "lever_arm_limit"] * 1e-3 * d * math.radians(20.0 * tc) == pytest.approx(dr)


def test_zero_lever_arm_gives_the_paper_bounds():
    p = paper_bounds([3.0], 0.5).to_frame()
    z = compute_bounds([3.0], 0.5, "lever-arm", wavelength_m=0.03).to_frame()
    pd.testing.assert_frame_equal(p, z)


def test_lever_arm_binds_arw_on_airborne_xband():
    s = get_preset("airborne_xband")
    t = lever_arm_terms(s.tc_s, s.range_resolution_m, s.wavelength_m, LeverArmAssumptions.from_scenario(s))
    arw = t[t["lever_arm_rule"].str.startswith("PGA residual")].iloc[0]
    assert arw["binding"] == "lever arm" and arw["paper_over_lever"] > 10  # 0.1× the paper bound fails


def test_check_flags_paper_vs_fast_phase_disagreement():
    from budget.check import check_parts
    cat = load_catalog(None)
    r = check_parts([cat["ADIS16405"], cat["HG9900"]], get_preset("airborne_xband"))
    recs = {x["part_id"]: x for x in r.to_dict()["scenarios"][0]["parts"]}
    assert recs["ADIS16405"]["verdict"] == "pass" and recs["ADIS16405"]["flag"]
    assert "beyond PGA's window" in recs["ADIS16405"]["flag_reason"]
    assert not recs["HG9900"]["flag"]
    df = r.to_frame()
    assert {"flag", "flag_reason"} <= set(df.columns)


# --- acceptance, options, results -----------------------------------------------------------

@pytest.mark.parametrize("spec", [{"acceptance": {"max_broadening": -0.1}},
                                  {"acceptance": {"max_pslr_db": 3.0}},
                                  {"acceptance": {"max_islr_db": float("nan")}},
                                  {"max_residual_phase_rms_deg": -1.0},
                                  {"max_range_migration_cells": float("nan")},
                                  {"clutter_to_target_db": 5.0},
                                  {"acceptance": {"axes": []}},
                                  {"acceptance": {"axes": ["azimuth", "azimuth"]}},
                                  {"acceptance": {"axes": ["doppler"]}}])
def test_bad_acceptance_specs_are_input_errors(spec):
    with pytest.raises(InputError) as e:
        McOptions.build(**spec)
    assert e.value.field  # names the field


def test_receiver_noise_matches_the_simulator():
    """The per-trial noise is the noise term of simulate_echoes (same level): compare powers."""
    geom = ChainSetup.build(get_preset("automotive_24ghz"), POINTS).geom
    scene = Scene.default(geom, snr_db=20.0)
    quiet = simulate_echoes(geom, scene.model_copy(update={"snr_db": None}))
    ref = simulate_echoes(geom, scene, None, np.random.default_rng(1)) - quiet
    ours = receiver_noise_echoes(geom, 20.0, np.random.default_rng(2))
    assert np.mean(np.abs(ours) ** 2) == pytest.approx(np.mean(np.abs(ref) ** 2), rel=0.03)


def test_pga_stall_is_its_own_failure():
    """One PGA iteration on a strongly defocused image cannot settle: the trial fails with
    ``pga_not_converged`` — never scored as focused."""
    scen = get_preset("automotive_24ghz")
    setup = ChainSetup.build(scen, POINTS.model_copy(update={"pga_max_iter": 1}))
    u = 2.0 * setup.geom.pulse_times_s / setup.geom.aperture_time_s
    err = los_offset_for_phase(setup.geom, 4.0 * u ** 2)
    o = run_trial_errors(setup, err, 0, 0, 0.1)
    assert not o.pga_converged and "pga_not_converged" in o.reasons and not o.passed_after


def test_single_term_smoke_zero_lever_arm():
    """4 trials: ARW at 0.1× its paper bound passes after PGA, at 10× fails (airborne X-band,
    lever arm 0); the full 64-trial version on two geometries is marked slow."""
    scen = _zero_lever("airborne_xband")
    setup = ChainSetup.build(scen, POINTS)
    ok = run_chunk(setup, single_term_model(scen, "gyro_arw", 0.1), 5, 0, 4)
    bad = run_chunk(setup, single_term_model(scen, "gyro_arw", 10.0), 5, 0, 4)
    assert all(o.passed_after for o in ok), [o.reasons for o in ok]
    assert not any(o.passed_after for o in bad)


# --- decisions on confidence ----------------------------------------------------------------

def test_probit_crossing_recovers_a_known_curve():
    from scipy.stats import norm
    s = np.logspace(-1, 1, 17)
    p = norm.cdf(-(np.log10(s) - np.log10(0.5)) / 0.3)
    k = np.random.default_rng(3).binomial(64, p)
    fit = probit_crossing(s, k, [64] * 17)
    assert fit["method"] == "probit" and fit["lo"] < 0.5 < fit["hi"] and fit["hi"] / fit["lo"] < 1.5
    sep = probit_crossing(s, [64] * 8 + [0] * 9, [64] * 17)
    assert sep["lo"] == pytest.approx(s[7]) and sep["hi"] == pytest.approx(s[8])
    # one pass of 16 at the smallest scale and none above: the crossing is below the grid
    below = probit_crossing(s, [1] + [0] * 16, [16] * 17)
    assert below["method"] == "below the grid" and below["hi"] == pytest.approx(s[0])
    assert math.isnan(below["scale"])


def test_cheapest_passing_decides_on_the_lower_wilson_bound():
    table = pd.DataFrame([
        {"scenario": "x", "part_id": "cheap", "grade": "industrial", "price_usd": 100.0,
         "p_pass_after": 0.92, "ci_after_lo": 0.83},
        {"scenario": "x", "part_id": "dear", "grade": "tactical", "price_usd": 5000.0,
         "p_pass_after": 1.0, "ci_after_lo": 0.94}])
    best = cheapest_passing(table, 0.9)
    assert best.loc[0, "part_id"] == "dear" and best.loc[0, "decided_on"] == "ci_after_lo"
    assert cheapest_passing(table, 0.9, use_lower_ci=False).loc[0, "part_id"] == "cheap"


# --- slow: the verdict on the presets -----------------------------------------------------

_SI_FIELD = {"accel_bias": "accel_bias_m_s2", "gyro_bias": "gyro_bias_rad_s",
             "accel_vrw": "accel_vrw_m_s2_rt_hz", "gyro_arw": "gyro_arw_rad_s_rt_hz"}


#: Cases where the 0.1× verdict fails less clearly than the analytic bound predicts, as measured.
_BEYOND_WINDOW_CREDIT = {
    ("airborne_xband", "accel_vrw"): "points scene, measured: 0.31 [0.21, 0.43] (20 of 64 pass; 0.11 before PGA's row floor, "
    "0.06 with its former 8-sample window floor): the analytic fast-phase bound (0.034× here) credits PGA "
    "with nothing beyond its settled window, and PGA's fast-phase stage removes part of it",
}


#: Cases where 0.1× passes less clearly than asserted on the realistic scene (the default), as
#: measured (64 trials, seed 1); every one passes 64 of 64 on the points scene:
#: (preset, term) → why a part the analytic share passes is an expected failure of the clutter
#: scene. Empty: the one case it held, the 77 GHz gyro bias at 0.1× (0.953 [0.871, 0.984], 3 of 64
#: trials failing ISLR by more than 3 dB against their perfect-IMU twin), passes since PGA's second
#: pass after a large correction: 1.00 [0.943, 1.00] (64 trials, seed 1; the pass ran on 38 trials,
#: kept on 29).
_CLUTTER_LIMITED: dict[tuple[str, str], str] = {}


def _judge_0p1(preset: str, term: str, res, predicted: float) -> None:
    """The 0.1× verdict against the analytic per-aperture pass share ``predicted``
    (:func:`budget.mc.consistency.fast_phase_share`; the Monte Carlo judges each trial):

    * ≥ 0.995: the part passes by the verdict's rule (lower 95 % Wilson bound ≥ 0.9, 64 trials),
      or — a case of :data:`_CLUTTER_LIMITED` — its point estimate is ≥ 0.9 and the case is an
      expected failure;
    * ≤ 0.05: it fails (P ≤ 0.1), or — on the points scene, :data:`_BEYOND_WINDOW_CREDIT` — PGA's
      fast-phase stage removes part of it, and the verdict still fails it (upper Wilson < 0.5);
    * between: the Monte Carlo's P(pass) agrees with the prediction — the prediction inside its
      99 % Wilson interval. A term that sits 1.5–2× inside its rms bound is not a sure pass:
      one aperture's residual scatters about the rms (77 GHz ARW at 0.1×: 0.98; sonar VRW: 0.89).
    """
    if predicted >= 0.995:
        if res.ci_after[0] >= 0.9:
            return
        assert (preset, term) in _CLUTTER_LIMITED, (predicted, res.summary())
        assert res.p_pass_after >= 0.9, res.summary()
        pytest.xfail(_CLUTTER_LIMITED[(preset, term)])
    elif predicted <= 0.05:
        if res.p_pass_after > 0.1 and (preset, term) in _BEYOND_WINDOW_CREDIT:
            assert res.ci_after[1] < 0.5, (predicted, res.summary())
            pytest.xfail(_BEYOND_WINDOW_CREDIT[(preset, term)])
        assert res.p_pass_after <= 0.1, (predicted, res.summary())
    else:
        from budget.mc.stats import wilson_interval
        lo, hi = wilson_interval(int(round(res.p_pass_after * res.trials)), res.trials, 0.99)
        assert lo <= predicted <= hi, (predicted, (lo, hi), res.summary())


@pytest.mark.slow
@pytest.mark.parametrize("preset,term", [(p, t) for p in ("airborne_xband", "automotive_77ghz")
                                         for t in ("accel_bias", "gyro_bias", "accel_vrw", "gyro_arw")])
def test_single_term_0p1_and_10x_as_the_bounds_predict(preset, term):
    """One term at 0.1× and 10× its paper bound, lever arm 0. At 10× every term fails: the noise
    terms with P ≤ 0.1; a turn-on bias is a Gaussian draw with 1σ = 10× its bound, so a trial whose
    draw falls within the crossing s₅₀ (≈ 2× on X band, above 1× on 77 GHz, P = 0.81 there at 1×)
    passes, with probability 2Φ(0.674·s₅₀/10) − 1 ≈ 11 % for s₅₀ = 2 (measured 7/64 for the 77 GHz
    accel bias once the image holds its defocus, budget.mc.defocus): held to P ≤ 0.25 and the
    verdict's own rule (upper 95 % Wilson bound < 0.5), as on the sonar geometry. At 0.1×
    the verdict is the one the analytic per-aperture pass share predicts (:func:`_judge_0p1`):
    the biases leave no residual beyond PGA's window (P = 1: they must pass), VRW at 0.1× leaves
    ≈ 3° (X band) / 5° (77 GHz) rms beyond it, P ≈ 0 (must fail: the paper's (10) ignores its
    fast phase when δr ≫ λ), ARW 0.3° / 0.54° (P = 1.00 / 0.98)."""
    scen = _zero_lever(preset)
    lo = run_mc(scen, single_term_model(scen, term, 0.1), 64, 1, options=McOptions(unspecified="zero"))
    try:
        ten = single_term_model(scen, term, 10.0)
    except Exception:  # noqa: BLE001 — pydantic refuses it: 10× the 77 GHz noise bounds is beyond
        ten = None     # any IMU the model accepts (VRW > 100 m/s/√h, ARW > 1000 deg/√h)
    if ten is not None:
        hi = run_mc(scen, ten, 64, 1, options=McOptions(unspecified="zero"))
        if term in ("accel_bias", "gyro_bias"):
            assert hi.p_pass_after <= 0.25 and hi.ci_after[1] < 0.5, hi.summary()
        else:
            assert hi.p_pass_after <= 0.1, hi.summary()
    _judge_0p1(preset, term, lo, fast_phase_share(scen, single_term_model(scen, term, 0.1)))


@pytest.mark.slow
@pytest.mark.parametrize("term", ["accel_bias", "gyro_bias", "accel_vrw", "gyro_arw"])
def test_single_term_0p1_passes_and_10x_fails_on_the_sonar_geometry(term):
    """A second geometry: the 100 kHz SAS preset (Tc = 10 s, λ = 1.5 cm,
    δr = 5 cm), lever arm 0. Its biases and ARW at 0.1× leave (almost) nothing beyond PGA's
    window, so they must pass after PGA (lower 95 % Wilson bound ≥ 0.9, 64 trials); VRW at 0.1×
    leaves 0.75° rms there (δr/λ = 3.3, against 16 on airborne X-band), which one aperture in
    nine exceeds (predicted share within 1°: 0.89), and the Monte Carlo must agree with that
    (:func:`_judge_0p1`). At 10× the noise terms and the accelerometer bias fail (P ≤ 0.1); a
    gyro turn-on bias drawn with 1σ = 10× its bound is a Gaussian draw, and one within twice the
    bound (|z| < 0.2) has probability 16 %: measured 10/64 pass, so it is held to P ≤ 0.25."""
    scen = _zero_lever("sas_100khz")
    lo = run_mc(scen, single_term_model(scen, term, 0.1), 64, 1, options=McOptions(unspecified="zero"))
    hi = run_mc(scen, single_term_model(scen, term, 10.0), 64, 1, options=McOptions(unspecified="zero"))
    assert hi.p_pass_after <= (0.25 if term == "gyro_bias" else 0.1), hi.summary()
    _judge_0p1("sas_100khz", term, lo, fast_phase_share(scen, single_term_model(scen, term, 0.1)))


@pytest.mark.slow
@pytest.mark.parametrize("term", ["accel_bias", "gyro_bias", "accel_vrw", "gyro_arw"])
def test_single_term_0p1_and_10x_on_a_squinted_aperture(term):
    """Airborne X band at 30° squint (simulated as its broadside equivalent,
    :mod:`budget.sar.squint`; Tc 3.61 s against 3.12 s at broadside), lever arm 0, realistic
    scene: the same rule as at broadside (:func:`_judge_0p1` against the analytic share, which
    projects each source on the squinted line of sight; 10×: P ≤ 0.25 for the biases, ≤ 0.1 for
    the noise terms). Measured
    (64 trials, seed 1): 0.1× 1.00 / 1.00 / 0.00 / 1.00, 10× 0.11 / 0.09 / 0.00 / 0.00."""
    scen = _zero_lever("airborne_xband").model_copy(update={"squint_deg": 30.0})
    lo = run_mc(scen, single_term_model(scen, term, 0.1), 64, 1, options=McOptions(unspecified="zero"))
    hi = run_mc(scen, single_term_model(scen, term, 10.0), 64, 1, options=McOptions(unspecified="zero"))
    assert "squint 30°" in lo.summary()
    if term in ("accel_bias", "gyro_bias"):
        assert hi.p_pass_after <= 0.25 and hi.ci_after[1] < 0.5, hi.summary()
    else:
        assert hi.p_pass_after <= 0.1, hi.summary()
    _judge_0p1("airborne_xband", term, lo, fast_phase_share(scen, single_term_model(scen, term, 0.1)))


@pytest.mark.slow
def test_arw_crossing_on_the_realistic_scene_is_the_analytic_one():
    """On the realistic scene PGA's fast-phase stage keeps no band, so an ARW-only part fails
    where its residual beyond PGA's window exceeds 1°: the Monte Carlo's probit crossing (64
    trials per scale, seed 1, lever arm 0) must contain the scale where the analytic share of
    apertures within 1° is one half (budget.mc.consistency.fast_phase_crossing). Measured:
    0.212× [0.199, 0.225] against 0.210×; per scale 0.97/0.98, 0.92/0.90, 0.73/0.75, 0.44/0.55,
    0.31/0.34, 0.22/0.16, 0.09/0.07 (Monte Carlo / analytic); on airborne X band 0.401×
    [0.380, 0.423] against 0.389×."""
    from budget.mc.consistency import consistency_table
    scen = _zero_lever("automotive_77ghz")
    df = consistency_table(scen, terms=["gyro_arw"], scales=[0.1, 0.13, 0.16, 0.2, 0.25, 0.32, 0.4],
                           trials=64, seed=1)
    row = df.iloc[0]
    assert row["crossing_lo"] <= row["fast_phase_crossing"] <= row["crossing_hi"], df.to_string()
    for _, r in df.iterrows():  # and scale by scale, within the Monte Carlo's 99 % interval
        from budget.mc.stats import wilson_interval
        lo, hi = wilson_interval(int(round(r["p_pass_after"] * 64)), 64, 0.99)
        assert lo <= r["fast_phase_share"] <= hi, df.to_string()


@pytest.mark.slow
@pytest.mark.parametrize("preset", ["airborne_xband", "automotive_77ghz"])
def test_navigation_grade_passes(preset):
    r = run_mc(get_preset(preset), get_part("HG9900", load_catalog(None)), 64, 1)
    assert r.ci_after[0] >= 0.9, r.summary()


@pytest.mark.slow
def test_dominated_part_never_passes_more():
    """Part B is worse than A in every term (A = B/2): P_A never falls below P_B beyond the CIs."""
    scen = get_preset("airborne_xband")
    b = NoiseModel(part_id="B", grade="industrial", source="synthetic", gyro_arw_deg_rt_h=0.6,
                   accel_vrw_m_s_rt_h=0.15, gyro_bias_repeatability_deg_h=20.0,
                   accel_bias_repeatability_ug=3000.0)
    a = NoiseModel(part_id="A", grade="industrial", source="synthetic", gyro_arw_deg_rt_h=0.3,
                   accel_vrw_m_s_rt_h=0.075, gyro_bias_repeatability_deg_h=10.0,
                   accel_bias_repeatability_ug=1500.0)
    opt = McOptions(unspecified="zero")
    ra, rb = run_mc(scen, a, 64, 2, options=opt), run_mc(scen, b, 64, 2, options=opt)
    assert ra.ci_after[1] >= rb.ci_after[0], (ra.summary(), rb.summary())


def _clutter_options(clutter_db: float = -20.0, **kw):
    from budget.mc.chain import realistic_scene_available
    if not realistic_scene_available():
        pytest.skip("Scene.realistic is not available in this tree")
    return McOptions(scene="realistic", clutter_to_target_db=clutter_db, snr_db=30.0, unspecified="zero", **kw)


@pytest.mark.slow
@pytest.mark.parametrize("clutter_db", [-25.0, -20.0])
def test_clutter_scene_small_error_passes(clutter_db):
    """A navigation-grade part (HG9900, catalog) on the realistic scene (SNR 30 dB, lever arm 0):
    its errors are far inside every bound, so the verdict must pass. The image and PGA's residual
    are judged relative to what a perfect IMU gets on the same scene (budget.mc.reference): with no
    motion error at all, PGA's clutter-limited estimate already lifts the Taylor PSLR of the
    clutter-free points from −35 to ≈ −25 dB, which no IMU can be blamed for. (VRW at 0.1× the paper
    bound is not a small error on X band: the fast-phase limit is 0.032× the paper bound.)"""
    scen = _zero_lever("airborne_xband")
    small = run_mc(scen, get_part("HG9900", load_catalog(None)), 64, 1, options=_clutter_options(clutter_db))
    assert small.ci_after[0] >= 0.9, small.summary()
    ref = small.judged_on["reference"]
    assert ref["scene_fails_spec"], ref  # the scene alone exceeds the Taylor spec: said in the result
    assert "perfect-IMU reference" in small.summary()


@pytest.mark.slow
def test_clutter_scene_against_the_bare_spec_fails_every_part():
    """scene_reference="none" applies the spec as it is: then the clutter-limited PGA fails even the
    navigation-grade part (the former behaviour, kept as an option and stated in the result)."""
    scen = _zero_lever("airborne_xband")
    bare = run_mc(scen, get_part("HG9900", load_catalog(None)), 64, 1,
                  options=_clutter_options(-25.0, scene_reference="none"))
    assert bare.p_pass_after <= 0.2, bare.summary()
    assert "reference" not in bare.judged_on


@pytest.mark.slow
def test_clutter_scene_large_error_fails_for_a_stated_reason():
    """An accel bias at 30× its paper bound moves the antenna by tens of range cells: the trial
    must fail, and for range migration (PGA cannot undo it), whatever PGA does on the clutter."""
    scen = _zero_lever("airborne_xband")
    large = run_mc(scen, single_term_model(scen, "accel_bias", 30.0), 64, 1, options=_clutter_options())
    assert large.p_pass_after <= 0.1, large.summary()
    assert large.agg.failure_reasons()["range_migration"] >= 58, large.summary()


def test_cli_bad_acceptance_spec_is_a_clear_error(tmp_path, capsys):
    from budget.cli.main import main
    spec = tmp_path / "acc.json"
    spec.write_text('{"max_pslr_db": 3}')
    assert main(["mc", "--preset", "automotive_24ghz", "--part", "ADIS16405", "--acceptance", str(spec)]) == 2
    err = capsys.readouterr().err
    assert "max_pslr_db" in err and "acc.json" in err  # the line names the spec's file
    spec.write_text('{"axes": []}')  # would turn every cut check off
    assert main(["mc", "--preset", "automotive_24ghz", "--part", "ADIS16405", "--acceptance", str(spec)]) == 2
    assert "acc.json, field acceptance.axes" in capsys.readouterr().err


def test_cli_clutter_level_on_the_points_scene_is_refused(capsys):
    """``--clutter-db`` applies to the realistic scene (the default): with ``--scene points`` it is
    refused naming the option."""
    from budget.cli.main import main
    assert main(["mc", "--preset", "automotive_24ghz", "--part", "ADIS16405", "--scene", "points",
                 "--clutter-db", "-3"]) == 2
    assert "--clutter-db" in capsys.readouterr().err


def test_result_states_the_imu_rate_it_was_simulated_at():
    """A part whose datasheet rate differs from the scenario's imu_rate_hz: the result says which
    rate was simulated and that the part's own was not used."""
    scen = get_preset("automotive_24ghz")
    part = get_part("ADIS16405").model_copy(update={"rate_hz": 100.0})
    r = run_mc(scen, part, 2, 1)
    note = r.judged_on["imu_rate"]
    assert f"imu_rate_hz = {scen.imu_rate_hz:g} Hz" in note and "100 Hz, is not used" in note
    assert note in r.summary()
    same = run_mc(scen, part.model_copy(update={"rate_hz": scen.imu_rate_hz}), 2, 1)
    assert "not used" not in same.judged_on["imu_rate"]


# --- a shifted target is not a defocused one ---------------------------------------------------

def test_a_target_shifted_30_cells_by_a_linear_phase_is_focused_and_only_a_shift_limit_fails_it():
    """A linear phase of 30 cycles over the aperture (a constant line-of-sight velocity error)
    moves every target 30 azimuth cells and defocuses none (a Fourier shift). The metrics must
    find the targets where they went (their search box is the whole image, up to halfway to a
    target in the same range extent), so the trial passes after PGA with a peak shift of 30 ± 1
    cells; an acceptance with a geolocation limit (max_peak_shift_cells = 5) fails it for that
    reason alone."""
    from budget.sar.acceptance import Acceptance

    scen = _zero_lever("airborne_xband")
    setup = ChainSetup.build(scen, POINTS)
    u = 2.0 * setup.geom.pulse_times_s / setup.geom.aperture_time_s
    err = los_offset_for_phase(setup.geom, 30.0 * np.pi * u)
    o = run_trial_errors(setup, err, 0, 0, 0.1)
    assert o.passed_after, o.reasons
    assert o.after["peak_loss_db"] < 0.5 and o.after["pslr_db"] < -30.0  # Taylor −35 dB: ideal
    outcome = {}
    for limit in (5.0, 29.0, 31.0):  # the shift lies between 29 and 31 cells
        opt = POINTS.model_copy(update={"acceptance": Acceptance(max_peak_shift_cells=limit)})
        outcome[limit] = run_trial_errors(ChainSetup.build(scen, opt), err, 0, 0, 0.1).reasons
    assert outcome == {5.0: ["peak_shift"], 29.0: ["peak_shift"], 31.0: []}
