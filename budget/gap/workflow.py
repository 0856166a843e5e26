"""The model-gap loop: compare, localise, name the missing effect, add it, compare again.

1. Simulate the model S times per channel at the log's rate and length; compute the gap of
   every channel (:mod:`budget.gap.metric`) and its null distribution (leave-one-out). With
   ``low_frequency`` the statistics include the record's low-frequency bands
   (:mod:`budget.gap.lowfreq`); with ``decorrelate`` the spectral terms (ADEV, PSD bands, low
   bands) are summed decorrelated, in a metric fitted once on the base model's realizations
   (:mod:`budget.gap.whitening`), so that every Σz² below — measured, predicted, simulated — is
   a Gaussian log-likelihood of those terms rather than a count of correlated views of one
   misfit. Both are off by default (see :func:`run_gap`).
2. While some channel's gap exceeds its null threshold: fit every candidate effect of the
   library (:mod:`budget.gap.candidates`) on every such channel; score each one by a penalised
   improvement of the channel's Σz²,

       score = ΔΣz²_q/φ_q + ΔΣz²_l/φ_l − χ²_p⁻¹(1 − α/M),

   with p the candidate's parameter count, M the number of (effect, channel) candidates
   tried at this step, counted over every channel (Bonferroni; the open channels are chosen
   from the data), and φ = Σλ²/K the variance inflation of Σz² from the null
   fit (:class:`~budget.gap.metric.NullModel`; φ = 1 for independent terms), taken separately
   for the quadratic statistics (q: Allan deviation, PSD, distribution) and the linear ones
   (l: time slope, temperature coefficient), which are uncorrelated under a Gaussian null
   (:meth:`~budget.gap.metric.NullModel.drop`) — a
   likelihood-ratio test in the spirit of GMWM's wavelet information criterion, where the
   penalty grows with the parameters (candidates that widen a statistic's scatter also pay
   ln(var'/var), see :meth:`~budget.gap.fitting.FitContext.sumsq`). With very long records every misfit is significant, so a candidate must also remove at least
   ``min_gain`` (default 5 %) of its channel's excess Σz² − n_terms·(null mean).
3. Add the best candidate if its score is positive, re-simulate that channel and keep the
   effect only if the *simulated* improvement passes the same test; otherwise discard it and
   try the next. Occam's step: on the chosen channel, a candidate with fewer parameters that
   already brings the channel within its null threshold is preferred to a better-fitting
   richer one unless the extra parameters pass the same test (:func:`budget.gap.choice.parsimonious`). A step
   must also shrink its channel's effect size (:func:`_size_gain`, predicted when the
   candidates are ranked and simulated when the step is kept): it must remove ≥ ``min_gain``
   of the excess Σz² or of the excess effect size, and may not leave every open size larger.
   Stop when every channel is close enough (:mod:`budget.gap.effect_size`), when nothing
   passes, or after ``max_steps`` (a ceiling).

An effect is never named on a channel whose gap is within its null threshold, so a log that
follows its model gets ``effects = []`` unless its gap exceeds the 1 − α quantile by chance
*and* a candidate passes the penalised test.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from pydantic import ValidationError
from scipy import stats
from threadpoolctl import threadpool_limits

from ..errors import InputError, from_validation_error
from ..imu import Effect, NoiseModel
from . import whitening
from .choice import alternatives, located_over_spread, parsimonious, richer_spread
from .candidates import LIBRARY
from .detectors import direct_proposals
from .fitting import CandidateFit, FitContext
from .gls import model_spectrum
from .regression_var import model_weight_mean, model_weight_variance
from .walk import model_cov as walk_model_cov
from .walk import model_mean as walk_model_mean
from .inputs import check_compatible, load_measured, load_model
from .effect_size import (DEFAULT_TOLERANCE_DB, EffectSizeBand, LooSizes, Sizes, db_terms,
                          kurtosis_size, loo_sizes)
from . import coherence, quieter, temperature_curve, two_valued, unit_slip
from .metric import LINEAR_KINDS, GapTerms, LinearMoments, ModelSummary, NullModel, gap_terms, loo_z
from .report import ChannelResult, GapReport, GapStep
from .signatures import Signature, SignatureGrid, series_signature, table_signature
from .simulate import simulate_signatures

DEFAULT_REALIZATIONS = 12
#: A ceiling, not the stop: runs stop by the effect-size rule (22 steps on a 10⁶-sample ADIS16405 log).
DEFAULT_MAX_STEPS = 30
#: Fewest leave-one-out gaps behind the null fit: with few channels, more realizations each.
MIN_NULL_SAMPLES = 48


@dataclass
class _State:
    grid: SignatureGrid
    meas: Signature
    true_value: float
    sims: list[Signature]
    summary: ModelSummary
    terms: GapTerms
    loo: np.ndarray       # leave-one-out z vectors (S, K)
    d_db: np.ndarray      # dB misfits measured − model (ADEV τ, PSD bands, line)
    loo_d: LooSizes       # the same for each realization against the others
    dkurt: float = 0.0    # |D|: excess-kurtosis difference of the first differences

    def sizes(self, band: EffectSizeBand, channel: str) -> Sizes:
        n_rms = self.d_db.size - (1 if self.meas.psd is not None else 0)
        return band.sizes(channel, self.d_db, self.dkurt, n_rms, self.terms.where[:self.d_db.size])

    @property
    def layout(self) -> tuple:
        return (self.terms.n_terms, tuple(self.terms.kind), tuple(self.grid.m))


def _state(model: NoiseModel, ch: str, grid: SignatureGrid, meas: Signature, true_value: float,
           n_real: int, seed: int) -> _State:
    sims = simulate_signatures(model, ch, grid, n_real, seed, true_value)
    linear = _linear_moments(model, ch, grid)
    summary = ModelSummary.from_signatures(sims, linear)
    return _State(grid, meas, true_value, sims, summary, gap_terms(meas, summary, grid),
                  loo_z(sims, grid, linear), db_terms(meas, summary, grid), loo_sizes(sims, grid),
                  kurtosis_size(meas, summary))


def _linear_moments(model: NoiseModel, ch: str, grid: SignatureGrid) -> LinearMoments | None:
    """The channel model's exact mean and variance of the time slope and the temperature
    coefficient (:mod:`budget.gap.regression_var`): judged against them, a ramp or a temperature
    term at 5σ reads 5σ, where against the mean and scatter of 12 realizations (Student t,
    11 degrees of freedom) it read ≈ 3.4σ. ``None`` for an Allan table."""
    if grid.time_w is None:
        return None
    effects = model.to_si().channel_effects(ch)

    def moments(w):
        return (model_weight_mean(effects, w, grid.rate_hz, grid.temp_c),
                model_weight_variance(effects, w, grid.dt_s))

    sm, sv = moments(grid.time_w)
    tm, tv = moments(grid.temp_w) if grid.temp_w is not None else (None, None)
    wc = walk_model_cov(effects, grid.walk) if grid.walk is not None else None
    wm = walk_model_mean(effects, grid.walk, grid.temp_c) if wc is not None else None
    return LinearMoments(sm, sv, tm, tv, wc, wm)


def _whitened(states: dict[str, _State]) -> dict[str, _State]:
    """The states again, in the metric whose spectral block is decorrelated on the model's own
    realizations (:mod:`budget.gap.whitening`): one map per layout of statistics, fitted on the
    pooled leave-one-out z of the channels that share it and kept for the rest of the run."""
    groups: dict[tuple, list[str]] = {}
    for ch, st in states.items():
        if st.grid.has_psd:
            groups.setdefault(st.layout, []).append(ch)
    out = dict(states)
    for chans in groups.values():
        pooled = np.concatenate([states[ch].loo for ch in chans])
        white = whitening.fit(pooled, states[chans[0]].terms.kind)
        for ch in chans:
            st = states[ch]
            grid = replace(st.grid, whitening=white)
            out[ch] = replace(st, grid=grid, terms=gap_terms(st.meas, st.summary, grid),
                              loo=loo_z(st.sims, grid, LinearMoments(
                                  st.summary.slope if st.summary.linear_exact else None, st.summary.slope_var,
                                  st.summary.temp_coef, st.summary.temp_var, st.summary.walk_cov,
                                  st.summary.walk_mean)))
    return out


def _spectrum(model: NoiseModel, ch: str, meas):
    """The channel model's noise spectrum, which weights the temperature statistic
    (:mod:`budget.gap.gls`); None without a temperature channel."""
    if meas.temp_c is None:
        return None
    return model_spectrum(model.to_si().channel_effects(ch), 1.0 / meas.rate_hz)


def _with_rate(model: NoiseModel, rate_hz: float) -> NoiseModel:
    data = model.model_dump()
    data["rate_hz"] = rate_hz
    try:
        return NoiseModel.model_validate(data)
    except ValidationError as err:
        raise from_validation_error(err) from None


def _overall(states: dict[str, _State]) -> float:
    return float(np.mean([s.terms.gap for s in states.values()]))


def _excess(ch: str, st: _State, null: NullModel) -> float:
    """Σz² above what the null expects for this channel."""
    return max(st.terms.sum_sq - null.mean(ch) * st.terms.n_terms, 0.0)


def _null(states: dict[str, _State], alpha: float, apart=()) -> NullModel:
    """The null of the channels' gaps, pooled over channels with the same statistics; the
    channels ``apart`` (not worked on: quieter than the model, a unit slip, two regimes) form
    pools of their own, so that their unchanged models do not set the thresholds of the channels
    being fitted."""
    return NullModel.fit({ch: (s.loo, s.layout + (ch in apart,)) for ch, s in states.items()}, alpha)


def _band(states: dict[str, _State], alpha: float, tolerance_db: float) -> EffectSizeBand:
    del alpha  # the band is the model's spread (a fixed quantile), not a significance level
    return EffectSizeBand.fit({ch: (s.loo_d, s.layout) for ch, s in states.items()}, tolerance_db)


def _open(ch: str, st: _State, band: EffectSizeBand, trend_z: float) -> bool:
    """A channel is worked on while one of its effect sizes (peak spectral misfit P, kurtosis
    difference D) is beyond its limit, or while its trend statistics lie beyond ``trend_z`` of
    the model's own distribution of them (:func:`_trend_open`). Whether an effect is named
    there is up to the penalised test of each candidate."""
    return band.beyond(ch, st.sizes(band, ch)) or _trend_open(st, trend_z)


def _trend_open(st: _State, trend_z: float) -> bool:
    """The time slope or temperature coefficient beyond ±``trend_z`` (what a ramp or a
    temperature sensitivity changes, and the long-τ Allan deviation of a one-hour log barely
    shows), or more slow power in the record's slowest modes than the model's (z > ``trend_z``,
    :mod:`budget.gap.walk`, on the split modes or on all of them): all judged against the
    model's exact distribution."""
    kind, z = st.terms.kind, st.terms.z
    trend = np.abs(z[np.isin(kind, LINEAR_KINDS)])
    slow = z[kind == "walk"]
    if st.terms.slow_whole_z is not None:
        slow = np.append(slow, st.terms.slow_whole_z)
    return bool((trend.size and trend.max() > trend_z) or (slow.size and slow.max() > trend_z))


