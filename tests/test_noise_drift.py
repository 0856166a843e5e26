"""A "static" log whose output drifts (warm-up, temperature, a record that was not static).

The Allan fit reads a deterministic drift as a rate ramp R (σ² = R²τ²/2, IEEE-952) and, in part,
as rate random walk; R has no catalog column. :func:`budget.noise.characterize` must say so — a
warning naming the channel, R in datasheet units per hour and what the drift did over the record
(the span of its block means) — and must stay silent on logs that follow a noise model.

The drift is written here (a quadratic warm-up plus a slow cycle, in deg/s), not by the detector;
the noise is the package's generator at tactical magnitudes (as in ``test_hardening_inputs2``).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from budget import units as u
from budget.noise import characterize
from budget.noise.characterize import DRIFT_BLOCKS
from tests.test_hardening_inputs2 import HOUR, RATE, _log, _tactical


def _drift_deg_s(n: int) -> np.ndarray:
    """0.2 deg/s of quadratic warm-up over the record plus a 0.05 deg/s cycle of 20 min."""
    t = np.arange(n) / RATE
    return 0.2 * (t / t[-1]) ** 2 + 0.05 * np.sin(2 * np.pi * t / 1200.0)


def test_a_drifting_gyro_is_warned_with_its_size_and_named_in_the_row():
    ch = _tactical(31)
    drift = u.deg_to_rad(_drift_deg_s(HOUR))
    ch["gyro_x"] = ch["gyro_x"] + drift
    res = characterize(_log(ch, "warm.csv"))
    drift_w = [w for w in res.warnings if "rate ramp resolved" in w]
    assert len(drift_w) == 1 and drift_w[0].startswith("gyro_x: "), res.warnings
    # the span of the drift's own block means (deg/h), against the one the warning states
    m = drift[: HOUR // DRIFT_BLOCKS * DRIFT_BLOCKS].reshape(DRIFT_BLOCKS, -1).mean(axis=1)
    truth = u.rad_s_to_deg_h(np.ptp(m))
    said = float(re.search(r"block means span ([\d.e+]+) deg/h", drift_w[0]).group(1))
    assert said == pytest.approx(truth, rel=0.05)  # the tactical noise adds < 1 % at 56-s blocks
    assert "not a noise term" in drift_w[0] and "doubtful" in drift_w[0]
    assert "rate ramp (drift, not noise) resolved on gyro_x" in res.part.notes
    assert drift_w[0] in res.summary() and drift_w[0] in res.to_dict()["warnings"]


@pytest.mark.parametrize("seed", [41, 42, 43])
def test_logs_that_follow_a_noise_model_get_no_drift_warning(seed):
    res = characterize(_log(_tactical(seed)))
    assert not [w for w in res.warnings if "rate ramp" in w], res.warnings
    assert "rate ramp" not in res.part.notes


def test_a_tone_the_ieee952_terms_cannot_describe_is_warned_at_its_tau():
    """A 1 mg (0.0098 m/s²) 2 Hz vibration tone on accel_x of a tactical log (written here): the
    Allan curve has a bump near τ ≈ 0.37/f the IEEE-952 set cannot follow; the fit's χ² rejects
    it and the warning names the channel and a τ within a factor 2 of 0.18 s — and no other
    channel."""
    ch = _tactical(32)
    t = np.arange(HOUR) / RATE
    ch["accel_x"] = ch["accel_x"] + 0.0098 * np.sin(2 * np.pi * 2.0 * t)
    res = characterize(_log(ch))
    mis = [w for w in res.warnings if "do not describe its Allan curve" in w]
    assert len(mis) == 1 and mis[0].startswith("accel_x: "), res.warnings
    tau = float(re.search(r"at τ = ([\d.e+-]+) s", mis[0]).group(1))
    assert 0.09 <= tau <= 0.37, mis[0]


@pytest.mark.parametrize("seed", [41, 42, 43])
def test_logs_that_follow_a_noise_model_get_no_misfit_warning(seed):
    res = characterize(_log(_tactical(seed)))
    assert not [w for w in res.warnings if "Allan curve" in w], res.warnings
