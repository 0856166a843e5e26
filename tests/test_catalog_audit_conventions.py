"""Conventions of the shipped catalog that the data alone can check (see budget/catalog/schema.py
and catalog/README.md, "Catalog audit").

Each bound below comes from the physics of the quantity or from the grade table of seed 004
(grades.csv), never from the parts' own values: a unit slip (deg/s stored as deg/h, deg/s/√Hz as
deg/√h, µg/√Hz as m/s/√h, % as ppm, kHz as Hz) or a convention mix-up (a turn-on figure in the
in-run column and an in-run one in the repeatability column) breaks one of them.
"""

from __future__ import annotations

import math

import pytest

from budget.catalog.io import load_grades, read_parts, shipped_catalog_dir
from budget.catalog.schema import CONSTANT_BIAS_CONVENTIONS, FLICKER_FLOOR, GRADE_RANK

G = 9.80665  # m/s² per g
#: Longest Allan record a datasheet bias instability is read from: Sensonor's 20 h test (the
#: longest stated for any shipped part; ADI and Xsens curves stop well before).
LONGEST_RECORD_S = 20 * 3600.0


@pytest.fixture(scope="module")
def parts():
    return read_parts(shipped_catalog_dir() / "parts.csv")


@pytest.fixture(scope="module")
def grades():
    return load_grades()


def _typical(lo: float, hi: float) -> float:
    """The grade's typical value as the fill uses it: geometric mean of its range."""
    return math.sqrt(lo * hi)


def _allan_floor(part, column: str) -> float:
    """The in-run figure as an Allan-deviation floor (IEEE 952: floor = 0.664·B for ieee_b)."""
    v = float(getattr(part, column))
    return v * FLICKER_FLOOR if part.bias_instability_convention == "ieee_b" else v


def test_repeatability_not_below_in_run_floor(parts):
    # A turn-on-to-turn-on bias (run-to-run scatter of the constant bias, 1σ) cannot be smaller
    # than the in-run Allan floor of the same sensor: each run's bias is estimated from a record
    # that itself wanders by the flicker floor, and for MEMS, FOG and RLG parts the run-to-run
    # part (restart of the drive loops, thermal history) adds to it. Checked true for the
    # shipped catalog before asserting: STIM300 accelerometer 750 µg on/off vs 50 µg in-run.
    pairs = [("gyro_bias_instability_deg_h", "gyro_bias_repeatability_deg_h"),
             ("accel_bias_instability_ug", "accel_bias_repeatability_ug")]
    checked = 0
    for p in parts.values():
        for inst, rep in pairs:
            if getattr(p, inst) is None or getattr(p, rep) is None:
                continue
            checked += 1
            assert getattr(p, rep) >= _allan_floor(p, inst), (p.part_id, rep)
    assert checked >= 1  # the catalog holds at least one such pair (STIM300)


def test_constant_bias_rows_leave_repeatability_empty(parts):
    # total_1sigma / turn_on_1sigma: the bias column already is the turn-on bias (schema).
    const = [p for p in parts.values() if p.bias_instability_convention in CONSTANT_BIAS_CONVENTIONS]
    assert const  # HG1700AG58, HG9900
    for p in const:
        assert p.gyro_bias_repeatability_deg_h is None and p.accel_bias_repeatability_ug is None, p.part_id


def test_in_run_floor_not_below_white_noise_line(parts):
    # The Allan deviation of white noise falls as N/√τ; the curve's floor, read within a record
    # of at most LONGEST_RECORD_S, cannot lie below that line at the record's end. With N in
    # deg/√h, σ(τ) = 60·N/√τ deg/h (τ in s); with VRW V in m/s/√h, σ(τ) = V/60/√τ m/s².
    # A bias in deg/s stored as deg/h (3600× too small) or an ARW in deg/h/√Hz stored as deg/√h
    # (60× too large) fails here. Applied to every row: a total 1σ bias includes the floor.
    n = 0
    for p in parts.values():
        if p.gyro_bias_instability_deg_h is not None and p.gyro_arw_deg_rt_h is not None:
            n += 1
            line = 60.0 * p.gyro_arw_deg_rt_h / math.sqrt(LONGEST_RECORD_S)
            assert _allan_floor(p, "gyro_bias_instability_deg_h") >= line, p.part_id
        if p.accel_bias_instability_ug is not None and p.accel_vrw_m_s_rt_h is not None:
            n += 1
            line_ug = p.accel_vrw_m_s_rt_h / 60.0 / math.sqrt(LONGEST_RECORD_S) / G * 1e6
            assert _allan_floor(p, "accel_bias_instability_ug") >= line_ug, p.part_id
    assert n >= 10


