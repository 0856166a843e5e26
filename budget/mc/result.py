"""Monte Carlo verdict of one part (or noise model) on one scenario."""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

from ..sar.residual import DEFAULT_PASS_SHARE
from ..scenario import Scenario
from .aggregate import Aggregate
from .chain import TRIAL_METRICS
from .notes import SIMULATION_NOTES
from .options import McOptions
from .stats import StreamingQuantiles, wilson_interval

#: How decisions use P(pass): the lower 95 % Wilson bound, not the point estimate (at p̂ = 0.9
#: with 64 trials the interval is [0.80, 0.95]).
DECISION_RULE = "pass when the lower 95 % Wilson bound of P(pass after PGA) ≥ the target"
#: How the table's percentiles are read (:class:`budget.mc.stats.StreamingQuantiles`: memory that
#: does not grow with the trials); the per-trial values, when kept, are in the JSON.
QUANTILE_NOTE = (f"p50 / p95: read from the run's streaming histograms ({StreamingQuantiles.per_decade} bins per "
                 f"decade: within {100 * (10 ** (1 / StreamingQuantiles.per_decade) - 1):.1f} % of the exact "
                 "order statistic); the per-trial values, when the run keeps them, are in the JSON (metrics_after)")

#: Unit of each per-trial metric of :meth:`McResult.to_frame` (broadening: 3 dB width / the
#: window's ideal − 1, a ratio; dB; degrees of phase).
METRIC_UNITS = {"azimuth_broadening": "ratio (width/ideal − 1)", "range_broadening": "ratio (width/ideal − 1)",
                "pslr_db": "dB", "islr_db": "dB", "peak_loss_db": "dB", "residual_phase_rms_deg": "deg rms",
                "pga_error_rms_deg": "deg rms", "fast_phase_rms_deg": "deg rms"}
#: The columns of :meth:`McResult.to_frame` its summary prints (the rest repeat the verdict).
FRAME_METRIC_COLUMNS = ("metric", "unit", "p50_before", "p95_before", "p50_after", "p95_after")

#: Per-trial metrics in the CLI JSON (``metrics_after``).
JSON_METRICS = ("azimuth_broadening", "range_broadening", "pslr_db", "islr_db", "residual_phase_rms_deg",
                "peak_loss_db", "pga_error_rms_deg", "fast_phase_rms_deg")


