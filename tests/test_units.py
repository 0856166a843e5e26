"""Unit identities and the range-to-phase sign convention of budget.units."""

import math

import numpy as np
import pytest

from budget import units as u


def test_arw_identity():
    # 1 deg/√h = 1/60 deg/s/√Hz
    assert u.deg_rt_h_to_rad_s_rt_hz(1.0) == pytest.approx(math.radians(1.0) / 60.0, rel=1e-15)
    assert u.rad_s_rt_hz_to_deg_rt_h(u.deg_rt_h_to_rad_s_rt_hz(0.15)) == pytest.approx(0.15)


def test_vrw_identities():
    # 1 m/s/√h = 1/60 m/s²/√Hz = 1/(60·9.80665e-6) = 1699.53 µg/√Hz (a quoted 1699.7 is a
    # 1e-4 rounding slip: the exact value is held here, not the rounded one)
    exact = 1.0 / (60.0 * 9.80665e-6)
    assert u.m_s_rt_h_to_ug_rt_hz(1.0) == pytest.approx(exact, rel=1e-12)
    assert u.ug_rt_hz_to_m_s_rt_h(exact) == pytest.approx(1.0, rel=1e-12)


def test_rate_and_ratio_identities():
    assert u.deg_h_to_rad_s(1.0) == pytest.approx(4.848e-6, rel=1e-3)
    assert u.rad_s_to_deg_h(u.deg_h_to_rad_s(25.2)) == pytest.approx(25.2)
    assert u.ppm_to_ratio(1.0) == 1e-6
    assert u.ug_to_m_s2(1e6) == pytest.approx(u.G0)
    assert u.deg_h_rt_h_to_rad_s_rt_s(1.0) == pytest.approx(math.radians(1) / 3600 / 60)


def test_phase_from_range():
    lam = u.C_LIGHT / 24e9
    # 1° of two-way phase at 24 GHz is 1.7e-5 m, at 77 GHz 5.4e-6 m (seed 004)
    assert u.phase_error_to_range_error(math.radians(1), lam) == pytest.approx(1.7e-5, rel=0.03)
    assert u.phase_error_to_range_error(math.radians(1), u.C_LIGHT / 77e9) == pytest.approx(5.4e-6, rel=0.01)
    # a quarter-wavelength range increase turns the echo by half a turn, backwards (e^{+jωt})
    assert u.range_to_phase(lam / 4, lam) == pytest.approx(-math.pi)
    assert u.range_error_to_phase_error(lam / 4, lam) == pytest.approx(math.pi)


def test_phase_conventions_are_consistent():
    lam, f = u.C_LIGHT / 9.6e9, 9.6e9
    dr = np.array([-3e-3, 0.0, 1e-4, 2.5e-2])
    assert np.allclose(u.phase_to_range(u.range_to_phase(dr, lam), lam), dr, rtol=1e-14, atol=0)
    assert np.allclose(u.phase_error_to_range_error(u.range_error_to_phase_error(dr, lam), lam), dr,
                       rtol=1e-14, atol=0)
    assert np.array_equal(u.range_error_to_phase_error(dr, lam), -u.range_to_phase(dr, lam))
    assert np.allclose(np.abs(u.range_to_phase(dr, lam)), u.two_way_wavenumber_rad_m(lam) * np.abs(dr),
                       rtol=1e-14, atol=0)
    assert u.two_way_wavenumber_at_frequency_rad_m(f, u.C_LIGHT) == pytest.approx(
        u.two_way_wavenumber_rad_m(lam), rel=1e-15)


@pytest.mark.parametrize("quarter_turns", [0.5, -0.3])
def test_range_to_phase_is_the_simulators_sign(quarter_turns):
    """A point target seen from an APC moved away from it along the line of sight by Δr: its
    range-compressed echo turns by range_to_phase(Δr) at every pulse (the echo simulator writes
    exp(−j 4π R/λ) per target; here the offset is built from geometry only)."""
    from budget.presets import get_preset
    from budget.sar import PointTarget, SarGeometry, Scene
    from budget.sar.echoes import simulate_echoes

    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    dr = quarter_turns * g.wavelength_m / 8.0  # |ψ| ≤ π/4: no wrapping, far below a range bin
    scene = Scene(targets=[PointTarget(azimuth_m=0.0, range_m=0.0)])
    target = g.scene_point_m(np.array([0.0]), np.array([g.ref_range_m]))[0]
    away = g.nominal_apc_m() - target
    away /= np.linalg.norm(away, axis=1, keepdims=True)
    d0 = simulate_echoes(g, scene)
    d1 = simulate_echoes(g, scene, dr * away)
    peak = np.argmax(np.abs(d0), axis=1)
    rows = np.arange(g.n_pulses)
    turn = np.angle(d1[rows, peak] * np.conj(d0[rows, peak]))
    expected = float(u.range_to_phase(dr, g.wavelength_m))
    assert abs(expected) > 0.1
    np.testing.assert_allclose(turn, expected, atol=1e-3 * abs(expected))


@pytest.mark.parametrize("name,expected", [("gyro_x_dps", ("gyro_x", "dps")),
                                           ("accel_z_g", ("accel_z", "g")),
                                           ("gyro_y_rps", ("gyro_y", "rps")),
                                           # the package's own suffix spelling, as in its field names
                                           ("gyro_x_rad_s", ("gyro_x", "rps")),
                                           ("gyro_z_deg_s", ("gyro_z", "dps")),
                                           ("gyro_y_deg_h", ("gyro_y", "dph")),
                                           ("accel_x_m_s2", ("accel_x", "mps2"))])
def test_channel_columns(name, expected):
    assert u.split_channel_column(name) == expected


@pytest.mark.parametrize("bad", ["gyro_x_mps2", "accel_x_dps", "gyro_q_dps", "temp_c", "gyro_x",
                                 "gyro_x_m_s2", "accel_y_rad_s", "gyro_x_rad"])
def test_channel_columns_bad(bad):
    with pytest.raises(ValueError, match="expected"):
        u.split_channel_column(bad)


def test_inverse_conversions_round_trip():
    assert u.rad_to_deg(u.deg_to_rad(37.5)) == pytest.approx(37.5, rel=1e-15)
    assert u.ratio_to_ppm(u.ppm_to_ratio(250.0)) == pytest.approx(250.0, rel=1e-15)
    assert u.rad_s_to_dps(u.dps_to_rad_s(3.0)) == pytest.approx(3.0, rel=1e-15)
    assert u.g_to_m_s2(1.0) == u.G0 and u.m_s2_to_ug(u.g_to_m_s2(1e-3)) == pytest.approx(1e3, rel=1e-12)


@pytest.mark.parametrize("channel", u.CHANNELS)
def test_channel_si_unit(channel):
    assert u.channel_si_unit(channel) == ("rad/s" if channel in u.GYRO_CHANNELS else "m/s²")