def _size_gain(old: Sizes, new: Sizes, band: EffectSizeBand, ch: str) -> tuple[float, bool]:
    """How much of a channel's excess effect size a step removes, and whether it makes the
    channel worse.

    Gain: the largest relative reduction among the peak misfit's excess over the tolerance
    (P − tol)/(P_old − tol), the rms misfit E and the kurtosis difference's excess over its
    limit (P and D only where they were beyond their limits); *worse*: none of them decreased
    (gain ≤ 0; a size within its limit moving by its own scatter does not count), or the
    kurtosis difference was pushed from within its limit to beyond twice it. On a
    record of 10⁶ samples every misfit is significant, so a step that lowers Σz² (at short τ, where z is largest) can leave the
    misfit that kept the channel open untouched or larger; such a step is not taken, and a
    long-τ effect that removes a large share of that misfit is, though its share of Σz² is
    small."""
    gains = []
    lim = band.limit(ch)
    if old.peak_db > lim:
        gains.append((old.peak_db - max(new.peak_db, lim)) / (old.peak_db - lim))
    if old.rms_db > 0:
        gains.append((old.rms_db - new.rms_db) / old.rms_db)
    klim = band.limit_kurtosis(ch)
    if old.kurtosis > klim:
        gains.append((old.kurtosis - max(new.kurtosis, klim)) / (old.kurtosis - klim))
    gain = max(gains) if gains else 0.0
    # a kurtosis difference within its limit pushed beyond it by more than the limit (a heavy
    # tail that makes the model's kurtosis explode while it trims a peak) is a new misfit, not
    # progress; a peak near its band moving across it by the term's scatter is not
    pushed = old.kurtosis <= klim < new.kurtosis and new.kurtosis - old.kurtosis > klim
    return gain, gain <= 0.0 or pushed


