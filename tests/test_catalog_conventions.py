"""Bias conventions honoured by the generator, no silent zeros in the Monte Carlo, cheapest part."""

import math

import numpy as np
import pandas as pd
import pytest

from budget.catalog.fill import resolve_unspecified, unspecified_quantities
from budget.catalog.io import get_part, load_catalog, load_grades, read_parts
from budget.catalog.schema import FLICKER_FLOOR, PartSpec
from budget.check import check_parts
from budget.errors import InputError
from budget.imu import NoiseModel, generate_imu_errors
from budget.mc.sweep import cheapest_passing
from budget.presets import get_preset

G0 = 9.80665


def test_total_1sigma_bias_is_a_turn_on_constant_not_flicker():
    """HG1700AG58's 1 mg total 1σ bias: one Gaussian constant per trial (σ = 1 mg); inside a
    trial the accelerometer error is its VRW white noise only (σ = N/√dt)."""
    part = get_part("HG1700AG58")
    assert part.bias_instability_convention == "total_1sigma"
    si = part.to_si()
    assert si.accel_bias_instability_b_m_s2 == 0.0 and si.gyro_bias_instability_b_rad_s == 0.0
    assert si.accel_turn_on_bias_m_s2 == pytest.approx(1e-3 * G0)
    rate, n, trials = 100.0, 2000, 200
    e = generate_imu_errors(part, trials, n, rate, np.random.default_rng(7)).accel_m_s2
    means = e.mean(axis=1)  # (T, 3): the per-trial constant (+ white-noise mean, σ/√n ≪ 1 mg)
    # 600 draws: the sample std is within ±3σ_rel = ±3/√(2·600) ≈ 9 % of 1 mg
    assert means.std() == pytest.approx(1e-3 * G0, rel=0.09)
    white = si.accel_vrw_m_s2_rt_hz * math.sqrt(rate)  # N/√dt
    within = (e - means[:, None, :]).std()
    assert within == pytest.approx(white, rel=0.02)  # 1.2e6 samples: ±0.1 % statistical


def test_same_figure_as_flicker_would_swamp_the_white_noise():
    """The convention matters: 1 mg read as an Allan minimum gives flicker noise far above the VRW
    within a trial (what the catalog did before); as total 1σ it does not."""
    hg = get_part("HG1700AG58")
    as_flicker = hg.model_copy(update={"bias_instability_convention": "adev_min"})
    rate, n = 100.0, 4096
    e_f = generate_imu_errors(as_flicker, 32, n, rate, np.random.default_rng(3)).accel_m_s2
    e_c = generate_imu_errors(hg, 32, n, rate, np.random.default_rng(3)).accel_m_s2
    wf = (e_f - e_f.mean(axis=1, keepdims=True)).std()
    wc = (e_c - e_c.mean(axis=1, keepdims=True)).std()
    assert wf > 5 * wc


def test_ieee_b_is_checked_as_its_allan_minimum():
    scen = get_preset("airborne_xband")
    a = PartSpec(part_id="A", grade="tactical", source="x", gyro_bias_instability_deg_h=1.0)
    b = PartSpec(part_id="B", grade="tactical", source="x", gyro_bias_instability_deg_h=1.0,
                 bias_instability_convention="ieee_b")
    ra, rb = check_parts([a, b], scen).to_dict()["scenarios"][0]["parts"]
    assert rb["margins"]["gyro_bias_instability_deg_h"] == pytest.approx(
        ra["margins"]["gyro_bias_instability_deg_h"] / FLICKER_FLOOR)
    assert rb["bias_convention"] == "ieee_b"


