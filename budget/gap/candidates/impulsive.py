"""Impulsive and heavy-tailed candidates: rare outliers (isolated spikes in the first
differences, Pauta-like) and Student-t white noise (a power-law tail of all sizes).

Parameters are SI channel units (see :mod:`budget.imu.noise_model`); θ is the search space.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

from .. import theory as th
from ..fitting import Candidate

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
