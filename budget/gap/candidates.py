"""The library of candidate effects: signature, fit and simulation of each vocabulary effect.

Each candidate knows

* its **signature**: the expected increment of every statistic (:mod:`budget.gap.theory`);
* how to **fit** its parameters θ to the measured channel: a closed-form start from the
  residual between measured and model signatures (white level from the τ⁻¹ part of the Allan
  variance residual, quantization from τ⁻², B from the flat part, K from τ, R from the
  least-squares slope, sinusoid from the largest PSD peak ratio, Gauss–Markov from the hump
  over a grid of correlation times, outliers from isolated spikes in the first differences
  (Pauta-like), temperature from the regression on temp_c), then a bounded search that
  minimises the predicted Σz² of the channel (:func:`budget.gap.metric.gap_terms` on the
  predicted model summary);
* how to be **simulated**: as an :class:`~budget.imu.Effect` handed to the IMU generator.

Parameters are SI channel units (see :mod:`budget.imu.noise_model`); θ is the search space
(logarithms of positive parameters).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy import ndimage, optimize, stats

from ..imu.effects import lowpass_gain2, thermal_lag, vibration_acov, vibration_psd
from ..imu.registry import EFFECT_NAMES, QUANTIZERS
from ..imu.flicker import flicker_bank
from . import lowfreq, walk
from . import regression_var as rv
from . import theory as th
from .fitting import Candidate, LinearVariance, amp2_start
from .signatures import overlapping_avar

#: Effects the workflow can name: the effect registry, in its order.
VOCABULARY = EFFECT_NAMES


class WhiteNoise(LinearVariance):
    name, param = "white_noise", "density"

    def shapes(self, ctx):
        g = ctx.grid
        psd = np.full(g.nperseg // 2 + 1, 2.0) if g.has_psd else None
        low = ctx.low_from_psd(np.full(ctx.low_freq().size, 2.0))
        return th.Increment(1.0 / g.tau_s, psd, 2.0 / g.dt_s, low=low)


class Quantization(LinearVariance):
    name, param = "quantization", "Q"

    def applicable(self, ctx):
        return super().applicable(ctx) and not any(f.name in QUANTIZERS for f in ctx.existing)

    def shapes(self, ctx):
        g = ctx.grid
        psd = th.psd_quantization(ctx.freq(), g.dt_s) if g.has_psd else None
        var = 6.0 / g.dt_s ** 2
        low = ctx.low_from_psd(th.psd_quantization(ctx.low_freq(), g.dt_s))
        return th.Increment(3.0 / g.tau_s ** 2, psd, var, -0.6 * var ** 2, low=low)


class RateQuantization(LinearVariance):
    """The output rate rounded to a lattice of step δ: a white error of variance δ²/12 per sample
    (density² δ²·dt/12) when the noise spans several steps, with the uniform error's negative
    excess kurtosis (−1.2, −0.6 in its first differences). Proposed at the measured lattice by
    the direct detector and judged by simulation, like ``quantization``."""

    name, param = "rate_quantization", "step"

    def applicable(self, ctx):
        # a rounded rate puts the values on a lattice; on continuous data this white shape with
        # light tails would only compete with white_noise for a misfit it does not explain
        return (super().applicable(ctx) and ctx.meas.lattice is not None
                and not any(f.name in QUANTIZERS for f in ctx.existing))

    def shapes(self, ctx):
        g = ctx.grid
        v = g.dt_s / 12.0  # density² of step 1
        psd = np.full(g.nperseg // 2 + 1, 2.0 * v) if g.has_psd else None
        low = ctx.low_from_psd(np.full(ctx.low_freq().size, 2.0 * v))
        dvar = 1.0 / 6.0
        return th.Increment(v / g.tau_s, psd, dvar, -0.6 * dvar ** 2, low=low)


class BiasInstability(LinearVariance):
    name, param = "bias_instability", "B"

    def shapes(self, ctx):
        g = ctx.grid
        avar = th.avar_flicker(g.m, g.dt_s, g.n_samples)
        psd = th.psd_flicker(g.nperseg, g.dt_s, g.n_samples, g.m) if g.has_psd else None
        tau, var = flicker_bank(1.0, g.dt_s, g.dt_s * (g.n_samples - 1))
        dvar = float(np.sum(2.0 * var * -np.expm1(-g.dt_s / tau)))
        low = ctx.low_from_psd(sum(v * th.psd_gm(ctx.low_freq(), g.dt_s, t) for t, v in zip(tau, var)))
        # the slope / temperature-coefficient variance a raised bias instability implies
        sv = _flicker_slope_var(g.n_samples, g.rate_hz) if g.time_w is not None else 0.0
        tv = rv.flicker_weight_variance(g.temp_w, g.dt_s, g.n_samples) if g.temp_w is not None else 0.0
        return th.Increment(avar, psd, dvar, low=low, slope_var=sv, temp_var=tv)


class RateRandomWalk(LinearVariance):
    name, param = "rate_random_walk", "K"

    def shapes(self, ctx):
        g = ctx.grid
        psd = th.psd_rrw(ctx.freq(), g.dt_s) if g.has_psd else None
        sv = th.random_walk_weight(g.time_w, g.dt_s) if g.time_w is not None else 0.0
        tv = th.random_walk_weight(g.temp_w, g.dt_s) if g.temp_w is not None else 0.0
        low = (lowfreq.random_walk_low(g.n_samples, g.dt_s, g.low_k_max)
               if g.has_low and ctx.meas.low is not None else None)
        return th.Increment(th.avar_rrw(g.m, g.dt_s), psd, g.dt_s, slope_var=sv, temp_var=tv, low=low)


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


class TemperatureLag(Candidate):
    """c·(T_e − T_0) with the sensing element's temperature T_e lagging the logged one by a
    first-order time constant τ (:func:`budget.imu.effects.thermal_lag`): θ = (c/c₀, ln τ),
    c₀ the coefficient the temperature regression reads. A lag of more than a few seconds
    against a warm-up leaves a drift beside the regression on T — c·(T_e − T) ≈ −c·τ·dT/dt —
    that a ramp or a random walk would otherwise take. Every statistic follows from the
    deterministic series T_e − T_0 itself (its Allan variance, Welch PSD, differences,
    regression weights and slowest modes), computed once per τ. The search profiles c at each
    τ (bounded, the coefficient brackets as :class:`TemperatureSensitivity`'s) and runs a bounded
    search over ln τ from the best of a grid; τ from 2 s to a quarter of the record (shorter
    is the instantaneous sensitivity at any temperature rate a log shows, longer a trend)."""

    name, n_params = "temperature_lag", 2
    needs_psd = needs_temp = True
    #: τ grid of the starts
    N_TAU = 10

    def _tau_range(self, ctx):
        g = ctx.grid
        return max(2.0, 4.0 * g.dt_s), 0.25 * g.n_samples * g.dt_s

    def _unit(self, ctx, tau):
        key = ("unit", self.name, round(math.log(tau), 9))
        if key not in ctx.cache:
            g = ctx.grid
            T = thermal_lag(g.temp_c, tau, g.dt_s)
            d = np.diff(T)
            c = d - d.mean()
            v = float(np.einsum("i,i->", c, c)) / c.size
            low = lowfreq.coefficients_sq(T, g.low_k_max) if g.has_low else None
            mean = walk.modes(T, g.walk) if g.walk is not None and ctx.model.walk_cov is not None else None
            ctx.cache[key] = th.Increment(overlapping_avar(T, g.m), th.psd_of_series(T, g.dt_s, g.nperseg), v,
                                          float(np.mean(c ** 4)) - 3.0 * v * v,
                                          slope=float(np.einsum("i,i->", g.time_w, T)),
                                          temp=float(np.einsum("i,i->", g.temp_w, T)), low=low,
                                          walk_mean=mean)
        return ctx.cache[key]

    def _c0(self, ctx, tau):
        u = self._unit(ctx, tau)
        dc = ctx.meas.temp_coef - ctx.model.temp_coef
        return dc / u.temp if u.temp != 0 else 0.0

    def applicable(self, ctx):
        return super().applicable(ctx) and ctx.grid.temp_w is not None and ctx.grid.temp_c is not None

    def _scale(self, ctx):
        if "lag_c_ref" not in ctx.cache:
            ctx.cache["lag_c_ref"] = abs(ctx.meas.temp_coef - ctx.model.temp_coef)
        return ctx.cache["lag_c_ref"]

    def _profile(self, ctx, log_tau):
        """(best c/c₀, Σz²) at τ = e^log_tau."""
        ref = self._scale(ctx)
        r0 = self._c0(ctx, math.exp(log_tau)) / ref
        f = lambda r: ctx.sumsq(self.full_increment(np.array([r, log_tau]), ctx))
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
        (r, val), lt = min(scored, key=lambda s: s[0][1])
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
        return th.Increment(u.avar * c * c, u.psd * c * c, u.diff_var * c * c, u.diff_cum4 * c ** 4,
                            slope=u.slope * c, temp=u.temp * c, low=None if u.low is None else u.low * c * c,
                            walk_mean=None if u.walk_mean is None else u.walk_mean * c)

    def params(self, theta, ctx):
        lo, hi = self._tau_range(ctx)
        return {"coefficient": float(theta[0]) * self._scale(ctx),
                "tau_s": float(np.clip(math.exp(theta[1]), lo, hi))}


class Sinusoid(Candidate):
    name, n_params = "sinusoid", 2

    def _f(self, theta, ctx):
        # slower than half a cycle over the longest τ it is a drift, not a line
        g = ctx.grid
        return float(np.clip(theta[0], 0.5 / g.tau_s[-1], 0.499 * g.rate_hz))

    def starts(self, ctx):
        g = ctx.grid
        if ctx.meas.psd is None:
            return self._adev_starts(ctx)
        lo, hi = g.band_start[0], g.bin_stop
        ratio = ctx.meas.psd[lo:hi] / ctx.model.psd[lo:hi]
        j = int(np.argmax(ratio)) + lo
        df = g.rate_hz / g.nperseg
        # the line is measured against the *measured* background around it, not the model: on
        # a real log the model's broadband level is off, and a fit of Σz² lets the tone soak up
        # that misfit (its Allan variance near τ = 1/(2f) stands in for missing white noise),
        # inflating the amplitude and pulling the frequency off the line
        p = ctx.meas.psd
        j = max(min(j - 2 + int(np.argmax(p[max(j - 2, 0):j + 3])), p.size - 4), 3)
        side = np.concatenate([p[max(j - 40, 1):max(j - 6, 1)], p[j + 7:j + 41]])
        background = float(np.median(side)) if side.size else float(ctx.model.psd[j])
        k = np.arange(j - 3, j + 4)
        excess = np.clip(p[k] - background, 0.0, None)
        a2 = 2.0 * float(np.sum(excess)) * df
        if a2 <= 0:
            return []
        f0 = float(np.sum(k * excess) / np.sum(excess)) * df
        ctx.cache["sin_df"] = df
        ctx.cache["sin_line"] = True
        return [np.array([f0, 0.5 * math.log(a2)])]

    def _adev_starts(self, ctx):
        g = ctx.grid
        freqs = np.geomspace(0.5 / g.tau_s[-1], 0.45 * g.rate_hz, 60)
        scored = []
        for f in freqs:
            a2 = amp2_start(ctx, th.avar_sinusoid(g.m, g.dt_s, f))
            if a2 > 0:
                t0 = np.array([f, 0.5 * math.log(a2)])
                scored.append((ctx.sumsq(self.increment(t0, ctx)), t0))
        scored.sort(key=lambda s: s[0])
        return [s[1] for s in scored[:2]]

    def search(self, theta0, ctx):
        if ctx.cache.get("sin_line"):  # measured from the line itself (see starts)
            return theta0, ctx.sumsq(self.increment(theta0, ctx))
        # frequency in units of the local resolution so Nelder–Mead steps are balanced
        scale = ctx.cache.get("sin_df") or theta0[0] * 0.05
        f = lambda u: ctx.sumsq(self.increment(np.array([theta0[0] + u[0] * scale, u[1]]), ctx))
        res = optimize.minimize(f, np.array([0.0, theta0[1]]), method="Nelder-Mead",
                                options={"maxiter": 200, "xatol": 1e-3, "fatol": 1e-3,
                                         "initial_simplex": [[0.0, theta0[1]], [0.3, theta0[1]],
                                                             [0.0, theta0[1] + 0.3]]})
        return np.array([theta0[0] + res.x[0] * scale, res.x[1]]), float(res.fun)

    def increment(self, theta, ctx):
        g, f, a2 = ctx.grid, self._f(theta, ctx), math.exp(2.0 * theta[1])
        psd = th.psd_sinusoid(ctx.freq(), g.nperseg, g.dt_s, f) * a2 if g.has_psd else None
        var = 2.0 * a2 * math.sin(math.pi * f * g.dt_s) ** 2
        low = None
        if g.has_low and ctx.meas.low is not None:
            key = ("sin_low", f)
            if key not in ctx.cache:  # exact (the record's leakage falls only as 1/Δk²)
                ctx.cache[key] = lowfreq.sinusoid_low(g.n_samples, g.dt_s, g.low_k_max, f)
            low = ctx.cache[key] * a2
        return th.Increment(th.avar_sinusoid(g.m, g.dt_s, f) * a2, psd, var, -1.5 * var * var, low=low)

    def params(self, theta, ctx):
        return {"frequency_hz": self._f(theta, ctx), "amplitude": math.exp(theta[1])}


def _time_weights(n_samples: int, rate_hz: float) -> np.ndarray:
    t = np.arange(n_samples) / rate_hz
    tc = t - t.mean()
    return tc / np.dot(tc, tc)  # the slope statistic's weights (SignatureGrid.time_w)


@lru_cache(maxsize=4)
def _flicker_slope_var(n_samples: int, rate_hz: float) -> float:
    return rv.flicker_weight_variance(_time_weights(n_samples, rate_hz), 1.0 / rate_hz, n_samples)


@lru_cache(maxsize=4)
def _gm_slope_table(n_samples: int, rate_hz: float) -> rv.GaussMarkovTable:
    dt = 1.0 / rate_hz
    return rv.GaussMarkovTable(_time_weights(n_samples, rate_hz), dt, 2.0 * dt, 0.5 * n_samples * dt)


class GaussMarkov(Candidate):
    name, n_params = "gauss_markov", 2

    def _tau(self, theta, ctx):
        # τc below 2·dt is white noise at this rate; beyond half the record a random walk
        g = ctx.grid
        return float(np.clip(math.exp(theta[0]), 2.0 * g.dt_s, 0.5 * g.n_samples * g.dt_s))

    def starts(self, ctx):
        g = ctx.grid
        scored = []
        for tau in np.geomspace(2.5 * g.dt_s, 0.5 * g.n_samples * g.dt_s, 28):
            a2 = amp2_start(ctx, th.avar_gm(g.m, g.dt_s, tau)[0])
            if a2 > 0:
                t0 = np.array([math.log(tau), 0.5 * math.log(a2)])
                scored.append((ctx.sumsq(self.increment(t0, ctx)), t0))
        scored.sort(key=lambda s: s[0])
        return [s[1] for s in scored[:2]]

    def increment(self, theta, ctx):
        g, tau, s2 = ctx.grid, self._tau(theta, ctx), math.exp(2.0 * theta[1])
        psd = th.psd_gm(ctx.freq(), g.dt_s, tau) * s2 if g.has_psd else None
        dvar = 2.0 * s2 * -math.expm1(-g.dt_s / tau)
        low = ctx.low_from_psd(th.psd_gm(ctx.low_freq(), g.dt_s, tau) * s2)
        sv = s2 * _gm_slope_table(g.n_samples, g.rate_hz)(tau) if g.time_w is not None else 0.0
        tv = 0.0
        if g.temp_w is not None:
            if "gm_temp" not in ctx.cache:
                ctx.cache["gm_temp"] = rv.GaussMarkovTable(g.temp_w, g.dt_s, 2.0 * g.dt_s,
                                                           0.5 * g.n_samples * g.dt_s)
            tv = s2 * ctx.cache["gm_temp"](tau)
        return th.Increment(th.avar_gm(g.m, g.dt_s, tau)[0] * s2, psd, dvar, low=low,
                            slope_var=sv, temp_var=tv)

    def params(self, theta, ctx):
        return {"tau_s": self._tau(theta, ctx), "sigma": math.exp(theta[1])}


#: Spikes on more than 1 sample in 1000 are not "rare": heavy-tailed noise describes that.
MAX_OUTLIER_RATE = 1e-3


class Outliers(Candidate):
    name, n_params = "outliers", 2
    needs_psd = True

    def _pm(self, theta, ctx):
        # spikes below 2σ of the differences are white noise; fewer than two per record are
        # not a rate (the sample kurtosis of a record with 0 or 1 spike is not its expectation),
        # and no spike can be much larger than the largest difference seen in the log
        n, sd = ctx.grid.n_samples, math.sqrt(ctx.model.diff_var)
        p = float(np.clip(math.exp(theta[0]), 2.0 / n, MAX_OUTLIER_RATE))
        top = max(1.2 * (ctx.meas.diff_max or 0.0), 2.0 * sd)
        return p, float(np.clip(math.exp(theta[1]), 2.0 * sd, top))

    def starts(self, ctx):
        m, n = ctx.meas, ctx.grid.n_samples
        sd = math.sqrt(ctx.model.diff_var)
        mag = m.spike_magnitude if m.spike_count else 6.0 * sd
        out = [np.array([math.log(max(m.spike_count, 2) / n), math.log(mag)])]
        dk = m.kurtosis - ctx.model.kurtosis
        if dk > 0:  # kurtosis excess with spikes of 8σ: Δκ·v² ≈ 2pM⁴
            mag8 = 8.0 * sd
            p = dk * ctx.model.diff_var ** 2 / (2.0 * mag8 ** 4)
            out.append(np.array([math.log(max(p, 2.0 / n)), math.log(mag8)]))
        return out

    def increment(self, theta, ctx):
        g = ctx.grid
        p, mag = self._pm(theta, ctx)
        v = p * mag * mag
        psd = np.full(g.nperseg // 2 + 1, 2.0 * v * g.dt_s)
        low = ctx.low_from_psd(np.full(ctx.low_freq().size, 2.0 * v * g.dt_s))
        return th.Increment(v * g.dt_s / g.tau_s, psd, 2.0 * v, 2.0 * p * mag ** 4 - 6.0 * p * p * mag ** 4,
                            outliers=(p, mag), low=low)

    def params(self, theta, ctx):
        p, mag = self._pm(theta, ctx)
        return {"rate": p, "magnitude": mag}


class Lowpass(Candidate):
    """The sensor's output filter: the measured PSD falls below the model's towards Nyquist
    and the Allan deviation at the shortest τ lies below the white-noise line. A start from a
    grid of cut-offs (0.03–1 × the rate), then the bounded 1-D search on ln f_c."""

    name = "lowpass"
    needs_psd = True

    def applicable(self, ctx):
        return super().applicable(ctx) and not any(f.name == "lowpass" for f in ctx.existing)

    def _fc(self, theta, ctx):
        # below 2 % of the rate it would remove the white noise itself; above 2× it does nothing
        return float(np.clip(math.exp(theta[0]), 0.02 * ctx.grid.rate_hz, 2.0 * ctx.grid.rate_hz))

    def starts(self, ctx):
        scored = []
        for fc in np.geomspace(0.03, 1.0, 14) * ctx.grid.rate_hz:
            t0 = np.array([math.log(fc)])
            scored.append((ctx.sumsq(self.increment(t0, ctx)), t0))
        return [min(scored, key=lambda s: s[0])[1]]

    def bracket(self, t0):
        return t0 - 0.6, t0 + 0.6

    def increment(self, theta, ctx):
        g, f = ctx.grid, ctx.freq()
        dpsd = ctx.model.psd * (lowpass_gain2(f, self._fc(theta, ctx), g.dt_s) - 1.0)
        low = None
        if g.has_low and ctx.model.low is not None:
            low = ctx.model.low * (lowpass_gain2(ctx.low_freq(), self._fc(theta, ctx), g.dt_s) - 1.0)
        return th.Increment(th.avar_from_psd(dpsd, f, g.m, g.dt_s), dpsd,
                            th.diff_var_from_psd(dpsd, f, g.dt_s), low=low)

    def params(self, theta, ctx):
        return {"cutoff_hz": self._fc(theta, ctx)}


class Vibration(Candidate):
    """Band-limited random vibration: a PSD peak with a width (a wandering line, a structural
    resonance). Fitted on the peak itself, like the sinusoid: centre, width and power of the
    resonator's PSD on top of the *measured* background around the peak (least squares in log
    PSD over a window of the Welch bins), so the fit cannot soak up a broadband misfit of the
    model. A peak no wider than the Welch resolution is a line: left to ``sinusoid``."""

    name, n_params = "vibration", 3
    needs_psd = True

    def _p(self, theta, ctx):
        g = ctx.grid
        df = g.rate_hz / g.nperseg
        f0 = float(np.clip(theta[0], 2.0 * df, 0.49 * g.rate_hz))
        # the simplex may wander far in log space: clip before exp (no overflow)
        w = float(np.clip(math.exp(min(theta[1], 700.0)), df, f0))
        return f0, w, math.exp(float(np.clip(theta[2], -700.0, 300.0)))

    def starts(self, ctx):
        g = ctx.grid
        lo, hi = g.band_start[0], g.bin_stop
        # a running median over ≈ 0.5 % of the bins removes lines (a few bins wide) and keeps
        # peaks with a width: the vibration is sought, and fitted, on that
        size = max(9, (g.nperseg // 2) // 200) | 1
        p = ndimage.median_filter(ctx.meas.psd, size=size, mode="nearest")
        ctx.cache["vib_psd"] = p
        ratio = p[lo:hi] / ctx.model.psd[lo:hi]
        j = int(np.argmax(ratio)) + lo
        df = g.rate_hz / g.nperseg
        # the half-maximum width on a smoothed excess: at fine resolution (10⁶ samples) single
        # Welch bins scatter enough to break the run of bins above half the peak
        span = int(min(max(60, p.size // 20), j - 1))
        near = p[j - span:j + span + 1]
        background = float(np.median(near))
        excess = np.clip(near - background, 0.0, None)
        if excess.max() <= 0:
            return []
        smooth = np.convolve(excess, np.ones(9) / 9.0, mode="same")
        k = span
        above = smooth > 0.5 * smooth[k]
        k0 = k1 = k
        while k0 > 0 and above[k0 - 1]:
            k0 -= 1
        while k1 < above.size - 1 and above[k1 + 1]:
            k1 += 1
        width_bins = k1 - k0 + 1
        # window: many widths either side, so the peak's own skirts do not pass for background
        half = int(min(max(60, 12 * width_bins), 0.45 * p.size))
        a, b = max(j - half, 1), min(j + half + 1, p.size - 1)
        power = float(np.sum(excess)) * df
        ctx.cache["vib"] = (a, b, df)
        return [np.array([j * df, math.log(max(width_bins, 1) * df),
                          0.5 * math.log(max(power, 1e-300)), math.log(background)])]

    def search(self, theta0, ctx):
        # least squares in log PSD over the window: centre (in bins), ln width, ln σ and the
        # local background level (free: a broadband misfit of the model stays out of σ)
        a, b, df = ctx.cache["vib"]
        f = ctx.freq()[a:b]
        logp = np.log(ctx.cache["vib_psd"][a:b])
        g = ctx.grid

        def misfit(u):
            f0, w, sigma = self._p(np.array([theta0[0] + u[0] * df, u[1], u[2]]), ctx)
            model = math.exp(float(np.clip(u[3], -700.0, 700.0))) + sigma ** 2 * vibration_psd(f, f0, w, g.dt_s)
            return float(np.sum((logp - np.log(model)) ** 2))

        x0 = np.array([0.0, theta0[1], theta0[2], theta0[3]])
        simplex = [x0, x0 + [1.0, 0, 0, 0], x0 + [0, 0.4, 0, 0], x0 + [0, 0, 0.3, 0],
                   x0 + [0, 0, 0, 0.3]]
        res = optimize.minimize(misfit, x0, method="Nelder-Mead",
                                options={"maxiter": 800, "xatol": 1e-4, "fatol": 1e-5,
                                         "initial_simplex": simplex})
        theta = np.array([theta0[0] + res.x[0] * df, res.x[1], res.x[2]])
        return theta, ctx.sumsq(self.increment(theta, ctx))

    def fit(self, ctx):
        out = super().fit(ctx)
        if out is not None and out.effect.params["width_hz"] < 1.5 * ctx.grid.rate_hz / ctx.grid.nperseg:
            return None  # unresolved: a line, which the simpler sinusoid describes
        return out

    def increment(self, theta, ctx):
        g = ctx.grid
        f0, w, sigma = self._p(theta, ctx)
        s2 = sigma * sigma
        psd = vibration_psd(ctx.freq(), f0, w, g.dt_s) * s2
        rho1 = float(vibration_acov(np.array([1.0]), f0, w, g.dt_s)[0])
        low = ctx.low_from_psd(vibration_psd(ctx.low_freq(), f0, w, g.dt_s) * s2)
        return th.Increment(th.avar_vibration(g.m, g.dt_s, f0, w) * s2, psd, 2.0 * s2 * (1.0 - rho1),
                            low=low)

    def params(self, theta, ctx):
        f0, w, sigma = self._p(theta, ctx)
        return {"center_hz": f0, "width_hz": w, "sigma": sigma}


class HeavyTailed(Candidate):
    """Student-t white noise: what is left when the differences have many large values of all
    sizes (a power-law tail: the count beyond twice the tail limit is a fixed fraction of the
    count beyond it), not a few spikes of one size. θ = (ln N, ln(ν − 2)); starts on a grid of
    ν with N from the excess of the difference variance."""

    name, n_params = "heavy_tailed", 2
    needs_psd = True

    def applicable(self, ctx):
        # only where the differences are heavier-tailed than the model's (3σ of the kurtosis)
        if not super().applicable(ctx):
            return False
        sd = math.sqrt(max(27.0 / ctx.grid.n_samples, ctx.model.kurt_var))
        return ctx.meas.kurtosis - ctx.model.kurtosis > 3.0 * sd

    def _p(self, theta):
        return math.exp(theta[0]), 2.0 + float(np.clip(math.exp(theta[1]), 0.05, 998.0))

    def starts(self, ctx):
        m, mod, g = ctx.meas, ctx.model, ctx.grid
        extra = max(m.diff_var - mod.diff_var, 0.05 * mod.diff_var)  # 2N²/dt
        dens = math.sqrt(extra * g.dt_s / 2.0)
        scored = []
        for nu in (2.5, 3.0, 4.0, 6.0, 10.0):
            t0 = np.array([math.log(dens), math.log(nu - 2.0)])
            scored.append((ctx.sumsq(self.increment(t0, ctx)), t0))
        scored.sort(key=lambda v: v[0])
        return [scored[0][1]]

    def increment(self, theta, ctx):
        g, mod = ctx.grid, ctx.model
        dens, nu = self._p(theta)
        var = dens * dens / g.dt_s                       # per-sample variance N²/dt
        scale = math.sqrt(var * (nu - 2.0) / nu)
        cum4 = 2.0 * th.student_t_cum4(nu, g.n_samples) * scale ** 4
        # the robust scale of the differences grows with the t core (MAD of t in σ units)
        c_nu = float(stats.t.ppf(0.75, nu) / stats.norm.ppf(0.75))
        sig_r = math.sqrt(mod.sigma_r ** 2 + 2.0 * (c_nu * scale) ** 2)
        n = g.n_samples - 1
        gauss_var = mod.diff_var
        p1 = th.student_t_tails(nu, scale, gauss_var, g.tail_k * sig_r)
        p2 = th.student_t_tails(nu, scale, gauss_var, 2.0 * g.tail_k * sig_r)
        tails = (max(p1 * n, 0.0), max(p2 * n, 0.0))
        psd = np.full(g.nperseg // 2 + 1, 2.0 * dens * dens)
        low = ctx.low_from_psd(np.full(ctx.low_freq().size, 2.0 * dens * dens))
        return th.Increment(dens * dens / g.tau_s, psd, 2.0 * var, cum4, tails=tails, low=low)

    def params(self, theta, ctx):
        dens, nu = self._p(theta)
        return {"density": dens, "dof": nu}


LIBRARY: dict[str, Candidate] = {c.name: c for c in (
    WhiteNoise(), Quantization(), RateQuantization(), BiasInstability(), RateRandomWalk(), RateRamp(), Sinusoid(),
    GaussMarkov(), TemperatureSensitivity(), TemperatureLag(), Outliers(), Lowpass(), Vibration(), HeavyTailed())}
