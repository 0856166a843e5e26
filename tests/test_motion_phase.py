"""Legendre phase decomposition and line-of-sight range error against analytic cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.motion.geometry import los_unit_vector, range_error, scene_targets
from budget.motion.phase import decompose_phase
from budget.presets import get_preset

U = np.linspace(-1.0, 1.0, 801)


def test_pure_quadratic_gives_edge_qpe():
    alpha = 2.7
    d = decompose_phase(alpha * U**2)
    assert d.quadratic_edge_rad == pytest.approx(alpha, rel=1e-12)
    assert d.constant_rad == pytest.approx(alpha / 3, rel=1e-3)  # discrete mean of u² → 1/3
    assert abs(d.linear_edge_rad) < 1e-12 and abs(d.cubic_edge_rad) < 1e-12
    assert d.residual_rms_deg < 1e-10


def test_pure_t_squared_in_time():
    """φ = a·t² over t ∈ [0, T]: edge QPE = a·T²/4 (u² coefficient), linear = a·T²/2."""
    a, tc = 3.0, 4.0
    t = np.linspace(0.0, tc, 801)
    d = decompose_phase(a * t**2)
    assert d.quadratic_edge_rad == pytest.approx(a * tc**2 / 4, rel=1e-12)
    assert d.linear_edge_rad == pytest.approx(a * tc**2 / 2, rel=1e-12)


def test_pure_cubic_edge_is_0p4_alpha():
    alpha = -1.5
    d = decompose_phase(alpha * U**3)
    assert d.cubic_edge_rad == pytest.approx(0.4 * alpha, rel=1e-12)
    assert d.linear_edge_rad == pytest.approx(0.6 * alpha, rel=2e-3)  # discrete sampling of u³·u
    assert abs(d.quadratic_edge_rad) < 1e-12 and d.residual_rms_deg < 1e-10


def test_residual_of_fast_sinusoid_and_batch_shapes():
    amp = math.radians(2.0)
    phase = amp * np.sin(2 * math.pi * 20 * (U + 1) / 2)  # 20 cycles: almost untouched by a cubic
    batch = np.stack([phase, 2 * phase, 0 * phase])[None]  # (1, 3, N)
    d = decompose_phase(batch)
    assert d.residual_rms_deg.shape == (1, 3)
    assert d.residual_rms_deg[0, 0] == pytest.approx(2.0 / math.sqrt(2), rel=0.02)
    assert d.residual_rms_deg[0, 1] == pytest.approx(2 * d.residual_rms_deg[0, 0], rel=1e-12)
    assert d.residual_rms_deg[0, 2] == 0.0
    with pytest.raises(ValueError, match="5 samples"):
        decompose_phase(np.zeros(4))


def test_los_unit_vector():
    u = los_unit_vector(30.0, 0.0)
    np.testing.assert_allclose(u, [0.0, math.cos(math.radians(30)), -0.5], atol=1e-15)
    v = los_unit_vector(10.0, 20.0)
    assert np.linalg.norm(v) == pytest.approx(1.0)
    assert v[0] > 0 and v[1] > 0 and v[2] < 0  # forward squint, imaged side +y, looking down


def test_default_target_is_scene_centre():
    s = get_preset("airborne_xband")
    t = scene_targets(s)
    assert t.shape == (1, 3)
    assert np.linalg.norm(t[0]) == pytest.approx(s.slant_range_m)
    assert t[0, 2] == pytest.approx(-s.slant_range_m * math.sin(math.radians(s.depression_deg)))


def test_range_error_exact_and_sign():
    rng = np.random.default_rng(0)
    target = np.array([100.0, 4000.0, -2500.0])
    apc_true = np.stack([np.linspace(-50, 50, 11), np.zeros(11), np.zeros(11)], axis=1)
    err = rng.normal(0, 0.5, (4, 11, 3))  # true − measured
    dr = range_error(apc_true, err, target)
    direct = np.linalg.norm(target - apc_true, axis=1) - np.linalg.norm(target - (apc_true - err), axis=2)
    np.testing.assert_allclose(dr, direct, rtol=1e-9)
    # true APC 1 mm closer to the target than measured → true range shorter → Δr = −1 mm
    u = (target - apc_true[5]) / np.linalg.norm(target - apc_true[5])
    one = range_error(apc_true[5:6], (1e-3 * u)[None, None, :], target)
    assert one[0, 0] == pytest.approx(-1e-3, rel=1e-9)
    with pytest.raises(Exception, match="targets"):
        scene_targets(get_preset("airborne_xband"), np.zeros((2, 2)))
