"""Compiled loops of the transient search (:func:`budget.noise.transients.transient_stats`): the
7-sample running median each sample is winsorized about, and the largest |y| of the window statistic at one window length, in one pass over the cumulative sum and
without the n-sample temporaries the NumPy form builds (four per window length). The arithmetic is
that of :func:`budget.noise.transients._hat`. Compiled by numba on first use and cached beside
this file (``cache=True``).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def hat_max(cs, L):
    """max over k = L … n−2L of |mean(x[k:k+L]) − ½[mean(x[k−L:k]) + mean(x[k+L:k+2L])]|, from the
    cumulative sum ``cs`` (cs[0] = 0, n + 1 values)."""
    n = cs.size - 1
    best = 0.0
    for k in range(L, n - 2 * L + 1):
        c0 = cs[k]
        c1 = cs[k + L]
        y = (c1 - c0) - 0.5 * ((c0 - cs[k - L]) + (cs[k + 2 * L] - c1))
        if y < 0:
            y = -y
        if y > best:
            best = y
    return best / L


@njit(cache=True)
def median7(x):
    """The median of x[k−3] … x[k+3] at every k; within 3 samples of an end, the median of the
    first (last) 7 samples (as :func:`budget.noise.spikes._median_residual` takes it). The seven
    are kept sorted as the window slides: one value out, one in."""
    n = x.size
    out = np.empty(n)
    w = np.empty(7)
    for i in range(7):  # the first window, sorted by insertion
        v = x[i]
        j = i - 1
        while j >= 0 and w[j] > v:
            w[j + 1] = w[j]
            j -= 1
        w[j + 1] = v
    for k in range(4):
        out[k] = w[3]
    for k in range(4, n - 3):  # window x[k−3] … x[k+3]: x[k−4] leaves, x[k+3] enters
        old, new = x[k - 4], x[k + 3]
        i = 0
        while w[i] != old:
            i += 1
        if new >= old:  # shift the values between left, insert above
            while i < 6 and w[i + 1] < new:
                w[i] = w[i + 1]
                i += 1
        else:
            while i > 0 and w[i - 1] > new:
                w[i] = w[i - 1]
                i -= 1
        w[i] = new
        out[k] = w[3]
    for k in range(max(n - 3, 4), n):
        out[k] = out[n - 4]
    return out
