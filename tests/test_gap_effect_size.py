"""The scale-free effect size and its stopping rule (``budget.gap.effect_size``).

Logs from the independent generators of ``tests/gap_truth.py``; the model is the base model
written as noise-model JSON. Closed forms: a white-noise density √2 × the model's raises the
ADEV by 1.5 dB and the PSD by 3 dB wherever white noise dominates, for any record length.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import gap_truth as gt
from budget.gap import log_from_arrays, run_gap
from budget.imu import NoiseModel

BASE = NoiseModel.model_validate(gt.base_model_dict())


def _white_only_log(n: int, seed: int, factor: float) -> dict:
    """gyro_x white noise at ``factor`` × the model's density; flicker as the model has."""
    rng = np.random.default_rng(seed)
    dens, floor = gt.base_levels("gyro_x")
    x = factor * dens * math.sqrt(gt.RATE) * rng.standard_normal(n) + gt.flicker(n, floor / gt.FLOOR_PER_B, rng)
    return {"gyro_x": x}


@pytest.mark.slow
def test_effect_size_means_the_same_for_short_and_long_records():
    """White density ×√2: the gap grows ≈ with N, the effect size stays put (within 0.4 dB)."""
    sizes, gaps = [], []
    for n in (8_192, 131_072):
        rep = run_gap(log_from_arrays(_white_only_log(n, 3, math.sqrt(2.0)), gt.RATE), BASE,
                      seed=1, max_steps=0, check_tau_range=False)
        sizes.append(rep.channels["gyro_x"].effect_size_before_db)
        gaps.append(rep.gap_before)
    assert gaps[1] > 5 * gaps[0]
    assert abs(sizes[1] - sizes[0]) < 0.5, sizes
    # white-dominated terms move by 3 dB (Allan variance and PSD); the flicker terms less
    assert 1.0 < sizes[1] < 3.0, sizes


def test_model_following_log_is_within_its_band():
    rep = run_gap(log_from_arrays(_white_only_log(32_768, 5, 1.0), gt.RATE), BASE, seed=2,
                  max_steps=3, check_tau_range=False)
    c = rep.channels["gyro_x"]
    assert rep.steps == []
    assert not rep.band_before.beyond("gyro_x", c.sizes_before)
    assert "close enough" in rep.stop_reason
    out = rep.to_dict()
    assert out["channels"]["gyro_x"]["effect_size_before"]["rms_db"] == pytest.approx(c.effect_size_before_db)
    assert out["close_enough_after"] is True


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_stops_on_effect_size_not_max_steps():
    """A clear tone is named, then the channel's effect size is within its band: the run stops
    for that reason, long before max_steps."""
    x = _white_only_log(32_768, 7, 1.0)
    t = np.arange(32_768) / gt.RATE
    x["gyro_x"] = x["gyro_x"] + 4e-3 * np.sin(2 * math.pi * 3.3 * t + 0.4)
    rep = run_gap(log_from_arrays(x, gt.RATE), BASE, seed=3, max_steps=10, check_tau_range=False)
    assert [s.name for s in rep.steps] == ["sinusoid"]
    s = rep.steps[0]
    assert s.params["amplitude"] == pytest.approx(4e-3, rel=0.1)
    assert s.sizes_after.peak_db < 0.5 < s.sizes_before.peak_db
    assert "close enough" in rep.stop_reason and rep.close_enough


def test_band_below_the_model_is_the_log_chi2_lower_tail():
    """The spread below the model of a term with ν degrees of freedom is the lower quantile of
    10·log10 χ²_ν about its mean, checked against NumPy's χ² draws (2·10⁶, quantile to ≈ 1 %):
    ν = 5 lies 1.35× beyond the normal band of the same variance; ν = 5000 is normal."""
    from scipy import stats as st

    from budget.gap.effect_size import DB_PER_NEPER, _log_chi2_low

    rng = np.random.default_rng(0)
    p = 0.0014
    for nu, wider in ((5, 1.3), (5000, 1.0)):
        x = np.log(rng.chisquare(nu, 2_000_000))
        d = (x - x.mean()) * DB_PER_NEPER
        ms = float(np.mean(d * d))
        got = float(_log_chi2_low(np.array([ms]), p)[0])
        assert got == pytest.approx(-np.quantile(d, p), rel=0.02)
        assert got >= wider * np.sqrt(ms) * st.norm.isf(p) * 0.99
