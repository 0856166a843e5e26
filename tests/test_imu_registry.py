"""The effect registry ties the noise model, the generator and the model-gap vocabulary.

Pinned here: the effect/parameter table, that every registered effect is accepted by the noise
model, changes the generator's output on its channel only, and has exactly one candidate in the
gap library whose parameters are the registry's.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from budget.errors import InputError
from budget.gap import LIBRARY, VOCABULARY
from budget.imu import EFFECT_PARAMS, NoiseModel, generate_imu_errors
from budget.imu.registry import REGISTRY, STAGES

#: One valid parameter set per effect (SI channel units): the table the docs describe.
EXAMPLES = {
    "white_noise": {"density": 1e-3},
    "quantization": {"Q": 1e-5},
    "rate_quantization": {"step": 2e-3},
    "bias_instability": {"B": 1e-4},
    "rate_random_walk": {"K": 1e-4},
    "rate_ramp": {"R": 1e-4},
    "warmup_transient": {"amplitude": 1e-3, "tau_s": 20.0},
    "bias_step": {"amplitude": 1e-3, "time_s": 15.0},
    "sinusoid": {"frequency_hz": 3.0, "amplitude": 1e-3},
    "gauss_markov": {"tau_s": 1.0, "sigma": 1e-3},
    "temperature_sensitivity": {"coefficient": 1e-4},
    "temperature_lag": {"coefficient": 1e-4, "tau_s": 60.0},
    "outliers": {"rate": 1e-2, "magnitude": 1e-2},
    "lowpass": {"cutoff_hz": 10.0},
    "vibration": {"center_hz": 12.0, "width_hz": 1.5, "sigma": 1e-3},
    "heavy_tailed": {"density": 1e-3, "dof": 4.0},
}


def test_one_table_everywhere():
    assert set(REGISTRY) == set(EFFECT_PARAMS) == set(VOCABULARY) == set(LIBRARY) == set(EXAMPLES)
    for name, spec in REGISTRY.items():
        assert spec.stage in STAGES
        assert set(spec.params) == set(EXAMPLES[name]), name
        assert (spec.simulate is not None) == (spec.stage == "additive"), name
        assert LIBRARY[name].name == name


@pytest.mark.parametrize("name", list(REGISTRY))
def test_generator_walks_every_registered_effect(name):
    base = NoiseModel(rate_hz=100.0, gyro_arw_deg_rt_h=0.5)
    model = base.with_effect({"name": name, "channel": "gyro_y", "params": EXAMPLES[name]})
    a = generate_imu_errors(base, 2, 4096, 100.0, np.random.default_rng(4)).gyro_rad_s
    b = generate_imu_errors(model, 2, 4096, 100.0, np.random.default_rng(4)).gyro_rad_s
    assert not np.allclose(a[:, :, 1], b[:, :, 1]), name
    if REGISTRY[name].stage != "gaussian":  # same draws before the effect: other axes untouched
        assert np.array_equal(a[:, :, [0, 2]], b[:, :, [0, 2]]), name


def test_every_deterministic_effect_has_its_mean_series_as_the_generator_draws_it():
    """The statistics' means read ``effects.mean_series``; the generator draws each deterministic
    effect through its registry entry: the two agree, sample for sample."""
    from budget.imu.effects import mean_series
    from budget.imu.registry import DETERMINISTIC_EFFECTS

    n, rate = 3000, 100.0
    temp = 25.0 + 5.0 * np.sin(np.arange(n) / 400.0)
    for name in DETERMINISTIC_EFFECTS:
        model = NoiseModel(rate_hz=rate).with_effect({"name": name, "channel": "gyro_y", "params": EXAMPLES[name]})
        drawn = generate_imu_errors(model, 1, n, rate, np.random.default_rng(0), temp_c=temp).gyro_rad_s[0, :, 1]
        want = mean_series(name, EXAMPLES[name], n, 1.0 / rate, temp)
        np.testing.assert_allclose(drawn, want, rtol=1e-12, atol=1e-15, err_msg=name)
        assert np.any(want != 0), name


@pytest.mark.parametrize("name, channel, params, fragment", [
    ("bias_step", "gyro_x", {"amplitude": 1e-4, "time_s": 0.0}, "time_s must be > 0 s"),
    ("bias_step", "gyro_x", {"amplitude": float("nan"), "time_s": 10.0}, "finite"),
    ("bias_step", "gyro_x", {"amplitude": 1e-4}, "needs parameter(s) time_s"),
    ("warmup_transient", "accel_z", {"amplitude": 1e-4, "tau_s": 0.0}, "tau_s must be > 0 s"),
    ("warmup_transient", "accel_z", {"amplitude": float("nan"), "tau_s": 10.0}, "finite"),
    ("warmup_transient", "accel_z", {"amplitude": 1e-4}, "needs parameter(s) tau_s"),
])
def test_bad_effect_parameters_in_a_model_file_are_refused_naming_file_and_field(tmp_path, name, channel,
                                                                                   params, fragment):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"effects": [{"name": name, "channel": channel, "params": params}]}))
    with pytest.raises(InputError) as err:
        NoiseModel.load(path)
    assert fragment in str(err.value) and "bad.json" in str(err.value)
