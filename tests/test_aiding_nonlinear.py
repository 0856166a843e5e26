"""DDF2 and the nonlinear heading model against their linear limits."""

from __future__ import annotations

import numpy as np

from budget.aiding.nonlinear import HeadingModel, ddf2_rts, kf_rts, simulate_heading_truth


def _model(f_h, n=200):
    return HeadingModel(0.1, np.broadcast_to(np.asarray(f_h, float), (n, 2)).copy(), 1e-3, 1e-5)


def test_jacobian_matches_finite_differences():
    m = _model([0.7, -1.3])
    J = m.jacobian_at_zero(3)
    eps = 1e-7
    num = np.stack([(m.step(eps * e, 3) - m.step(-eps * e, 3)) / (2 * eps) for e in np.eye(6)], axis=1)
    assert np.allclose(J, num, rtol=1e-6, atol=1e-12)


def test_large_heading_error_rotates_the_specific_force_exactly():
    m = _model([0.0, 2.0], n=3)
    x = np.zeros(6)
    x[4] = np.radians(90.0)                # INS believes north is east: f seen rotated by −90°
    out = m.step(x, 0)
    # (R(−ψ) − I) f = (f_y, −f_x) − f for ψ = 90°: (2, 0) − (0, 2) = (2, −2)
    assert np.allclose(out[2:4], 0.1 * np.array([2.0, -2.0]), atol=1e-12)


def test_ddf2_rts_equals_kf_rts_when_the_model_is_linear():
    """With no horizontal specific force the heading does not enter: both are the same RTS."""
    m = _model([0.0, 0.0])
    P0 = np.diag([1.0, 1.0, 0.1, 0.1, 0.5, 1e-6])
    rng = np.random.default_rng(0)
    x = simulate_heading_truth(m, P0, 4, rng)
    idx = np.arange(5, m.n_samples, 5)
    R = np.diag([0.04, 0.04, 1e-4, 1e-4])
    z = x[:, idx, :4] + rng.standard_normal((4, idx.size, 4)) @ np.sqrt(R)
    a, b = kf_rts(m, z, 5, R, P0), ddf2_rts(m, z, 5, R, P0)
    assert np.allclose(a, b, rtol=1e-7, atol=1e-10)
