"""Choosing among the candidates of one step of the model-gap workflow (:mod:`budget.gap.workflow`):
which of the effects that pass the penalised test is named, and which others are said beside it.

* :func:`located_over_spread` — a located pattern of the slow modes (a bias step) over a spread
  (a walk) that Σz² ranks about equal, when the modes' own likelihood tells them apart;
* :func:`richer_spread` — a spread whose family holds the best-ranked spread as a limit (a
  Gauss–Markov term over a walk), when the modes' profile likelihood tells them apart;
* :func:`parsimonious` — Occam's step: a richer effect keeps its place only when its extra
  parameters buy a significant drop (of Σz², or of the modes' likelihood for a located one or
  a nested spread);
* :func:`alternatives` — the effects the record does not tell apart from the named one.

``st`` is the channel's state of the workflow: its grid, measured signature, model summary and
gap terms."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy import stats

from ..imu import Effect
from . import walk
from .candidates import LIBRARY
from .fitting import CandidateFit
from .metric import NullModel

if TYPE_CHECKING:
    from .workflow import _State as State


#: An alternative whose penalised improvement is within this of the named effect's is said in
#: the step: 2 ln B < 6, i.e. a likelihood ratio below 20 — at most "positive" evidence for the
#: named effect on Kass & Raftery's scale (JASA 90(430), 1995), not "strong".
ALTERNATIVE_MARGIN = 6.0


def alternatives(ch: str, best: CandidateFit, scored, score, st: State | None = None) -> tuple[dict, ...]:
    """Other effects on the named effect's channel that pass the same test and whose score
    (penalised Σz² improvement, the ranking's own) is within :data:`ALTERNATIVE_MARGIN` of
    ``best``'s: the record does not tell them apart (e.g. a rate random walk and a ramp or a
    flicker term over one hour) — unless the slow modes' likelihood does, by more than the same
    margin, for an effect located in time (:func:`located_mode_lr`) or for a named spread whose
    family holds the other as a limit (:func:`spread_mode_lr`; ``st``: the channel's state,
    ``None``: scores only). Best first; ``margin`` is how far below ``best`` each lies."""
    top = score((ch, best))
    out = []
    for c, f in scored:
        if c != ch or f.effect.name == best.effect.name:
            continue
        s = score((c, f))
        if np.isfinite(s) and s > 0 and top - s <= ALTERNATIVE_MARGIN:
            lr = None if st is None else located_mode_lr(st, f.effect, best.effect)
            if lr is None and st is not None:
                back = located_mode_lr(st, best.effect, f.effect)
                lr = None if back is None else -back
            if lr is None and st is not None:
                lr = spread_mode_lr(st, f.effect, best.effect)
            if lr is not None and lr > ALTERNATIVE_MARGIN:
                continue
            out.append((s, f))
    seen, alts = set(), []
    for s, f in sorted(out, key=lambda t: -t[0]):
        if f.effect.name not in seen:  # one entry per effect (its best fit)
            seen.add(f.effect.name)
            alts.append({"name": f.effect.name, "params": dict(f.effect.params),
                         "margin": float(top - s)})
    return tuple(alts)


def located_over_spread(ch: str, best: CandidateFit, scored, score, st: State,
                         alpha: float) -> CandidateFit:
    """When the best-scoring candidate explains the slow modes by a spread (a walk, a flicker
    term) and another on its channel, within :data:`ALTERNATIVE_MARGIN` of it on the ranking's
    penalised Σz², explains them by a located pattern whose modes' likelihood is higher by more
    than χ²_Δp(1 − α) (Δp its extra parameters, at least 1; :func:`located_mode_lr`), the
    located one is taken: Σz² does not tell the two apart, the modes do. Conversely, when the
    best is located and a spread with fewer parameters lies within the margin, the spread is
    taken unless the located one's modes' likelihood beats it by that much: the extra
    parameters of a near-tie must be bought where the two differ (a one-hour walk with a
    step-like excursion on a high-end tactical log scored as a step on Σz², 2·ln LR 1.4)."""
    top = score((ch, best))
    better, simpler = [], []
    for c, f in scored:
        if c != ch or f.effect.name == best.effect.name or not (np.isfinite(score((c, f))) and score((c, f)) > 0):
            continue
        if top - score((c, f)) > ALTERNATIVE_MARGIN:
            continue
        lr = located_mode_lr(st, best.effect, f.effect)
        if lr is not None and lr > stats.chi2.isf(alpha, max(f.n_params - best.n_params, 1)):
            better.append((lr, f))
        back = located_mode_lr(st, f.effect, best.effect)
        if (back is not None and f.n_params < best.n_params
                and back <= stats.chi2.isf(alpha, best.n_params - f.n_params)):
            simpler.append((score((c, f)), f))
    if better:
        return max(better, key=lambda t: t[0])[1]
    return max(simpler, key=lambda t: t[0])[1] if simpler else best


def parsimonious(ch: str, best: CandidateFit, scored, score, st: State, null: NullModel,
                  alpha: float) -> CandidateFit:
    """Occam's step on the channel of the best-scoring candidate. If a significant candidate
    with fewer parameters already brings the channel within its null threshold, ``best`` keeps
    its place only when its extra parameters buy a significant further drop of Σz²:

        (Σz²_simple − Σz²_best)/φ > χ²_Δp⁻¹(1 − α),

    a likelihood-ratio test of the extra parameters Δp at the workflow's level α (one
    pairwise question, so no multiplicity correction). Near the
    detection limit a two-parameter shape (a Gauss–Markov hump) fits one realization of a
    one-parameter effect (flicker) a little better than the effect itself; a drop that small
    is not evidence for the richer effect."""
    limit = null.channel_threshold(ch) * st.terms.n_terms
    simpler = [item for item in scored if item[0] == ch and item[1].n_params < best.n_params
               and item[1].sum_sq <= limit and score(item) > 0]
    if not simpler:
        return best
    simple = max(simpler, key=score)[1]
    extra = null.drop(ch, simple.sum_sq, simple.linear_sq, best.sum_sq, best.linear_sq)
    need = stats.chi2.isf(alpha, best.n_params - simple.n_params)
    if extra > need:
        return best
    lr = located_mode_lr(st, simple.effect, best.effect)
    if lr is None:
        lr = spread_mode_lr(st, simple.effect, best.effect)
    return best if lr is not None and lr > need else simple


def richer_spread(ch: str, best: CandidateFit, scored, score, st: State, alpha: float) -> CandidateFit:
    """When the best-scoring candidate is a spread (a walk) and another on its channel, within
    :data:`ALTERNATIVE_MARGIN` of it on the ranking's penalised Σz² and with a positive score,
    is a richer spread whose family holds it as a limit (a Gauss–Markov term,
    :data:`budget.gap.walk.NESTED_SPREADS`), the richer one is taken when the slow modes'
    profile likelihood ratio (:func:`spread_mode_lr`) exceeds χ²_Δp(1 − α), Δp its extra
    parameters: the likelihood-ratio test of nested models (Wilks), on the part of the record
    where the two differ.

    Σz² does not tell them apart where it matters: a walk's spectrum keeps rising as f⁻² below
    the Gauss–Markov corner 1/(2πτ), the Gauss–Markov term's is flat there, and only the
    record's slowest modes lie below it (periods 3600 … 630 s for τ = 100 s on a 30-min log,
    5 of the 48 modes). Σz² sees them through the slow-mode statistic T (one number, their
    summed power) and the last Allan octaves (a few degrees of freedom); the modes' likelihood
    sees each mode's variance against the f⁻² or flat shape."""
    top = score((ch, best))
    better = []
    for c, f in scored:
        if c != ch or f.n_params <= best.n_params or not (np.isfinite(score((c, f))) and score((c, f)) > 0):
            continue
        if top - score((c, f)) > ALTERNATIVE_MARGIN:
            continue
        lr = spread_mode_lr(st, best.effect, f.effect)
        if lr is not None and lr > stats.chi2.isf(alpha, f.n_params - best.n_params):
            better.append((lr, f))
    return max(better, key=lambda t: t[0])[1] if better else best


