"""Compiled loop of the cut measurements (:func:`budget.sar.irf.measure_cuts`): every definition of
:func:`budget.sar.irf.measure_cut` (peak, 3 dB width, PSLR, ISLR) on one cut after the other.

The NumPy form read each (L, n) stack of 16× upsampled cuts a dozen times (powers, fancy-indexed
windows, a masked copy for the PSLR, the sums of the ISLR) and built as many temporaries; here
each cut's power is formed once into a scratch line and every measurement reads it there. The
comparisons and the arithmetic are those of the NumPy form; only the sums of the ISLR add in
sequence where NumPy pairs them (last bits). Compiled by numba on first use and cached beside this
file (``cache=True``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def parabolic_peak(p_m: float, p_0: float, p_p: float) -> tuple:
    """(offset in samples, amplitude) of the parabola through the amplitudes √p of a power peak
    p_0 and its neighbours p_m, p_p; (0, √p_0) when the three do not curve down."""
    a_m, a_0, a_p = math.sqrt(p_m), math.sqrt(p_0), math.sqrt(p_p)
    den = a_m - 2 * a_0 + a_p
    delta = 0.5 * (a_m - a_p) / den if den < 0 else 0.0
    return delta, a_0 - 0.25 * (a_m - a_p) * delta


@njit(cache=True)
def _crossing(p: np.ndarray, ip: int, direction: int, half: float, limit: int) -> float:
    """Distance (samples) from ``ip`` to the half-power crossing in ``direction``: the first
    k = 1 … limit−1 with p[ip + direction·k] < half, linearly interpolated; ``limit`` when none."""
    n = p.size
    for k in range(1, limit):
        p1 = p[(ip + direction * k) % n]
        if p1 < half:
            p0 = p[(ip + direction * (k - 1)) % n]
            return (k - 1) + (p0 - half) / (p0 - p1)
    return float(limit)


@njit(cache=True)
def _first_min(p: np.ndarray, ip: int, direction: int, k_stop: int) -> int:
    """Main-lobe extent in ``direction``: k − 1 for the first k = 1 … k_stop−1 at which the power
    rises (p[ip + direction·k] > p[ip + direction·(k−1)]), ``k_stop`` when it never does."""
    n = p.size
    prev = p[ip]
    for k in range(1, k_stop):
        cur = p[(ip + direction * k) % n]
        if cur > prev:
            return k - 1
        prev = cur
    return k_stop


@njit(cache=True)
def measure_rows(cuts: np.ndarray, spacing: np.ndarray, origin: np.ndarray, expected: np.ndarray,
                 search_half: int, null: np.ndarray, extent: np.ndarray) -> tuple:
    """(peak position, peak amplitude, 3 dB width, PSLR dB, ISLR dB) of every row of the complex
    ``cuts`` (L, n), per-row ``spacing``, ``origin``, ``expected`` index, ``null`` (cut units)
    and ``extent`` (cut units; inf: the whole line), as :func:`budget.sar.irf.measure_cuts`."""
    n_l, n = cuts.shape
    limit = n // 2
    pos = np.empty(n_l)
    amp = np.empty(n_l)
    width = np.empty(n_l)
    pslr = np.empty(n_l)
    islr = np.empty(n_l)
    p = np.empty(n)
    for r in range(n_l):
        total = 0.0
        for i in range(n):
            v = cuts[r, i]
            p[i] = v.real * v.real + v.imag * v.imag
            total += p[i]
        # peak: the first maximum over the search window, in window order
        base = int(math.floor(expected[r]))
        ip = (base - search_half) % n
        top = p[ip]
        for m in range(-search_half + 1, search_half + 2):
            i = (base + m) % n
            if p[i] > top:
                top = p[i]
                ip = i
        delta, peak_amp = parabolic_peak(p[(ip - 1) % n], p[ip], p[(ip + 1) % n])
        centre = ip + delta
        half = p[ip] / 2.0
        width[r] = (_crossing(p, ip, 1, half, limit) + _crossing(p, ip, -1, half, limit)) * spacing[r]
        null_s = null[r] / spacing[r]
        k_stop = min(max(2, int(math.ceil(3.0 * null_s))), limit)
        k_right, k_left = _first_min(p, ip, 1, k_stop), _first_min(p, ip, -1, k_stop)
        finite_ext = math.isfinite(extent[r])
        ext_s = min(extent[r] / spacing[r], n / 2.0) if finite_ext else n / 2.0
        # PSLR: highest sample outside the measured main lobe (and, for a finite extent, within it)
        cut_far = finite_ext and ext_s < n / 2.0
        fe = int(math.floor(ext_s))
        # the samples at distance d = (i − ip) mod n with k_right < d < n − k_left, and for a
        # finite extent without fe < d < n − fe: one or two runs of d, read without a modulo
        # (the maximum does not depend on the order it is taken in)
        q_max = 0.0
        d_lo, d_hi = k_right + 1, n - k_left - 1
        for run in range(2):
            lo, hi = d_lo, d_hi
            if cut_far:
                if run == 0:
                    hi = min(hi, fe)
                else:
                    lo = max(lo, n - fe)
            elif run == 1:
                break
            i = ip + lo - n if ip + lo >= n else ip + lo
            for _ in range(lo, hi + 1):
                if p[i] > q_max:
                    q_max = p[i]
                i += 1
                if i == n:
                    i = 0
        pslr[r] = 10 * math.log10(q_max / (peak_amp * peak_amp)) if q_max > 0 else -np.inf
        # ISLR: energy around the sub-pixel centre, main lobe ±ideal null, sidelobes to the extent
        fc = int(math.floor(centre))
        lim = int(math.ceil(ext_s + 1))
        reach = min(int(math.ceil(null_s)) + 1, lim)
        # (boundary samples count with the fraction of their interval inside: irf.py, eq. 1)
        e_main = 0.0
        for m in range(-reach, reach + 1):
            f_main = min(max(null_s - abs((fc + m) - centre) + 0.5, 0.0), 1.0)
            if f_main > 0.0:
                e_main += p[(fc + m) % n] * f_main
        if finite_ext:
            e_side = 0.0
            for m in range(-lim, lim + 1):
                dist = abs((fc + m) - centre)
                f_side = min(max(ext_s - dist + 0.5, 0.0), 1.0) - min(max(null_s - dist + 0.5, 0.0), 1.0)
                if f_side > 0.0:
                    e_side += p[(fc + m) % n] * f_side
        else:
            e_side = total - e_main
        islr[r] = 10 * math.log10(e_side / e_main) if e_side > 0 else -np.inf
        pos[r] = origin[r] + centre * spacing[r]
        amp[r] = peak_amp
    return pos, amp, width, pslr, islr
