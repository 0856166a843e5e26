"""Held-out scenarios no preset describes (a Ku-band UAV at 30 m/s and 2 km, a 30 kHz sonar):
the analytic bounds against their closed forms, the Monte Carlo verdict against the bounds, what
a verdict states it was judged with, and a carrier written in the wrong unit.

Every expected number is computed here from its definition (seed 004 (5)–(11) and the physics
behind them), not read from the library.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from budget.bounds import compute_bounds, fast_phase_limits
from budget.cli.main import main
from budget.errors import InputError
from budget.imu.noise_model import NoiseModel
from budget.mc.options import McOptions
from budget.mc.runner import run_mc
from budget.sar.acceptance import Acceptance
from budget.scenario import Scenario

C = 299_792_458.0
G0 = 9.80665
UG = 1e-6 * G0                       # 1 µg in m/s²
DEG_H = math.pi / 180.0 / 3600.0     # 1 deg/h in rad/s
KU_UAV = {"name": "ku_uav", "carrier_frequency_hz": 16e9, "slant_range_m": 2000.0,
          "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3, "platform_speed_m_s": 30.0,
          "depression_deg": 20.0}


def _ku_tc() -> float:
    """Seed 004 (5): Tc = a_w λ R / (2 δℓ V sin θ), broadside, a_w = 1."""
    return (C / 16e9) * 2000.0 / (2 * 0.3 * 30.0)


# --- bounds on a held-out geometry against closed forms -------------------------------------------

def test_ku_uav_bounds_are_the_closed_forms():
    sc = Scenario.from_dict(KU_UAV)
    tc, dr, lam = _ku_tc(), 0.3, C / 16e9
    assert sc.tc_s == pytest.approx(tc, rel=1e-12) and tc == pytest.approx(2.0819, abs=1e-4)
    paper = {k: float(v[0]) for k, v in compute_bounds(tc, dr, "paper").datasheet().items()}
    # seed 004 (6)–(11) as printed (tolerance: float rounding only)
    want = {"accel_scale_factor_ppm": 0.2 * dr / tc**2 * 1e6, "gyro_scale_factor_ppm": 0.1 * dr / tc**2 * 1e6,
            "misalignment_mrad": math.asin(0.2 * dr / tc**2) * 1e3, "accel_bias_ug": 1.4e5 * dr / tc**2,
            "gyro_bias_deg_h": 8.93e4 * dr / tc**3, "accel_vrw_ug_rt_hz": 8.8e4 * dr / tc**1.5,
            "gyro_arw_deg_rt_h": 784.0 * dr / tc**2.5}
    for key, value in want.items():
        assert paper[key] == pytest.approx(value, rel=1e-12), key
    # derived mode = the physics behind the coefficients: β a Tc²/2 ≤ δr, g γ Tc²/2 ≤ δr/2,
    # b Tc²/2 ≤ δr/√2, g ε Tc³/6 ≤ δr/√2, 2 N √(Tc³/3) ≤ δr, 2 g N √(Tc⁵/20) ≤ δr
    derived = {k: float(v[0]) for k, v in compute_bounds(tc, dr, "derived").datasheet().items()}
    physics = {"accel_scale_factor_ppm": 2 * dr / (G0 * tc**2) * 1e6,
               "gyro_scale_factor_ppm": dr / (G0 * tc**2) * 1e6,
               "accel_bias_ug": math.sqrt(2) * dr / tc**2 / UG,
               "gyro_bias_deg_h": 6 * dr / (math.sqrt(2) * G0 * tc**3) / DEG_H,
               "accel_vrw_ug_rt_hz": dr / (2 * math.sqrt(tc**3 / 3)) / UG,
               "gyro_arw_deg_rt_h": dr / (2 * G0 * math.sqrt(tc**5 / 20)) * 180 / math.pi * 60}
    for key, value in physics.items():
        assert derived[key] == pytest.approx(value, rel=1e-12), key
        assert paper[key] == pytest.approx(value, rel=0.03), key  # the paper's two-digit rounding
    # no autofocus: edge quadratic 4π/λ · b Tc²/8 ≤ π/4 → b ≤ λ/(2 Tc²); gyro bias: quadratic
    # 4π/λ · g ε Tc³/16 ≤ π/4 binds before the cubic (4π/λ · g ε Tc³/120 ≤ π/8) → ε ≤ λ/(g Tc³)
    noaf = {k: float(v[0]) for k, v in compute_bounds(tc, dr, "no-autofocus", wavelength_m=lam).datasheet().items()}
    assert noaf["accel_bias_ug"] == pytest.approx(lam / (2 * tc**2) / UG, rel=1e-12)
    assert noaf["gyro_bias_deg_h"] == pytest.approx(lam / (G0 * tc**3) / DEG_H, rel=1e-12)


def _sampled_highpass_rms(power: int, cutoff_cycles: float, draws: int = 4000, n: int = 400) -> float:
    """rms beyond PGA's bandwidth of e(t) = ∫₀ᵗ (t − s)^p/p! dW(s), unit density, Tc = 1 s, by
    sampling: least-squares residual after Legendre P0…P3 and the DCT-II cosines j ≤ 2K
    (unweighted aperture). Independent of the library's exact covariance."""
    rng = np.random.default_rng(11)
    e = np.cumsum(rng.standard_normal((n, draws)) / math.sqrt(n), axis=0)
    for _ in range(power):
        e = np.cumsum(e, axis=0) / n
    u = np.linspace(-1.0, 1.0, n)
    i = np.arange(n) + 0.5
    basis = np.column_stack([np.polynomial.legendre.legval(u, np.eye(4)[k]) for k in range(4)]
                            + [np.cos(np.pi * j * i / n) for j in range(1, int(2 * cutoff_cycles) + 1)])
    r = e - basis @ np.linalg.lstsq(basis, e, rcond=None)[0]
    return float(math.sqrt(np.mean(r * r)))