def spread_mode_lr(st: State, simple: Effect, rich: Effect) -> float | None:
    """2·ln of the likelihood ratio of the record's slowest modes (:mod:`budget.gap.walk`) with
    ``rich``'s family added to the model against with ``simple``'s, each maximised over its own
    parameters (:func:`budget.gap.walk.nested_spread_lr`: profile likelihoods), when ``rich``'s
    family holds ``simple`` as a limit (a Gauss–Markov term of τ → ∞ is a walk in the modes);
    ``None`` otherwise, or when the channel has no slow modes. The candidates' parameters are
    fitted on Σz², not on the modes: at those parameters the ratio is not a likelihood-ratio
    statistic of the two families (on a 30-min log with a τ = 100 s term, −1.6 where the
    profiles give 0.0), so each family is maximised afresh; the fitted walk level centres the
    search. A likelihood of a part of the data, its ratio is a fair second test at the
    workflow's level, as :func:`located_mode_lr` is for located effects."""
    if (simple.name, rich.name) not in walk.NESTED_SPREADS:
        return None
    lay, y, cov0 = st.grid.walk, st.meas.walk, st.summary.walk_cov
    if lay is None or y is None or cov0 is None:
        return None
    level = float(dict(simple.params).get("K", 0.0)) ** 2
    if not level > 0:
        return None
    return walk.nested_spread_lr(simple.name, rich.name, y, st.summary.walk_mean, cov0, lay, level)


