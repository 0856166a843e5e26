"""Motion engine against closed forms at odd IMU rates and long apertures, and its odd inputs.

Closed forms (level flight, no lever arm, x/y/z per axis, position error at time t):
accelerometer white noise N (m/s/√s): rms N·t^{3/2}/√3; gyro white noise N_g (rad/√s):
rms g·N_g·t^{5/2}/√20 on the horizontal axes; a constant gyro bias ε: g·ε·t³/6. Aided: a GNSS
position fix of σ at f Hz on an INS with VRW N reaches the steady state of the continuous
position/velocity Riccati equation, P_pp = √2·q^{1/4}·r^{3/4} (q = N², r = σ²/f).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from budget.aiding import InitialUncertainty, correct_free_inertial
from budget.aiding_spec import parse_aiding
from budget.errors import InputError
from budget.imu.noise_model import NoiseModel
from budget.motion import simulate_motion
from budget.nav.earth import flat_earth_neglect, propagate_errors_earth
from budget.nav.strapdown import propagate_errors
from budget.scenario import Scenario
from budget.units import G0

# X band, broadside, no lever arm: Tc = λR/(2δℓV) = 1.00 s at R = 1601 m.
BASE = dict(name="h7", carrier_frequency_hz=9.6e9, slant_range_m=1601.0, azimuth_resolution_m=0.5,
            range_resolution_m=0.5, platform_speed_m_s=50.0, depression_deg=30.0, imu_rate_hz=200.0)


def scen(**upd) -> Scenario:
    return Scenario.model_validate(BASE | upd)


def model(**kw) -> NoiseModel:
    return NoiseModel(part_id="h7", grade="tactical", source="synthetic", **kw)


def pooled_rms(err: np.ndarray, k: int, axes) -> float:
    return float(np.sqrt(np.mean(err[:, k, list(axes)] ** 2)))


@pytest.mark.parametrize("rate", [10.0, 4000.0])
def test_white_noise_closed_forms_at_odd_imu_rates(rate):
    """VRW and ARW position rms at the aperture end against N·t^{3/2}/√3 and g·N_g·t^{5/2}/√20,
    at 10 Hz and 4 kHz. 512 trials pooled over the axes the term drives: 1 SE of the rms ≈
    1/(2√(512·axes)) ≤ 2.2 %; tolerance 9 % (4 SE). Measured (2,000–8,000 trials): 0.99–1.00."""
    s = scen(imu_rate_hz=rate)
    n_vrw, n_arw = 0.1, 0.5  # m/s/√h, deg/√h
    vrw = simulate_motion(s, model(accel_vrw_m_s_rt_h=n_vrw), 512, 1, keep_series="position")
    t = vrw.time_s[-1]
    assert pooled_rms(vrw.position_error_m, -1, (0, 1, 2)) == pytest.approx(
        n_vrw / 60.0 * t ** 1.5 / math.sqrt(3.0), rel=0.09)
    arw = simulate_motion(s, model(gyro_arw_deg_rt_h=n_arw), 512, 2, keep_series="position")
    assert pooled_rms(arw.position_error_m, -1, (0, 1)) == pytest.approx(
        G0 * math.radians(n_arw / 60.0) * t ** 2.5 / math.sqrt(20.0), rel=0.09)
    assert np.all(arw.position_error_m[..., 2] == 0.0)  # tilt drives no vertical error


def test_a_100_s_aperture_runs_and_states_its_earth_model():
    """Tc ≈ 100 s at 10 Hz: a gyro turn-on bias gives g·ε·t³/6 (Schuler's correction at 100 s is
    (ω_s·t)²/20 ≈ 0.08 %); 256 trials × 2 axes, 1 SE 2.2 %, tolerance 9 %. The result names the
    flat-earth model and the size of what it neglects (≈ 0.4 %)."""
    s = scen(slant_range_m=160_100.0, imu_rate_hz=10.0)
    eps_deg_h = 1.0
    res = simulate_motion(s, model(gyro_bias_repeatability_deg_h=eps_deg_h), 256, 3, keep_series="position")
    t = res.time_s[-1]
    assert t == pytest.approx(100.0, abs=0.1)
    closed = G0 * math.radians(eps_deg_h / 3600.0) * t ** 3 / 6.0
    assert pooled_rms(res.position_error_m, -1, (0, 1)) == pytest.approx(closed, rel=0.09)
    assert res.earth_model.startswith("flat earth") and "Schuler" in res.earth_model
    assert "≈ 0.4 %" in res.earth_model
    assert "earth model: flat earth" in res.summary()
    assert res.to_dict()["earth_model"] == res.earth_model


def test_flat_earth_estimate_against_the_earth_model():
    """flat_earth_neglect(t) against the relative difference of propagate_errors_earth and the
    flat propagation for constant accelerometer and gyro biases (2 Hz, 100 m/s, heading 45°):
    within a factor 1.6 from 300 s to 1000 s (measured 1.0–1.3)."""
    for tc in (300.0, 1000.0):
        n, dt = int(tc * 2) + 1, 0.5
        g = np.zeros((2, n, 3))
        a = np.zeros((2, n, 3))
        a[0, :, :2] = 1e-3
        g[1, :, 1] = 1e-6
        flat = propagate_errors(g, a, dt).apc_position_m
        full = propagate_errors_earth(g, a, dt, speed_m_s=100.0, heading_rad=math.radians(45.0)).apc_position_m
        rel = np.linalg.norm(full - flat, axis=2).max(axis=1) / np.linalg.norm(flat, axis=2).max(axis=1)
        est = flat_earth_neglect(tc, 100.0)
        assert rel.max() / 1.6 < est < 1.6 * rel.max()


def test_a_free_inertial_coast_beyond_the_flat_earth_model_is_refused():
    """Tc ≈ 937 s: the flat model's t³ growth would overstate the Schuler-bounded error (2× at
    3000 s), silently; refused with the derived field, the size and the longest Tc allowed."""
    s = scen(slant_range_m=1_500_000.0, imu_rate_hz=10.0)
    with pytest.raises(InputError) as info:
        simulate_motion(s, model(gyro_bias_repeatability_deg_h=1.0), 2, 0)
    text = str(info.value)
    assert "tc_s (derived)" in text and "flat-earth" in text and "Schuler" in text
    assert "expected Tc ≤ 7" in text and "frozen" in text
    # frozen aiding coasts over the aperture too
    frozen = s.model_copy(update={"aiding": parse_aiding([{"type": "gnss", "rate_hz": 1, "sigma_m": 0.05}]),
                                  "aiding_mode": "frozen", "aiding_warmup_s": 10.0})
    with pytest.raises(InputError, match="flat-earth"):
        simulate_motion(frozen, model(gyro_bias_repeatability_deg_h=1.0), 2, 0)


def test_a_frozen_run_with_no_fix_before_the_aperture_says_so():
    """Warm-up 0 (or a GNSS slower than the warm-up) in frozen mode: no correction exists at the
    aperture start, so the aperture is free-inertial from the initial errors — the result says it
    (and warns) instead of reading as an aided run. A smoothed run gets fixes inside it."""
    gnss = {"type": "gnss", "rate_hz": 10.0, "sigma_m": 0.02}
    m = model(accel_bias_repeatability_ug=100.0)
    for upd in ({"aiding_warmup_s": 0.0}, {"aiding": [gnss | {"rate_hz": 0.001}]}):
        s = scen(**({"aiding": [gnss]} | upd))
        with pytest.warns(UserWarning, match="no aiding fix reaches the filter by the aperture start"):
            res = simulate_motion(s, m, 2, 0, keep_series=False)
        assert res.aiding.startswith("gnss, frozen") and "free-inertial from the initial errors" in res.aiding
    s = scen(aiding=[gnss], aiding_mode="smoothed", aiding_warmup_s=0.0)
    with warnings.catch_warnings():
        warnings.filterwarnings("error", message=".*no aiding fix.*")
        res = simulate_motion(s, m, 2, 0, keep_series=False)
    assert res.aiding == "gnss, smoothed, 0 s warm-up"


def test_an_aperture_cut_to_whole_imu_intervals_is_named():
    """Tc·rate = 4.49: round → 4 intervals, 4/4.49 ≈ 0.891 of Tc simulated (−10.9 %, a bias's
    quadratic phase −21 %): warned and stated; at 200 Hz nothing is said."""
    tc = scen().tc_s
    s = scen(imu_rate_hz=4.49 / tc)
    with pytest.warns(UserWarning, match=r"4 IMU intervals = 0\.8908 s, 10\.9 % shorter than Tc"):
        res = simulate_motion(s, model(accel_bias_repeatability_ug=100.0), 2, 0, keep_series=False)
    assert "simulated over 0.8908 s" in res.summary()
    assert res.to_dict()["aperture_simulated_s"] == pytest.approx(4 * tc / 4.49, rel=1e-9)
    with warnings.catch_warnings():
        warnings.filterwarnings("error", message=".*IMU intervals.*")
        res = simulate_motion(scen(), model(accel_bias_repeatability_ug=100.0), 2, 0, keep_series=False)
    assert "simulated over" not in res.summary()


@pytest.mark.parametrize("entry, field, expected", [
    ({"type": "gnss", "rate_hz": 10, "sigma_m": "2 cm"}, "aiding[0].sigma_m", "0.02 for 2 cm"),
    ({"type": "gnss", "rate_hz": "10 Hz", "sigma_m": 0.02}, "aiding[0].rate_hz", "10 for 10 Hz"),
    ({"type": "gnss", "rate_hz": 10, "sigma_m": 0.02, "latency_s": "50 ms"}, "aiding[0].latency_s",
     "0.05 for 50 ms"),
    ({"type": "gnss", "rate_hz": 10, "sigma_m": 0.02, "lever_arm_m": [1, "20 cm", 0]},
     "aiding[0].lever_arm_m[1]", "0.2 for 20 cm"),
    ({"type": "dvl", "rate_hz": 5, "sigma_m_s": "1 kn"}, "aiding[0].sigma_m_s", "0.514444 for 1 kn"),
    ({"type": "star_tracker", "rate_hz": 1, "sigma_arcsec": "15 arcsec"}, "aiding[0].sigma_arcsec",
     "15 for 15 arcsec"),
    ({"type": "gnss", "rate_hz": "ten", "sigma_m": 0.02}, "aiding[0].rate_hz", "a plain number in Hz"),
])
def test_aiding_values_written_with_units_name_the_number_to_write(entry, field, expected):
    for call in (lambda: parse_aiding([entry]), lambda: Scenario.from_dict(BASE | {"aiding": [entry]})):
        with pytest.raises(InputError) as info:
            call()
        text = str(info.value)
        assert f"field {field}:" in text and expected in text and "\n" not in text


@pytest.mark.parametrize("rate_hz", [1.0, 20.0])
def test_gnss_aided_steady_state_matches_the_textbook_riccati(rate_hz):
    """VRW 0.1 m/s/√h, GNSS σ = 2 cm at 1 or 20 Hz, realtime output over the second minute:
    horizontal rms against √(√2·q^{1/4}·r^{3/4}) (12.8 mm at 1 Hz, 4.2 mm at 20 Hz). The
    filter's bandwidth (q/r)^{1/4} ≤ 0.61 rad/s ≪ 2π·f, so the continuous form applies; 64
    trials, tolerance 10 % (measured 1.01 / 1.00 with 200 trials)."""
    rate, dur, sigma, n_vrw = 100.0, 120.0, 0.02, 0.1 / 60.0
    dt, n = 1.0 / rate, int(dur * rate) + 1
    rng = np.random.default_rng(5)
    nav = propagate_errors(np.zeros((64, n, 3)), rng.standard_normal((64, n, 3)) * n_vrw / math.sqrt(dt),
                           dt, keep_states=True)
    imu = model(accel_vrw_m_s_rt_h=0.1).to_si().errors
    pos, _ = correct_free_inertial(nav.position_m, nav.velocity_m_s, nav.attitude_rad, imu,
                                   [{"type": "gnss", "rate_hz": rate_hz, "sigma_m": sigma}], dt,
                                   np.random.default_rng(6), mode="realtime",
                                   initial=InitialUncertainty(1e-3, 1e-3, 1e-6))
    r, q = sigma ** 2 / rate_hz, n_vrw ** 2
    theory = math.sqrt(math.sqrt(2.0) * q ** 0.25 * r ** 0.75)
    assert float(np.sqrt(np.mean(pos[:, n // 2:, :2] ** 2))) == pytest.approx(theory, rel=0.10)
