"""True platform motion: kinematic consistency of position, force, attitude and body rates."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from pydantic import ValidationError

from budget.errors import InputError
from budget.nav.platform import Disturbance, RandomMotion, true_motion
from budget.units import G0

RATE = 1000.0
TIME = np.arange(4001) / RATE


def _d2(x, dt):
    """Central second difference (interior samples)."""
    return (x[..., 2:] - 2 * x[..., 1:-1] + x[..., :-2]) / dt**2


def test_straight_flight_is_level_and_unaccelerated():
    m = true_motion(50.0, TIME)
    np.testing.assert_allclose(m.position_m[:, 0], 50.0 * (TIME - TIME[-1] / 2))
    assert not m.position_m[:, 1:].any() and not m.rate_b_rad_s.any() and m.c_b_n is None
    np.testing.assert_allclose(m.force_b_m_s2, np.tile([0.0, 0.0, G0], (TIME.size, 1)))


def test_sinusoidal_translation_force_is_second_derivative_plus_gravity():
    dist = Disturbance(sinusoids=[{"axis": "heave", "frequency_hz": 0.7, "amplitude_m": 0.2},
                                  {"axis": "sway", "frequency_hz": 1.3, "amplitude_m": 0.05, "phase_rad": 1.0}])
    m = true_motion(30.0, TIME, dist)
    dt = 1.0 / RATE
    for axis in (1, 2):
        acc_fd = _d2(m.position_m[:, axis], dt)
        expected = m.force_n_m_s2[1:-1, axis] - (G0 if axis == 2 else 0.0)
        np.testing.assert_allclose(acc_fd, expected, atol=1e-5 * np.abs(expected).max())
    assert m.position_m[:, 1].max() == pytest.approx(0.05, rel=1e-4)


def test_attitude_motion_dcm_and_body_rate_are_consistent():
    dist = Disturbance(sinusoids=[{"axis": "roll", "frequency_hz": 0.3, "amplitude_rad": 0.1},
                                  {"axis": "pitch", "frequency_hz": 0.5, "amplitude_rad": 0.05},
                                  {"axis": "yaw", "frequency_hz": 0.2, "amplitude_rad": 0.08, "phase_rad": 0.4}])
    m = true_motion(30.0, TIME, dist)
    c = m.c_b_n
    np.testing.assert_allclose(np.einsum("nij,nkj->nik", c, c), np.broadcast_to(np.eye(3), c.shape), atol=1e-12)
    dt = 1.0 / RATE
    cdot = (c[2:] - c[:-2]) / (2 * dt)
    skew = np.einsum("nji,njk->nik", c[1:-1], cdot)  # Cᵀ·Ċ = [ω_b×]
    w = m.rate_b_rad_s[1:-1]
    np.testing.assert_allclose(skew[:, 2, 1], w[:, 0], atol=1e-6)
    np.testing.assert_allclose(skew[:, 0, 2], w[:, 1], atol=1e-6)
    np.testing.assert_allclose(skew[:, 1, 0], w[:, 2], atol=1e-6)
    np.testing.assert_allclose(m.force_b_m_s2, np.einsum("nji,nj->ni", c, m.force_n_m_s2), atol=1e-12)


def test_random_motion_variance_matches_psd_and_derivatives_are_consistent():
    s0 = 1e-3  # m²/Hz, flat from 0.2 to 2 Hz → variance ≈ 1.8e-3 m²
    comp = RandomMotion(axis="sway", frequency_hz=(0.2, 2.0), psd_m2_per_hz=(s0, s0))
    dist = Disturbance(random=[comp])
    time = np.arange(2001) / 100.0
    m = true_motion(20.0, time, dist, n_trials=400, rng=np.random.default_rng(1))
    y = m.position_m[:, :, 1]
    assert y.shape == (400, 2001)
    # ∫S df = 1.8e-3 m²; the line grid Δf = 1/(2·20 s) adds up to one extra line (1.4 %);
    # 400 trials × 73 lines: standard error 0.6 %.
    assert y.var() == pytest.approx(s0 * (2.0 - 0.2), rel=0.04)
    acc_fd = _d2(y, 0.01)
    np.testing.assert_allclose(acc_fd, m.force_n_m_s2[:, 1:-1, 1], atol=2e-3 * np.abs(acc_fd).max())
    with pytest.raises(ValueError, match="Generator"):
        true_motion(20.0, time, dist)


def test_psd_interpolation_is_log_log():
    comp = RandomMotion(axis="pitch", frequency_hz=(0.1, 10.0), psd_rad2_per_hz=(1e-2, 1e-6))
    np.testing.assert_allclose(comp.psd_at(np.array([0.05, 0.1, 1.0, 10.0, 20.0])),
                               [0.0, 1e-2, 1e-4, 1e-6, 0.0], rtol=1e-12)


@pytest.mark.parametrize("bad, fragment", [
    ({"sinusoids": [{"axis": "roll", "frequency_hz": 1.0, "amplitude_m": 0.1}]}, "rotation"),
    ({"sinusoids": [{"axis": "heave", "frequency_hz": -1.0, "amplitude_m": 0.1}]}, "greater than 0"),
    ({"sinusoids": [{"axis": "bob", "frequency_hz": 1.0, "amplitude_m": 0.1}]}, "surge"),
    ({"random": [{"axis": "sway", "frequency_hz": [1.0, 0.5], "psd_m2_per_hz": [1, 1]}]}, "increasing"),
    ({"random": [{"axis": "sway", "frequency_hz": [1.0, 2.0], "psd_m2_per_hz": [1]}]}, "same length"),
])
def test_invalid_disturbances(tmp_path, bad, fragment):
    with pytest.raises(ValidationError, match=fragment):
        Disturbance.model_validate(bad)
    path = tmp_path / "d.json"
    path.write_text(json.dumps(bad))
    with pytest.raises(InputError, match="d.json"):
        Disturbance.load(path)


def test_disturbance_max_frequency():
    d = Disturbance(sinusoids=[{"axis": "yaw", "frequency_hz": 3.0, "amplitude_rad": 0.01}],
                    random=[{"axis": "heave", "frequency_hz": [0.1, 7.5], "psd_m2_per_hz": [1e-3, 1e-5]}])
    assert d.max_frequency_hz() == 7.5 and d.is_random and d.has_rotation
    assert math.isclose(d.sinusoids[0].amplitude, 0.01)