def _fits(model: NoiseModel, ch: str, st: _State) -> list[CandidateFit]:
    existing = tuple(model.to_si().channel_effects(ch))
    ctx = FitContext(ch, st.grid, st.meas, st.summary, existing)
    out = []
    for cand in LIBRARY.values():
        fit = cand.fit(ctx)
        if fit is not None:
            out.append(fit)
    return out


def _simulate_candidate(model: NoiseModel, ch: str, old: _State, fit: CandidateFit, n_real: int,
                        seed: int, null: NullModel) -> tuple[NoiseModel, _State, Effect]:
    """Add ``fit``'s effect and re-simulate the channel. When a one-parameter effect behaves
    differently in the generator than its closed form predicts (quantization of a slowly moving
    accumulator is the known case) and the channel stays above its threshold, its parameter is
    refined on the *simulated* Σz² (golden section over ×1/3…×3, common random numbers)."""

    def run(effect):
        trial = model.with_effect(effect)
        return trial, _state(trial, ch, old.grid, old.meas, old.true_value, n_real, seed)

    trial, new = run(fit.effect)
    predicted = fit.sum_sq / old.terms.n_terms
    if fit.n_params != 1 or new.terms.gap <= max(null.channel_threshold(ch), 1.5 * predicted):
        return trial, new, fit.effect
    cand = LIBRARY[fit.effect.name]
    theta = float(fit.theta[0])

    def effect_at(u):
        t = theta + u if cand.log_param else theta * float(np.exp(u))
        return Effect(name=fit.effect.name, channel=ch, params=cand.params(np.array([t]), None))

    best = (fit.effect, trial, new)
    lo, hi = -np.log(3.0), np.log(3.0)
    g = (np.sqrt(5.0) - 1.0) / 2.0
    memo = {}

    def f(u):
        if u not in memo:
            eff = effect_at(u)
            tr, st = run(eff)
            memo[u] = (st.terms.sum_sq, tr, st, eff)
        return memo[u][0]

    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    for _ in range(6):
        if f(c) < f(d):
            b, d = d, c
            c = b - g * (b - a)
        else:
            a, c = c, d
            d = a + g * (b - a)
    for val, tr, st, eff in memo.values():
        if val < best[2].terms.sum_sq:
            best = (eff, tr, st)
    return best[1], best[2], best[0]


