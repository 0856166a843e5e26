"""Cross-validation of the model gap: fit on one log, test on another of the same part.

An effect named on one record may describe that record only (a vibration of the bench that
day, a chance fluctuation fitted at 10⁶ samples). :func:`cross_validate` runs the workflow on
the *fit* log, then judges the named effects on the *test* log by forward selection, in the
order they were named: starting from the base model, an effect **carries over** when adding
it lowers the test log's Σz² on its channel by more than the likelihood-ratio penalty
χ²_p⁻¹(1 − α) (p its parameter count, Σz² deflated by the channel's null inflation φ, as in
the workflow), given the effects kept before it. Effects that do not carry over are not named: the
validated model is the base model plus the effects that do. Both gaps are reported — the fit
log's (before/after) and the test log's for the base, the fitted and the validated model —
each with its scale-free effect size (dB) and null band (:mod:`budget.gap.effect_size`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy import stats

from ..imu import NoiseModel
from .candidates import LIBRARY
from .effect_size import DEFAULT_TOLERANCE_DB, EffectSizeBand
from .inputs import check_compatible, load_measured, load_model
from .metric import NullModel
from .report import GapReport
from .signatures import SignatureGrid, series_signature
from .workflow import DEFAULT_REALIZATIONS, _spectrum, _state, _whitened, _with_rate, run_gap


@dataclass
class ChannelTest:
    """The test log's comparison on one channel for one model."""

    gap: float
    threshold: float
    effect_size_db: float   # rms misfit beyond the model's spread (E)
    peak_db: float          # peak misfit beyond the model's spread (P)
    close_enough: bool      # P within the tolerance and kurtosis within its band


@dataclass
class CrossValidation:
    """Result of :func:`cross_validate` (``summary()``, ``to_frame()``, ``to_dict()``)."""

    fit: GapReport
    test_source: str
    test: dict[str, dict[str, ChannelTest]]        # model label → channel → comparison
    carried: list[dict] = field(default_factory=list)
    dropped: list[dict] = field(default_factory=list)
    validated_model: NoiseModel | None = None
    options: dict = field(default_factory=dict)

    def overall(self, label: str) -> tuple[float, float]:
        """(mean channel gap, rms channel effect size dB) of the test log under ``label``."""
        rows = self.test[label].values()
        return (float(np.mean([r.gap for r in rows])),
                float(np.sqrt(np.mean([r.effect_size_db ** 2 for r in rows]))))

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([{"model": lab, "channel": ch, **vars(r)}
                             for lab, chans in self.test.items() for ch, r in chans.items()])

    def to_dict(self) -> dict:
        return {"fit": {"source": self.fit.source, "gap_before": self.fit.gap_before,
                        "gap_after": self.fit.gap_after,
                        "effect_size_db_before": self.fit.effect_size_before_db,
                        "effect_size_db_after": self.fit.effect_size_after_db,
                        "effects": [s.to_dict() for s in self.fit.steps]},
                "test": {"source": self.test_source,
                         **{lab: {"gap": self.overall(lab)[0], "effect_size_db": self.overall(lab)[1],
                                  "channels": {ch: vars(r) for ch, r in chans.items()}}
                            for lab, chans in self.test.items()}},
                "carried_over": self.carried, "not_carried_over": self.dropped,
                "validated_model": self.validated_model.to_dict() if self.validated_model else None,
                "options": dict(self.options)}

    def summary(self) -> str:
        lines = [f"cross-validation: fit on {self.fit.source}, test on {self.test_source}",
                 f"fit log: gap {self.fit.gap_before:.4g} → {self.fit.gap_after:.4g}, effect size "
                 f"{self.fit.effect_size_before_db:.2f} → {self.fit.effect_size_after_db:.2f} dB, "
                 f"{len(self.fit.steps)} effects named"]
        for lab in self.test:
            g, e = self.overall(lab)
            lines.append(f"test log, {lab} model: gap {g:.4g}, effect size {e:.2f} dB")
        for c in self.carried:
            lines.append(f"  carries over: {c['name']} on {c['channel']} (test Σz² drop {c['drop']:.3g} "
                         f"> {c['penalty']:.3g})")
        for c in self.dropped:
            lines.append(f"  not named (does not carry over): {c['name']} on {c['channel']} "
                         f"(test Σz² drop {c['drop']:.3g} ≤ {c['penalty']:.3g})")
        return "\n".join(lines)


