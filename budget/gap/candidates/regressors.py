"""Deterministic-regressor candidates: a rate ramp (drift linear in time), a temperature
sensitivity (output linear in the temperature column), a thermal lag (linear in the
temperature seen through a first-order lag of time constant τ), a warm-up transient
(a bias settling as e^(−t/τ) from the log's start) and a bias step (a jump of the bias at t₀). Each is a known series times
its coefficient: it moves the mean of the slope and temperature regression statistics, and adds
that series' own Allan variance, PSD and slow-mode coefficients (no variance of its own).

Parameters are SI channel units (see :mod:`budget.imu.noise_model`); θ is the search space.
"""

from __future__ import annotations

import math
from abc import abstractmethod

import numpy as np
from scipy import optimize

from ...imu.effects import step_response, thermal_lag, warmup_response
from .. import lowfreq, walk
from .. import theory as th
from ..fitting import Candidate, amp2_start
from ..signatures import overlapping_avar


class RateRamp(Candidate):
    name = "rate_ramp"
    log_param = False

    def _unit(self, ctx):
        key = ("unit", self.name)
        if key not in ctx.cache:
            g = ctx.grid
            psd = th.psd_ramp(g.nperseg, g.dt_s, g.n_samples) if g.has_psd else None
            temp = 0.0
            if g.temp_w is not None:
                temp = float(np.einsum("i,i->", g.temp_w, np.arange(g.n_samples) * g.dt_s))
            ctx.cache[key] = th.Increment(g.tau_s ** 2 / 2.0, psd, slope=1.0, temp=temp)
        return ctx.cache[key]

    def starts(self, ctx):
        unit = self._unit(ctx)
        r_adev = math.sqrt(max(amp2_start(ctx, unit.avar), 0.0))
        if ctx.meas.slope is not None:
            r0 = ctx.meas.slope - ctx.model.slope
            return [np.array([r0])] if (r0 != 0 or r_adev > 0) else []
        return [np.array([r_adev])] if r_adev > 0 else []

    def bracket(self, t0):
        return -4.0 * abs(t0), 4.0 * abs(t0)

    def increment(self, theta, ctx):
        u, r = self._unit(ctx), float(theta[0])
        return th.Increment(u.avar * r * r, None if u.psd is None else u.psd * r * r,
                            slope=r, temp=u.temp * r)

    def params(self, theta, ctx):
        return {"R": float(theta[0])}


class TemperatureSensitivity(Candidate):
    name = "temperature_sensitivity"
    log_param = False
    needs_psd = needs_temp = True

    def _unit(self, ctx):
        key = ("unit", self.name)
        if key not in ctx.cache:
            g = ctx.grid
            T = g.temp_c - g.temp_c[0]
            avar = overlapping_avar(T, g.m)
            d = np.diff(T)
            c = d - d.mean()
            v = float(np.einsum("i,i->", c, c)) / c.size
            cum4 = float(np.mean(c ** 4)) - 3.0 * v * v
            # deterministic: the coefficients of T itself (the cross term with the noise averages out)
            low = lowfreq.coefficients_sq(T, g.low_k_max) if g.has_low else None
            ctx.cache[key] = th.Increment(avar, th.psd_of_series(T, g.dt_s, g.nperseg), v, cum4,
                                          slope=float(np.einsum("i,i->", g.time_w, T)), temp=1.0,
                                          low=low)
        return ctx.cache[key]

    def starts(self, ctx):
        c0 = ctx.meas.temp_coef - ctx.model.temp_coef
        return [np.array([c0])] if c0 != 0 else []

    def bracket(self, t0):
        return -4.0 * abs(t0), 4.0 * abs(t0)

    def increment(self, theta, ctx):
        u, c = self._unit(ctx), float(theta[0])
        return th.Increment(u.avar * c * c, u.psd * c * c, u.diff_var * c * c, u.diff_cum4 * c ** 4,
                            slope=u.slope * c, temp=c, low=None if u.low is None else u.low * c * c)

    def params(self, theta, ctx):
        return {"coefficient": float(theta[0])}


