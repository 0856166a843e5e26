"""Noise lab: IMU logs and Allan tables → Allan deviation, IEEE-952 terms, catalog rows;
ARMA modelling and the state-augmented Kalman filter of seed 000.

Public API (SI inside: rad/s, m/s²):

* :func:`read_log` → :class:`ImuLog`; :class:`LogMapping` for other layouts
* :func:`read_adev_table` → ``{channel: AllanResult}``
* :func:`allan_deviation` → :class:`AllanResult`; :func:`fit_noise_terms` → :class:`NoiseTerms`
* :func:`characterize` → :class:`Characterization` (``.part`` PartSpec, ``.channels``,
  ``.warnings``: e.g. a log that is not one stationary regime, :func:`check_stationarity`)
* :func:`welch_psd` → :class:`PsdResult`
* :func:`preprocess`, :func:`check_series`
* :func:`select_arma` / :func:`fit_arma` → :class:`ArmaSelection` / :class:`ArmaFit`
* :class:`ArmaKalman` (``.filter(z)``, ``.smooth(z)``), :func:`frequency_response`,
  :func:`motion_distortion`
"""

from .adev_table import read_adev_table
from .allan import AllanResult, allan_deviation
from .arma import ArmaFit, ArmaSelection, fit_arma, select_arma
from .characterize import Characterization, characterize
from .checks import CheckReport, check_series
from .kalman import ArmaKalman, KalmanResult
from .kalman_response import FrequencyResponse, frequency_response, motion_distortion
from .log_checks import LogIssue, LogReport
from .log_mapping import LogMapping
from .logs import ImuLog, LogError, read_log
from .preprocess import Preprocessed, preprocess
from .psd import PsdResult, welch_psd
from .stationarity import check_stationarity
from .terms import NoiseTerms, adev_model, fit_noise_terms

__all__ = [
    "AllanResult", "ArmaFit", "ArmaKalman", "ArmaSelection", "Characterization", "CheckReport",
    "FrequencyResponse", "ImuLog", "KalmanResult", "LogError", "LogIssue", "LogMapping",
    "LogReport", "NoiseTerms", "Preprocessed", "PsdResult", "adev_model", "allan_deviation",
    "characterize", "check_series", "check_stationarity", "fit_arma", "fit_noise_terms",
    "frequency_response",
    "motion_distortion", "preprocess", "read_adev_table", "read_log", "select_arma", "welch_psd",
]
