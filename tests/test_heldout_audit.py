"""Held-out audit: scenarios the tool was not tuned on, derived by hand, and what a user gets wrong.

The expected values here come from closed forms written out in each test (not from the tool's
output): Tc = λR/(2 δℓ V) at broadside with an unweighted aperture, λ = c/f0.
"""

from __future__ import annotations

import warnings

import pytest

from budget.scenario import Scenario

#: A small synthetic-aperture sonar (held out: not a preset): 100 kHz, 1.5 m/s, 50 m, 3 cm cells.
SAS_50M = {"name": "sas_50m", "medium": "sonar", "carrier_frequency_hz": 100e3, "slant_range_m": 50.0,
           "azimuth_resolution_m": 0.03, "range_resolution_m": 0.03, "platform_speed_m_s": 1.5,
           "depression_deg": 10.0, "lever_arm_m": [0.1, 0.0, 0.0], "platform_rate_deg_s": 0.5,
           "imu_rate_hz": 100.0}


def test_a_sonar_carrier_in_khz_that_the_resolution_checks_let_through_is_noted():
    """100 (kHz) written into carrier_frequency_hz is a 100 Hz sonar: λ = 1500/100 = 15 m. With
    5 m cells the range resolution needs only c/(2δr) = 150 Hz of bandwidth (< 2·f0) and δℓ ≥ λ/4,
    so no refusal fires and Tc = λR/(2δℓV) = 15·50/(2·5·1.5) = 50 s instead of the 100 kHz
    sonar's 0.05 s — the unit slip must be said, with the reading that puts it in band."""
    data = {**SAS_50M, "carrier_frequency_hz": 100.0, "azimuth_resolution_m": 5.0, "range_resolution_m": 5.0}
    with pytest.warns(UserWarning) as w:
        s = Scenario.from_dict(data)
    assert s.tc_s == pytest.approx(15.0 * 50.0 / (2 * 5.0 * 1.5), rel=1e-12)
    carrier = [str(x.message) for x in w if "carrier" in str(x.message)]
    assert len(carrier) == 1, [str(x.message) for x in w]
    assert "carrier_frequency_hz" in carrier[0] and "1e+05 Hz if it was in kHz" in carrier[0]
    assert carrier[0] in s.notes()


def test_carriers_inside_their_bands_carry_no_carrier_note():
    """The held-out sonar at 100 kHz and radars from L (1.3 GHz) to W band (94 GHz) are quiet."""
    radar = {"name": "r", "medium": "radar", "slant_range_m": 5000.0, "azimuth_resolution_m": 0.3,
             "range_resolution_m": 0.3, "platform_speed_m_s": 100.0}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Scenario.from_dict(SAS_50M).notes() == []
        for f0 in (1.3e9, 5.3e9, 16e9, 94e9):
            assert Scenario.from_dict({**radar, "carrier_frequency_hz": f0}).notes() == []



