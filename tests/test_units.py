"""Unit identities of DESIGN.md §1."""

import math

import pytest

from budget import units as u


def test_arw_identity():
    # 1 deg/√h = 1/60 deg/s/√Hz
    assert u.deg_rt_h_to_rad_s_rt_hz(1.0) == pytest.approx(math.radians(1.0) / 60.0, rel=1e-15)
    assert u.rad_s_rt_hz_to_deg_rt_h(u.deg_rt_h_to_rad_s_rt_hz(0.15)) == pytest.approx(0.15)


def test_vrw_identities():
    # 1 m/s/√h = 1/60 m/s²/√Hz = 1699.7 µg/√Hz
    assert u.m_s_rt_h_to_m_s2_rt_hz(1.0) == pytest.approx(1 / 60.0, rel=1e-15)
    # 1/(60·9.80665e-6) = 1699.53; DESIGN.md prints 1699.7 (a 1e-4 rounding difference)
    assert u.m_s_rt_h_to_ug_rt_hz(1.0) == pytest.approx(1699.7, rel=2e-4)
    assert u.ug_rt_hz_to_m_s_rt_h(1699.7) == pytest.approx(1.0, rel=2e-4)


def test_rate_and_ratio_identities():
    assert u.deg_h_to_rad_s(1.0) == pytest.approx(4.848e-6, rel=1e-3)
    assert u.rad_s_to_deg_h(u.deg_h_to_rad_s(25.2)) == pytest.approx(25.2)
    assert u.ppm_to_ratio(1.0) == 1e-6
    assert u.ug_to_m_s2(1e6) == pytest.approx(u.G0)
    assert u.deg_h_rt_h_to_rad_s_rt_s(1.0) == pytest.approx(math.radians(1) / 3600 / 60)


def test_phase_from_range():
    lam = u.C_LIGHT / 24e9
    # 1° of two-way phase at 24 GHz is 1.7e-5 m, at 77 GHz 5.4e-6 m (seed 004)
    assert u.phase_to_range(math.radians(1), lam) == pytest.approx(1.7e-5, rel=0.03)
    assert u.phase_to_range(math.radians(1), u.C_LIGHT / 77e9) == pytest.approx(5.4e-6, rel=0.01)
    assert u.range_to_phase(lam / 4, lam) == pytest.approx(math.pi)


@pytest.mark.parametrize("name,expected", [("gyro_x_dps", ("gyro_x", "dps")),
                                           ("accel_z_g", ("accel_z", "g")),
                                           ("gyro_y_rps", ("gyro_y", "rps"))])
def test_channel_columns(name, expected):
    assert u.split_channel_column(name) == expected


@pytest.mark.parametrize("bad", ["gyro_x_mps2", "accel_x_dps", "gyro_q_dps", "temp_c", "gyro_x"])
def test_channel_columns_bad(bad):
    with pytest.raises(ValueError, match="expected"):
        u.split_channel_column(bad)
