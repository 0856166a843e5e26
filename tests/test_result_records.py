"""Results say what they were computed for.

A Monte Carlo verdict records the values of the model it simulated, not just its name.
A user's catalog row may carry a shipped part's id with other figures (a newer datasheet); the
verdict's JSON, frame and result must say which values were judged — the row as written, with
the terms it left empty filled from its grade (and those fills stated). The bounds table of a
scenario names it; a preset's name given where a file is expected names the preset option."""

from __future__ import annotations

import json

import pytest

from budget.catalog.io import get_part
from budget.imu.noise_model import NoiseModel
from budget.mc import McOptions, run_mc
from budget.presets import get_preset


@pytest.fixture(scope="module")
def verdicts():
    shipped = get_part("STIM300")
    # the same id, a user's figures: ARW halved, the accelerometer scale factor left empty
    user = shipped.model_copy(update={"gyro_arw_deg_rt_h": shipped.gyro_arw_deg_rt_h / 2,
                                      "accel_scale_factor_ppm": None})
    s = get_preset("airborne_xband")
    opts = McOptions(unspecified="fill_grade_typical")
    return shipped, user, run_mc(s, shipped, 2, 3, options=opts), run_mc(s, user, 2, 3, options=opts)


@pytest.mark.slow
def test_the_verdict_names_the_values_it_simulated(verdicts):
    shipped, user, r_shipped, r_user = verdicts
    assert r_shipped.model_label == r_user.model_label == "STIM300"  # the names cannot tell them apart
    assert r_shipped.model_spec["gyro_arw_deg_rt_h"] == shipped.gyro_arw_deg_rt_h
    assert r_user.model_spec["gyro_arw_deg_rt_h"] == pytest.approx(shipped.gyro_arw_deg_rt_h / 2, rel=1e-15)
    for r in (r_shipped, r_user):
        d = json.loads(json.dumps(r.to_dict()))  # JSON-ready
        assert d["model_spec"] == r.model_spec
        assert r.to_frame().attrs["model_spec"] == r.model_spec
        assert r.to_frame().attrs["judged_on"] == r.judged_on


def test_a_filled_term_is_recorded_with_its_value_and_said(verdicts):
    _, user, _, r_user = verdicts
    filled = r_user.extra["unspecified_terms"]["filled"]
    fill = next(f for f in filled if f["column"] == "accel_scale_factor_ppm")
    # the model simulated holds the fill, and the record says where it came from
    assert r_user.model_spec["accel_scale_factor_ppm"] == pytest.approx(fill["value"], rel=1e-15)
    assert user.grade in fill["source"]


def test_a_noise_model_file_is_recorded_with_its_effects():
    model = NoiseModel.from_dict({"part_id": "my-model", "grade": "tactical", "gyro_arw_deg_rt_h": 0.15,
                                  "accel_vrw_m_s_rt_h": 0.05,
                                  "effects": [{"name": "sinusoid", "channel": "gyro_z",
                                               "params": {"frequency_hz": 3.0, "amplitude": 1e-5}}]})
    r = run_mc(get_preset("airborne_xband"), model, 1, 0, options=McOptions(unspecified="zero"))
    assert r.model_spec["gyro_arw_deg_rt_h"] == 0.15
    assert r.model_spec["effects"][0]["params"]["frequency_hz"] == 3.0


# --- the CLI's scenario options: a preset's name given as a file, the bounds table's heading ---------

def test_a_preset_name_given_as_a_scenario_file_names_the_preset_option(tmp_path, monkeypatch, capsys):
    from budget.cli.main import main

    monkeypatch.chdir(tmp_path)  # no file of that name here
    assert main(["bounds", "--scenario", "airborne_xband"]) == 2
    err = capsys.readouterr().err.strip()
    assert "is the name of a preset" in err and "--preset airborne_xband" in err and "\n" not in err, err
    assert main(["bounds", "--preset", "missile_borne"]) == 0
    assert capsys.readouterr().out.startswith("Bounds (paper mode) for missile_borne")


# --- the sar demonstration scores a PGA that did not finish as the Monte Carlo does -------------------

def test_an_image_pga_did_not_finish_is_never_scored_as_focused():
    import numpy as np

    from budget.sar import SarGeometry, Scene
    from budget.sar.injected import run_injected_phase_trial, with_pga_outcome
    from budget.sar.pga import pga

    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    ideal = run_injected_phase_trial(g, Scene.default(g, snr_db=None), 0.0, None)
    assert ideal.pga.converged and ideal.evaluation_after.passed  # a clean image passes, PGA finished
    assert with_pga_outcome(ideal.evaluation_after, ideal.pga) is ideal.evaluation_after
    noise = np.random.default_rng(2).standard_normal((64, 128)) * (1 + 1j)
    stalled = pga(noise)  # no scatterer to estimate from: PGA gives up, its image unchanged
    assert not stalled.converged
    judged = with_pga_outcome(ideal.evaluation_after, stalled)
    assert judged.passed is False and judged.reasons[0].startswith("PGA found no usable scatterers")
    assert ideal.evaluation_after.passed  # the evaluation it was given is left as it was


# --- a verdict says when one pulse in flight could not sample the aperture -----------------------

def test_a_range_ambiguous_aperture_is_said_in_the_verdict():
    from budget.catalog.io import get_part
    from budget.mc.notes import range_ambiguity_note
    from budget.sar import SarGeometry

    for name, ambiguous in (("sas_100khz", True), ("airborne_xband", False)):
        s = get_preset(name)
        g = SarGeometry.from_scenario(s)
        # independently: B_a = 2V²Tc/(λR) against one pulse in flight's c/(2R)
        lam = g.c_m_s / s.carrier_frequency_hz
        b_a = 2 * s.platform_speed_m_s ** 2 * s.tc_s / (lam * s.slant_range_m)
        assert g.doppler_bandwidth_hz == pytest.approx(b_a, rel=1e-9)
        assert (b_a > g.c_m_s / (2 * s.slant_range_m)) is ambiguous
        assert bool(range_ambiguity_note(g)) is ambiguous
    note = range_ambiguity_note(SarGeometry.from_scenario(get_preset("sas_100khz")))
    assert f"≤ c/(2R) = {1500 / 200:.3g} Hz" in note
    r = run_mc(get_preset("sas_100khz"), get_part("HG9900"), 1, 0)
    assert r.judged_on["ambiguity_note"] == note and note in r.summary()