def test_a_vhf_foliage_penetrating_radar_gets_no_carrier_note():
    """VHF SAR flies 20–90 MHz (λ = 3.3–15 m; 3 m cells need an aperture of tens of degrees, which
    the scenario notes on its own): its carrier is no unit slip, so no note names the carrier."""
    vhf = {"name": "vhf", "medium": "radar", "carrier_frequency_hz": 50e6, "slant_range_m": 20000.0,
           "azimuth_resolution_m": 3.0, "range_resolution_m": 3.0, "platform_speed_m_s": 120.0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        notes = Scenario.from_dict(vhf).notes()
    assert not [n for n in notes if "carrier" in n], notes


# --- an aperture time of hours: beyond the bounds' free-inertial, flat-earth error growth -------

#: Schuler frequency ω_s = √(g/R_E) (R_E = 6371 km): period 2π/ω_s ≈ 84.4 min.
OMEGA_S = (9.80665 / 6_371_000.0) ** 0.5

#: A held-out Ku-band UAV strip map: 16 GHz, 5 km, 0.3 m cells at 100 m/s (Tc ≈ 1.56 s).
KU_UAV = {"name": "ku_uav", "medium": "radar", "carrier_frequency_hz": 16e9, "slant_range_m": 5000.0,
          "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3, "platform_speed_m_s": 100.0,
          "depression_deg": 35.0, "lever_arm_m": [0.3, 0.1, -0.2], "platform_rate_deg_s": 0.5}


def _schuler_over_flat(tc_s: float) -> float:
    """Schuler-bounded error of an accelerometer bias, b/ω_s²·(1 − cos ω_s t), over the flat
    b·t²/2 the bounds use: 2(1 − cos x)/x², x = ω_s·Tc."""
    import math
    x = OMEGA_S * tc_s
    return 2.0 * (1.0 - math.cos(x)) / x**2


def _at_speed(v_m_s: float) -> dict:
    return {**KU_UAV, "name": f"ku_uav_at_{v_m_s:g}", "platform_speed_m_s": v_m_s}


def test_an_aperture_of_hours_is_refused_by_the_check_and_the_bounds(capsys):
    """V = 0.01 m/s (a speed in the wrong unit): Tc = λR/(2δℓV) = 0.018737·5000/(2·0.3·0.01) ≈
    15 614 s, 4.3 h. Over Tc the Schuler loop bounds an accelerometer bias's error at a fraction
    2(1 − cos ω_s Tc)/(ω_s Tc)² ≈ 7e-4 of the flat b·Tc²/2 the bounds assume: a margin of 1e-8 would
    be a silently wrong number. The check, the bounds (API and CLI) refuse it, naming the derived Tc
    and what is expected."""
    import budget
    from budget.check import check_parts
    from budget.cli.main import main
    from budget.errors import InputError

    lam = 299_792_458.0 / 16e9
    tc = lam * 5000.0 / (2 * 0.3 * 0.01)
    assert tc > 3600.0 and _schuler_over_flat(tc) < 1e-3
    with pytest.warns(UserWarning):
        s = Scenario.from_dict(_at_speed(0.01))
    assert s.tc_s == pytest.approx(tc, rel=1e-12)
    for call in (lambda: check_parts([budget.load_part("STIM300")], s), lambda: budget.compute_bounds(s)):
        with pytest.raises(InputError) as e:
            call()
        assert e.value.field == "tc_s (derived)" and "Tc ≤ 3000 s" in str(e.value)
    assert main(["bounds", "--tc", "5000", "--range-resolution", "0.3"]) == 2
    err = capsys.readouterr().err
    assert "--tc" in err and "Tc ≤ 3000 s" in err and "Traceback" not in err


def test_an_aperture_past_the_flat_earth_model_is_noted_and_a_short_one_is_quiet():
    """Tc = 1000 s (V ≈ 0.156 m/s): the Schuler-bounded accelerometer-bias error is
    2(1 − cos 1.24)/1.24² ≈ 0.88 of the flat one, more than 10 % off: the bounds still compute
    (the Monte Carlo with aiding runs to 3000 s) but the scenario says the flat growth overstates
    it. The held-out Ku-band UAV at Tc ≈ 1.56 s (flat within 2e-7) carries no such note."""
    lam = 299_792_458.0 / 16e9
    v = lam * 5000.0 / (2 * 0.3 * 1000.0)
    assert 0.85 < _schuler_over_flat(1000.0) < 0.9
    with pytest.warns(UserWarning) as w:
        s = Scenario.from_dict(_at_speed(v))
    assert s.tc_s == pytest.approx(1000.0, rel=1e-12)
    text = [str(x.message) for x in w if "Schuler" in str(x.message)]
    assert len(text) == 1 and "overstate" in text[0] and text[0] in s.notes()
    import budget
    assert budget.compute_bounds(s).tc_s[0] == pytest.approx(1000.0)
    assert 1.0 - _schuler_over_flat(1.5614) < 1e-6
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Scenario.from_dict(KU_UAV).notes() == []


@pytest.mark.parametrize("key", ["range_resolution_m", "azimuth_resolution_m"])
def test_a_resolution_cell_as_wide_as_the_slant_range_is_refused(key):
    """δr = 6 km at R = 5 km: one range cell holds the whole scene and the platform, yet the
    paper bounds (∝ δr) would pass any IMU with margins 2·10⁴ times those of 0.3 m cells; δℓ = 6 km
    gives L = λR/(2δℓ) = 0.0187·5000/12000 = 7.8 mm, an 'aperture' shorter than the wavelength.
    Refused naming the field and the range; a cell just below R (a coarse mode) is accepted."""
    from budget.errors import InputError

    lam = 299_792_458.0 / 16e9
    assert lam * 5000.0 / (2 * 6000.0) < lam
    with pytest.raises(InputError) as e:
        Scenario.from_dict({**KU_UAV, key: 6000.0}, source="s.json")
    assert e.value.field == key and "slant_range_m" in str(e.value) and "s.json" in str(e.value)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        Scenario.from_dict({**KU_UAV, key: 100.0})


# --- the bounds on held-out scenarios, from closed forms ---------------------------------------

G = 9.80665
C_LIGHT = 299_792_458.0

#: Held-out scenarios (none is a preset): Ku UAV strip map, C-band wide area, W-band helicopter,
#: L-band long aperture, and the small sonar above.
HELD_OUT = {
    "ku_uav": KU_UAV,
    "c_wide": {"name": "c_wide", "medium": "radar", "carrier_frequency_hz": 5.3e9, "slant_range_m": 20000.0,
               "azimuth_resolution_m": 3.0, "range_resolution_m": 3.0, "platform_speed_m_s": 150.0,
               "depression_deg": 20.0},
    "w_heli": {"name": "w_heli", "medium": "radar", "carrier_frequency_hz": 94e9, "slant_range_m": 1000.0,
               "azimuth_resolution_m": 0.1, "range_resolution_m": 0.1, "platform_speed_m_s": 30.0,
               "depression_deg": 15.0},
    "l_long": {"name": "l_long", "medium": "radar", "carrier_frequency_hz": 1.3e9, "slant_range_m": 30000.0,
               "azimuth_resolution_m": 1.0, "range_resolution_m": 1.0, "platform_speed_m_s": 120.0,
               "depression_deg": 25.0},
    "sas_50m": SAS_50M,
}


def _legendre_stats(p: int):
    """Exact std of the Legendre coefficients c_0…c_3 and rms beyond the cubic of the unit random
    walk e(t) = ∫₀ᵗ (t − s)^p/p! dW(s) over t ∈ [0, 1], u = 2t − 1: c_k = (2k+1)∫₀¹ e P_k(2t−1) dt,
    so Var c_k = (2k+1)² ∫₀¹ g_k(s)² ds with g_k(s) = ∫ₛ¹ (t − s)^p/p! P_k(2t − 1) dt (polynomials,
    integrated exactly); E[mean e²] = 1/((2p+1)(2p+2)(p!)²) less Σ Var c_k/(2k+1)."""
    import math

    import numpy as np
    from numpy.polynomial import Polynomial as Poly, legendre as L

    var = []
    for k in range(4):
        q = Poly(L.leg2poly(np.eye(k + 1)[k]))(Poly([-1.0, 2.0]))
        g = Poly([0.0])
        for i in range(p + 1):
            r = (Poly.basis(i) * q).integ()
            g = g + math.comb(p, i) * Poly([0.0, -1.0]) ** (p - i) * (r(1.0) - r) / math.factorial(p)
        sq = (((2 * k + 1) * g) ** 2).integ()
        var.append(sq(1.0) - sq(0.0))
    mean_e2 = 1.0 / ((2 * p + 1) * (2 * p + 2) * math.factorial(p) ** 2)
    return [v ** 0.5 for v in var], (mean_e2 - sum(v / (2 * k + 1) for k, v in enumerate(var))) ** 0.5


@pytest.mark.parametrize("name", sorted(HELD_OUT))
def test_held_out_bounds_match_the_closed_forms(name):
    """Each source alone, error accumulated from the aperture start (aligned at t = 0):

    * derived (range cell δr, seed 004's shares): b·Tc²/2 ≤ δr/√2 → b ≤ √2·δr/Tc²;
      g·ε·Tc³/6 ≤ δr/√2 → ε ≤ 3√2·δr/(g·Tc³); 2·N·√(Tc³/3) ≤ δr; 2·g·N_θ·√(Tc⁵/20) ≤ δr;
    * no autofocus (phase 4π/λ·Δr, quadratic ≤ π/4 at the aperture edge, cubic ≤ π/8, rest ≤ 1°
      rms): b·Tc²/8 of edge quadratic → b ≤ λ/(2Tc²); g·ε·Tc³/16 edge quadratic and g·ε·Tc³/120
      cubic → ε ≤ min(λ, 3.75λ)/(g·Tc³); VRW and ARW from the exact Legendre statistics
      (2σ of the edge quadratic 1.5·c₂ and of the cubic c₃, 1σ of the rest)."""
    import math

    import budget

    sc = HELD_OUT[name]
    c = C_LIGHT if sc["medium"] == "radar" else 1500.0
    lam = c / sc["carrier_frequency_hz"]
    dr = sc["range_resolution_m"]
    tc = lam * sc["slant_range_m"] / (2 * sc["azimuth_resolution_m"] * sc["platform_speed_m_s"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # none of them needs a note
        s = Scenario.from_dict(sc)
    assert s.tc_s == pytest.approx(tc, rel=1e-12)

    d = budget.compute_bounds(s, "derived")
    assert d.accel_bias_m_s2[0] == pytest.approx(math.sqrt(2) * dr / tc**2, rel=1e-9)
    assert d.gyro_bias_rad_s[0] == pytest.approx(3 * math.sqrt(2) * dr / (G * tc**3), rel=1e-9)
    assert d.accel_vrw_m_s2_rt_hz[0] == pytest.approx(dr / (2 * math.sqrt(tc**3 / 3)), rel=1e-9)
    assert d.gyro_arw_rad_s_rt_hz[0] == pytest.approx(dr / (2 * G * math.sqrt(tc**5 / 20)), rel=1e-9)

    n = budget.compute_bounds(s, "no-autofocus")
    quad, cub, rest = lam / 16, lam / 32, lam / (4 * math.pi) * math.radians(1.0)
    assert n.accel_bias_m_s2[0] == pytest.approx(lam / (2 * tc**2), rel=1e-9)
    assert n.gyro_bias_rad_s[0] == pytest.approx(lam / (G * tc**3), rel=1e-9)
    for (p, scale, power), got in (((1, 1.0, 1.5), n.accel_vrw_m_s2_rt_hz[0]),
                                   ((2, G, 2.5), n.gyro_arw_rad_s_rt_hz[0])):
        sd, resid = _legendre_stats(p)
        per_unit = scale * tc**power
        want = min(quad / (2 * 1.5 * sd[2] * per_unit), cub / (2 * sd[3] * per_unit), rest / (resid * per_unit))
        assert got == pytest.approx(want, rel=2e-3)


def test_a_rotating_platform_motion_over_a_squinted_scenario_is_refused():
    """The check's rotation (gyro scale factor, misalignment) is the broadside one: a roll error
    tilts g cross-track, a pitch error along-track. The line of sight u = (cos ψ sin s, cos ψ cos s,
    −sin ψ) sees the along-track error by cos ψ·sin s: 0.819·0.643 = 0.53 at ψ = 35°, s = 40° —
    as much as the cross-track share cos ψ·cos s = 0.63 — which the broadside excursion leaves out.
    Refused naming the squint; straight flight (no rotation) and no motion still check."""
    import math

    import budget
    from budget.check import check_parts
    from budget.errors import InputError

    assert math.cos(math.radians(35)) * math.sin(math.radians(40)) == pytest.approx(0.5265, abs=1e-4)
    s = Scenario.from_dict({**KU_UAV, "squint_deg": 40.0})
    part = budget.load_part("STIM300")
    with pytest.raises(InputError) as e:
        check_parts([part], s, platform_motion={"kind": "oscillation"})
    assert e.value.field == "squint_deg" and "0.53" in str(e.value)
    check_parts([part], s, platform_motion={"kind": "straight"})
    check_parts([part], s)
