"""Aided and distributed navigation: error-state Kalman filter, RTS smoother, flexure (issue 9).

* :mod:`.config` — pydantic ``aiding`` configs (gnss | dvl | master_ins | star_tracker), flexure.
* :mod:`.ins_error_model` — error state, F, noise, Van Loan discretisation; sign conventions.
* :mod:`.measurements` — H and R of each sensor; :mod:`.system` — truth/filter systems.
* :mod:`.kalman` — trial-vectorised Joseph-form filter; :mod:`.rts` — fixed-interval smoother.
* :mod:`.flexure` — bending mode as a noise-driven oscillator; :mod:`.consistency` — NEES/NIS.
* :mod:`.chain` — :func:`aided_position_error` for the Monte Carlo verdict.
* :mod:`.nonlinear` — large heading misalignment: nonlinear model, DDF2-RTS vs KF-RTS.
* :mod:`.point_target` — azimuth IRF of one target from its phase error.
* :mod:`.seeds` — the seed-paper cases (001 master–slave, 001 PRF slaving, 002 KF vs RTS and
  large misalignment, 003 sonar fusion).
"""

from .chain import AidedResult, aided_position_error, estimate_errors, run_aided
from .config import (AIDING_TYPES, AidingConfig, AidingPlan, DvlAiding, FlexureConfig, GnssAiding,
                     MasterInsAiding, StarTrackerAiding, parse_aiding)
from .consistency import ConsistencyReport, nees_report, nis_report
from .flexure import antenna_flexure_error, simulate_flexure
from .ins_error_model import ImuErrorModel, NominalTrajectory
from .kalman import run_kalman
from .rts import run_rts
from .system import (AidedSystem, InitialUncertainty, build_system, embed_ins_truth,
                     simulate_measurements, simulate_truth, transfer_truth)

__all__ = ["AIDING_TYPES", "AidedResult", "AidedSystem", "AidingConfig", "AidingPlan",
           "ConsistencyReport", "DvlAiding", "FlexureConfig", "GnssAiding", "ImuErrorModel",
           "InitialUncertainty", "MasterInsAiding", "NominalTrajectory", "StarTrackerAiding",
           "aided_position_error", "antenna_flexure_error", "build_system", "embed_ins_truth",
           "estimate_errors", "nees_report", "nis_report", "parse_aiding", "run_aided",
           "run_kalman", "run_rts", "simulate_flexure", "simulate_measurements",
           "simulate_truth", "transfer_truth"]