class _ScaledSeries(Candidate):
    """A deterministic series y_τ(t) with a time constant τ, times a signed coefficient: θ =
    (coefficient/c_ref, ln τ). Every statistic follows from y_τ itself (its Allan variance,
    Welch PSD, differences, regression weights, low-frequency coefficients and slowest modes),
    computed once per τ. The search profiles the coefficient at each τ — bracketed around the
    value that explains the regression statistic the subclass reads (``_delta``) — and runs a
    bounded search over ln τ from the best of a grid; τ from 2 s to a quarter of the record."""

    n_params = 2
    #: τ grid of the starts
    N_TAU = 10
    #: name of the coefficient in the effect's parameters
    coefficient = ""

    @abstractmethod
    def _series(self, ctx, tau: float) -> np.ndarray:
        """y_τ over the record's samples."""

    @abstractmethod
    def _delta(self, ctx) -> float:
        """Measured − model value of the regression statistic the coefficient must explain."""

    @abstractmethod
    def _unit_stat(self, unit: th.Increment) -> float:
        """That statistic for the coefficient 1."""

    def _ref_factor(self, ctx) -> float:
        """c_ref = |Δ| × this (1 by default)."""
        return 1.0

    def _tau_range(self, ctx):
        g = ctx.grid
        return max(2.0, 4.0 * g.dt_s), 0.25 * g.n_samples * g.dt_s

    def _unit(self, ctx, tau):
        key = ("unit", self.name, round(math.log(tau), 9))
        if key not in ctx.cache:
            g = ctx.grid
            y = self._series(ctx, tau)
            d = np.diff(y)
            c = d - d.mean()
            v = float(np.einsum("i,i->", c, c)) / c.size
            low = lowfreq.coefficients_sq(y, g.low_k_max) if g.has_low else None
            mean = walk.modes(y, g.walk) if g.walk is not None and ctx.model.walk_cov is not None else None
            temp = float(np.einsum("i,i->", g.temp_w, y)) if g.temp_w is not None else 0.0
            ctx.cache[key] = th.Increment(overlapping_avar(y, g.m),
                                          th.psd_of_series(y, g.dt_s, g.nperseg) if g.has_psd else None, v,
                                          float(np.mean(c ** 4)) - 3.0 * v * v,
                                          slope=float(np.einsum("i,i->", g.time_w, y)), temp=temp, low=low,
                                          walk_mean=mean)
        return ctx.cache[key]

    def _c0(self, ctx, tau):
        stat = self._unit_stat(self._unit(ctx, tau))
        return self._delta(ctx) / stat if stat != 0 else 0.0

    def _scale(self, ctx):
        key = (self.name, "c_ref")
        if key not in ctx.cache:
            ctx.cache[key] = abs(self._delta(ctx)) * self._ref_factor(ctx)
        return ctx.cache[key]

    def _profile(self, ctx, log_tau):
        """(best coefficient/c_ref, Σz²) at τ = e^log_tau."""
        ref = self._scale(ctx)
        r0 = self._c0(ctx, math.exp(log_tau)) / ref
        f = lambda r: ctx.sumsq(self.full_increment(np.array([r, log_tau]), ctx))  # noqa: E731
        lo, hi = -4.0 * abs(r0), 4.0 * abs(r0)
        grid = np.sort(np.append(np.linspace(lo, hi, 9), r0))
        vals = [f(x) for x in grid]
        i = int(np.argmin(vals))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = optimize.minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-3 * abs(b - a)})
        return (float(res.x), float(res.fun)) if res.fun <= vals[i] else (float(grid[i]), float(vals[i]))

    def starts(self, ctx):
        if self._scale(ctx) == 0:
            return []
        lo, hi = self._tau_range(ctx)
        scored = [(self._profile(ctx, lt), lt) for lt in np.linspace(math.log(lo), math.log(hi), self.N_TAU)]
        (r, _), lt = min(scored, key=lambda s: s[0][1])
        return [np.array([r, lt])]

    def search(self, theta0, ctx):
        lo, hi = self._tau_range(ctx)
        step = (math.log(hi) - math.log(lo)) / (self.N_TAU - 1)
        a, b = max(math.log(lo), theta0[1] - step), min(math.log(hi), theta0[1] + step)
        res = optimize.minimize_scalar(lambda lt: self._profile(ctx, lt)[1], bounds=(a, b), method="bounded",
                                       options={"xatol": 0.01})
        lt = float(res.x) if res.fun <= ctx.sumsq(self.full_increment(theta0, ctx)) else float(theta0[1])
        r, val = self._profile(ctx, lt)
        return np.array([r, lt]), val

    def increment(self, theta, ctx):
        lo, hi = self._tau_range(ctx)
        tau = float(np.clip(math.exp(theta[1]), lo, hi))
        u, c = self._unit(ctx, tau), float(theta[0]) * self._scale(ctx)
        return th.Increment(u.avar * c * c, None if u.psd is None else u.psd * c * c, u.diff_var * c * c,
                            u.diff_cum4 * c ** 4, slope=u.slope * c, temp=u.temp * c,
                            low=None if u.low is None else u.low * c * c,
                            walk_mean=None if u.walk_mean is None else u.walk_mean * c)

    def params(self, theta, ctx):
        lo, hi = self._tau_range(ctx)
        return {self.coefficient: float(theta[0]) * self._scale(ctx),
                "tau_s": float(np.clip(math.exp(theta[1]), lo, hi))}