@pytest.mark.parametrize("cell,words", [
    ("allan", "one of adev_min, ieee_b, total_1sigma, turn_on_1sigma"),
    ("total_1sigma", "accel_bias_repeatability_ug is also given"),
])
def test_bad_convention_names_file_row_field(tmp_path, cell, words):
    p = tmp_path / "mine.csv"
    p.write_text("part_id,grade,accel_bias_instability_ug,accel_bias_repeatability_ug,source,"
                 "bias_instability_convention\n"
                 "OK1,tactical,50,750,ds,adev_min\n"
                 f"BAD,tactical,1000,750,ds,{cell}\n", encoding="utf-8")
    with pytest.raises(InputError) as e:
        read_parts(p)
    msg = str(e.value)
    assert "mine.csv" in msg and "row 3" in msg and "field bias_instability_convention" in msg
    assert words in msg


def test_every_total_bias_row_is_stored_as_such():
    parts = load_catalog()
    for pid in ("HG1700AG58", "HG9900"):  # Honeywell brochures quote total 1σ biases
        assert parts[pid].bias_instability_convention == "total_1sigma"
    for p in parts.values():
        assert p.verified in ("datasheet", "second_hand", "partial", "unverified"), p.part_id


# --- no silent zeros ------------------------------------------------------------------------

def test_fill_from_grade_typical_is_recorded():
    part = get_part("ADIS16465-1")  # industrial; no VRW, scale factors or accel misalignment
    assert "accel_vrw_m_s_rt_h" in unspecified_quantities(part)
    res = resolve_unspecified(part, "fill_grade_typical", load_grades())
    fills = {f.column: f for f in res.filled}
    # industrial accel noise 100 µg/√Hz (seed 004 Table 3) = 100/1699.53 m/s/√h
    assert fills["accel_vrw_m_s_rt_h"].value == pytest.approx(100 / 1699.527, rel=1e-6)
    assert res.model.accel_vrw_m_s_rt_h == pytest.approx(100 / 1699.527, rel=1e-6)
    assert res.model.gyro_arw_deg_rt_h == part.gyro_arw_deg_rt_h  # specified values untouched
    d = res.to_dict()
    assert d["policy"] == "fill_grade_typical" and "accel_vrw_m_s_rt_h" in d["unspecified"]
    assert "industrial" in res.summary()


def test_missing_bias_is_filled_as_a_turn_on_constant():
    res = resolve_unspecified(get_part("MPU-6050"), "fill_grade_typical", load_grades())
    by_q = {f.quantity: f for f in res.filled}
    # consumer gyro bias 30–1000 deg/h → geometric mean √30000 deg/h, into the repeatability column
    assert by_q["gyro_bias_instability_deg_h"].column == "gyro_bias_repeatability_deg_h"
    assert res.model.gyro_bias_repeatability_deg_h == pytest.approx(math.sqrt(30 * 1000))
    assert res.model.to_si().gyro_bias_instability_b_rad_s == 0.0


def test_refuse_and_zero_and_gradeless():
    part = get_part("KVH1775")
    with pytest.raises(InputError, match="accel_vrw_m_s_rt_h"):
        resolve_unspecified(part, "refuse")
    z = resolve_unspecified(part, "zero")
    assert z.model is part and "accel_vrw_m_s_rt_h" in z.zeroed
    gradeless = NoiseModel(gyro_arw_deg_rt_h=0.1)
    r = resolve_unspecified(gradeless, "fill_grade_typical")
    assert r.filled == () and "accel_vrw_m_s_rt_h" in r.zeroed and "no grade" in r.notes[0]
    with pytest.raises(InputError, match="unspecified"):
        resolve_unspecified(part, "guess")


def test_effects_count_as_specified():
    m = NoiseModel(grade="tactical", gyro_arw_deg_rt_h=0.1).with_effect(
        {"name": "white_noise", "channel": "accel_x", "params": {"density": 1e-4}})
    assert "accel_vrw_m_s_rt_h" not in unspecified_quantities(m)
    assert "accel_scale_factor_ppm" in unspecified_quantities(m)


def test_fully_specified_part_is_untouched():
    stim = get_part("STIM300")  # all eight quantities given; only the gyro turn-on bias is not
    assert unspecified_quantities(stim) == ("gyro_bias_repeatability_deg_h",)
    full = stim.model_copy(update={"gyro_bias_repeatability_deg_h": 5.0})
    res = resolve_unspecified(full)
    assert res.unspecified == () and res.model is full and res.summary().startswith("no unspecified")


