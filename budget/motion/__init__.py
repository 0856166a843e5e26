"""Motion-error engine: IMU errors → antenna-phase-centre error → range and phase error.

One path for free-inertial and aided navigation (:func:`simulate_motion`; aiding and the IMU
pre-filter are options, the scenario's aiding section the default).
"""

from .engine import aperture_samples, simulate_motion
from .geometry import los_unit_vector, range_error, scene_targets
from .phase import PhaseDecomposition, decompose_phase
from .result import MotionResult

__all__ = ["MotionResult", "PhaseDecomposition", "aperture_samples", "decompose_phase",
           "los_unit_vector", "range_error", "scene_targets", "simulate_motion"]