def located_mode_lr(st: State, spread: Effect, located: Effect) -> float | None:
    """2·ln of the likelihood ratio of the record's slowest modes (:mod:`budget.gap.walk`) with
    ``located`` added to the model against with ``spread``, when ``located`` gives the modes a
    mean — a pattern located in time (a bias step, a transient, a thermal lag) — and ``spread``
    gives them covariance and no mean (a walk, a flicker or Gauss–Markov term); ``None``
    otherwise.

    The slow-mode statistic T is quadratic: a walk and a step of the same slow power leave it
    equally well explained, so Σz² can neither rank them (a step 0.2 below a walk on one of ten
    one-hour step logs) nor pay the step's second parameter (0.9–2.3 better on four, under
    χ²₁(0.99) = 6.6). The modes' own Gaussian likelihood (:func:`budget.gap.walk.log_likelihood`)
    tells a located mean from a spread; it is the likelihood of a part of the data, so its ratio
    is a fair second test at the same level. Between a located pattern and nothing in the modes
    (a ramp, which the modes project out) T and the early statistic already see the pattern's
    power, and Σz² alone judges.

    Each side is its family's profile likelihood near the candidates' fit, since the fits
    minimise Σz², which barely locates a pattern in time: the located pattern's coefficient by
    generalised least squares (:func:`budget.gap.walk.located_log_likelihood`) and a step's
    time over the block boundaries within ± half the modes' shortest period of the fitted time
    (the resolution the modes hold, which is how far the Σz² fit may be off); a walk's or
    Gauss–Markov term's parameters by :func:`budget.gap.walk.profile_log_likelihood`. At the
    fitted parameters alone a one-hour step log (step at 890 s, 3× the model's Allan deviation)
    read 3.6, its step fitted at 815 s; at 872 s, its change-point scan's best, 31."""
    lay, y, cov0 = st.grid.walk, st.meas.walk, st.summary.walk_cov
    if lay is None or y is None or cov0 is None:
        return None
    temp = st.grid.temp_c
    params = dict(located.params)
    mean_rich = walk.effect_mean(located.name, params, lay, temp)
    if mean_rich is None or not np.any(mean_rich):
        return None
    cov_s = walk.effect_cov(spread.name, dict(spread.params), lay)
    mean_s = walk.effect_mean(spread.name, dict(spread.params), lay, temp)
    if cov_s is None or not np.any(cov_s) or mean_s is None or np.any(mean_s):
        return None
    base = st.summary.walk_mean
    coefficient = LIBRARY[located.name].coefficient
    shapes = [params]
    if located.name in _LOCATED_TIME:
        key, block_s = _LOCATED_TIME[located.name], lay.block * lay.dt_s
        t_fit, half, span = float(params[key]), 0.5 * lay.shortest_period_s, lay.n_samples * lay.dt_s
        edges = np.arange(np.ceil((t_fit - half) / block_s), np.floor((t_fit + half) / block_s) + 1) * block_s
        shapes += [{**params, key: float(t)} for t in edges if 0.0 < t < span]
    units = []
    for p in shapes:
        u = walk.effect_mean(located.name, {**p, coefficient: 1.0}, lay, temp)
        if u is not None:
            units.append(u)
    c_loc = walk.effect_cov(located.name, params, lay)
    try:
        a, _, _ = walk.located_log_likelihood(y, base, cov0 if c_loc is None else cov0 + c_loc, np.array(units))
        if spread.name in walk.PROFILED_SPREADS:
            level = walk.walk_level(spread.name, dict(spread.params))
            b, _ = walk.profile_log_likelihood(spread.name, y, base, cov0, lay, level)
        else:
            b = walk.log_likelihood(y, base, cov0 + cov_s)
    except (np.linalg.LinAlgError, ValueError, KeyError):
        return None
    return 2.0 * (a - b)


#: Located effects whose time the modes resolve: the parameter :func:`located_mode_lr` profiles.
_LOCATED_TIME = {"bias_step": "time_s"}
