"""Aided and distributed navigation: error-state Kalman filter, RTS smoother, flexure.

* :mod:`budget.aiding_spec` — pydantic ``aiding`` configs (gnss | dvl | master_ins |
  star_tracker), flexure, correction modes (on the scenario's floor; re-exported here).
* :mod:`.ins_error_model` — error state, F, noise, Van Loan discretisation; sign conventions.
* :mod:`.measurements` — H and R of each sensor; :mod:`.system` — truth/filter systems.
* :mod:`.kalman` — trial-vectorised Joseph-form filter; :mod:`.rts` — fixed-interval smoother.
* :mod:`.flexure` — bending mode as a noise-driven oscillator; :mod:`.consistency` — NEES/NIS.
* :mod:`.chain` — :func:`correct_free_inertial` (the motion engine's aided path, every
  correction mode) and :func:`aided_position_error` (array in, array out).
* :mod:`.nonlinear` — large heading misalignment: nonlinear model, DDF2-RTS vs KF-RTS.

The seed-paper applications live in :mod:`budget.seeds`, the point-target helper in
:mod:`budget.sar.point_target`; nothing here imports the scenario or the presets.
"""

from ..aiding_spec import (AIDING_TYPES, CORRECTION_MODES, AidingConfig, AidingPlan, DvlAiding,
                           FlexureConfig, GnssAiding, MasterInsAiding, StarTrackerAiding, parse_aiding)
from .chain import AidedResult, aided_position_error, correct_free_inertial, estimate_errors, run_aided
from .consistency import ConsistencyReport, nees_report, nis_report
from .flexure import antenna_flexure_error, simulate_flexure
from .ins_error_model import ImuErrorModel, NominalTrajectory
from .kalman import run_kalman
from .rts import run_rts
from .system import (AidedSystem, InitialUncertainty, build_system, embed_ins_truth,
                     simulate_measurements, simulate_truth, transfer_truth)

__all__ = ["AIDING_TYPES", "CORRECTION_MODES", "AidedResult", "AidedSystem", "AidingConfig",
           "AidingPlan", "ConsistencyReport", "DvlAiding", "FlexureConfig", "GnssAiding",
           "ImuErrorModel", "InitialUncertainty", "MasterInsAiding", "NominalTrajectory",
           "StarTrackerAiding", "aided_position_error", "antenna_flexure_error", "build_system",
           "correct_free_inertial", "embed_ins_truth", "estimate_errors", "nees_report",
           "nis_report", "parse_aiding", "run_aided", "run_kalman", "run_rts", "simulate_flexure",
           "simulate_measurements", "simulate_truth", "transfer_truth"]
