"""Fitting machinery shared by the candidate effects of :mod:`budget.gap.candidates`.

:class:`FitContext` holds one channel's measured signature and model summary and evaluates the
predicted Σz² of the channel with an effect added (:meth:`FitContext.sumsq`);
:class:`Candidate` is the base class of an effect (closed-form starts, increments, parameters)
with the bounded search that minimises that Σz²; :class:`LinearVariance` covers the effects
whose increments are amplitude² × a fixed shape. θ is the search space (logarithms of positive
parameters, or the signed parameter itself).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import optimize

from ..imu import Effect
from . import lowfreq, walk
from . import theory as th
from .effect_size import db_terms, kurtosis_size
from .metric import ModelSummary, adev_variance, gap_terms
from .signatures import Signature, SignatureGrid, band_means


@dataclass
class FitContext:
    """Everything a candidate needs to fit one channel."""

    channel: str
    grid: SignatureGrid
    meas: Signature
    model: ModelSummary
    existing: tuple[Effect, ...] = ()
    cache: dict = field(default_factory=dict)

    @property
    def dt(self) -> float:
        return self.grid.dt_s

    def sumsq(self, inc: th.Increment) -> float:
        """Predicted Σz² of the channel with the effect added (:meth:`sumsq_parts`)."""
        return self.sumsq_parts(inc)[0]

    def sumsq_parts(self, inc: th.Increment) -> tuple[float, float]:
        """(predicted Σz², its linear part) with the effect added. A candidate that widens the
        scatter of the slope, the temperature coefficient or the early statistic (random walk,
        flicker, Gauss–Markov) also pays ln(var'/var),
        the Gaussian log-likelihood term that Σz² alone would leave out (in the linear part)."""
        pred = self.model.predict(inc, self.grid)
        terms = gap_terms(self.meas, pred, self.grid)
        linear = terms.linear_sq
        if inc.slope_var > 0:
            linear += _widening(pred.slope_var, self.model.slope_var)
        if inc.temp_var > 0 and self.meas.temp_coef is not None:
            linear += _widening(pred.temp_var, self.model.temp_var)
        if (inc.walk_cov is not None and self.model.walk_cov is not None and pred.walk_cov is not None
                and self.grid.walk is not None and self.grid.walk.early is not None and self.meas.walk is not None):
            linear += _widening(walk.early_var(pred.walk_cov, self.grid.walk),
                                walk.early_var(self.model.walk_cov, self.grid.walk))
        return terms.sum_sq - terms.linear_sq + linear, linear

    def walk_cov(self, name: str, params: dict) -> np.ndarray | None:
        """Covariance an effect adds to the record's slowest modes
        (:func:`budget.gap.walk.effect_cov`); ``None`` when the channel has no slow-mode term."""
        if self.grid.walk is None or self.model.walk_cov is None:
            return None
        return walk.effect_cov(name, params, self.grid.walk)

    def freq(self) -> np.ndarray:
        if "freq" not in self.cache:
            self.cache["freq"] = self.grid.freq_hz
        return self.cache["freq"]

    def low_freq(self) -> np.ndarray:
        """f_k of the low-frequency coefficients (Hz; empty without them)."""
        if "low_freq" not in self.cache:
            self.cache["low_freq"] = self.grid.low_freq_hz
        return self.cache["low_freq"]

    def low_from_psd(self, psd: np.ndarray) -> np.ndarray | None:
        """ΔE c_k² of a stationary term whose one-sided PSD at :meth:`low_freq` is ``psd``
        (``None`` when the channel has no low-frequency coefficients)."""
        return lowfreq.from_psd(psd, self.dt) if self.grid.has_low and self.meas.low is not None else None

    def adev_residual(self) -> tuple[np.ndarray, np.ndarray]:
        """Allan-variance residual (measured − model) and its least-squares weights."""
        y = 2.0 * self.model.avar * (0.5 * np.log(self.meas.avar) - self.model.ln_adev)
        v = adev_variance(self.model, self.grid)
        v_meas = 0.5 / self.meas.edf if self.meas.edf is not None else v
        w = 1.0 / ((2.0 * self.model.avar) ** 2 * (v_meas + v / self.model.n_real))
        return y, w


def _widening(var_new: float, var_old: float) -> float:
    """ln(var'/var): what a candidate that widens a linear statistic's scatter pays beside its
    z² (the Gaussian log-likelihood's −2·ln of the density's scale); 0 when either is not
    positive."""
    return math.log(var_new / var_old) if var_new > 0 and var_old > 0 else 0.0


@dataclass
class CandidateFit:
    """A fitted candidate: the effect, its predicted channel Σz² and its parameter count."""

    effect: Effect
    sum_sq: float
    n_params: int
    theta: np.ndarray
    #: predicted dB misfits (:func:`budget.gap.effect_size.db_terms`) and kurtosis difference
    #: of the channel with the effect added (``None``: not predicted, e.g. a direct proposal)
    pred_db: np.ndarray | None = None
    pred_kurtosis: float = 0.0
    #: the linear statistics' part of ``sum_sq`` (:meth:`FitContext.sumsq_parts`)
    linear_sq: float = 0.0


def amp2_start(ctx: FitContext, shape: np.ndarray) -> float:
    y, w = ctx.adev_residual()
    den = float(np.sum(w * shape ** 2))
    return float(np.sum(w * shape * y) / den) if den > 0 else 0.0


class Candidate(ABC):
    """Base class: subclasses set ``name``, ``n_params`` and implement the three hooks."""

    name = ""
    n_params = 1
    #: θ of a one-parameter candidate is ln(parameter) (else the signed parameter itself).
    log_param = True
    needs_psd = False
    needs_temp = False

    def applicable(self, ctx: FitContext) -> bool:
        if self.needs_psd and ctx.meas.psd is None:
            return False
        return not (self.needs_temp and ctx.meas.temp_coef is None)

    @abstractmethod
    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        """Closed-form starting points θ0 (empty: nothing to fit)."""

    @abstractmethod
    def increment(self, theta: np.ndarray, ctx: FitContext) -> th.Increment:
        """Expected signature increments for parameters θ."""

    @abstractmethod
    def params(self, theta: np.ndarray, ctx: FitContext) -> dict[str, float]:
        """Effect parameters (SI channel units) for θ."""

    def full_increment(self, theta: np.ndarray, ctx: FitContext) -> th.Increment:
        """:meth:`increment` with the covariance the effect adds to the record's slowest modes
        (:func:`budget.gap.walk.effect_cov`, from the effect's own parameters), when the
        channel has them and the increment does not carry it already."""
        inc = self.increment(theta, ctx)
        if inc.walk_cov is not None:
            return inc
        return replace(inc, walk_cov=ctx.walk_cov(self.name, self.params(theta, ctx)))

    def search(self, theta0: np.ndarray, ctx: FitContext) -> tuple[np.ndarray, float]:
        """Minimise the predicted Σz² from ``theta0`` (1-D bounded, else Nelder–Mead)."""
        f = lambda th_: ctx.sumsq(self.full_increment(np.atleast_1d(th_), ctx))
        if theta0.size == 1:
            lo, hi = self.bracket(theta0[0])
            grid = np.sort(np.append(np.linspace(lo, hi, 13), theta0[0]))
            vals = [f(g) for g in grid]
            i = int(np.argmin(vals))
            a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
            res = optimize.minimize_scalar(f, bounds=(a, b), method="bounded",
                                           options={"xatol": 1e-4 * abs(b - a)})
            best = (np.array([res.x]), float(res.fun))
            return best if best[1] <= vals[i] else (np.array([grid[i]]), float(vals[i]))
        res = optimize.minimize(f, theta0, method="Nelder-Mead",
                                options={"maxiter": 200, "xatol": 1e-3, "fatol": 1e-3})
        return res.x, float(res.fun)

    def bracket(self, t0: float) -> tuple[float, float]:
        return t0 - 4.0, t0 + 2.5  # log-amplitude: from e⁻⁴ to e²·⁵ times the start

    def fit(self, ctx: FitContext) -> CandidateFit | None:
        if not self.applicable(ctx):
            return None
        best = None
        for t0 in self.starts(ctx):
            theta, val = self.search(np.asarray(t0, float), ctx)
            if best is None or val < best[1]:
                best = (theta, val)
        if best is None:
            return None
        params = self.params(best[0], ctx)
        inc = self.full_increment(best[0], ctx)
        pred = ctx.model.predict(inc, ctx.grid)
        return CandidateFit(Effect(name=self.name, channel=ctx.channel, params=params), best[1],
                            self.n_params, best[0], db_terms(ctx.meas, pred, ctx.grid),
                            kurtosis_size(ctx.meas, pred), linear_sq=ctx.sumsq_parts(inc)[1])


class LinearVariance(Candidate):
    """Effects whose increments are amplitude² × a fixed shape (θ = ln amplitude)."""

    param = ""

    @abstractmethod
    def shapes(self, ctx: FitContext) -> th.Increment:
        """Increments for amplitude 1."""

    def _unit(self, ctx: FitContext) -> th.Increment:
        key = ("unit", self.name)
        if key not in ctx.cache:
            unit = self.shapes(ctx)
            if unit.walk_cov is None:
                # every parameter here is an amplitude: the modes' covariance scales with its square
                unit = replace(unit, walk_cov=ctx.walk_cov(self.name, {self.param: 1.0}))
            ctx.cache[key] = unit
        return ctx.cache[key]

    def starts(self, ctx):
        unit = self._unit(ctx)
        a2 = amp2_start(ctx, unit.avar)
        if a2 <= 0 and unit.psd is not None:
            a2 = psd_amp2_start(ctx, unit.psd)
        out = [np.array([0.5 * math.log(a2)])] if a2 > 0 else []
        # a second start from the low-frequency bands, where a slow term may show more clearly
        # than in the last few Allan τ (2–5 degrees of freedom)
        b2 = low_amp2_start(ctx, unit.low) if unit.low is not None else 0.0
        if b2 > 0 and (a2 <= 0 or abs(math.log(b2 / a2)) > 0.5):
            out.append(np.array([0.5 * math.log(b2)]))
        return out

    def increment(self, theta, ctx):
        u, a2 = self._unit(ctx), math.exp(2.0 * theta[0])
        return th.Increment(u.avar * a2, None if u.psd is None else u.psd * a2, u.diff_var * a2,
                            u.diff_cum4 * a2 * a2, slope_var=u.slope_var * a2, temp_var=u.temp_var * a2,
                            low=None if u.low is None else u.low * a2,
                            walk_cov=None if u.walk_cov is None else u.walk_cov * a2)

    def params(self, theta, ctx):
        return {self.param: math.exp(theta[0])}


def low_amp2_start(ctx: FitContext, unit_low: np.ndarray) -> float:
    """Amplitude² of a unit low-frequency shape from the band residual measured − model,
    weighted least squares with the weights of the band means' variance (∝ model²/n)."""
    if ctx.meas.low is None or ctx.model.low is None:
        return 0.0
    st, n = ctx.grid.low_starts, ctx.grid.low_counts
    mod = lowfreq.band_means(ctx.model.low, st)
    resid = lowfreq.band_means(ctx.meas.low, st) - mod
    shape = lowfreq.band_means(unit_low, st)
    w = n / mod ** 2
    den = float(np.sum(w * shape ** 2))
    return float(np.sum(w * shape * resid) / den) if den > 0 else 0.0


def psd_amp2_start(ctx: FitContext, unit_psd: np.ndarray) -> float:
    g = ctx.grid
    resid = band_means(ctx.meas.psd, g) - band_means(ctx.model.psd, g)
    shape = band_means(unit_psd, g)
    w = 1.0 / band_means(ctx.model.psd, g) ** 2
    return float(np.sum(w * shape * resid) / np.sum(w * shape ** 2))
