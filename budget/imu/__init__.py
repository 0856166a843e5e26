"""IMU noise model (catalog row + effects) and the vectorised IMU error generator."""

from .generator import ImuErrors, generate_imu_errors, simulate_static_log
from .noise_model import EFFECT_NAMES, EFFECT_PARAMS, Effect, NoiseModel, NoiseModelSI

__all__ = ["EFFECT_NAMES", "EFFECT_PARAMS", "Effect", "ImuErrors", "NoiseModel", "NoiseModelSI",
           "generate_imu_errors", "simulate_static_log"]