class TemperatureLag(_ScaledSeries):
    """c·(T_e − T_0) with the sensing element's temperature T_e lagging the logged one by a
    first-order time constant τ (:func:`budget.imu.effects.thermal_lag`): θ = (c/c₀, ln τ),
    c₀ the coefficient the temperature regression reads. A lag of more than a few seconds
    against a warm-up leaves a drift beside the regression on T — c·(T_e − T) ≈ −c·τ·dT/dt —
    that a ramp or a random walk would otherwise take. The coefficient brackets as
    :class:`TemperatureSensitivity`'s; τ from 2 s to a quarter of the record (shorter is the
    instantaneous sensitivity at any temperature rate a log shows, longer a trend)."""

    name, coefficient = "temperature_lag", "coefficient"
    needs_psd = needs_temp = True

    def _series(self, ctx, tau):
        return thermal_lag(ctx.grid.temp_c, tau, ctx.grid.dt_s)

    def _delta(self, ctx):
        return ctx.meas.temp_coef - ctx.model.temp_coef

    def _unit_stat(self, unit):
        return unit.temp

    def applicable(self, ctx):
        return super().applicable(ctx) and ctx.grid.temp_w is not None and ctx.grid.temp_c is not None


class _SlopeScaled(_ScaledSeries):
    """A series whose coefficient the time-slope regression reads: c_ref = |Δslope|·T
    (Δslope = measured − model time slope, T the record's length)."""

    def _delta(self, ctx):
        return ctx.meas.slope - ctx.model.slope

    def _unit_stat(self, unit):
        return unit.slope

    def _ref_factor(self, ctx):
        return ctx.grid.n_samples * ctx.grid.dt_s

    def applicable(self, ctx):
        return (super().applicable(ctx) and ctx.grid.time_w is not None and ctx.meas.slope is not None
                and ctx.model.slope is not None)


class WarmupTransient(_SlopeScaled):
    """A turn-on transient A·e^(−t/τ), t from the log's first sample (a bias settling after
    power-up, with or without a temperature column): θ = (A/A₀, ln τ), A₀ = |Δslope|·T, the
    amplitude scale the slope regression reads (Δslope = measured − model time slope, T the
    record's length). Over an hour a transient of a few minutes tilts the slope regression and
    puts a pattern in the slowest modes concentrated at the record's start — which a rate random
    walk, a ramp or a slow Gauss–Markov term would otherwise take (a bias step is
    :class:`BiasStep`). τ from 2 s to a quarter of the
    record (longer is a trend)."""

    name, coefficient = "warmup_transient", "amplitude"

    def _series(self, ctx, tau):
        return warmup_response(tau, ctx.grid.n_samples, ctx.grid.dt_s)