def run_gap(measured, model, *, seed: int = 0, realizations: int = DEFAULT_REALIZATIONS,
            channels=None, rate_hz: float | None = None, samples: int | None = None,
            max_steps: int = DEFAULT_MAX_STEPS, alpha: float = 0.01, min_gain: float = 0.05,
            check_tau_range: bool = True, tolerance_db: float = DEFAULT_TOLERANCE_DB,
            catalog_csv=None, mapping=None, repair: bool = False, max_rows: int | None = None,
            ci_level: float = 0.95, low_frequency: bool = False,
            decorrelate: bool = False, slow_modes: bool = True) -> GapReport:
    """Compare ``measured`` with ``model``, name the missing effects, return a :class:`GapReport`.

    ``measured``: log path, :class:`~budget.noise.ImuLog`, Allan-table path (with ``rate_hz``
    and ``samples``) or ``{channel: AllanResult}``. ``model``: :class:`~budget.imu.NoiseModel`,
    catalog part / part_id, or MODEL.json path. ``realizations`` S ≥ 4 per channel; ``seed``
    fixes every random stream; ``alpha`` is the false-alarm level of the null thresholds and
    of the penalised test. ``report.updated_model`` is the base model plus the named effects,
    at the log's rate. ``low_frequency`` adds the low-frequency bands of the record
    (:mod:`budget.gap.lowfreq`) to the statistics of a log; ``decorrelate`` sums the spectral
    terms decorrelated (:mod:`budget.gap.whitening`). Both are off by default: on the benchmark
    they turn one bias instability named on a hidden random walk into the random walk, but also
    name a random walk on two more logs with a hidden ramp, and a ramp on one more
    model-following log (README, "Model gap"). CLI: ``--low-frequency``, ``--decorrelate``; the
    report records both in ``options``; both need a log (an Allan table with either is an
    :class:`~budget.errors.InputError`). ``slow_modes`` (on by default; CLI ``--no-slow-modes``
    turns it off): the record's slowest modes judged against the model's exact covariance
    (:mod:`budget.gap.walk`), recorded in ``options`` too. BLAS runs on one thread inside (small
    matrices; a shared machine).
    """
    with threadpool_limits(limits=1, user_api="blas"):
        return _run_gap(measured, model, seed=seed, realizations=realizations, channels=channels,
                        rate_hz=rate_hz, samples=samples, max_steps=max_steps, alpha=alpha,
                        min_gain=min_gain, check_tau_range=check_tau_range,
                        tolerance_db=tolerance_db, catalog_csv=catalog_csv, mapping=mapping,
                        repair=repair, max_rows=max_rows, ci_level=ci_level,
                        low_frequency=low_frequency, decorrelate=decorrelate,
                        slow_modes=slow_modes)


