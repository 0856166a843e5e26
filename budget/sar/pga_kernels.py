"""Compiled loops for PGA's per-line operations (:mod:`budget.sar.pga_lines`, :mod:`budget.sar.pga_fast`):
the phase correction, the centre shift's peak fit and phase ramps, the centroid slope, the window,
the line weights, the kernel's line sums, the increment's integration, detrending, smoothing and
rms, and the fast-phase bands' group sums.

Each loop computes what the NumPy expression in its docstring computes, element by element and
in the same order where the order matters (a ramp's powers are the same sequential products as
``np.cumprod``; sums add one after the other where NumPy may pair them, so their last bits can
differ: on PGA's outputs ≤ 3e-11 rad), without the (n, L) temporaries and the per-call
overhead: PGA on the Monte Carlo's 462 × 41 lines and on 128² image chips spent most of its time
allocating, filling and reading those, and in the calls of many small NumPy steps, not in its
FFTs.
Compiled by numba on first use and cached beside this file (``cache=True``); each function is
tested against its NumPy form in ``tests/test_sar_pga_kernels.py``.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _ramp_columns(out: np.ndarray, src: np.ndarray, cols: np.ndarray, z: np.ndarray) -> None:
    """out[:, j] = src[:, cols[j]] · z_j^{m(k)} for every j, m(k) the signed DFT index of row k
    (numpy order), the powers z_j^1, z_j^2, … formed as sequential products and z^{−m} = conj(z^m).
    ``out`` may be ``src`` itself with ``cols`` = 0, 1, …. Row after row across all the columns:
    each column's chain of products is the same, but the columns' chains run side by side instead
    of one long dependent chain after the other."""
    n = out.shape[0]
    n_c = cols.size
    n_pos = (n - 1) // 2 + 1
    n_neg = n // 2
    for j in range(n_c):
        out[0, j] = src[0, cols[j]]
    p = z.copy()
    for m in range(1, max(n_pos - 1, n_neg) + 1):
        if m < n_pos:
            for j in range(n_c):
                out[m, j] = src[m, cols[j]] * p[j]
        if m <= n_neg:
            for j in range(n_c):
                out[n - m, j] = src[n - m, cols[j]] * np.conj(p[j])
        for j in range(n_c):
            p[j] = p[j] * z[j]


@njit(cache=True)
def centroid_slope(shifted: np.ndarray, rows: np.ndarray, rot: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Mean phase slope (rad per bin) of each selected line's windowed phase history, from the
    image: arg(Σ_x |w(x)|² e^{j2πx/n}/n − (Σ_x w(x)) (Σ_x w(x) e^{−j2πx/n})*/n²) over the window
    ``rows`` (``rot`` = e^{j2πx/n} on them), w = ``shifted[rows, col]``; each line's sums over the
    rows in order, the lines side by side."""
    n = shifted.shape[0]
    n_c = cols.size
    circ = np.zeros(n_c, dtype=np.complex128)
    total = np.zeros(n_c, dtype=np.complex128)
    turned = np.zeros(n_c, dtype=np.complex128)
    for i in range(rows.size):
        r = rot[i]
        rc = np.conj(r)
        for j in range(n_c):
            w = shifted[rows[i], cols[j]]
            circ[j] += (w.real * w.real + w.imag * w.imag) * r
            total[j] += w
            turned[j] += w * rc
    out = np.empty(n_c)
    for j in range(n_c):
        c = circ[j] / n - total[j] * np.conj(turned[j]) / (n * n)
        out[j] = np.arctan2(c.imag, c.real)
    return out


@njit(cache=True)
def window_in_place(win: np.ndarray, inside: np.ndarray, w_line: np.ndarray, cols: np.ndarray) -> None:
    """win[k, j] *= inside[k] · √w_line[cols[j]] (inside: 0/1 per row): the window, and each
    selected line scaled by the root of its weight."""
    n, n_l = win.shape
    scale = np.sqrt(w_line[cols])
    for k in range(n):
        if inside[k]:
            for col in range(n_l):
                win[k, col] *= scale[col]
        else:
            for col in range(n_l):
                win[k, col] = 0.0


