"""Monte Carlo verdict: does autofocus absorb what the IMU leaves? (P(pass) per part and scenario)."""

from .chain import REASONS, TRIAL_METRICS, ChainSetup, TrialOutcome, run_chunk
from .options import McOptions, VERDICT_ACCEPTANCE
from .result import McResult
from .runner import run_mc
from .stats import StreamingQuantiles, WorstTrials, wilson_interval

__all__ = ["REASONS", "TRIAL_METRICS", "ChainSetup", "TrialOutcome", "run_chunk", "McOptions",
           "VERDICT_ACCEPTANCE", "McResult", "run_mc", "StreamingQuantiles", "WorstTrials",
           "wilson_interval"]
