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

import numpy as np
from scipy import optimize

from ..imu.effects import lowpass_gain2
from ..imu.flicker import flicker_bank
from . import theory as th
from .fitting import Candidate, LinearVariance, amp2_start
from .signatures import overlapping_avar

#: Effects the workflow can name, in the shared vocabulary's order.
VOCABULARY = ("white_noise", "quantization", "bias_instability", "rate_random_walk", "rate_ramp",
              "sinusoid", "gauss_markov", "temperature_sensitivity", "outliers", "lowpass")


class WhiteNoise(LinearVariance):
    name, param = "white_noise", "density"

    def shapes(self, ctx):
        g = ctx.grid
        psd = np.full(g.nperseg // 2 + 1, 2.0) if g.has_psd else None
        return th.Increment(1.0 / g.tau_s, psd, 2.0 / g.dt_s)


class Quantization(LinearVariance):
    name, param = "quantization", "Q"

    def applicable(self, ctx):
        return super().applicable(ctx) and not any(f.name == "quantization" for f in ctx.existing)

    def shapes(self, ctx):
        g = ctx.grid
        psd = th.psd_quantization(ctx.freq(), g.dt_s) if g.has_psd else None
        var = 6.0 / g.dt_s ** 2
        return th.Increment(3.0 / g.tau_s ** 2, psd, var, -0.6 * var ** 2)


class BiasInstability(LinearVariance):
    name, param = "bias_instability", "B"

    def shapes(self, ctx):
        g = ctx.grid
        avar = th.avar_flicker(g.m, g.dt_s, g.n_samples)
        psd = th.psd_flicker(g.nperseg, g.dt_s, g.n_samples, g.m) if g.has_psd else None
        tau, var = flicker_bank(1.0, g.dt_s, g.dt_s * (g.n_samples - 1))
        dvar = float(np.sum(2.0 * var * -np.expm1(-g.dt_s / tau)))
        return th.Increment(avar, psd, dvar)


class RateRandomWalk(LinearVariance):
    name, param = "rate_random_walk", "K"

    def shapes(self, ctx):
        g = ctx.grid
        psd = th.psd_rrw(ctx.freq(), g.dt_s) if g.has_psd else None
        sv = th.random_walk_weight(g.time_w, g.dt_s) if g.time_w is not None else 0.0
        tv = th.random_walk_weight(g.temp_w, g.dt_s) if g.temp_w is not None else 0.0
        return th.Increment(th.avar_rrw(g.m, g.dt_s), psd, g.dt_s, slope_var=sv, temp_var=tv)


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
            ctx.cache[key] = th.Increment(avar, th.psd_of_series(T, g.dt_s, g.nperseg), v, cum4,
                                          slope=float(np.einsum("i,i->", g.time_w, T)), temp=1.0)
        return ctx.cache[key]

    def starts(self, ctx):
        c0 = ctx.meas.temp_coef - ctx.model.temp_coef
        return [np.array([c0])] if c0 != 0 else []

    def bracket(self, t0):
        return -4.0 * abs(t0), 4.0 * abs(t0)

    def increment(self, theta, ctx):
        u, c = self._unit(ctx), float(theta[0])
        return th.Increment(u.avar * c * c, u.psd * c * c, u.diff_var * c * c, u.diff_cum4 * c ** 4,
                            slope=u.slope * c, temp=c)

    def params(self, theta, ctx):
        return {"coefficient": float(theta[0])}


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
        r = np.log(ctx.meas.psd[j - 1:j + 2] / ctx.model.psd[j - 1:j + 2])
        den = r[0] - 2 * r[1] + r[2]
        shift = float(np.clip(0.5 * (r[0] - r[2]) / den, -0.5, 0.5)) if den < 0 else 0.0
        excess = np.clip(ctx.meas.psd[j - 3:j + 4] - ctx.model.psd[j - 3:j + 4], 0.0, None)
        a2 = 2.0 * float(np.sum(excess)) * df
        if a2 <= 0:
            return []
        ctx.cache["sin_df"] = df
        return [np.array([(j + shift) * df, 0.5 * math.log(a2)])]

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
        return th.Increment(th.avar_sinusoid(g.m, g.dt_s, f) * a2, psd, var, -1.5 * var * var)

    def params(self, theta, ctx):
        return {"frequency_hz": self._f(theta, ctx), "amplitude": math.exp(theta[1])}


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
        return th.Increment(th.avar_gm(g.m, g.dt_s, tau)[0] * s2, psd, dvar)

    def params(self, theta, ctx):
        return {"tau_s": self._tau(theta, ctx), "sigma": math.exp(theta[1])}


class Outliers(Candidate):
    name, n_params = "outliers", 2
    needs_psd = True

    def _pm(self, theta, ctx):
        # spikes below 2σ of the differences are white noise; fewer than two per record are
        # not a rate (the sample kurtosis of a record with 0 or 1 spike is not its expectation),
        # and no spike can be much larger than the largest difference seen in the log
        n, sd = ctx.grid.n_samples, math.sqrt(ctx.model.diff_var)
        p = float(np.clip(math.exp(theta[0]), 2.0 / n, 0.2))
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
        return th.Increment(v * g.dt_s / g.tau_s, psd, 2.0 * v, 2.0 * p * mag ** 4 - 6.0 * p * p * mag ** 4,
                            outliers=(p, mag))

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
        return th.Increment(th.avar_from_psd(dpsd, f, g.m, g.dt_s), dpsd,
                            th.diff_var_from_psd(dpsd, f, g.dt_s))

    def params(self, theta, ctx):
        return {"cutoff_hz": self._fc(theta, ctx)}


LIBRARY: dict[str, Candidate] = {c.name: c for c in (
    WhiteNoise(), Quantization(), BiasInstability(), RateRandomWalk(), RateRamp(), Sinusoid(),
    GaussMarkov(), TemperatureSensitivity(), Outliers(), Lowpass())}