def test_ku_uav_fast_phase_limits_match_a_sampled_random_walk():
    # 1° rms beyond 2.5 cycles per aperture as a range error: λ/(4π)·1°; VRW limit = that over
    # c_vrw·Tc^1.5, ARW limit over c_arw·g·Tc^2.5 (share=None: the rms over apertures within the
    # limit; the share-of-apertures factor is checked against sampled walks in
    # test_fast_phase_distribution). 4000 draws: the rms to ≈ 1 %; tolerance 3 %.
    tc, lam = _ku_tc(), C / 16e9
    lim = fast_phase_limits(lam, [tc], pga_bandwidth_cycles=2.5, aperture_window="rect", share=None)
    range_m = lam / (4 * math.pi) * math.radians(1.0)
    c_vrw, c_arw = _sampled_highpass_rms(1, 2.5), _sampled_highpass_rms(2, 2.5)
    assert float(lim.vrw_m_s2_rt_hz[0]) == pytest.approx(range_m / (c_vrw * tc**1.5), rel=0.03)
    assert float(lim.arw_rad_s_rt_hz[0]) == pytest.approx(range_m / (c_arw * G0 * tc**2.5), rel=0.03)


# --- the verdict against the bounds on the held-out geometry ----------------------------------------

@pytest.mark.parametrize("scale, passes", [(0.1, True), (10.0, False)])
def test_ku_uav_vrw_alone_passes_at_a_tenth_and_fails_at_ten_times_its_fast_phase_limit(scale, passes):
    # VRW alone, lever arm 0, straight flight, points scene, 16 trials: the limit on what PGA
    # cannot remove (1° rms beyond its window, the verdict's Taylor weighting) is the binding
    # bound here (0.034× seed 004's (10), δr/λ = 16). At 0.1× the predicted residual is 0.1°,
    # at 10× it is 10°: every trial must land on its side (measured 32/32 and 0/32, seed 1).
    sc = Scenario.from_dict(KU_UAV)
    lim = fast_phase_limits(sc.wavelength_m, [sc.tc_s], aperture_window="taylor")
    vrw_m_s_rt_h = float(lim.vrw_m_s2_rt_hz[0]) * 60.0
    model = NoiseModel(part_id="vrw_only", grade="tactical", source="synthetic",
                       accel_vrw_m_s_rt_h=scale * vrw_m_s_rt_h)
    r = run_mc(sc, model, 16, 1, options=McOptions(unspecified="zero", keep_trial_metrics=False))
    assert r.p_pass_after == (1.0 if passes else 0.0), r.agg.failure_reasons()
    if not passes:
        assert r.agg.failure_reasons()["residual_phase_noise"] == 16


# --- what a verdict states it was judged with ------------------------------------------------------