class BiasStep(_SlopeScaled):
    """A bias step A·H(t − t₀): the bias jumps once by A at t₀ and stays (a MEMS bias jump, a
    mode change). θ = (A/A₀, ln t₀), A₀ = |Δslope|·T as for :class:`WarmupTransient`. Over a
    record the step tilts the slope regression and gives the slowest modes a mean located at t₀
    — where a rate random walk, a ramp or a transient would only explain its power, its slope or
    its start.

    Starts: the change points of the slow modes under the model's covariance C (the
    generalised-least-squares change-point scan): for each block boundary a, the modes
    v_a = D·S(H_a) of a unit step there and the score (v_aᵀC⁻¹y)²/(v_aᵀC⁻¹v_a) — the
    likelihood-ratio statistic of a step of unknown size at a against the model (Hinkley 1970,
    with the model's correlated noise whitened) — its three best separated maxima; without
    slow modes an even grid of 16 positions. t₀ from 1/64 to 63/64 of the record (nearer an end
    a step is the turn-on bias or a run of outliers); the search refines t₀ within ±2 blocks."""

    name, coefficient = "bias_step", "amplitude"
    N_GRID = 16
    N_PEAKS = 3

    def _series(self, ctx, t0):
        return step_response(t0, ctx.grid.n_samples, ctx.grid.dt_s)

    def _tau_range(self, ctx):
        span = ctx.grid.n_samples * ctx.grid.dt_s
        return span / 64.0, span * 63.0 / 64.0

    def _block_s(self, ctx):
        lay = ctx.grid.walk
        return (lay.block if lay is not None else max(ctx.grid.n_samples // walk.N_BLOCKS, 1)) * ctx.grid.dt_s

    def _change_points(self, ctx) -> list[float]:
        """t₀ (s) of the best separated maxima of the GLS change-point score (class docstring)."""
        lay, cov = ctx.grid.walk, ctx.model.walk_cov
        lo, hi = self._tau_range(ctx)
        if lay is None or cov is None or ctx.meas.walk is None:
            return list(np.linspace(lo, hi, self.N_GRID))
        y = ctx.meas.walk if ctx.model.walk_mean is None else ctx.meas.walk - ctx.model.walk_mean
        nb, m = lay.n_blocks, lay.block
        # block sums of a unit step at the start of block a: m in blocks ≥ a
        steps = m * np.triu(np.ones((nb, nb)))  # [b, a] = m for b ≥ a
        v = lay.basis @ steps                   # (K, nb): modes of each step
        ci = np.linalg.solve(cov, np.column_stack([y, v]))
        num, den = (y @ ci[:, 1:]), np.einsum("ka,ka->a", v, ci[:, 1:])
        score = np.where(den > 0, num * num / np.where(den > 0, den, 1.0), 0.0)
        t = np.arange(nb) * m * ctx.grid.dt_s
        score[(t < lo) | (t > hi)] = -np.inf
        out: list[float] = []
        for a in np.argsort(score)[::-1]:
            if not np.isfinite(score[a]) or len(out) == self.N_PEAKS:
                break
            if all(abs(t[a] - u) > 4 * m * ctx.grid.dt_s for u in out):
                out.append(float(t[a]))
        return out

    def starts(self, ctx):
        if self._scale(ctx) == 0:
            return []
        scored = [(self._profile(ctx, math.log(t0)), math.log(t0)) for t0 in self._change_points(ctx)]
        (r, _), lt = min(scored, key=lambda s: s[0][1])
        return [np.array([r, lt])]

    def search(self, theta0, ctx):
        lo, hi = self._tau_range(ctx)
        t0, half = math.exp(theta0[1]), 2.0 * self._block_s(ctx)
        a, b = math.log(max(lo, t0 - half)), math.log(min(hi, t0 + half))
        base = ctx.sumsq(self.full_increment(theta0, ctx))
        res = optimize.minimize_scalar(lambda lt: self._profile(ctx, lt)[1], bounds=(a, b), method="bounded",
                                       options={"xatol": 1e-3})
        lt = float(res.x) if res.fun <= base else float(theta0[1])
        r, val = self._profile(ctx, lt)
        return np.array([r, lt]), val

    def params(self, theta, ctx):
        lo, hi = self._tau_range(ctx)
        return {"amplitude": float(theta[0]) * self._scale(ctx),
                "time_s": float(np.clip(math.exp(theta[1]), lo, hi))}
