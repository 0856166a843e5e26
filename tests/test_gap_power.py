"""The Neyman–Pearson power bounds of the model-gap benchmark (``tests/gap_power.py``) rest on
closed-form block-sum covariances of the independent generators; checked here against the
generators themselves. 800 realizations: a sample variance has a relative standard deviation
√(2/799) = 5 %, so 4.5σ = 22 % bounds each check."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gap_power as gp
import gap_truth as gt

N, M, DRAWS = 20_000, 500, 800
TOL = 4.5 * math.sqrt(2.0 / (DRAWS - 1))


def _probes(nb: int, rng: np.random.Generator) -> np.ndarray:
    """Contrast vectors that weigh slow and fast block-to-block changes: the trend, the first
    difference, a half-record step and two random contrasts."""
    i = np.arange(nb, dtype=float)
    vecs = [i - i.mean(), np.r_[1.0, -1.0, np.zeros(nb - 2)], np.where(i < nb / 2, 1.0, -1.0)]
    vecs += [v - v.mean() for v in rng.standard_normal((2, nb))]
    return np.array(vecs)


@pytest.mark.slow
def test_base_channel_block_covariance():
    rng = np.random.default_rng(5)
    sums = np.array([gp.block_sums(gt.base_channel("gyro_x", N, rng), M) for _ in range(DRAWS)])
    cov = gp.base_block_cov("gyro_x", N, M)
    for v in _probes(N // M, rng):
        ratio = np.var(sums @ v, ddof=1) / float(v @ cov @ v)
        assert abs(ratio - 1.0) < TOL, ratio


def test_random_walk_block_covariance():
    rng = np.random.default_rng(6)
    step = 1e-3
    sums = np.array([gp.block_sums(step * np.cumsum(rng.standard_normal(N)), M) for _ in range(DRAWS)])
    cov = gp.walk_block_cov(N // M, M, step)
    for v in _probes(N // M, rng):
        ratio = np.var(sums @ v, ddof=1) / float(v @ cov @ v)
        assert abs(ratio - 1.0) < TOL, ratio
    # with a constant added: the contrasts do not see it
    assert np.allclose(gp.contrasts(N // M) @ np.ones(N // M), 0.0, atol=1e-12)


@pytest.mark.slow
def test_bounds_are_ordered_and_saturate():
    """More magnitude never lowers the bound; at 5× every effect is certain to be seen."""
    for name in ("rate_random_walk", "rate_ramp", "temperature_sensitivity"):
        p = [gp.power_bound(name, r, rng=np.random.default_rng(0)) for r in (1.3, 2.0, 5.0)]
        assert p[0] <= p[1] + 0.01 <= p[2] + 0.02 and p[2] > 0.999, (name, p)