def test_a_verdict_states_its_lever_arm_acceptance_and_earth_model_defaults():
    # Formerly the summary and judged_on said nothing of the lever arm (a scenario without one is
    # flown with d = 0, seed 004's assumption), of the acceptance limits, or of the latitude and
    # heading the motion engine uses (45°, north: defaults the verdict does not let a user set).
    sc = Scenario.from_dict(KU_UAV)
    model = NoiseModel(part_id="quiet", grade="navigation", source="synthetic", accel_vrw_m_s_rt_h=0.001)
    r = run_mc(sc, model, 2, 1, options=McOptions(unspecified="zero", keep_trial_metrics=False))
    j, text = r.to_dict()["judged_on"], r.summary()
    assert "[0, 0, 0] m" in j["lever_arm"] and "default" in j["lever_arm"]
    assert "broadening ≤ 10 %" in j["acceptance"] and "peak loss ≤ 1.5 dB" in j["acceptance"]
    assert "range migration ≤ 1 range cell" in j["acceptance"] and "≤ 1° rms" in j["acceptance"]
    # it is judged at 1000 cells (a response that left the scene fails it): never "not judged"
    assert "peak shift ≤ 1000 cells" in j["acceptance"] and "not judged" not in j["acceptance"]
    assert "flat earth" in j["earth_model"] and "latitude 45° (default" in j["earth_model"]
    for key in ("lever_arm", "acceptance", "earth_model"):
        assert j[key] in text, key
    json.dumps(r.to_dict())  # still JSON-ready

    # the scenario's own lever arm and a user's acceptance are stated as given
    sc2 = Scenario.from_dict({**KU_UAV, "lever_arm_m": [0.3, 0.0, 0.4]})
    opts = McOptions(unspecified="zero", keep_trial_metrics=False, max_range_migration_cells=0.5,
                     max_residual_phase_rms_deg=None,
                     acceptance=Acceptance(max_pslr_db=-25.0, max_peak_shift_cells=2.0))
    r2 = run_mc(sc2, model, 2, 1, options=opts)
    j2 = r2.judged_on
    assert "[0.3, 0, 0.4] m" in j2["lever_arm"] and "|d| = 0.5 m" in j2["lever_arm"]
    assert "default" not in j2["lever_arm"]
    assert "PSLR ≤ -25 dB" in j2["acceptance"] and "peak shift ≤ 2 cells" in j2["acceptance"]
    assert "range migration ≤ 0.5 range cell" in j2["acceptance"]
    assert "what PGA cannot remove not judged" in j2["acceptance"]


# --- a carrier written in the wrong unit --------------------------------------------------------------

def test_a_radar_carrier_written_in_ghz_names_the_field_and_the_unit(tmp_path, capsys):
    # 9.6 (GHz) in carrier_frequency_hz: formerly "did you mean medium 'sonar'?" with no field,
    # value or range — and 9.6 Hz is no sonar carrier either (sonar: 10 Hz … 5 MHz)
    with pytest.raises(InputError) as e:
        Scenario.from_dict({**KU_UAV, "carrier_frequency_hz": 9.6})
    assert e.value.field == "carrier_frequency_hz" and e.value.value == 9.6
    text = str(e.value)
    assert "9.6e+09 Hz if it was in GHz" in text and "sonar" not in text.split("expected")[0]
    assert "1e+06 … 1e+13 Hz" in text
    # 35 (GHz) is also a sonar frequency: both readings are offered
    with pytest.raises(InputError, match=r"3\.5e\+10 Hz if it was in GHz.*medium 'sonar'") as e:
        Scenario.from_dict({**KU_UAV, "carrier_frequency_hz": 35.0})
    # 9600 (MHz) for X band
    with pytest.raises(InputError, match=r"9\.6e\+09 Hz if it was in MHz"):
        Scenario.from_dict({**KU_UAV, "carrier_frequency_hz": 9600.0})
    # a sonar given a radar carrier: the field is named too
    with pytest.raises(InputError, match="did you mean medium 'radar'") as e:
        Scenario.from_dict({"medium": "sonar", "carrier_frequency_hz": 9.6e9, "slant_range_m": 100.0,
                            "azimuth_resolution_m": 0.1, "range_resolution_m": 0.05,
                            "platform_speed_m_s": 1.5})
    assert e.value.field == "carrier_frequency_hz"
    # from a file on the command line: one line naming file, field and the unit; exit status 2
    f = tmp_path / "ghz.json"
    f.write_text(json.dumps({**KU_UAV, "carrier_frequency_hz": 16}))
    assert main(["bounds", "--scenario", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    assert str(f) in err and "carrier_frequency_hz" in err and "1.6e+10 Hz if it was in GHz" in err


def test_a_sonar_carrier_written_in_khz_is_named_beside_the_resolution_it_breaks():
    # 30 (kHz) in carrier_frequency_hz is a 30 Hz sonar (λ = 50 m): the 5 cm range resolution
    # then needs a bandwidth of c/(2δr) = 15 kHz, above twice the carrier. The refusal is the
    # resolution's, and now says the carrier is outside the sonar bands and what 30 kHz would be.
    with pytest.raises(InputError) as e:
        Scenario.from_dict({"medium": "sonar", "carrier_frequency_hz": 30.0, "slant_range_m": 100.0,
                            "azimuth_resolution_m": 0.1, "range_resolution_m": 0.05,
                            "platform_speed_m_s": 1.5})
    assert e.value.field == "range_resolution_m"
    text = str(e.value)
    assert f"{1500.0 / (2 * 0.05):.4g} Hz" in text  # the bandwidth it needs, c/(2δr)
    assert "3e+04 Hz if it was in kHz" in text
    # a carrier within the sonar bands keeps the message as it was (no unit guess)
    with pytest.raises(InputError) as e:
        Scenario.from_dict({"medium": "sonar", "carrier_frequency_hz": 3000.0, "slant_range_m": 100.0,
                            "azimuth_resolution_m": 0.2, "range_resolution_m": 0.1,
                            "platform_speed_m_s": 1.5})
    assert "if it was in" not in str(e.value)
