"""The check-vs-Monte-Carlo comparison names causes from facts of the two results, and a
Monte Carlo result says what its platform does (straight, level, unrotated flight)."""

from __future__ import annotations


import numpy as np

from budget.catalog.io import get_part
from budget.mc import McOptions, run_mc
from budget.presets import get_preset
from budget.report.content import check_vs_mc
from mc_stub import stub_mc


def _mc(p, lo, hi, reasons, filled=()):
    return stub_mc(p, lo, hi, reasons, filled, trials=64)


def test_check_pass_mc_fail_names_the_reason_and_the_filled_terms_not_the_fast_phase():
    rec = {"part_id": "P", "verdict": "pass", "binding": "gyro_arw_deg_rt_h", "flag": False}
    out = check_vs_mc(rec, _mc(0.02, 0.0, 0.08, {"range_migration": 53, "pslr": 2},
                               [("accel_bias_repeatability_ug", 224.0, "µg")]))
    assert out["agree"] is False
    assert "range_migration (53 of 64 trials)" in out["reason"]
    assert "accel_bias_repeatability_ug = 224 µg" in out["reason"]
    assert "fast phase" not in out["reason"]


def test_check_pass_mc_fail_on_the_residual_points_to_the_pga_limited_check():
    rec = {"part_id": "P", "verdict": "pass", "binding": "gyro_arw_deg_rt_h", "flag": False}
    out = check_vs_mc(rec, _mc(0.1, 0.05, 0.2, {"residual_phase_noise": 50}))
    assert "PGA-limited check" in out["reason"] and "filled" not in out["reason"]


def test_check_fail_mc_pass_on_a_rotation_term_says_the_simulated_flight_has_none():
    rec = {"part_id": "P", "verdict": "fail", "binding": "gyro_scale_factor_ppm", "flag": False}
    out = check_vs_mc(rec, _mc(1.0, 0.94, 1.0, {}))
    assert out["agree"] is False and "unrotated" in out["reason"]
    rec_bias = dict(rec, binding="accel_bias_instability_ug")
    assert "unrotated" not in check_vs_mc(rec_bias, _mc(1.0, 0.94, 1.0, {}))["reason"]
    assert check_vs_mc(dict(rec, verdict="pass"), _mc(1.0, 0.94, 1.0, {}))["reason"] == ""


def test_mc_states_its_straight_level_flight_and_a_gyro_scale_factor_changes_nothing_in_it():
    """The statement is true: 100× STIM300's gyro scale factor and misalignment leave every
    trial's numbers unchanged (the simulated gyros see no rotation), and the result says that
    the scenario's 5 deg/s platform rate is not simulated."""
    scen, part = get_preset("missile_borne"), get_part("STIM300")
    big = part.model_copy(update={"gyro_scale_factor_ppm": 100 * part.gyro_scale_factor_ppm,
                                  "gyro_misalignment_mrad": 100 * part.gyro_misalignment_mrad})
    opt = McOptions(scene="points")
    a, b = run_mc(scen, part, 8, 3, options=opt), run_mc(scen, big, 8, 3, options=opt)
    ta, tb = a.agg.trial_metrics, b.agg.trial_metrics
    assert ta.keys() == tb.keys() and len(ta["trial"]) == 8
    for k in ta:
        assert np.array_equal(np.asarray(ta[k], float), np.asarray(tb[k], float), equal_nan=True), k
    note = a.judged_on["platform_motion"]
    assert "unrotated" in note and "platform_rate_deg_s = 5" in note and note in a.summary()