@njit(cache=True)
def power(a: np.ndarray) -> np.ndarray:
    """|a|² element-wise (a.real² + a.imag²)."""
    n, n_l = a.shape
    out = np.empty((n, n_l))
    for k in range(n):
        for col in range(n_l):
            v = a[k, col]
            out[k, col] = v.real * v.real + v.imag * v.imag
    return out


@njit(cache=True)
def line_weights(pw: np.ndarray, rows: np.ndarray, c_line: np.ndarray, bias: float) -> tuple[np.ndarray, np.ndarray]:
    """Per line l: SCR_l = max(Σ_{rows} pw[:, l] / (W c_l) − 1 − bias, 0) and its kernel weight
    SCR_l/(2 SCR_l + 1)/(W c_l), W = max(len(rows), 1)."""
    n_l = pw.shape[1]
    w_in = max(rows.size, 1)
    total = np.zeros(n_l)
    for i in range(rows.size):
        for col in range(n_l):
            total[col] += pw[rows[i], col]
    scr = np.empty(n_l)
    weight = np.empty(n_l)
    for col in range(n_l):
        level = w_in * c_line[col]
        s = max(total[col] / level - 1.0 - bias, 0.0)
        scr[col] = s
        weight[col] = s / (2.0 * s + 1.0) / level
    return scr, weight


@njit(cache=True)
def weighted_rows(pw: np.ndarray, w_line: np.ndarray) -> np.ndarray:
    """Σ_l pw[k, l] w_l per row k (pw @ w_line)."""
    n, n_l = pw.shape
    out = np.zeros(n)
    for k in range(n):
        acc = 0.0
        for col in range(n_l):
            acc += pw[k, col] * w_line[col]
        out[k] = acc
    return out


