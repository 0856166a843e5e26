"""True platform motion and linearised strapdown error propagation over the aperture."""

from .platform import Disturbance, RandomMotion, SinusoidalMotion, TrueMotion, true_motion
from .strapdown import InitialErrors, NavErrors, propagate_errors

__all__ = ["Disturbance", "InitialErrors", "NavErrors", "RandomMotion", "SinusoidalMotion",
           "TrueMotion", "propagate_errors", "true_motion"]
