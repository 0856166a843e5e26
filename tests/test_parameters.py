"""The one parameter table: pinned, and the places that used to keep their own copies read it."""

import math

import pytest

from budget import units as u
from budget.bounds import BOUND_FIELDS, BoundsTable, paper_bounds
from budget.catalog.schema import PART_NUMERIC_COLUMNS, GradeSpec
from budget.check import PARAM_NAMES
from budget.parameters import BOUNDS, BY_COLUMN, FAMILIES, PARAMETERS, grade_value
from budget.plots.bounds import BOUND_LABELS, GRADE_FIELDS
from budget.plots.check import PARAM_LABELS

# key, column, unit, grade columns, bound attribute, bound key — seed 004 Tables 1–4
PINNED = [
    ("accel_scale_factor", "accel_scale_factor_ppm", "ppm",
     ("accel_scale_factor_ppm_min", "accel_scale_factor_ppm_max"), "accel_scale_factor", "accel_scale_factor_ppm"),
    ("gyro_scale_factor", "gyro_scale_factor_ppm", "ppm",
     ("gyro_scale_factor_ppm_min", "gyro_scale_factor_ppm_max"), "gyro_scale_factor", "gyro_scale_factor_ppm"),
    ("accel_misalignment", "accel_misalignment_mrad", "mrad",
     ("accel_misalignment_mrad",) * 2, "misalignment_rad", "misalignment_mrad"),
    ("gyro_misalignment", "gyro_misalignment_mrad", "mrad",
     ("gyro_misalignment_mrad",) * 2, "misalignment_rad", "misalignment_mrad"),
    ("accel_bias", "accel_bias_instability_ug", "µg",
     ("accel_bias_ug_min", "accel_bias_ug_max"), "accel_bias_m_s2", "accel_bias_ug"),
    ("gyro_bias", "gyro_bias_instability_deg_h", "deg/h",
     ("gyro_bias_deg_h_min", "gyro_bias_deg_h_max"), "gyro_bias_rad_s", "gyro_bias_deg_h"),
    ("accel_vrw", "accel_vrw_m_s_rt_h", "m/s/√h",
     ("accel_noise_ug_rt_hz_min", "accel_noise_ug_rt_hz_max"), "accel_vrw_m_s2_rt_hz", "accel_vrw_ug_rt_hz"),
    ("gyro_arw", "gyro_arw_deg_rt_h", "deg/√h",
     ("gyro_arw_deg_rt_h_min", "gyro_arw_deg_rt_h_max"), "gyro_arw_rad_s_rt_hz", "gyro_arw_deg_rt_h"),
]

# one datasheet value → SI, by the unit functions of budget.units (an independent path)
TO_SI = {"ppm": u.ppm_to_ratio, "mrad": u.mrad_to_rad, "µg": u.ug_to_m_s2, "deg/h": u.deg_h_to_rad_s,
         "m/s/√h": u.m_s_rt_h_to_m_s2_rt_hz, "deg/√h": u.deg_rt_h_to_rad_s_rt_hz,
         "µg/√Hz": u.ug_rt_hz_to_m_s2_rt_hz}


def test_table_is_pinned():
    got = [(p.key, p.column, p.unit, p.grade_columns, p.bound, p.bound_key) for p in PARAMETERS]
    assert got == PINNED
    for p in PARAMETERS:
        assert p.to_si == pytest.approx(TO_SI[p.unit](1.0), rel=1e-15)
        assert p.grade_to_si == pytest.approx(TO_SI[p.grade_unit](1.0), rel=1e-15)
        assert p.bound_to_si == pytest.approx(TO_SI[p.bound_unit](1.0), rel=1e-15)
        assert p.grade_unit == p.bound_unit  # grade bands are drawn on the bound's axis
        assert PART_NUMERIC_COLUMNS[p.column][0] == p.unit  # the catalog schema's unit
        assert set(p.grade_columns) <= set(GradeSpec.model_fields)
        assert p.bound in BoundsTable.__dataclass_fields__


def test_design_identities():
    # 1 m/s/√h = 1/60 m/s²/√Hz = 1/(60·9.80665e-6) µg/√Hz ≈ 1699.5; 1 deg/h = 4.848e-6 rad/s
    vrw = BY_COLUMN["accel_vrw_m_s_rt_h"]
    assert vrw.to_si / vrw.grade_to_si == pytest.approx(1.0 / (60 * 9.80665e-6), rel=1e-12)
    assert BY_COLUMN["gyro_bias_instability_deg_h"].to_si == pytest.approx(4.848e-6, rel=1e-4)


def test_consumers_use_the_table():
    assert PARAM_NAMES == tuple(p.column for p in PARAMETERS)
    assert list(BOUND_FIELDS) == [p.bound_key for p in BOUNDS] == [
        "accel_scale_factor_ppm", "gyro_scale_factor_ppm", "misalignment_mrad", "accel_bias_ug",
        "gyro_bias_deg_h", "accel_vrw_ug_rt_hz", "gyro_arw_deg_rt_h"]
    assert PARAM_LABELS == {p.column: p.label for p in PARAMETERS}
    assert set(BOUND_LABELS) == set(BOUND_FIELDS)
    assert GRADE_FIELDS["misalignment_mrad"] == ("accel_misalignment_mrad", "gyro_misalignment_mrad")
    assert FAMILIES["noise"] == ("accel_vrw_m_s_rt_h", "gyro_arw_deg_rt_h")
    # the bounds' datasheet keys come back in their units: Tc = 10 s, δr = 0.1 m (seed 004 table)
    ds = paper_bounds(10.0, 0.1).datasheet()
    assert ds["accel_bias_ug"][0] == pytest.approx(140.0)
    assert ds["accel_vrw_ug_rt_hz"][0] == pytest.approx(278.3, rel=1e-3)
    assert ds["gyro_bias_deg_h"][0] == pytest.approx(8.93, rel=1e-3)


def test_grade_value_units_and_modes():
    g = GradeSpec(grade="tactical", rank=4, accel_scale_factor_ppm_min=1000, accel_scale_factor_ppm_max=3000,
                  accel_misalignment_mrad=0.5, accel_bias_ug_min=300, accel_bias_ug_max=1000,
                  accel_noise_ug_rt_hz_min=50, accel_noise_ug_rt_hz_max=75, gyro_scale_factor_ppm_min=500,
                  gyro_scale_factor_ppm_max=1500, gyro_misalignment_mrad=0.5, gyro_bias_deg_h_min=0.1,
                  gyro_bias_deg_h_max=30, gyro_arw_deg_rt_h_min=0.1, gyro_arw_deg_rt_h_max=0.5, source="x")
    vrw = BY_COLUMN["accel_vrw_m_s_rt_h"]
    # µg/√Hz → m/s/√h: 50 µg/√Hz = 50/1699.7 m/s/√h
    assert grade_value(g, vrw, "best") == pytest.approx(50 / 1699.527, rel=1e-6)
    assert grade_value(g, BY_COLUMN["gyro_bias_instability_deg_h"], "typical") == pytest.approx(math.sqrt(3.0))
    assert grade_value(g, BY_COLUMN["accel_misalignment_mrad"], "worst") == 0.5
    with pytest.raises(ValueError):
        grade_value(g, vrw, "median")
