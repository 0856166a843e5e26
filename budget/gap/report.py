"""The result of the model-gap workflow: steps, per-channel gaps, localisation, JSON.

JSON contract (REPORT.json, scripts rely on it)::

    {"gap_before": float, "gap_after": float,
     "effects": [{"name", "channel", "params": {...}, "gap_before", "gap_after"}, ...],
     "channels": {channel: {"gap_before", "gap_after"}, ...}}

``effects`` in the order they were added (``[]`` when nothing is missing); an effect's
``gap_before``/``gap_after`` are the gap *of its channel* before and after the step; the top
level ``gap_before``/``gap_after`` are the overall gaps (mean over channels) of the base and of
the updated model. Parameters in SI channel units. Further keys (thresholds, localisation,
null distribution, notes, an effect's ``alternatives``: the effects on its channel that the record
does not tell apart from it) are additions; ``options`` records the opt-in statistics the run used
(``{"low_frequency": bool, "decorrelate": bool}``, both false by default). ``cross_channel``: pairs
of channels with a common component the per-channel model cannot express (channels, bands_hz,
coherence, null_mean, peak, phase_deg, log10_p; :mod:`budget.gap.coherence`); ``slow_shape``: per
named Gauss–Markov term, the slow part's excess kurtosis against the updated model's
(``two_valued``: a random telegraph signal's shape; :mod:`budget.gap.two_valued`), and per channel
with a slow effect named on a log with temperature, the share of its slow part (T − T̄)² explains
(``curved``; :mod:`budget.gap.temperature_curve`); all worded in
``notes`` when they find something.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..fileio import atomic_write_text, json_text
from ..imu import NoiseModel
from .effect_size import EffectSizeBand, Sizes
from .metric import GapTerms, ModelSummary, NullModel
from .signatures import Signature, SignatureGrid

#: |z| above which a term is reported as a localised disagreement.
LOCAL_Z = 3.0

GAP_DEFINITION = (
    "per channel: gap = mean of z^2 over its statistics (ADEV at octave tau, PSD octave bands, "
    "largest PSD line, kurtosis and tail count of first differences, time slope, temperature "
    "coefficient, slow power in the record's slowest modes (walk: against the model's exact "
    "covariance of them) and their projection on a start-of-record pattern e^(-t/tau0), tau0 = 1/8 "
    "of the record (early: a turn-on transient); with low_frequency also the low-frequency bands of the detrended record's DCT "
    "below the first PSD band), z = standardized difference between the measured value and the "
    "mean of S simulated realizations of the model (≈ N(0,1) when the log follows the model); "
    "with decorrelate the spectral terms (ADEV, PSD bands, low-frequency bands) are summed as "
    "innovations under the model's own leave-one-out covariance, shrunk toward its diagonal; overall gap "
    "= mean of the channel gaps. Null: leave-one-out gaps of the realizations fitted by a·chi2_nu; "
    "within noise = every channel below its 1 - alpha/n_channels quantile and the overall gap below "
    "the 1 - alpha quantile of the mean.")


class _EffectSizes:
    """``effect_size_before_db`` / ``_after_db``: the rms dB misfit beyond the model's spread
    (NaN where the sizes were not computed), from ``sizes_before`` / ``sizes_after``."""

    sizes_before: Sizes | None
    sizes_after: Sizes | None

    @property
    def effect_size_before_db(self) -> float:
        return self.sizes_before.rms_db if self.sizes_before else float("nan")

    @property
    def effect_size_after_db(self) -> float:
        return self.sizes_after.rms_db if self.sizes_after else float("nan")


@dataclass(frozen=True)
class GapStep(_EffectSizes):
    """One named effect: where, which parameters, and the gap of its channel before/after."""

    name: str
    channel: str
    params: dict[str, float]
    gap_before: float
    gap_after: float
    overall_before: float
    overall_after: float
    predicted_gap: float
    improvement: float     # ΔΣz²/φ from the re-simulated model
    penalty: float         # χ²_p quantile it had to exceed
    n_params: int
    sizes_before: Sizes | None = None  # the channel's effect sizes before/after the step
    sizes_after: Sizes | None = None
    #: other effects the record does not tell apart from this one on its channel (name, params,
    #: margin below this effect's penalised improvement: :data:`budget.gap.choice.ALTERNATIVE_MARGIN`)
    alternatives: tuple[dict, ...] = ()

    def to_dict(self) -> dict:
        return {"name": self.name, "channel": self.channel, "params": dict(self.params),
                "alternatives": [dict(a) for a in self.alternatives],
                "gap_before": self.gap_before, "gap_after": self.gap_after,
                "overall_gap_before": self.overall_before, "overall_gap_after": self.overall_after,
                "predicted_gap": self.predicted_gap, "improvement": self.improvement,
                "penalty": self.penalty, "n_params": self.n_params,
                "effect_size_before": vars(self.sizes_before) if self.sizes_before else None,
                "effect_size_after": vars(self.sizes_after) if self.sizes_after else None}


def localize(terms: GapTerms) -> dict:
    """Where a channel disagrees: strongest terms, τ ranges and bands with |z| > 3, shares."""
    order = np.argsort(-np.abs(terms.z))[:5]
    top = [{"statistic": str(terms.kind[i]), "where": terms.where[i], "z": float(terms.z[i])}
           for i in order if abs(terms.z[i]) > LOCAL_Z]
    return {"top": top, "tau_ranges_s": _runs(terms, "adev"), "bands_hz": _runs(terms, "psd_band"),
            "share": terms.share()}


def _runs(terms: GapTerms, kind: str) -> list[dict]:
    sel = np.flatnonzero(terms.kind == kind)
    out, run = [], []
    for i in list(sel) + [None]:
        if i is not None and abs(terms.z[i]) > LOCAL_Z and (not run or np.sign(terms.z[i]) == np.sign(terms.z[run[-1]])):
            run.append(i)
            continue
        if run:
            out.append({"from": float(terms.locus[run[0]]), "to": float(terms.locus[run[-1]]),
                        "direction": "measured above model" if terms.z[run[0]] > 0 else "measured below model",
                        "max_abs_z": float(np.max(np.abs(terms.z[run])))})
            run = []
        if i is not None and abs(terms.z[i]) > LOCAL_Z:
            run = [i]
    return out


@dataclass
class ChannelResult(_EffectSizes):
    """One channel: measured signature, model summaries and gap terms before and after."""

    channel: str
    grid: SignatureGrid
    measured: Signature
    terms_before: GapTerms
    terms_after: GapTerms
    model_before: ModelSummary
    model_after: ModelSummary
    sizes_before: Sizes | None = None
    sizes_after: Sizes | None = None

    @property
    def gap_before(self) -> float:
        return self.terms_before.gap

    @property
    def gap_after(self) -> float:
        return self.terms_after.gap


@dataclass
class GapReport:
    """Result of :func:`budget.gap.run_gap` (see module docstring for the JSON form)."""

    source: str
    kind: str
    model_label: str
    rate_hz: float
    n_samples: int
    seed: int
    realizations: int
    alpha: float
    gap_before: float
    gap_after: float
    null_before: NullModel
    null_after: NullModel
    steps: list[GapStep]
    channels: dict[str, ChannelResult]
    rejected: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    stop_reason: str = ""
    base_model: NoiseModel | None = None
    updated_model: NoiseModel | None = None
    band_before: EffectSizeBand | None = None
    band_after: EffectSizeBand | None = None
    #: opt-in statistics of the run: ``low_frequency``, ``decorrelate`` (see :func:`run_gap`)
    options: dict = field(default_factory=dict)
    #: pairs of channels with a common component (:func:`budget.gap.coherence.findings`)
    cross_channel: list[dict] = field(default_factory=list)
    #: the slow part's shape where a slow effect was named: its kurtosis under a Gauss–Markov
    #: term (:mod:`budget.gap.two_valued`), its curve in the temperature
    #: (:mod:`budget.gap.temperature_curve`)
    slow_shape: list[dict] = field(default_factory=list)

    @property
    def effects(self) -> list[GapStep]:
        return list(self.steps)

    @property
    def threshold(self) -> float:
        """Overall within-noise threshold of the final model."""
        return self.null_after.overall_threshold

    @property
    def channels_within_noise(self) -> bool:
        """Every channel's gap within its own threshold (1 − α/n_channels quantile)."""
        return all(c.gap_after <= self.null_after.channel_threshold(ch) for ch, c in self.channels.items())

    @property
    def overall_within_noise(self) -> bool:
        """The overall gap (mean of the channels') within its threshold (1 − α quantile)."""
        return self.gap_after <= self.null_after.overall_threshold

    @property
    def within_noise(self) -> bool:
        """Both tests of :data:`GAP_DEFINITION` pass: every channel and the overall gap. A log
        whose channels each sit just under their thresholds can still carry more excess than
        the model allows in their mean (1.54 over an overall threshold of 1.47, every channel
        within its own)."""
        return self.channels_within_noise and self.overall_within_noise

    @property
    def effect_size_before_db(self) -> float:
        """Overall effect size: rms of the channels' E before the first step (dB)."""
        return float(np.sqrt(np.mean([c.effect_size_before_db ** 2 for c in self.channels.values()])))

    @property
    def effect_size_after_db(self) -> float:
        return float(np.sqrt(np.mean([c.effect_size_after_db ** 2 for c in self.channels.values()])))

    @property
    def close_enough(self) -> bool:
        """No channel worth working on any more: every peak misfit beyond the model's spread within
        the tolerance and every kurtosis difference within its band."""
        if self.band_after is None:
            return self.within_noise
        return all(not self.band_after.beyond(ch, c.sizes_after) for ch, c in self.channels.items()
                   if c.sizes_after is not None)

    def channel_state(self, ch: str) -> str:
        """"GAP" beyond the channel's null threshold; "MISFIT" within it but with a misfit beyond
        the tolerance (peak P or kurtosis: a heavy-tailed null, e.g. after a few huge spikes,
        makes the threshold too wide to say so); "ok" within both."""
        c = self.channels[ch]
        if not c.gap_after <= self.null_after.channel_threshold(ch):
            return "GAP"
        if self.band_after is not None and c.sizes_after is not None and self.band_after.beyond(ch, c.sizes_after):
            return "MISFIT"
        return "ok"

    def to_dict(self) -> dict:
        chans = {}
        for ch, c in self.channels.items():
            chans[ch] = {"gap_before": c.gap_before, "gap_after": c.gap_after,
                         "threshold_before": self.null_before.channel_threshold(ch),
                         "threshold_after": self.null_after.channel_threshold(ch),
                         "within_noise_after": c.gap_after <= self.null_after.channel_threshold(ch),
                         "state_after": self.channel_state(ch),
                         "n_terms": c.terms_after.n_terms,
                         "effect_size_before": vars(c.sizes_before) if c.sizes_before else None,
                         "effect_size_after": vars(c.sizes_after) if c.sizes_after else None,
                         "localization_before": localize(c.terms_before),
                         "localization_after": localize(c.terms_after)}
        return {
            "gap_before": self.gap_before, "gap_after": self.gap_after,
            "effects": [s.to_dict() for s in self.steps],
            "channels": chans,
            "threshold_before": self.null_before.overall_threshold,
            "threshold_after": self.null_after.overall_threshold,
            "within_noise_after": self.within_noise,
            "effect_size_db_before": self.effect_size_before_db,
            "effect_size_db_after": self.effect_size_after_db,
            "close_enough_after": self.close_enough,
            "effect_size_definition": self.band_after.to_dict() if self.band_after else None,
            "input": {"source": self.source, "kind": self.kind, "rate_hz": self.rate_hz,
                      "samples": self.n_samples,
                      "signatures": "adev" if self.kind == "adev_table" else
                      "adev, psd_band, psd_line, kurtosis, tails, slope"
                      + (", temperature" if any(c.measured.temp_coef is not None for c in self.channels.values()) else "")
                      + (", psd_low" if any(c.measured.low is not None for c in self.channels.values()) else "")
                      + (", walk, early" if any(c.model_before.walk_cov is not None for c in self.channels.values()) else "")},
            "model": self.model_label, "seed": self.seed, "realizations": self.realizations,
            "alpha": self.alpha, "options": {k: bool(v) for k, v in self.options.items()},
            "gap_definition": GAP_DEFINITION,
            "null_before": self.null_before.to_dict(), "null_after": self.null_after.to_dict(),
            "rejected": self.rejected, "stop_reason": self.stop_reason, "notes": list(self.notes),
            "cross_channel": [dict(f) for f in self.cross_channel],
            "slow_shape": [dict(f) for f in self.slow_shape],
            "tolerance_db": self.band_after.tolerance_db if self.band_after else None,
            "units": "parameters in SI channel units: rad/s-based (gyro), m/s^2-based (accel); s; Hz",
        }

    def unexplained_notes(self) -> list[str]:
        """One note per channel that effects were named on and that is still not ``ok``: the
        named effects are the nearest the vocabulary has, and where the misfit is left (an effect
        outside the vocabulary — a fractional spectral slope, say — is named as a chain of the
        nearest ones and leaves this)."""
        out = []
        for ch in self.channels:
            named = list(dict.fromkeys(s.name for s in self.steps if s.channel == ch))
            state = self.channel_state(ch)
            if not named or state == "ok":
                continue
            top = localize(self.channels[ch].terms_after)["top"][:3]
            where = "; ".join(f"{t['statistic']} {t['where']} z={t['z']:+.1f}" for t in top) or \
                "its effect sizes (peak misfit or kurtosis) beyond the tolerance"
            out.append(f"{ch}: unexplained misfit ({state}) after {', '.join(named)}: {where} — what is "
                       "left is beyond what the vocabulary can make smaller; the effects named there are "
                       "the nearest it has, not a confirmed description of this channel")
        return out

    def options_text(self) -> str:
        """The statistics chosen against their default, in words ("" when none was): the
        opt-in ones that were on, the slow modes when a log was run without them."""
        words = {"low_frequency": "low-frequency bands of the record (--low-frequency)",
                 "decorrelate": "spectral terms summed decorrelated (--decorrelate)"}
        out = [w for k, w in words.items() if self.options.get(k)]
        if self.kind == "log" and self.options.get("slow_modes") is False:
            out.append("slow modes left out (--no-slow-modes)")
        return "; ".join(out)

    def save(self, path: str | Path) -> None:
        """Write the JSON report atomically (non-finite numbers become null)."""
        atomic_write_text(Path(path), json_text(self.to_dict()))

    def to_frame(self) -> pd.DataFrame:
        """Every gap term of every channel, before and after (one row per term)."""
        rows = []
        for ch, c in self.channels.items():
            for i in range(c.terms_before.n_terms):
                rows.append({"channel": ch, "statistic": c.terms_before.kind[i],
                             "where": c.terms_before.where[i], "z_before": c.terms_before.z[i],
                             "z_after": c.terms_after.z[i] if i < c.terms_after.n_terms else np.nan})
        return pd.DataFrame(rows)

    def summary(self) -> str:
        thr = {ch: self.null_after.channel_threshold(ch) for ch in self.channels}
        lines = [f"model gap: {self.source} ({self.kind}, {self.n_samples} samples at {self.rate_hz:g} Hz) "
                 f"vs {self.model_label}; {self.realizations} realizations/channel, seed {self.seed}",
                 f"overall gap {self.gap_before:.3g} → {self.gap_after:.3g} "
                 f"({'within' if self.within_noise else 'NOT within'} noise: overall threshold "
                 f"{self.null_after.overall_threshold:.3g}"
                 f"{'' if self.overall_within_noise else ' exceeded'}, channel thresholds "
                 f"{min(thr.values()):.3g}–{max(thr.values()):.3g}"
                 f"{'' if self.channels_within_noise else ' exceeded on ' + ', '.join(ch for ch in self.channels if self.channel_state(ch) == 'GAP')})"]
        on = self.options_text()
        if on:
            lines.append(f"options: {on} (not the default)")
        if not self.steps:
            lines.append("effects named: none")
        for i, s in enumerate(self.steps, 1):
            par = ", ".join(f"{k}={v:.4g}" for k, v in s.params.items())
            lines.append(f"  {i}. {s.name} on {s.channel} ({par}): channel gap {s.gap_before:.3g} → "
                         f"{s.gap_after:.3g}, peak misfit {s.sizes_before.peak_db:.2f} → "
                         f"{s.sizes_after.peak_db:.2f} dB" if s.sizes_before and s.sizes_after else "")
            if s.alternatives:
                lines.append("     not told apart from: " + "; ".join(
                    f"{a['name']} (" + ", ".join(f"{k}={v:.4g}" for k, v in a["params"].items())
                    + (f"; {a['margin']:.1f} below)" if a["margin"] >= 0 else
                       f"; {-a['margin']:.1f} above, with more parameters)") for a in s.alternatives)
                    + " — the record explains the gap about as well with either")
        for ch, c in self.channels.items():
            loc = localize(c.terms_after)["top"][:2]
            where = "; ".join(f"{t['statistic']} {t['where']} z={t['z']:+.1f}" for t in loc)
            flag = self.channel_state(ch)
            size = ""
            if c.sizes_before and c.sizes_after:
                size = (f"  E {c.sizes_before.rms_db:.2f} → {c.sizes_after.rms_db:.2f} dB, peak "
                        f"{c.sizes_before.peak_db:.2f} → {c.sizes_after.peak_db:.2f} dB")
            lines.append(f"  {ch:8s} {c.gap_before:9.3g} → {c.gap_after:9.3g}  {flag}{size}"
                         + (f"  [{where}]" if where else ""))
        states = {self.channel_state(ch) for ch in self.channels}
        if states - {"ok"}:
            lines.append("  (ok: within noise and tolerance; GAP: beyond the channel's null threshold; MISFIT: "
                         "within it, but a misfit beyond the tolerance remains — peak P "
                         f"> {self.band_after.tolerance_db:g} dB or the kurtosis band)" if self.band_after else
                         "  (ok: within noise; GAP: beyond the channel's null threshold)")
        lines.append(f"stop: {self.stop_reason}")
        still = [ch for ch in self.channels if self.channel_state(ch) == "GAP"]
        if still and self.stop_reason.startswith("every channel is close enough"):
            lines.append(f"  ({', '.join(still)}: still beyond the null threshold (GAP) — a misfit the record "
                         "resolves, but within the effect-size tolerance and bands the stop rule uses; its "
                         "top terms are listed above)")
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)
