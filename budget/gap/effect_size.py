"""A scale-free size of the gap: how far the measured spectra lie from the model's, in dB.

The gap (mean z²) is a *significance*: with 10⁶ samples every misfit is significant, so it
grows with the record and can never say "close enough". Its companions here are **effect
sizes** that do not depend on the record length. Per channel, the dB misfits

    d_i = 10·log10(σ̂²_meas/σ̄²_model)(τ_i)   (Allan variance at octave τ; σ̄: geometric mean of
                                              the S realizations)
          10·log10(P̄_meas/P̄_model)(band_i)   (Welch PSD, octave band means)
          10·log10 max_f P_meas/P_model        (the largest line)

are compared with the model's **own spread**: each realization in turn is compared with the
others (leave one out), pooled over channels with the same statistics. Then

* **E** (rms, dB) = √max(mean d² − mean d²_null, 0) over the ADEV and PSD-band terms — the
  rms log-ratio of ADEV and PSD, de-biased for the estimator scatter (what a log following the
  model would score), so it estimates the true misfit at 10³ or 10⁶ samples alike;
* **P** (peak, dB) = max_i √max(d_i² − q_i², 0), with q_i = s_i·z the model's own spread of
  term i (s_i² = mean of d_i² over the realizations, z the two-sided normal quantile that keeps
  all K terms of a model-following channel within q at 90 %): the largest misfit beyond the
  model's spread, for misfits confined to a few τ or one line that an rms would dilute;
* **D** = |κ_meas − κ̄_model|: the excess-kurtosis difference of the first differences (outliers
  and heavy tails barely move the spectra), with its own null band (90 % quantile of √(a·χ²_ν)
  matched to the leave-one-out values).

A channel is worked on while P > ``tolerance_db`` (default 0.5 dB: 12 % in Allan variance, the
smallest spectral misfit worth naming an effect for) or D is beyond max(its band,
``tolerance_kurtosis`` = 0.5); whether an effect is then named is up to each candidate's
penalised likelihood-ratio test. Both limits are stated in the report. This is what lets a
10⁶-sample log stop before ``max_steps``: once every term is within 0.5 dB of the model beyond
its spread, nothing is worth naming, however significant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special, stats

from .metric import ModelSummary
from .signatures import Signature, SignatureGrid, band_means

DB_PER_NEPER = 10.0 / math.log(10.0)
#: Default smallest peak misfit (dB, beyond the model's spread) worth naming an effect for.
DEFAULT_TOLERANCE_DB = 0.5
#: Default smallest excess-kurtosis difference of the first differences worth modelling.
DEFAULT_TOLERANCE_KURTOSIS = 0.5
#: Quantile of the realizations' leave-one-out values that makes the model's own spread.
BAND_LEVEL = 0.9


def db_terms(meas: Signature, model: ModelSummary, grid: SignatureGrid) -> np.ndarray:
    """dB misfits measured − model: ADEV at every τ, the PSD octave bands, the largest line."""
    d = [DB_PER_NEPER * (np.log(meas.avar) - 2.0 * model.ln_adev)]
    if meas.psd is not None and model.psd is not None:
        d.append(DB_PER_NEPER * (np.log(band_means(meas.psd, grid)) - np.log(band_means(model.psd, grid))))
        lo, hi = grid.band_start[0], grid.bin_stop
        d.append(np.array([DB_PER_NEPER * float(np.max(np.log(meas.psd[lo:hi] / model.psd[lo:hi])))]))
    return np.concatenate(d)


def kurtosis_size(meas: Signature, model: ModelSummary) -> float:
    """|D|: excess-kurtosis difference of the first differences (0 for an Allan table)."""
    if meas.kurtosis is None or model.kurtosis is None:
        return 0.0
    return float(abs(meas.kurtosis - model.kurtosis))


@dataclass(frozen=True)
class LooSizes:
    """Leave-one-out dB misfits (S, K) and kurtosis differences (S,) of the realizations."""

    d: np.ndarray
    kurt: np.ndarray


def loo_sizes(sigs: list[Signature], grid: SignatureGrid) -> LooSizes:
    d, k = [], []
    for i, s in enumerate(sigs):
        rest = ModelSummary.from_signatures(sigs[:i] + sigs[i + 1:])
        d.append(db_terms(s, rest, grid))
        k.append(kurtosis_size(s, rest))
    return LooSizes(np.array(d), np.array(k))


def _chi2_quantile(values: np.ndarray) -> float:
    """``BAND_LEVEL`` quantile of √(a·χ²_ν) matched to the mean and variance of values²."""
    e2 = np.asarray(values, float) ** 2
    mu, var = float(e2.mean()), float(e2.var(ddof=1)) if e2.size > 1 else 0.0
    if var <= 0 or mu <= 0:
        return float(np.sqrt(e2.max())) if e2.size else 0.0
    a, nu = var / (2.0 * mu), 2.0 * mu * mu / var
    return float(math.sqrt(a * stats.chi2.ppf(BAND_LEVEL, nu)))


def _log_chi2_low(ms_db2: np.ndarray, p: float) -> np.ndarray:
    """Magnitude (dB) of the lower ``p`` quantile of d = 10·log10(χ²_ν/ν) − its mean, the
    misfit of an estimate with ν degrees of freedom against its geometric mean, for ν matched to
    the term's mean square ``ms_db2`` (dB²): Var ln χ²_ν = ψ′(ν/2). An Allan variance at the
    last octaves has a few degrees of freedom; its log is skewed with a long lower tail (ν = 5:
    the lower 0.14 % point lies 1.35× further from the centre than a normal one of the same
    variance), so a symmetric normal band calls model-following channels "measured below the
    model" (4 of 66 channels on eleven model-following one-hour logs, all below, at τ = 41–328 s).
    The upper side keeps the normal band: it is the narrower one, and the one effects are named on."""
    v = np.asarray(ms_db2, float) / DB_PER_NEPER ** 2
    out = np.zeros_like(v)
    for i, vi in enumerate(v):
        if not vi > 1e-8:  # ν beyond 10⁸: normal
            out[i] = math.sqrt(max(vi, 0.0)) * stats.norm.isf(p) * DB_PER_NEPER
            continue
        # ψ′(ν/2) = vi: ψ′ falls from ∞ (ν → 0) to 0 (ν → ∞)
        nu = optimize.brentq(lambda n: float(special.polygamma(1, 0.5 * n)) - vi, 1e-3, 1e9)
        centre = float(special.digamma(0.5 * nu)) + math.log(2.0)
        out[i] = (centre - math.log(stats.chi2.ppf(p, nu))) * DB_PER_NEPER
    return out


@dataclass(frozen=True)
class Sizes:
    """Effect sizes of one channel: rms E (dB), peak P (dB), kurtosis difference D."""

    rms_db: float
    peak_db: float
    kurtosis: float
    where: str = ""


@dataclass(frozen=True)
class EffectSizeBand:
    """The model's own spread per channel (per-term quantiles, mean square, kurtosis band) and
    the tolerances; :meth:`sizes` turns a channel's dB misfits into (E, P, D)."""

    term_q: dict[str, np.ndarray]
    term_ms: dict[str, np.ndarray]
    band_kurtosis: dict[str, float]
    tolerance_db: float = DEFAULT_TOLERANCE_DB
    tolerance_kurtosis: float = DEFAULT_TOLERANCE_KURTOSIS
    #: the spread below the model (measured < model), ≥ ``term_q``: a log-χ² term's lower tail
    #: (:func:`_log_chi2_low`); ``None``: ``term_q`` on both sides
    term_q_low: dict[str, np.ndarray] | None = None

    @classmethod
    def fit(cls, loo: dict[str, tuple[LooSizes, tuple]], tolerance_db: float = DEFAULT_TOLERANCE_DB,
            tolerance_kurtosis: float = DEFAULT_TOLERANCE_KURTOSIS) -> "EffectSizeBand":
        """``loo``: channel → (leave-one-out sizes, layout key); same keys are pooled."""
        groups: dict[tuple, list[str]] = {}
        for ch, (_, key) in loo.items():
            groups.setdefault(key, []).append(ch)
        q, ql, ms, kb = {}, {}, {}, {}
        for chans in groups.values():
            d = np.concatenate([loo[ch][0].d for ch in chans])
            k = np.concatenate([loo[ch][0].kurt for ch in chans])
            tm = np.mean(d * d, axis=0)
            # family-wise: all K terms of a model-following channel within q at BAND_LEVEL
            # (each term ≈ N(0, s²) over the realizations; K of them, Šidák-corrected)
            level = 1.0 - (1.0 - BAND_LEVEL) / d.shape[1]
            tq = np.sqrt(tm) * stats.norm.isf(0.5 * (1.0 - level))
            tql = np.maximum(tq, _log_chi2_low(tm, 0.5 * (1.0 - level)))
            kq = _chi2_quantile(k)
            for ch in chans:
                q[ch], ql[ch], ms[ch], kb[ch] = tq, tql, tm, kq
        return cls(q, ms, kb, float(tolerance_db), float(tolerance_kurtosis), ql)

    def sizes(self, channel: str, d: np.ndarray, kurt: float, n_rms: int,
              labels: list[str] | None = None) -> Sizes:
        """(E, P, D) of one channel from its dB misfits ``d`` (the first ``n_rms`` are the ADEV
        and PSD-band terms, then the line) and kurtosis difference."""
        q, ms = self.term_q[channel], self.term_ms[channel]
        if self.term_q_low is not None:
            q = np.where(d < 0, self.term_q_low[channel], q)
        rms = math.sqrt(max(float(np.mean(d[:n_rms] ** 2) - np.mean(ms[:n_rms])), 0.0))
        excess = np.sqrt(np.clip(d ** 2 - q ** 2, 0.0, None))
        i = int(np.argmax(excess))
        where = labels[i] if labels is not None and i < len(labels) else ""
        return Sizes(rms, float(excess[i]), float(kurt), where)

    def limit(self, channel: str) -> float:
        """Peak misfit P below which the channel is close enough (dB)."""
        return self.tolerance_db

    def limit_kurtosis(self, channel: str) -> float:
        return max(self.band_kurtosis.get(channel, 0.0), self.tolerance_kurtosis)

    def beyond(self, channel: str, sizes: Sizes) -> bool:
        """Is a channel with these sizes worth working on?"""
        return sizes.peak_db > self.limit(channel) or sizes.kurtosis > self.limit_kurtosis(channel)

    def to_dict(self) -> dict:
        return {"tolerance_db": self.tolerance_db, "tolerance_kurtosis": self.tolerance_kurtosis,
                "band_kurtosis": dict(self.band_kurtosis), "band_level": BAND_LEVEL,
                "model_spread_db": {ch: float(np.sqrt(np.mean(v))) for ch, v in self.term_ms.items()},
                "definition": "d = 10*log10 measured/model for ADEV at octave tau, PSD octave bands "
                              "and the largest PSD line; rms E = sqrt(mean d^2 - mean d^2 of the "
                              "model's own leave-one-out realizations) over ADEV and bands; peak "
                              "P = max sqrt(d^2 - q^2), q = the model's own spread of the term "
                              "(90 % family-wise over the terms); a channel is worked on while P > tolerance_db or the "
                              "kurtosis difference exceeds its band and tolerance_kurtosis"}
