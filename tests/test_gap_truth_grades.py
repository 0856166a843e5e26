"""The independent generators' other grades and rates (``gap_truth.use``), which the model-gap
benchmark draws to check the workflow beyond the logs it was built on: the base model JSON and
the generated noise must describe the same sensor."""

import math

import numpy as np
import pytest

import gap_truth as gt
from budget.imu import NoiseModel


@pytest.fixture
def restore_grade():
    yield
    gt.use("tactical", 100.0)


@pytest.mark.parametrize("grade, rate", [("consumer", 100.0), ("high_tactical", 200.0), ("tactical", 100.0)])
def test_base_model_and_generated_noise_describe_one_sensor(grade, rate, restore_grade):
    gt.use(grade, rate)
    arw, bi, vrw, abi = gt.GRADES[grade]
    model = NoiseModel.model_validate(gt.base_model_dict())
    assert model.rate_hz == rate
    assert model.gyro_arw_deg_rt_h == arw and model.accel_bias_instability_ug == abi
    # the generated channel's Allan deviation follows the closed form N²/τ + floor² the sizing
    # uses: white noise at short τ (±10 %: 5·10⁴ samples), the flicker floor near its minimum
    n = 100_000
    rng = np.random.default_rng(3)
    for channel in ("gyro_x", "accel_x"):
        x = gt.base_channel(channel, n, rng)
        m = np.array([1, 4])
        ratio = gt.adev(x, m) / gt.base_adev(channel, m / rate)
        assert np.all(np.abs(ratio - 1.0) < 0.1), (channel, ratio)
        dens, _ = gt.base_levels(channel)
        expected = (arw * math.pi / 180 / 60) if channel == "gyro_x" else vrw / 60
        assert dens == pytest.approx(expected, rel=1e-12)


def test_unknown_grade_and_bad_rate_are_refused(restore_grade):
    with pytest.raises(ValueError, match="no grade"):
        gt.use("automotive")
    with pytest.raises(ValueError, match="positive"):
        gt.use("tactical", 0.0)
    assert gt.GRADE == "tactical" and gt.RATE == 100.0


@pytest.mark.parametrize("flicker", ["spectral", "kasdin"])
def test_both_flicker_generators_give_the_ieee_floor(flicker):
    """Either base flicker (spectral shaping; Kasdin & Walter's fractional integrator) of
    coefficient B has the IEEE Std 952 Allan floor 0.664·B from τ = 16 to 1024 samples: the mean
    of 8 draws of 10⁵ samples within 5 % (measured 0.656–0.666 for both). Longer τ is left out:
    at τ = 4096 (≈ 24 averaging times per record) one draw scatters by ≈ 20 %, too much for a
    5 % check of a mean of 8 (this seed's read 8–11 % low)."""
    make = {"spectral": gt.flicker, "kasdin": gt.kasdin_flicker}[flicker]
    rng = np.random.default_rng(11)
    m = np.array([16, 64, 256, 1024])
    floor = np.mean([gt.adev(make(100_000, 2.0, rng), m) for _ in range(8)], axis=0)
    assert np.all(np.abs(floor / (2.0 * gt.FLOOR_PER_B) - 1.0) < 0.05), floor / 2.0