def cross_validate(fit_measured, test_measured, model, *, seed: int = 0,
                   realizations: int = DEFAULT_REALIZATIONS, channels=None,
                   alpha: float = 0.01, tolerance_db: float = DEFAULT_TOLERANCE_DB,
                   mapping=None, max_rows: int | None = None, **gap_kw) -> CrossValidation:
    """Fit on ``fit_measured`` with :func:`run_gap`, test on ``test_measured`` (a log of the
    same part, same rate) — see the module docstring. ``gap_kw`` go to :func:`run_gap`."""
    fit = run_gap(fit_measured, model, seed=seed, realizations=realizations, channels=channels,
                  alpha=alpha, tolerance_db=tolerance_db, mapping=mapping, max_rows=max_rows, **gap_kw)
    meas = load_measured(test_measured, mapping=mapping, max_rows=max_rows)
    if meas.kind != "log":
        raise ValueError("cross-validation needs a log to test on")
    base, from_catalog, _ = load_model(model)
    chans, _ = check_compatible(meas, base, from_catalog, channels, False)
    base = _with_rate(base, meas.rate_hz)
    fitted = _with_rate(fit.updated_model, meas.rate_hz)
    # the fit's grids: the temperature statistic weighted by each channel's base spectrum
    grids = {ch: SignatureGrid.for_log(meas.n_samples, meas.rate_hz, meas.temp_c,
                                       bool(gap_kw.get("low_frequency", False)),
                                       noise_psd=_spectrum(base, ch, meas),
                                       slow_modes=bool(gap_kw.get("slow_modes", True))) for ch in chans}
    sig = {ch: series_signature(meas.series[ch], grids[ch], lattice=True) for ch in chans}
    mean = {ch: float(np.mean(meas.series[ch])) for ch in chans}
    test_seed = seed + 1  # other random streams than the fit's

    def evaluate(m: NoiseModel, only=None) -> dict:
        return {ch: _state(m, ch, grids[ch], sig[ch], mean[ch], realizations, test_seed)
                for ch in (only or chans)}

    def table(states: dict) -> dict[str, ChannelTest]:
        null = NullModel.fit({ch: (s.loo, s.layout) for ch, s in states.items()}, alpha)
        band = EffectSizeBand.fit({ch: (s.loo_d, s.layout) for ch, s in states.items()}, tolerance_db)
        out = {}
        for ch, s in states.items():
            sz = s.sizes(band, ch)
            out[ch] = ChannelTest(s.terms.gap, null.channel_threshold(ch), sz.rms_db, sz.peak_db,
                                  not band.beyond(ch, sz))
        return out

    base_states = evaluate(base)
    if gap_kw.get("decorrelate", False):
        # the test log's metric: its spectral terms decorrelated on the base model's realizations
        base_states = _whitened(base_states)
    grids = {ch: st.grid for ch, st in base_states.items()}
    fitted_states = evaluate(fitted)
    null = NullModel.fit({ch: (s.loo, s.layout) for ch, s in base_states.items()}, alpha)
    # forward selection on the test log, in the order the effects were named: an effect is
    # kept when it improves the test log given the effects kept before it (so one that does
    # not carry over cannot spoil the judgement of the others)
    carried, dropped = [], []
    validated = base
    current = dict(base_states)
    for eff in fitted.effects:
        if eff in base.effects or eff.channel not in chans:
            continue
        ch = eff.channel
        trial = validated.with_effect(eff)
        st = evaluate(trial, [ch])[ch]
        drop = null.drop(ch, current[ch].terms.sum_sq, current[ch].terms.linear_sq, st.terms.sum_sq,
                         st.terms.linear_sq)
        penalty = float(stats.chi2.isf(alpha, LIBRARY[eff.name].n_params))
        row = {"name": eff.name, "channel": ch, "params": dict(eff.params), "drop": float(drop),
               "penalty": penalty}
        if drop > penalty:
            carried.append(row)
            validated, current[ch] = trial, st
        else:
            dropped.append(row)
    test = {"base": table(base_states), "fitted": table(fitted_states),
            "validated": table(current)}
    return CrossValidation(fit, meas.source, test, carried, dropped, validated,
                           {"seed": seed, "realizations": realizations, "alpha": alpha,
                            "tolerance_db": tolerance_db, "test_seed": test_seed,
                            "low_frequency": bool(gap_kw.get("low_frequency", False)),
                            "decorrelate": bool(gap_kw.get("decorrelate", False)),
                            "slow_modes": bool(gap_kw.get("slow_modes", True))})