def test_mc_result_records_the_fills():
    from budget.mc import McOptions, run_mc
    r = run_mc(get_preset("automotive_77ghz"), get_part("ADIS16465-1"), 1, 1)
    d = r.to_dict()["unspecified_terms"]
    assert d["policy"] == "fill_grade_typical"
    assert {f["column"] for f in d["filled"]} >= {"accel_vrw_m_s_rt_h"}
    assert "filled from the industrial grade" in r.summary()
    with pytest.raises(InputError, match="unspecified"):
        run_mc(get_preset("automotive_77ghz"), get_part("ADIS16465-1"), 1, 1,
               options=McOptions(unspecified="refuse"))


# --- tactical parts of similar datasheets ------------------------------------------------

def test_tactical_parts_get_comparable_models_and_checks():
    """STIM300, HG1700AG58 and ADIS16488A: same check verdict on both presets; the constant
    accelerometer bias each simulates is of the same order (STIM300 on/off 0.75 mg, HG1700 total
    1 mg, ADIS16488A its tactical-grade fill) and none carries flicker above 100 µg."""
    parts = [get_part(p) for p in ("STIM300", "HG1700AG58", "ADIS16488A")]
    for scen in ("airborne_xband", "automotive_77ghz"):
        verdicts = {r["verdict"] for r in check_parts(parts, get_preset(scen)).to_dict()["scenarios"][0]["parts"]}
        assert verdicts == {"pass"}
    grades = load_grades()
    turn_on = [resolve_unspecified(p, grades=grades).model.to_si().accel_turn_on_bias_m_s2 for p in parts]
    assert max(turn_on) / min(turn_on) < 2.0
    for p in parts:
        assert p.to_si().accel_bias_instability_adev_m_s2 <= 100e-6 * G0 * 1.0000001


def test_cheapest_passing_states_its_basis():
    df = pd.DataFrame({"scenario": ["a"] * 3 + ["b"] * 2, "part_id": ["T", "I", "N", "T", "I"],
                       "grade": ["tactical", "industrial", "navigation", "tactical", "industrial"],
                       "price_usd": [1000.0, None, 5e4, 3000.0, 2000.0], "p_pass_after": [1.0] * 5,
                       "ci_after_lo": [0.94] * 5})
    best = cheapest_passing(df, 0.9).set_index("scenario")
    assert best.loc["a", "part_id"] == "I" and best.loc["a", "basis"].startswith("grade")
    assert best.loc["a", "cheapest_priced"] == "T" and best.loc["a", "cheapest_priced_usd"] == 1000.0
    assert best.loc["b", "part_id"] == "I" and best.loc["b", "basis"].startswith("price_usd")


@pytest.mark.slow
def test_tactical_parts_get_comparable_mc_verdicts():
    """Monte Carlo on airborne_xband (64 trials, seed 1): the three tactical parts' 95 % intervals
    of P(pass after PGA) overlap, and HG1700AG58 read as flicker (the old convention) does worse
    than as its total 1σ turn-on bias. Measured: 0.92 / 0.98 / 1.00; flicker reading 0.34."""
    from budget.mc import run_mc
    scen = get_preset("airborne_xband")
    res = {p: run_mc(scen, get_part(p), 64, 1) for p in ("STIM300", "HG1700AG58", "ADIS16488A")}
    lo = max(r.ci_after[0] for r in res.values())
    hi = min(r.ci_after[1] for r in res.values())
    assert lo <= hi, {p: r.ci_after for p, r in res.items()}
    hg = get_part("HG1700AG58")
    flicker = run_mc(scen, hg.model_copy(update={"bias_instability_convention": "adev_min"}), 64, 1)
    assert flicker.ci_after[1] < res["HG1700AG58"].ci_after[0]
