"""Allan-floor candidates: white noise, quantization (angle/velocity and rate), bias instability
(flicker) and rate random walk — each linear in one variance parameter, fitted by the least
squares of :class:`~budget.gap.fitting.LinearVariance` on its unit signature.

Parameters are SI channel units (see :mod:`budget.imu.noise_model`).
"""

from __future__ import annotations

import numpy as np

from ...imu.flicker import flicker_bank
from ...imu.registry import QUANTIZERS
from .. import lowfreq
from .. import regression_var as rv
from .. import theory as th
from ..fitting import LinearVariance


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
        sv = rv.flicker_slope_variance(g.n_samples, g.rate_hz) if g.time_w is not None else 0.0
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
