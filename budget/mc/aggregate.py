"""Streaming aggregation of trial outcomes: memory bounded whatever the number of trials."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from .chain import REASONS, TRIAL_METRICS, TrialOutcome
from .stats import StreamingQuantiles, WorstTrials


@dataclass
class Aggregate:
    """Counts, failure reasons, metric quantiles and the worst trials of a run.

    ``keep_trial_metrics`` also keeps per-trial metric lists (ordered by trial index) for the
    CLI JSON; sweeps turn it off so memory stays constant.
    """

    keep_worst: int = 5
    keep_trial_metrics: bool = True
    n: int = 0
    pass_before: int = 0
    pass_after: int = 0
    pga_converged: int = 0
    #: trials passed against their perfect-IMU twin after failing the scene's reference
    twin_pass: int = 0
    #: trials on which PGA ran its second pass, and on which it kept it (budget.sar.pga)
    pga_second_pass_ran: int = 0
    pga_second_pass_kept: int = 0
    reasons: Counter = field(default_factory=Counter)
    q_before: dict = field(default_factory=lambda: {m: StreamingQuantiles() for m in TRIAL_METRICS})
    q_after: dict = field(default_factory=lambda: {m: StreamingQuantiles() for m in TRIAL_METRICS})
    q_cells: StreamingQuantiles = field(default_factory=StreamingQuantiles)
    worst: WorstTrials = field(default_factory=WorstTrials)
    trial_metrics: dict = field(default_factory=dict)

    def __post_init__(self):
        self.worst = WorstTrials(k=self.keep_worst)

    def add(self, outcomes: list[TrialOutcome]) -> None:
        for o in outcomes:
            self.n += 1
            self.pass_before += o.passed_before
            self.pass_after += o.passed_after
            self.pga_converged += o.pga_converged
            self.twin_pass += o.twin_pass
            self.pga_second_pass_ran += bool(o.pga_second_pass)
            self.pga_second_pass_kept += o.pga_second_pass == "kept"
            self.reasons.update(o.reasons)
            for m in TRIAL_METRICS:
                self.q_before[m].add([o.before[m]])
                self.q_after[m].add([o.after[m]])
            self.q_cells.add([o.peak_range_cells])
            if self.keep_worst:
                self.worst.offer(o.score, o.trial, o)
            if self.keep_trial_metrics:
                self.trial_metrics.setdefault("trial", []).append(o.trial)
                for m in TRIAL_METRICS:
                    self.trial_metrics.setdefault(m, []).append(o.after[m])
                self.trial_metrics.setdefault("peak_range_cells", []).append(o.peak_range_cells)
                self.trial_metrics.setdefault("passed_after", []).append(o.passed_after)

    def failure_reasons(self) -> dict[str, int]:
        return {r: int(self.reasons.get(r, 0)) for r in REASONS}
