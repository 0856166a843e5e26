"""One example parameter set (SI channel units) per registered effect, for the tests that check
every entry of the registry has its closed forms (variance of a linear statistic, covariance of
the slow modes). A new registered effect must be added here, or those tests fail."""

EXAMPLE_PARAMS = {
    "white_noise": {"density": 1e-4}, "quantization": {"Q": 1e-6},
    "rate_quantization": {"step": 1e-4}, "bias_instability": {"B": 1e-4},
    "rate_random_walk": {"K": 1e-5}, "rate_ramp": {"R": 1e-6},
    "warmup_transient": {"amplitude": 1e-4, "tau_s": 300.0},
    "bias_step": {"amplitude": 1e-4, "time_s": 60.0},
    "sinusoid": {"frequency_hz": 1.0, "amplitude": 1e-4},
    "gauss_markov": {"tau_s": 1.0, "sigma": 1e-4},
    "temperature_sensitivity": {"coefficient": 1e-5},
    "temperature_lag": {"coefficient": 1e-5, "tau_s": 300.0},
    "outliers": {"rate": 1e-3, "magnitude": 1e-2}, "lowpass": {"cutoff_hz": 10.0},
    "vibration": {"center_hz": 5.0, "width_hz": 1.0, "sigma": 1e-4},
    "heavy_tailed": {"density": 1e-4, "dof": 5.0},
}