def _run_gap(measured, model, *, seed, realizations, channels, rate_hz, samples, max_steps,
             alpha, min_gain, check_tau_range, tolerance_db, catalog_csv, mapping, repair,
             max_rows, ci_level, low_frequency, decorrelate, slow_modes) -> GapReport:
    if not isinstance(realizations, (int, np.integer)) or realizations < 4:
        raise InputError("realizations must be an integer ≥ 4", field="realizations", value=realizations)
    if not 0 < alpha < 0.5:
        raise InputError("alpha must be in (0, 0.5)", field="alpha", value=alpha)
    if not 0 <= min_gain < 1:
        raise InputError("min_gain must be in [0, 1)", field="min_gain", value=min_gain)
    if not (isinstance(tolerance_db, (int, float)) and 0 <= tolerance_db < 100):
        raise InputError("tolerance_db must be a number of dB in [0, 100)", field="tolerance_db",
                         value=tolerance_db)
    meas = load_measured(measured, rate_hz=rate_hz, samples=samples, mapping=mapping, repair=repair,
                         max_rows=max_rows, ci_level=ci_level, channels=channels)
    if meas.kind != "log" and (low_frequency or decorrelate):
        # both act on statistics only a log has: the record's DCT bands, and the PSD block that
        # decorrelation needs; on an Allan table they would be silently ignored
        on = [o for o, flag in (("low_frequency", low_frequency), ("decorrelate", decorrelate)) if flag]
        opt = " and ".join(f"{o} (--{o.replace('_', '-')})" for o in on)
        raise InputError(f"{opt} needs a log: an Allan table has no record to take low-frequency "
                         "bands from and no PSD terms to decorrelate", field=on[0],
                         expected="a time-series log, or the option left off")
    base, from_catalog, label = load_model(model, catalog_csv=catalog_csv)
    chans, notes = check_compatible(meas, base, from_catalog, channels, check_tau_range)
    current = _with_rate(base, meas.rate_hz)
    n_real = max(int(realizations), -(-MIN_NULL_SAMPLES // len(chans)))
    if n_real > realizations:
        notes.append(f"{n_real} realizations per channel (not {realizations}) so that the null "
                     f"distribution rests on ≥ {MIN_NULL_SAMPLES} leave-one-out gaps")
    states: dict[str, _State] = {}
    for ch in chans:
        if meas.kind == "log":
            grid = SignatureGrid.for_log(meas.n_samples, meas.rate_hz, meas.temp_c, low_frequency,
                                         noise_psd=_spectrum(current, ch, meas),
                                         slow_modes=slow_modes)
            x = meas.series[ch]
            sig, mean = series_signature(x, grid, lattice=True), float(np.mean(x))
        else:
            grid = SignatureGrid.for_table(meas.tables[ch])
            sig, mean = table_signature(meas.tables[ch]), 0.0
        states[ch] = _state(current, ch, grid, sig, mean, n_real, seed)
    if decorrelate:
        states = _whitened(states)
    null = _null(states, alpha)
    band = _band(states, alpha, tolerance_db)
    trend_z = float(stats.norm.isf(alpha / (2.0 * len(chans))))
    # a channel quieter than the model is not worked on: every candidate adds noise
    quiet = {ch: q for ch, st in states.items()
             if (q := quieter.median_db(st.d_db, st.terms.gap, null.channel_threshold(ch))) is not None
             and not _trend_open(st, trend_z)}
    # a channel a unit factor off the model at every τ and band: a unit slip, not effects
    slipped = {ch: found for ch, st in states.items() if (found := unit_slip.slip(st.d_db)) is not None}
    notes += [quieter.note(ch, q) for ch, q in quiet.items() if ch not in slipped]
    notes += [unit_slip.note(ch, found) for ch, found in slipped.items()]
    regimes = {ch: msg for ch, msg in meas.regimes.items() if ch in states}
    # the channels not worked on, and why (the stop reason names them)
    apart = ({ch: "quieter than the model" for ch in quiet} | {ch: "a likely unit error" for ch in slipped}
             | {ch: "two noise regimes" for ch in regimes})
    if apart:
        null = _null(states, alpha, apart)
    start = {ch: (st.terms, st.summary, st.sizes(band, ch)) for ch, st in states.items()}
    null_before, overall_before, band_before = null, _overall(states), band
    steps: list[GapStep] = []
    rejected: list[dict] = []
    skip: set[tuple[str, str]] = set()
    cache: dict[str, list[CandidateFit]] = {}
    stop = f"stopped after max_steps = {max_steps}"
    # every rejected (effect, channel) is skipped from then on, so the trials are bounded
    for _ in range(max_steps + (len(LIBRARY) + 1) * len(chans)):
        if len(steps) >= max_steps:
            break
        # a channel is worked on while its effect size exceeds its band; whether an effect is
        # named there is then up to the penalised test of each candidate (a targeted test:
        # far more power than the omnibus gap for a misfit confined to a few τ)
        over = [ch for ch in chans if ch not in apart and _open(ch, states[ch], band, trend_z)]
        if not over:
            stop = ("every channel is close enough: its peak misfit beyond the model's own spread is "
                    f"within {tolerance_db:g} dB, its kurtosis within its band and its trend "
                    "statistics within the model's")
            if apart:
                stop = ("every other channel is close enough" if len(apart) < len(chans) else
                        "nothing to name") + "".join(
                    f"; {', '.join(c for c in apart if apart[c] == w)}: {w} (notes), where no added effect can help"
                    for w in dict.fromkeys(apart.values()))
            break
        direct = [(ch, eff) for ch in over for eff in direct_proposals(current, ch, states[ch].meas,
                                                                         states[ch].grid)
                  if (eff.name, ch) not in skip]
        if direct:
            # direct evidence (a lattice of values) names its effect at the measured value;
            # the simulated improvement must still pass the test below
            ch, effect = direct[0]
            old = states[ch]
            n_cand = len(chans)
            best = CandidateFit(effect, old.terms.sum_sq, 1, np.zeros(1), linear_sq=old.terms.linear_sq)
            alts = ()
            trial = current.with_effect(effect)
            new = _state(trial, ch, old.grid, old.meas, old.true_value, n_real, seed)
        else:
            scored = []
            for ch in over:
                if ch not in cache:
                    cache[ch] = _fits(current, ch, states[ch])
                scored += [(ch, f) for f in cache[ch] if (f.effect.name, ch) not in skip]
            if not scored:
                stop = "no candidate effect can be fitted where the gap is"
                break
            # which channels are open is itself read off the data (a trend z beyond its limit
            # on one of six channels): the candidates are counted as if tried on every channel
            n_cand = len(scored) * len(chans) / len({c for c, _ in scored})

            def score(item):
                ch, f = item
                st = states[ch]
                drop = st.terms.sum_sq - f.sum_sq
                ok = drop >= min_gain * _excess(ch, st, null)
                if f.pred_db is not None:
                    old_sz = st.sizes(band, ch)
                    new_sz = band.sizes(ch, f.pred_db, f.pred_kurtosis, st.d_db.size - (st.meas.psd is not None),
                                        st.terms.where[:st.d_db.size])
                    size_gain, worse = _size_gain(old_sz, new_sz, band, ch)
                    if worse and not _trend_open(st, trend_z):
                        return -np.inf
                    ok = ok or size_gain >= min_gain
                if not ok:
                    return -np.inf
                return (null.drop(ch, st.terms.sum_sq, st.terms.linear_sq, f.sum_sq, f.linear_sq)
                        - stats.chi2.isf(alpha / n_cand, f.n_params))

            ch, best = max(scored, key=score)
            best = located_over_spread(ch, best, scored, score, states[ch], alpha)
            best = richer_spread(ch, best, scored, score, states[ch], alpha)
            best = parsimonious(ch, best, scored, score, states[ch], null, alpha)
            if score((ch, best)) <= 0:
                stop = ("no candidate gives a significant penalised improvement that also removes "
                        f"≥ {min_gain:.0%} of its channel's excess gap or excess effect size "
                        "without making the effect size worse")
                break
            old = states[ch]
            alts = alternatives(ch, best, scored, score, states[ch])
            trial, new, effect = _simulate_candidate(current, ch, old, best, n_real, seed, null)
        gain = null.drop(ch, old.terms.sum_sq, old.terms.linear_sq, new.terms.sum_sq, new.terms.linear_sq)
        penalty = float(stats.chi2.isf(alpha / n_cand, best.n_params))
        band_new = _band({**states, ch: new}, alpha, tolerance_db)
        size_gain, worse = _size_gain(old.sizes(band, ch), new.sizes(band_new, ch), band, ch)
        worse = worse and not _trend_open(old, trend_z)
        big = old.terms.sum_sq - new.terms.sum_sq >= min_gain * _excess(ch, old, null) or size_gain >= min_gain
        if gain <= penalty or not big or worse:
            skip.add((effect.name, ch))
            rejected.append({"name": effect.name, "channel": ch, "params": dict(effect.params),
                             "predicted_gap": best.sum_sq / old.terms.n_terms,
                             "simulated_gap": new.terms.gap,
                             "reason": ("the simulated model makes the channel's effect size worse"
                                        if worse and gain > penalty else
                                        "the simulated improvement was not significant")})
            continue
        before_all = _overall(states)
        states[ch] = new
        current = trial
        cache.pop(ch, None)
        null = _null(states, alpha, apart)
        band_step, band = band, _band(states, alpha, tolerance_db)
        steps.append(GapStep(effect.name, ch, dict(effect.params), old.terms.gap,
                             new.terms.gap, before_all, _overall(states),
                             best.sum_sq / old.terms.n_terms, float(gain), penalty, best.n_params,
                             old.sizes(band_step, ch), new.sizes(band, ch), alts))
        if effect.name == "outliers" and effect.params["rate"] * old.grid.n_samples <= 2.0 + 1e-9:
            seen = old.meas.spike_count or 0
            notes.append(f"{ch}: outliers rate at its floor of 2 per record ({seen} spike"
                         f"{'' if seen == 1 else 's'} seen): fewer spikes do not measure a rate — read it "
                         "as 'a few per record at most'; the magnitude is what the record shows")
    if len(steps) < max_steps and stop.startswith("stopped after max_steps"):
        stop = "every candidate that could be fitted was tried and rejected"
    cross, shapes = [], []
    if meas.kind == "log":
        # what the per-channel vocabulary cannot say: a component common to channels
        # (:mod:`budget.gap.coherence`), a Gauss–Markov spectrum on a two-valued slow part
        # (:mod:`budget.gap.two_valued`); findings beside the steps, not steps
        cross = coherence.findings({ch: meas.series[ch] for ch in chans}, meas.rate_hz, meas.temp_c, alpha)
        notes += coherence.notes(cross)
        for s in steps:
            if s.name == "gauss_markov":
                got = two_valued.check(current, s.channel, meas.series[s.channel], meas.rate_hz,
                                       s.params["tau_s"], seed, states[s.channel].true_value, meas.temp_c)
                if got is not None:
                    shapes.append(got)
                    if got["two_valued"]:
                        notes.append(two_valued.note(got))
        if meas.temp_c is not None:
            for ch in chans:
                named = tuple(dict.fromkeys(s.name for s in steps if s.channel == ch
                                            and s.name in temperature_curve.SLOW))
                if named:
                    got = temperature_curve.check(current, ch, meas.series[ch], meas.rate_hz, meas.temp_c,
                                                  seed, named, states[ch].true_value)
                    shapes.append(got)
                    if got["curved"]:
                        notes.append(temperature_curve.note(got))
    channels_out = {ch: ChannelResult(ch, st.grid, st.meas, start[ch][0], st.terms, start[ch][1],
                                      st.summary, start[ch][2], st.sizes(band, ch))
                    for ch, st in states.items()}
    report = GapReport(
        source=meas.source, kind=meas.kind, model_label=label, rate_hz=meas.rate_hz,
        n_samples=meas.n_samples, seed=int(seed), realizations=n_real, alpha=alpha,
        gap_before=overall_before, gap_after=_overall(states), null_before=null_before,
        null_after=null, steps=steps, channels=channels_out, rejected=rejected,
        notes=meas.notes + notes, stop_reason=stop, base_model=base,
        band_before=band_before, band_after=band,
        updated_model=_updated(base, current, steps, meas.rate_hz),
        options={"low_frequency": bool(low_frequency), "decorrelate": bool(decorrelate),
                 "slow_modes": bool(slow_modes) and meas.kind == "log"},
        cross_channel=cross, slow_shape=shapes)
    report.notes += report.unexplained_notes()
    return report


def _updated(base: NoiseModel, current: NoiseModel, steps, rate_hz: float) -> NoiseModel:
    data = current.model_dump()
    data["rate_hz"] = rate_hz
    if steps:
        extra = "model-gap workflow: + " + ", ".join(f"{s.name} on {s.channel}" for s in steps)
        data["notes"] = (base.notes + " | " if base.notes else "") + extra
    return NoiseModel.model_validate(data)
