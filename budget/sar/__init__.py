"""Point-target SAR/SAS simulator, image formation, phase gradient autofocus and IRF metrics.

Chain: ``SarGeometry.from_scenario`` → ``Scene.default`` → ``simulate_echoes``
(true trajectory) → ``form_image`` (measured trajectory; "rda" or "backprojection") →
``measure_targets`` → ``pga`` → ``measure_targets`` → ``evaluate``.
"""

from .acceptance import Acceptance, Evaluation, evaluate
from .echoes import simulate_echoes
from .geometry import SarGeometry
from .image import SarImage, form_image
from .metrics import AxisMetrics, TargetMetrics, TargetMetricsTable, measure_targets
from .pga import PgaResult, pga
from .phase import (los_offset_for_phase, phase_on_bins, residual_phase_rad, residual_rms_rad,
                    smooth_phase_error)
from .scene import PointTarget, Scene
from .windows import IdealIrf, Window, ideal_irf

__all__ = [
    "Acceptance", "AxisMetrics", "Evaluation", "IdealIrf", "PgaResult", "PointTarget", "SarGeometry",
    "SarImage", "Scene", "TargetMetrics", "TargetMetricsTable", "Window", "evaluate", "form_image",
    "ideal_irf", "los_offset_for_phase", "measure_targets", "pga", "phase_on_bins", "residual_phase_rad",
    "residual_rms_rad", "simulate_echoes", "smooth_phase_error",
]