@dataclass
class McResult:
    """P(pass) before/after PGA with 95 % Wilson intervals, failure reasons, metric percentiles.

    ``worst`` holds the worst trials (:class:`~budget.mc.chain.TrialOutcome`, with images when
    the run kept details); ``cancelled`` is True when the run was stopped early (the numbers then
    cover the ``trials`` completed).
    """

    scenario_name: str
    model_label: str
    seed: int
    tc_s: float
    agg: Aggregate
    cancelled: bool = False
    extra: dict = field(default_factory=dict)
    options: McOptions | None = None
    scenario: Scenario | None = None
    judged_on: dict = field(default_factory=dict)
    #: the values of the model simulated (:func:`budget.mc.runner.model_spec`: datasheet units,
    #: unspecified terms as filled); None for a model given in SI
    model_spec: dict | None = None

    @property
    def trials(self) -> int:
        return self.agg.n

    @property
    def p_pass_before(self) -> float:
        return self.agg.pass_before / self.agg.n if self.agg.n else float("nan")

    @property
    def p_pass_after(self) -> float:
        return self.agg.pass_after / self.agg.n if self.agg.n else float("nan")

    @property
    def ci_before(self) -> tuple[float, float]:
        return wilson_interval(self.agg.pass_before, self.agg.n)

    @property
    def ci_after(self) -> tuple[float, float]:
        return wilson_interval(self.agg.pass_after, self.agg.n)

    def meets(self, target: float = DEFAULT_PASS_SHARE) -> bool:
        """Decision at P(pass after PGA) ≥ ``target`` (default 0.9, the share the analytic
        fast-phase limits and ``cheapest_passing`` ask for) on the lower Wilson bound
        (:data:`DECISION_RULE`)."""
        return bool(self.ci_after[0] >= target)

    def verdict(self, target: float = DEFAULT_PASS_SHARE) -> str:
        """``pass`` (lower Wilson bound ≥ ``target``), ``fail`` (upper bound < ``target``) or
        ``undecided`` (the interval straddles it: more trials decide)."""
        lo, hi = self.ci_after
        return "pass" if lo >= target else "fail" if hi < target else "undecided"

    def percentiles(self, when: str = "after") -> dict[str, dict[str, float]]:
        """p50 and p95 of every metric from the run's streaming histograms (:data:`QUANTILE_NOTE`)."""
        q = self.agg.q_after if when == "after" else self.agg.q_before
        return {m: {"p50": q[m].quantile(0.5), "p95": q[m].quantile(0.95)} for m in TRIAL_METRICS}

    def worst_trials(self) -> list:
        return [o for _, _, o in self.agg.worst.items()]

    def to_dict(self) -> dict:
        """JSON-ready verdict with the options and scenario it was computed with (the CLI JSON)."""
        out = {"trials": self.trials, "seed": self.seed, "tc_s": self.tc_s,
               "scenario": self.scenario_name, "model": self.model_label,
               "p_pass_before": self.p_pass_before, "p_pass_after": self.p_pass_after,
               "ci_before": list(self.ci_before), "ci_after": list(self.ci_after),
               "failure_reasons": self.agg.failure_reasons(),
               "percentiles_before": self.percentiles("before"),
               "percentiles_after": self.percentiles("after"),
               "pga_converged_fraction": self.agg.pga_converged / self.agg.n if self.agg.n else None,
               "twin_passes": self.agg.twin_pass,
               "pga_second_pass": {"ran": self.agg.pga_second_pass_ran, "kept": self.agg.pga_second_pass_kept},
               "worst_trials": [{"trial": o.trial, "reasons": o.reasons, "metrics_after": o.after,
                                 "peak_range_cells": o.peak_range_cells} for o in self.worst_trials()],
               "cancelled": self.cancelled, "decision_rule": DECISION_RULE,
               "judged_on": dict(self.judged_on), "model_spec": self.model_spec,
               "options": self.options.model_dump(mode="json") if self.options is not None else None,
               "scenario_spec": self.scenario.model_dump(mode="json") if self.scenario is not None else None}
        if self.agg.keep_trial_metrics:
            out["metrics_after"] = {m: list(self.agg.trial_metrics.get(m, [])) for m in JSON_METRICS}
        out.update(self.extra)
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per metric: its ``unit`` (:data:`METRIC_UNITS`) and p50/p95 before and after PGA,
        then the verdict repeated on every row (so that a CSV export or a concatenation of frames
        keeps it): ``model``, ``scenario``, ``trials``, ``seed``, ``p_pass_before``, ``p_pass_after``,
        ``ci_after_lo``, ``ci_after_hi`` (95 % Wilson) and ``verdict`` (:meth:`verdict`). ``attrs`` hold
        the same and the options, ``judged_on`` and ``model_spec``."""
        b, a = self.percentiles("before"), self.percentiles("after")
        lo, hi = self.ci_after
        frame = pd.DataFrame([{"metric": m, "unit": METRIC_UNITS.get(m, ""), "p50_before": b[m]["p50"],
                               "p95_before": b[m]["p95"], "p50_after": a[m]["p50"], "p95_after": a[m]["p95"],
                               "model": self.model_label, "scenario": self.scenario_name, "trials": self.trials,
                               "seed": self.seed, "p_pass_before": self.p_pass_before,
                               "p_pass_after": self.p_pass_after, "ci_after_lo": lo, "ci_after_hi": hi,
                               "verdict": self.verdict()} for m in TRIAL_METRICS])
        frame.attrs.update({"model": self.model_label, "scenario": self.scenario_name, "tc_s": self.tc_s,
                            "trials": self.trials, "seed": self.seed, "p_pass_before": self.p_pass_before,
                            "p_pass_after": self.p_pass_after, "ci_before": list(self.ci_before),
                            "ci_after": list(self.ci_after), "cancelled": self.cancelled,
                            "judged_on": dict(self.judged_on), "model_spec": self.model_spec,
                            "options": self.options.model_dump(mode="json") if self.options is not None else None})
        return frame

    def _judged_line(self) -> str:
        j = self.judged_on
        if not j:
            return ""
        scene = j.get("scene")
        if scene == "realistic":
            scene = (f"realistic scene ({j.get('n_targets')} scatterers, clutter "
                     f"{j.get('clutter_to_target_db'):g} dB, SNR {j.get('snr_db'):g} dB)")
        line = f"judged on: {scene}, {j.get('window')} window; {DECISION_RULE}\n"
        if j.get("scenario_notes"):
            line += j["scenario_notes"] + "\n"
        if j.get("window_resolution"):
            line += j["window_resolution"] + "\n"
        if j.get("navigation"):
            line += f"navigation: {j['navigation']}\n"
        if j.get("aiding_defaults"):
            line += j["aiding_defaults"] + "\n"
        if j.get("imu_rate"):
            line += j["imu_rate"] + "\n"
        if j.get("platform_motion"):
            line += j["platform_motion"] + "\n"
        for key in ("lever_arm", "scenario_defaults", "acceptance"):
            if j.get(key):
                line += j[key] + "\n"
        if j.get("earth_model"):
            line += f"earth model: {j['earth_model']}\n"
        for key in (*SIMULATION_NOTES, "defocus_room", "fast_phase_prediction"):
            if j.get(key):
                line += j[key] + "\n"
        if j.get("reference_summary"):
            line += j["reference_summary"] + "\n"
        if self.agg.pga_second_pass_ran:
            from ..sar.pga import SECOND_PASS_ABOVE_RAD
            line += (f"PGA's second pass (after a correction of more than {SECOND_PASS_ABOVE_RAD:.3g} rad rms from a "
                     "clutter-limited start; "
                     f"kept when the image is sharper) ran on {self.agg.pga_second_pass_ran} of {self.agg.n} trials, "
                     f"kept on {self.agg.pga_second_pass_kept}\n")
        if self.agg.twin_pass:
            line += (f"{self.agg.twin_pass} of {self.agg.n} trials exceeded that reference but met the acceptance "
                     "relative to their own perfect-IMU twin (same clutter and noise draw, no motion error): "
                     "passed\n")
        return line

    def _unspecified_line(self) -> str:
        text = self.unspecified_summary()
        return text + "\n" if text else ""

    def unspecified_summary(self) -> str:
        """How the model's empty datasheet terms were resolved (``budget.catalog.fill``): each
        value filled from the grade (with its unit), each term taken as 0, and each empty term
        without a grade value that is simulated as 0 (rate random walk); '' if there is none."""
        u = self.extra.get("unspecified_terms") or {}
        fills = ", ".join(f"{f['column']} = {f['value']:.4g} {f['unit']}" for f in u.get("filled", []))
        zero = ", ".join(u.get("zero", []))
        absent = ", ".join(u.get("not_modelled", []))
        texts = [f"filled from the {u.get('grade')} grade's typical values: {fills}" if fills else "",
                 f"taken as 0: {zero}" if zero else "",
                 f"empty and without a grade value, simulated as 0: {absent}" if absent else ""]
        texts += list(u.get("warnings", []))  # a grade the row's own figures contradict, a 0 figure
        text = "; ".join(t for t in texts if t)
        return f"unspecified datasheet terms ({u.get('policy')}): {text}" if text else ""

    def summary(self) -> str:
        lo, hi = self.ci_after
        lb, hb = self.ci_before
        reasons = ", ".join(f"{k} {v}" for k, v in self.agg.failure_reasons().items() if v) or "none"
        return (f"{self.model_label} on {self.scenario_name} (Tc = {self.tc_s:.3g} s), {self.trials} trials, "
                f"seed {self.seed}{' (cancelled)' if self.cancelled else ''}"
                f"{', IMU pre-filter: ' + self.extra['prefilter'] if self.extra.get('prefilter') else ''}\n"
                f"P(pass) before PGA {self.p_pass_before:.3f} [{lb:.3f}, {hb:.3f}], "
                f"after PGA {self.p_pass_after:.3f} [{lo:.3f}, {hi:.3f}] (95 % Wilson)\n"
                f"verdict at P(pass after PGA) ≥ {DEFAULT_PASS_SHARE:g}: {self.verdict()}"
                f"{' (the interval straddles the target: more trials decide)' if self.verdict() == 'undecided' else ''}\n"
                f"failure reasons: {reasons}\n" + self._judged_line() + self._unspecified_line() + self.to_frame()[list(FRAME_METRIC_COLUMNS)].to_string(
                    index=False, na_rep="n/a", float_format=lambda v: f"{v:.4g}")  # PGA's error: after only
                + f"\n{QUANTILE_NOTE}")