@njit(cache=True)
def line_sums(h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """From phase histories ``h`` (n, L, numpy order): per centred bin c (c = 0 … n−1 ↔ row
    (c − n//2) mod n, as ``np.fft.fftshift``) the energy Σ_l |G(c, l)|², and for c ≥ 1 the ML
    kernel's sum Σ_l G(c, l) G*(c−1, l) (entry 0 is 0)."""
    n, n_l = h.shape
    half = n // 2
    energy = np.zeros(n)
    prod = np.zeros(n, dtype=np.complex128)
    for c in range(n):
        k = (c - half) % n
        acc = 0.0
        for col in range(n_l):
            v = h[k, col]
            acc += v.real * v.real + v.imag * v.imag
        energy[c] = acc
        if c > 0:
            kp = (c - 1 - half) % n
            s = 0.0 + 0.0j
            for col in range(n_l):
                s += h[k, col] * np.conj(h[kp, col])
            prod[c] = s
    return energy, prod


@njit(cache=True)
def group_products(h: np.ndarray, lo: int, hi: int, starts: np.ndarray) -> np.ndarray:
    """Σ over the lines of each group of G(c, l) G*(c−1, l) for the centred bins c = lo+1 … hi−1
    (rows of the result), groups being the runs of lines that begin at ``starts`` (columns);
    ``h`` and the bin order as :func:`line_sums`."""
    n, n_l = h.shape
    half = n // 2
    n_g = starts.size
    out = np.zeros((hi - lo - 1, n_g), dtype=np.complex128)
    for c in range(lo + 1, hi):
        k = (c - half) % n
        kp = (c - 1 - half) % n
        for g in range(n_g):
            end = starts[g + 1] if g + 1 < n_g else n_l
            s = 0.0 + 0.0j
            for col in range(starts[g], end):
                s += h[k, col] * np.conj(h[kp, col])
            out[c - lo - 1, g] = s
    return out


@njit(cache=True)
def phase_corrected(hist: np.ndarray, phi_c: np.ndarray) -> np.ndarray:
    """hist · e^{−jφ} per row: ``hist`` (n, L) in numpy order, ``phi_c`` (n,) in centred order
    (row k takes φ_c[(k + n//2) mod n], as ``np.fft.ifftshift``)."""
    n, n_l = hist.shape
    half = n // 2
    out = np.empty((n, n_l), dtype=np.complex128)
    for k in range(n):
        p = phi_c[(k + half) % n]
        e = complex(np.cos(p), -np.sin(p))
        for col in range(n_l):
            out[k, col] = hist[k, col] * e
    return out


@njit(cache=True)
def _ramp_factor(shift: float, n: int) -> complex:
    """z = e^{−j2π s/n}, the angle formed as (−2π s)·(1/n), as NumPy's complex division by n
    forms it."""
    y = (-2.0 * np.pi * shift) * (1.0 / n)
    return complex(np.cos(y), np.sin(y))


@njit(cache=True)
def centre_in_place(corr: np.ndarray, spec: np.ndarray) -> None:
    """Moves each line of ``corr`` (phase histories, numpy order) so that the brightest point of
    its image ``spec`` = DFT(corr) lands at index 0: corr[:, l] ·= e^{−j2π f_k s_l}
    (the powers of z_l = e^{−j2π s_l/n}, :func:`_ramp_columns`), s_l = the index of the largest
    |spec| plus the parabolic fit's offset 0.5 (a₋ − a₊)/(a₋ − 2a₀ + a₊) through |spec| there and at
    its circular neighbours (where that denominator is < 0, else 0). The largest is
    found on |spec|² (no square roots over the whole line), the three magnitudes of the fit are
    |·| as np.abs forms them."""
    n, n_l = spec.shape
    top = np.empty(n_l)
    best = np.zeros(n_l, dtype=np.int64)
    for col in range(n_l):
        v = spec[0, col]
        top[col] = v.real * v.real + v.imag * v.imag
    for i in range(1, n):
        for col in range(n_l):
            v = spec[i, col]
            p = v.real * v.real + v.imag * v.imag
            if p > top[col]:  # first maximum, as np.argmax
                top[col] = p
                best[col] = i
    z = np.empty(n_l, dtype=np.complex128)
    for col in range(n_l):
        b = best[col]
        a_0 = abs(spec[b, col])
        a_m = abs(spec[(b - 1) % n, col])
        a_p = abs(spec[(b + 1) % n, col])
        den = a_m - 2.0 * a_0 + a_p
        shift = b + (0.5 * (a_m - a_p) / den if den < 0 else 0.0)
        z[col] = _ramp_factor(shift, n)
    _ramp_columns(corr, corr, np.arange(n_l), z)


@njit(cache=True)
def refine_ramp(shifted: np.ndarray, h_shift: np.ndarray, rows: np.ndarray, rot: np.ndarray,
                cols: np.ndarray) -> np.ndarray:
    """The selected lines ``h_shift[:, cols]`` moved by their centroid offsets s = slope·n/(2π),
    slope from :func:`centroid_slope` of ``shifted`` over the window ``rows``: a new (n, len(cols))
    array (the ramps of :func:`_ramp_columns`)."""
    n = h_shift.shape[0]
    slope = centroid_slope(shifted, rows, rot, cols)
    z = np.empty(cols.size, dtype=np.complex128)
    for j in range(cols.size):
        z[j] = _ramp_factor(slope[j] * n / (2.0 * np.pi), n)
    out = np.empty((n, cols.size), dtype=np.complex128)
    _ramp_columns(out, h_shift, cols, z)
    return out


@njit(cache=True)
def detrend(phi: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """``phi`` less its weighted least-squares constant + linear term in the bin index k
    (closed form: k̄, φ̄ weighted means, slope Σw(k−k̄)(φ−φ̄)/Σw(k−k̄)²); ``phi`` itself when
    Σw ≤ 0."""
    n = phi.size
    sw = 0.0
    swk = 0.0
    swp = 0.0
    for i in range(n):
        sw += weight[i]
        swk += weight[i] * i
        swp += weight[i] * phi[i]
    if sw <= 0:
        return phi.copy()
    km = swk / sw
    pm = swp / sw
    var = 0.0
    cov = 0.0
    for i in range(n):
        dk = i - km
        var += weight[i] * dk * dk
        cov += weight[i] * dk * (phi[i] - pm)
    slope = cov / var if var > 0 else 0.0
    out = np.empty(n)
    for i in range(n):
        out[i] = phi[i] - pm - slope * (i - km)
    return out


@njit(cache=True)
def band_weight(energy: np.ndarray, band_db: float) -> np.ndarray:
    """The bins' weights: ``energy`` where it is within ``band_db`` of its peak, else 0."""
    thr = energy.max() * 10.0 ** (-band_db / 10.0)
    weight = np.empty(energy.size)
    for i in range(energy.size):
        weight[i] = energy[i] if energy[i] >= thr else 0.0
    return weight


@njit(cache=True)
def ml_increment(prod: np.ndarray, energy: np.ndarray, band_db: float) -> tuple[np.ndarray, np.ndarray]:
    """The ML kernel's integrated, detrended estimate (centred bins) and the bins' weights
    (:func:`band_weight`): increments arg(prod) between two weighted bins (0 elsewhere), summed
    from 0, then :func:`detrend` with the weights."""
    n = energy.size
    weight = band_weight(energy, band_db)
    est = np.empty(n)
    est[0] = 0.0
    acc = 0.0
    for i in range(1, n):
        if weight[i] > 0 and weight[i - 1] > 0:
            acc += np.arctan2(prod[i].imag, prod[i].real)
        est[i] = acc
    return detrend(est, weight), weight


@njit(cache=True)
def savgol_span(weight: np.ndarray, window: float, stretch: float, max_fraction: float) -> tuple[int, int, int]:
    """(lo, hi, length) of the increment smoothing (:func:`~budget.sar.pga_lines._lowpass`): the
    bins lo … hi−1 from the first to the last with weight ≥ 0.1 × its peak, and the odd filter
    length min(stretch·n/window, max_fraction·span) ≤ span; length 0 when the span has < 8 such
    bins, ``window`` ≤ 0 or the length would be < 7 (no smoothing)."""
    n = weight.size
    thr = 0.1 * weight.max()
    lo = -1
    hi = -1
    count = 0
    for i in range(n):
        if weight[i] >= thr:
            if lo < 0:
                lo = i
            hi = i + 1
            count += 1
    if count < 8 or window <= 0:
        return 0, 0, 0
    span = hi - lo
    length = min(int(stretch * n / window), int(max_fraction * span)) | 1
    length = min(length, span if span % 2 else span - 1)
    if length < 7:
        return 0, 0, 0
    return lo, hi, length


@njit(cache=True)
def savgol_in_place(x: np.ndarray, lo: int, hi: int, coef: np.ndarray, ends: np.ndarray) -> None:
    """x[lo:hi] replaced by its cubic Savitzky–Golay filter (mode "interp") of len(coef) bins:
    interior outputs Σ_j x[i+j] coef[j] over the window, the len//2 outputs at each end the end
    fit operator ``ends`` applied to the first (last) len bins."""
    length = coef.size
    half = length // 2
    seg = x[lo:hi].copy()
    m = seg.size
    for i in range(m - length + 1):
        acc = 0.0
        for j in range(length):
            acc += seg[i + j] * coef[j]
        x[lo + half + i] = acc
    for i in range(half):
        a = 0.0
        b = 0.0
        for j in range(length):
            a += ends[i, j] * seg[j]
            b += ends[length - half + i, j] * seg[m - length + j]
        x[lo + i] = a
        x[lo + m - half + i] = b


@njit(cache=True)
def wrms(phi: np.ndarray, weight: np.ndarray) -> float:
    """√(Σ w φ² / max(Σ w, 1e-300))."""
    num = 0.0
    sw = 0.0
    for i in range(phi.size):
        num += weight[i] * phi[i] * phi[i]
        sw += weight[i]
    return np.sqrt(num / max(sw, 1e-300))


@njit(cache=True)
def window_width(summed: np.ndarray, win_db: float, win_scale: float) -> int:
    """⌈win_scale · (right + left + 1)⌉: right (left) the first index after (before) 0, circularly,
    at which ``summed`` falls below ``win_db`` under summed[0], searched over n//2 − 1 (n//2)
    samples and n//2 where it never does."""
    n = summed.size
    half = n // 2
    thr = summed[0] * 10.0 ** (-win_db / 10.0)
    right = half
    for i in range(1, half):
        if summed[i] < thr:
            right = i - 1
            break
    left = half
    for i in range(half):
        if summed[n - 1 - i] < thr:
            left = i
            break
    return int(np.ceil(win_scale * (right + left + 1)))


@njit(cache=True)
def group_starts(groups: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """Positions, among the kept lines, where a new group begins (groups are runs of sorted lines):
    ``np.flatnonzero(np.diff(groups[keep], prepend=-1))``."""
    out = np.empty(groups.size, dtype=np.int64)
    m = 0
    j = 0
    prev = -1
    for i in range(groups.size):
        if keep[i]:
            if groups[i] != prev:
                out[m] = j
                m += 1
            prev = groups[i]
            j += 1
    return out[:m]


@njit(cache=True)
def band_phases(per_group: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """From the ML products per group (bins × groups): the estimate over the span
    [0, cumsum(arg Σ_g)] and its delete-one-group versions [0, cumsum(arg(Σ_g − group g))]
    (span × groups)."""
    m, n_g = per_group.shape
    est = np.zeros(m + 1)
    jk = np.zeros((m + 1, n_g))
    for i in range(m):
        t = 0.0 + 0.0j
        for g in range(n_g):
            t += per_group[i, g]
        est[i + 1] = est[i] + np.arctan2(t.imag, t.real)
        for g in range(n_g):
            r = t - per_group[i, g]
            jk[i + 1, g] = jk[i, g] + np.arctan2(r.imag, r.real)
    return est, jk


@njit(cache=True)
def measured_width(pw: np.ndarray, rows: np.ndarray, c_line: np.ndarray, bias: float, win_db: float,
                   win_scale: float, fallback: int) -> int:
    """Step 3's measured width: :func:`window_width` of the lines' intensity ``pw`` weighted as
    :func:`line_weights` weighs them in the window ``rows`` and summed (:func:`weighted_rows`);
    ``fallback`` when that sum is not > 0 at index 0."""
    _, weight = line_weights(pw, rows, c_line, bias)
    summed = weighted_rows(pw, weight)
    if summed[0] > 0:
        return window_width(summed, win_db, win_scale)
    return fallback


@njit(cache=True)
def weights_and_lines(pw: np.ndarray, rows: np.ndarray, c_line: np.ndarray,
                      bias: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`line_weights` and the indices of the lines of weight > 0."""
    scr, weight = line_weights(pw, rows, c_line, bias)
    return scr, weight, np.flatnonzero(weight > 0)


@njit(cache=True)
def ml_step(h: np.ndarray, band_db: float, window: float, stretch: float,
            max_fraction: float) -> tuple[np.ndarray, np.ndarray, int, int, int]:
    """One iteration's ML increment from the windowed lines' phase histories ``h``: (detrended
    increment and bin weights of :func:`ml_increment` on :func:`line_sums`; lo, hi, length of the
    increment's smoothing, :func:`savgol_span` at ``window``, length 0 for none or ``window`` ≤ 0)."""
    energy, prod = line_sums(h)
    inc, weight = ml_increment(prod, energy, band_db)
    lo, hi, length = savgol_span(weight, window, stretch, max_fraction)
    return inc, weight, lo, hi, length


@njit(cache=True)
def smoothed_rms(inc: np.ndarray, weight: np.ndarray, lo: int, hi: int, coef: np.ndarray,
                 ends: np.ndarray) -> float:
    """:func:`savgol_in_place` on ``inc`` (lo … hi−1), then its :func:`wrms` with ``weight``."""
    savgol_in_place(inc, lo, hi, coef, ends)
    return wrms(inc, weight)
