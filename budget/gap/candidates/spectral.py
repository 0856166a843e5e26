"""Spectral candidates: a sinusoid, a first-order Gauss–Markov term, the sensor's output
low-pass filter and band-limited vibration — each shows as a shape in the PSD and the Allan
variance, fitted from a start on the largest PSD/Allan residual, then a bounded search.

Parameters are SI channel units (see :mod:`budget.imu.noise_model`); θ is the search space
(logarithms of positive parameters).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage, optimize

from ...imu.effects import lowpass_gain2, vibration_acov, vibration_psd
from .. import lowfreq
from .. import regression_var as rv
from .. import theory as th
from ..fitting import Candidate, amp2_start


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
        sv = s2 * rv.gauss_markov_slope_table(g.n_samples, g.rate_hz)(tau) if g.time_w is not None else 0.0
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
