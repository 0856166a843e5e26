"""Model-gap workflow: where a measured IMU log and its noise model disagree, which effect of
the shared vocabulary is missing, and the gap after adding it.

Public API (SI inside: rad/s, m/s²):

* :func:`run_gap` (measurement, model) → :class:`GapReport` (``.to_dict()``, ``.save()``,
  ``.summary()``, ``.to_frame()``, ``.updated_model``)
* :func:`cross_validate` (fit log, test log, model) → :class:`CrossValidation`: effects that
  do not carry over to a second log of the same part are not named
* :func:`log_from_arrays` — an :class:`~budget.noise.ImuLog` from SI arrays
* :mod:`budget.gap.signatures`, :mod:`budget.gap.metric` (gap definition and null),
  :mod:`budget.gap.walk` (the record's slowest modes against the model's exact covariance),
  :mod:`budget.quadform` (weighted-χ² tails, shared with the bounds), :mod:`budget.gap.candidates` (effect
  library); figures in :mod:`budget.plots.gap`
"""

from .candidates import LIBRARY, VOCABULARY
from .crossval import CrossValidation, cross_validate
from .effect_size import EffectSizeBand, Sizes
from .inputs import log_from_arrays
from .metric import GapTerms, ModelSummary, NullModel, gap_terms
from .report import GAP_DEFINITION, GapReport, GapStep
from .workflow import run_gap

__all__ = ["CrossValidation", "EffectSizeBand", "GAP_DEFINITION", "GapReport", "GapStep", "GapTerms",
           "LIBRARY", "ModelSummary", "NullModel", "VOCABULARY", "Sizes", "cross_validate",
           "gap_terms", "log_from_arrays", "run_gap"]
