"""Reference numbers from the seed papers and the project's reference list that no other test pins, each against an
independent computation and against the printed value.

Tolerance rule: a printed value is met when the tool's value rounds to it, i.e. within half a
unit of its last printed digit (``_printed``); an independent closed form or exact quadrature is
met to the tool's numerical accuracy (stated per test). Where the printed value does not round
from the exact one, the test says so and pins the exact value (README/docstrings say so too).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.polynomial import legendre as L

from budget import units as u
from budget.bounds import derived_bounds, fast_phase_limits, random_walk_constants
from budget.bounds.lever_arm import LeverArmAssumptions, lever_arm_terms
from budget.catalog.io import load_catalog, load_grades
from budget.noise.arma import ArmaFit
from budget.presets import get_preset
from budget.scenario import Scenario
from budget.seeds.master_slave import MasterSlaveParams
from budget.seeds.transfer_alignment import LEVER_ARM_M, MOUNTING_ANGLES_DEG

G = 9.80665


def _printed(value: float, printed: str) -> bool:
    """``value`` rounds to ``printed`` (within half a unit of its last printed digit)."""
    mant, _, exp = printed.lower().partition("e")
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    half = 0.5 * 10.0 ** (-decimals + (int(exp) if exp else 0))
    return abs(value - float(printed)) <= half * (1 + 1e-9)


# --- §1 units -----------------------------------------------------------------------------------

def test_vrw_unit_identity_exact():
    # 1 m/s/√h = 1/60 m/s²/√Hz = 1/(60·g·1e-6) µg/√Hz = 1699.53 µg/√Hz with g = 9.80665 m/s².
    # (A quoted 1699.7 is 1.0e-4 high.)
    exact = 1.0 / (60.0 * G * 1e-6)
    assert u.m_s_rt_h_to_ug_rt_hz(1.0) == pytest.approx(exact, rel=1e-12)
    assert _printed(u.m_s_rt_h_to_ug_rt_hz(1.0), "1699.53")
    assert not _printed(u.m_s_rt_h_to_ug_rt_hz(1.0), "1699.7")


def test_constants_and_rate_identity():
    assert u.C_LIGHT == 299_792_458.0 and u.G0 == G and u.C_SOUND_WATER == 1500.0
    assert u.deg_h_to_rad_s(1.0) == pytest.approx(math.pi / 180 / 3600, rel=1e-15)
    assert _printed(u.deg_h_to_rad_s(1.0), "4.848e-6")
    assert u.ppm_to_ratio(1.0) == 1e-6


def test_sonar_two_way_phase_seed003_eq12():
    # Δφ = 4π f / c · Δr with c = 1500 m/s (seed 003 (12)); 100 kHz, 1 mm → 0.838 rad
    k = u.two_way_wavenumber_at_frequency_rad_m(100e3, u.C_SOUND_WATER)
    assert k * 1e-3 == pytest.approx(4 * math.pi * 100e3 / 1500 * 1e-3, rel=1e-14)
    assert u.range_error_to_phase_error(1e-3, get_preset("sas_100khz").wavelength_m) == pytest.approx(
        4 * math.pi * 1e-3 / 0.015, rel=1e-12)


# --- §2 aperture time and the derived coefficients -----------------------------------------------

def test_automotive_tc_below_one_second_over_the_whole_speed_range():
    # seed 004: 24 GHz R ≤ 50 m / 77 GHz R ≤ 500 m, V = 15–40 m/s, δℓ = 0.1 m → Tc < 1 s
    # (longest: 77 GHz, R = 500 m, V = 15 m/s: λR/(2δℓV) = 0.649 s)
    for f0, r in ((24e9, 50.0), (77e9, 500.0)):
        for v in (15.0, 20.0, 40.0):
            s = Scenario(carrier_frequency_hz=f0, slant_range_m=r, azimuth_resolution_m=0.1,
                         range_resolution_m=0.1, platform_speed_m_s=v)
            assert s.tc_s == pytest.approx(u.C_LIGHT / f0 * r / (2 * 0.1 * v), rel=1e-12)
            assert s.tc_s < 1.0
    worst = Scenario(carrier_frequency_hz=77e9, slant_range_m=500, azimuth_resolution_m=0.1,
                     range_resolution_m=0.1, platform_speed_m_s=15)
    assert _printed(worst.tc_s, "0.649")


def test_airborne_tc_seconds_to_minutes():
    # seed 004: R up to 100 km, V up to 200 m/s → seconds to minutes (X band, δℓ 1 … 0.1 m: 7.8–78 s)
    tcs = [Scenario(carrier_frequency_hz=9.6e9, slant_range_m=100e3, azimuth_resolution_m=dl,
                    range_resolution_m=dl, platform_speed_m_s=200.0).tc_s for dl in (1.0, 0.3, 0.1)]
    assert 1.0 < min(tcs) and max(tcs) < 600.0
    assert _printed(tcs[1], "26.0") and _printed(get_preset("airborne_xband_long_range").tc_s, "26.0")


DERIVED = {  # datasheet key: (closed form at δr = 1 m, Tc = 1 s, printed value, as in the README)
    "accel_scale_factor_ppm": (2 / G * 1e6, "0.204e6"),
    "gyro_scale_factor_ppm": (1 / G * 1e6, "0.102e6"),
    "accel_bias_ug": (math.sqrt(2) / G * 1e6, "1.44e5"),
    "gyro_bias_deg_h": (6 / (math.sqrt(2) * G) * 180 / math.pi * 3600, "8.92e4"),
    "accel_vrw_ug_rt_hz": (math.sqrt(3) / 2 / G * 1e6, "8.83e4"),
    "gyro_arw_deg_rt_h": (0.5 / (G * math.sqrt(1 / 20)) * 60 * 180 / math.pi, "784"),
}


@pytest.mark.parametrize("key", list(DERIVED))
def test_derived_coefficients_from_their_derivation(key):
    """Seed 004 coefficients re-derived: 2/g = 0.204; √2 δr/Tc² = 1.44e5 µg; g b Tc³/6 ≤ δr/√2 → 8.92e4 deg/h;
    (√3/2) δr/Tc^1.5 = 8.83e4 µg/√Hz; g N √(Tc⁵/20) ≤ δr/2 → 784 deg/√h (γ: 1/g = 0.102)."""
    got = float(derived_bounds(1.0, 1.0).datasheet()[key][0])
    closed, printed = DERIVED[key]
    assert got == pytest.approx(closed, rel=1e-12)
    assert _printed(got, printed), (key, got, printed)


def test_misalignment_bound_is_arcsin_of_the_scale_factor_bound():
    b = derived_bounds([1.0, 10.0], 0.1)
    np.testing.assert_allclose(b.misalignment_rad, np.arcsin(2 * 0.1 / (G * np.array([1.0, 100.0]))), rtol=1e-14)


# --- §2 what PGA cannot remove: 1° rms / 1° peak -----------------------------------------------

def test_fast_phase_range_limits_and_sidelobe_energy():
    one = math.radians(1.0)
    for f0, printed in ((24e9, "1.7e-5"), (77e9, "5.4e-6")):
        lam = u.C_LIGHT / f0
        f = fast_phase_limits(lam)
        assert f.noise_range_rms_m == pytest.approx(lam / (4 * math.pi) * one, rel=1e-14)
        assert f.harmonic_range_peak_m == pytest.approx(lam / (4 * math.pi) * one, rel=1e-14)
        assert _printed(f.noise_range_rms_m, printed)
    lam = u.C_LIGHT / 9.6e9
    # σ² of the main-lobe energy: 1° → −35.2 dB, 5.7° → −20.0 dB; paired echoes 20·log10(β/2) = −41.2 dB
    assert fast_phase_limits(lam).noise_islr_db == pytest.approx(10 * math.log10(one**2), abs=1e-12)
    assert _printed(fast_phase_limits(lam).noise_islr_db, "-35.2")
    assert _printed(fast_phase_limits(lam, noise_rms_deg=5.7).noise_islr_db, "-20")
    assert _printed(fast_phase_limits(lam).paired_echo_db, "-41.2")
    # seed 004 quotes −30 dB at 2° rms (σ² gives −29.1: within 1 dB) and −40 dB at 1° rms, 4.8 dB
    # below σ²'s −35.2: a disagreement the README states; the tool keeps σ².
    two = fast_phase_limits(lam, noise_rms_deg=2.0).noise_islr_db
    assert _printed(two, "-29.1") and abs(two - -30.0) < 1.0
    assert fast_phase_limits(lam).noise_islr_db - -40.0 == pytest.approx(4.84, abs=0.01)


# --- §4 random-walk residual constants ------------------------------------------------------------

def _exact_residual(power: int, degree: int, nodes: int = 40) -> float:
    """√E[∫₀¹ r² dt] for e(t) = ∫₀ᵗ (t − s)^p/p! dW(s) after the L² projection on polynomials of
    degree ≤ ``degree``: Gauss–Legendre in s and on [s, 1] in t. The integrands are polynomials
    of degree ≤ 2(p + degree + 1) in s and p + degree in t, so ``nodes`` = 40 is exact for the
    degrees used here (independent of the tool's grid covariance)."""
    x, w = L.leggauss(nodes)
    total = 0.0
    for s, ws in zip(0.5 * (x + 1), 0.5 * w):
        t = s + (1 - s) * 0.5 * (x + 1)
        wt = (1 - s) * 0.5 * w
        k = (t - s) ** power / math.factorial(power)
        phi = L.legvander(2 * t - 1, degree) * np.sqrt(2 * np.arange(degree + 1) + 1)  # orthonormal on [0, 1]
        c = (wt * k) @ phi  # coefficients on the orthonormal basis
        total += ws * (np.sum(wt * k * k) - c @ c)
    return math.sqrt(total)


# (kind, power, degree removed, printed reference value, closed form where one is known)
RW_CONSTANTS = [
    ("vrw", 1, 1, "0.049", 1 / math.sqrt(420)),
    ("vrw", 1, 2, "0.020", 1 / math.sqrt(2520)),
    ("arw", 2, 1, "0.024", None),
    ("arw", 2, 2, "0.0042", None),   # quoted as 0.0043 in the reference list: exactly 0.004247
    ("vrw", 1, 10, "0.00245", None),
    ("rw", 0, 10, "0.107", None),
]


@pytest.mark.parametrize("kind, power, degree, printed, closed", RW_CONSTANTS)
def test_random_walk_residual_constants(kind, power, degree, printed, closed):
    tool = float(random_walk_constants(kind, max_degree=max(3, degree))["resid_rms"][degree])
    exact = _exact_residual(power, degree)
    if closed is not None:
        assert exact == pytest.approx(closed, rel=1e-10)
    # the tool's 1500-point midpoint grid: ≤ 5e-4 relative (measured 4e-4 on ARW after the line)
    assert tool == pytest.approx(exact, rel=1e-3)
    assert _printed(exact, printed) and _printed(tool, printed), (kind, degree, tool, exact, printed)


def test_quoted_arw_quadratic_constant_is_a_rounding_slip():
    exact = _exact_residual(2, 2)
    assert exact == pytest.approx(0.0042471, rel=1e-4)
    assert not _printed(exact, "0.0043")


def test_random_walk_endpoint_closed_forms():
    # σ(e(Tc)) = N√(Tc³/3) (VRW), g N √(Tc⁵/20) (ARW), N√Tc (random walk): grid error < 1e-3
    for kind, closed in (("rw", 1.0), ("vrw", math.sqrt(1 / 3)), ("arw", math.sqrt(1 / 20))):
        assert random_walk_constants(kind)["endpoint_std"] == pytest.approx(closed, rel=1e-3)


def test_lever_arm_arw_migration_limit_is_n_sqrt_t_d():
    # attitude random walk seen through d: σ = N·√Tc·|d|; k·σ ≤ δr (k = 2) → N ≤ δr/(k √Tc |d|)
    d, tc, dr = (0.3, 0.4, 0.0), 4.0, 0.5
    terms = lever_arm_terms(tc, dr, 0.03, LeverArmAssumptions(lever_arm_m=d)).set_index("lever_arm_rule")
    got = terms.loc["range migration k·N·√Tc·|d| ≤ δr", "lever_arm_limit"]  # deg/√h
    assert got == pytest.approx(u.rad_s_rt_hz_to_deg_rt_h(dr / (2.0 * math.sqrt(tc) * 0.5)), rel=1e-12)


# --- §2 grade table (seed 004 Tables 3–4) and the parts it names ---------------------------------

GRADES = {  # accel: SF (ratio), mis (mrad), bias (µg), noise (µg/√Hz); gyro: SF, mis, bias (deg/h), ARW
    "strategic": ((1e-7, 1e-5), 0.01, (0.1, 10), (2, 5), (1e-6, 1e-5), 0.01, (1e-4, 5e-3), (1e-5, 5e-4)),
    "navigation": ((1e-5, 1.5e-4), 0.05, (20, 50), (5, 20), (1e-5, 3e-5), 0.05, (3e-3, 1e-2), (1e-3, 2e-3)),
    "stabilization": ((1e-4, 5e-4), 0.1, (100, 500), (25, 40), (1e-4, 5e-4), 0.1, (0.05, 3), (5e-3, 5e-2)),
    "tactical": ((1e-3, 3e-3), 0.5, (300, 1000), (50, 75), (5e-4, 1.5e-3), 0.5, (0.1, 30), (0.1, 0.5)),
    "industrial": ((1e-3, 1e-3), 1, (3000, 3000), (100, 100), (2e-3, 2e-3), 1, (1, 30), (3, 3)),
    "consumer": ((0.1, 0.1), 10, (125000, 125000), (150, 150), (0.6, 0.6), 10, (30, 1000), (5, 5)),
}


@pytest.mark.parametrize("grade", list(GRADES))
def test_grade_table_is_seed004_tables_3_4(grade):
    g = load_grades()[grade]
    asf, amis, ab, an, gsf, gmis, gb, garw = GRADES[grade]
    got = [(g.accel_scale_factor_ppm_min * 1e-6, g.accel_scale_factor_ppm_max * 1e-6), g.accel_misalignment_mrad,
           (g.accel_bias_ug_min, g.accel_bias_ug_max), (g.accel_noise_ug_rt_hz_min, g.accel_noise_ug_rt_hz_max),
           (g.gyro_scale_factor_ppm_min * 1e-6, g.gyro_scale_factor_ppm_max * 1e-6), g.gyro_misalignment_mrad,
           (g.gyro_bias_deg_h_min, g.gyro_bias_deg_h_max), (g.gyro_arw_deg_rt_h_min, g.gyro_arw_deg_rt_h_max)]
    np.testing.assert_allclose(np.hstack(got), np.hstack([asf, amis, ab, an, gsf, gmis, gb, garw]), rtol=1e-12)
    if grade in ("industrial", "consumer"):  # the garbled printed accelerometer rows are flagged
        assert "garbled" in g.notes and "as printed" in g.notes


def test_parts_named_by_the_seeds():
    cat = load_catalog()
    named = {"industrial": ("ADIS16460", "ADIS16445", "ADIS16375"),
             "tactical": ("ADIS16490", "ADIS16488A", "ADIS16485", "HG1700AG58"), "navigation": ("HG9900",)}
    for grade, ids in named.items():
        for pid in ids:
            assert cat[pid].grade == grade, pid
    s = cat["STIM300"]  # seed 000: 0.5 deg/h, 0.15 deg/√h, 0.05 mg, 1 mrad, 55 g
    assert (s.gyro_bias_instability_deg_h, s.gyro_arw_deg_rt_h, s.accel_bias_instability_ug,
            s.accel_misalignment_mrad, s.gyro_misalignment_mrad, s.mass_g) == (0.5, 0.15, 50.0, 1.0, 1.0, 55.0)


# --- §5 the paper's ARMA table, read with the tool's AIC and FPE --------------------------------

PAPER_AIC = (-4.835, -4.855, -4.875, -4.892, -4.948)          # AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1)
PAPER_FPE = (0.007789, 0.007779, 0.007768, 0.007719, 0.007666)


def test_paper_arma_table_is_not_self_consistent():
    """With AIC = ln σ̂² + 2k/n and FPE = σ̂²(n+k)/(n−k) (the tool's, seed 000's definitions),
    AIC − ln FPE = 2k/n − ln((n+k)/(n−k)) is below 1e-6 for k ≤ 3 and n ≥ 1000, and FPE > σ̂².
    The paper's rows give AIC − ln FPE from +0.020 to −0.077, and the chosen ARMA(2,1)'s FPE
    0.007666 lies below its own var(w) = 0.007778 (docs/noise-lab.md says so). Both orderings
    still pick ARMA(2,1), which the tool selects on data simulated from the paper's model
    (tests/test_noise_arma.py)."""
    phi, theta, s2 = np.array([0.8397, 0.1288]), np.array([0.9596]), 0.007778
    for n in (1000, 10_000, 100_000):
        f = ArmaFit(2, 1, phi, theta, s2, n, "paper", 1.0, np.zeros(3))
        assert abs(f.aic - math.log(f.fpe)) < 1e-6
        assert f.fpe > s2 > PAPER_FPE[-1]
    gap = np.array(PAPER_AIC) - np.log(PAPER_FPE)
    assert gap.max() - gap.min() == pytest.approx(0.097, abs=0.001)
    assert int(np.argmin(PAPER_AIC)) == int(np.argmin(PAPER_FPE)) == 4


# --- §6 seed parameters ------------------------------------------------------------------------

def test_seed001_and_seed002_parameters():
    p = MasterSlaveParams()
    assert (p.gyro_drift_deg_h, p.gyro_random_deg_h, p.accel_bias_mg, p.accel_random_mg, p.imu_rate_hz,
            p.correction_rate_hz, p.sigma_velocity_m_s, p.sigma_position_m) == (0.05, 0.005, 0.5, 0.05, 100.0,
                                                                               1.0, 0.02, 2.0)
    # lever arm l = 2 m, θl = −20° (elevation), φl = 15° (azimuth)
    d = np.array(get_preset("missile_borne").lever_arm_m)
    assert np.linalg.norm(d) == pytest.approx(2.0, rel=1e-12)
    assert math.degrees(math.asin(d[2] / 2.0)) == pytest.approx(-20.0, abs=1e-9)
    assert math.degrees(math.atan2(d[1], d[0])) == pytest.approx(15.0, abs=1e-9)
    assert LEVER_ARM_M == (0.175, -0.180, 0.002)
    assert MOUNTING_ANGLES_DEG == (-0.3051, -0.0877, -0.1015)