def test_high_grades_beat_tactical_typical_arw(parts, grades):
    # A navigation- or stabilization-grade part (RLG / FOG) has an ARW at most the tactical
    # grade's typical value (seed 004 Table 4): otherwise its grade, or its ARW unit, is wrong.
    tac = grades["tactical"]
    limit = _typical(tac.gyro_arw_deg_rt_h_min, tac.gyro_arw_deg_rt_h_max)
    high = [p for p in parts.values() if GRADE_RANK[p.grade] < GRADE_RANK["tactical"]
            and p.gyro_arw_deg_rt_h is not None]
    assert high  # HG9900, KVH1775
    for p in high:
        assert p.gyro_arw_deg_rt_h <= limit, p.part_id


def test_navigation_bias_below_tactical_range(parts, grades):
    # A navigation-grade gyro's bias (total or in-run) is below the best end of the tactical
    # range: the grades are defined by it (seed 004 Table 4).
    tac_best = grades["tactical"].gyro_bias_deg_h_min
    nav = [p for p in parts.values() if p.grade == "navigation" and p.gyro_bias_instability_deg_h is not None]
    assert nav
    for p in nav:
        assert p.gyro_bias_instability_deg_h < tac_best, p.part_id


def test_low_grades_do_not_reach_navigation_arw(parts, grades):
    # MEMS parts of the industrial and consumer grades do not reach the navigation grade's
    # ARW: one that seems to has its figure in deg/s/√Hz (60× too small) or in the wrong row.
    nav_worst = grades["navigation"].gyro_arw_deg_rt_h_max
    low = [p for p in parts.values() if GRADE_RANK[p.grade] >= GRADE_RANK["industrial"]
           and p.gyro_arw_deg_rt_h is not None]
    assert len(low) >= 5
    for p in low:
        assert p.gyro_arw_deg_rt_h > 10 * nav_worst, p.part_id


# Plausible windows per grade, from the physics of the technologies (not from the rows):
# RLG/FOG navigation units 1e-4…0.01 deg/√h; FOG / tactical MEMS 0.005…1; industrial and
# consumer MEMS 0.05…10 (rate noise 0.001…0.17 deg/s/√Hz).
ARW_WINDOW = {"navigation": (1e-4, 0.01), "stabilization": (0.002, 0.1), "tactical": (0.005, 1.0),
              "industrial": (0.05, 10.0), "consumer": (0.05, 10.0)}


def test_arw_within_grade_window(parts):
    n = 0
    for p in parts.values():
        if p.gyro_arw_deg_rt_h is None:
            continue
        lo, hi = ARW_WINDOW[p.grade]
        n += 1
        assert lo <= p.gyro_arw_deg_rt_h <= hi, (p.part_id, p.grade, p.gyro_arw_deg_rt_h)
    assert n >= 15


def test_vrw_in_m_s_rt_h_not_ug_rt_hz(parts):
    # 1 m/s/√h = 1699.7 µg/√Hz: every accelerometer shipped has a noise density between about
    # 1 µg/√Hz (navigation quartz) and 1000 µg/√Hz (consumer MEMS), i.e. 6e-4…0.6 m/s/√h. A
    # density stored unconverted in this column would be 1700× too large.
    vals = [(p.part_id, p.accel_vrw_m_s_rt_h) for p in parts.values() if p.accel_vrw_m_s_rt_h is not None]
    assert len(vals) >= 5
    for pid, v in vals:
        assert 1.0 / 1699.7 <= v <= 1000.0 / 1699.7, pid


def test_scale_factor_in_ppm_and_consumer_tolerance(parts):
    # ppm, not % or a ratio: every scale-factor error is ≥ 1 ppm (the best navigation gyros
    # are specified at a few ppm), and an uncalibrated consumer MEMS sensitivity tolerance is
    # at least 0.1 % = 1000 ppm (so "3" for 3 % would fail).
    n = 0
    for p in parts.values():
        for c in ("gyro_scale_factor_ppm", "accel_scale_factor_ppm"):
            v = getattr(p, c)
            if v is None:
                continue
            n += 1
            assert v >= 1.0, (p.part_id, c)
            if p.grade == "consumer":
                assert v >= 1000.0, (p.part_id, c)
    assert n >= 6


def test_rate_in_hz(parts):
    # Strapdown IMUs sample at ≥ 100 Hz and at most tens of kHz: a rate in kHz stored as is
    # would be < 10.
    rates = [(p.part_id, p.rate_hz) for p in parts.values() if p.rate_hz is not None]
    assert len(rates) >= 10
    for pid, r in rates:
        assert 100.0 <= r <= 50_000.0, pid
