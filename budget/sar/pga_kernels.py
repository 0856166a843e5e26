"""Compiled loops for PGA's per-line operations (:mod:`budget.sar.pga_lines`): the centre shift's
peak fit and phase ramps, the centroid slope, the window, and the kernel's line sums.

Each loop computes what the NumPy expression in its docstring computes, element by element and
in the same order where the order matters (a ramp's powers are the same sequential products as
``np.cumprod``; sums over lines add one after the other where NumPy may pair them, so their last
bits can differ), without the (n, L) temporaries: PGA on the Monte Carlo's 462 × 41 lines and on
128² image chips spends most of its time allocating, filling and reading those, not in its FFTs.
Compiled by numba on first use and cached beside this file (``cache=True``); each function is
tested against its NumPy form in ``tests/test_sar_pga_kernels.py``.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def peak_shift(mag: np.ndarray) -> np.ndarray:
    """Per column of ``mag`` (n, L): the index of its largest value plus the parabolic fit's
    sub-sample offset through it and its circular neighbours,
    0.5 (a₋ − a₊)/(a₋ − 2a₀ + a₊) where that denominator is < 0, else 0."""
    n, n_l = mag.shape
    out = np.empty(n_l)
    for col in range(n_l):
        best = 0
        top = mag[0, col]
        for i in range(1, n):
            if mag[i, col] > top:  # first maximum, as np.argmax
                top = mag[i, col]
                best = i
        a_m = mag[(best - 1) % n, col]
        a_p = mag[(best + 1) % n, col]
        den = a_m - 2.0 * top + a_p
        out[col] = best + (0.5 * (a_m - a_p) / den if den < 0 else 0.0)
    return out


@njit(cache=True)
def _ramp_column(out: np.ndarray, src: np.ndarray, col_out: int, col_src: int, z: complex) -> None:
    """out[:, col_out] = src[:, col_src] · z^{m(k)}, m(k) the signed DFT index of row k (numpy
    order), the powers z^1, z^2, … formed as sequential products and z^{−m} = conj(z^m)."""
    n = out.shape[0]
    n_pos = (n - 1) // 2 + 1
    n_neg = n // 2
    out[0, col_out] = src[0, col_src]
    p = z
    for m in range(1, max(n_pos - 1, n_neg) + 1):
        if m < n_pos:
            out[m, col_out] = src[m, col_src] * p
        if m <= n_neg:
            out[n - m, col_out] = src[n - m, col_src] * np.conj(p)
        p = p * z


@njit(cache=True)
def ramp_in_place(h: np.ndarray, z: np.ndarray) -> None:
    """h[:, l] *= e^{−j2π f_k s_l} (n × L, in place), given z_l = e^{−j2π s_l/n}: moves line l
    by s_l samples in the image domain (f_k the DFT frequencies, numpy order)."""
    for col in range(h.shape[1]):
        _ramp_column(h, h, col, col, z[col])


@njit(cache=True)
def ramp_columns(h: np.ndarray, cols: np.ndarray, z: np.ndarray) -> np.ndarray:
    """h[:, cols] times the ramps of :func:`ramp_in_place` for z (one per selected column), as a
    new (n, len(cols)) array."""
    out = np.empty((h.shape[0], cols.size), dtype=np.complex128)
    for j in range(cols.size):
        _ramp_column(out, h, j, cols[j], z[j])
    return out


@njit(cache=True)
def centroid_slope(shifted: np.ndarray, rows: np.ndarray, rot: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Mean phase slope (rad per bin) of each selected line's windowed phase history, from the
    image: arg(Σ_x |w(x)|² e^{j2πx/n}/n − (Σ_x w(x)) (Σ_x w(x) e^{−j2πx/n})*/n²) over the window
    ``rows`` (``rot`` = e^{j2πx/n} on them), w = ``shifted[rows, col]``."""
    n = shifted.shape[0]
    out = np.empty(cols.size)
    for j in range(cols.size):
        col = cols[j]
        circ = 0.0 + 0.0j
        total = 0.0 + 0.0j
        turned = 0.0 + 0.0j
        for i in range(rows.size):
            w = shifted[rows[i], col]
            circ += (w.real * w.real + w.imag * w.imag) * rot[i]
            total += w
            turned += w * np.conj(rot[i])
        c = circ / n - total * np.conj(turned) / (n * n)
        out[j] = np.arctan2(c.imag, c.real)
    return out


@njit(cache=True)
def window_in_place(win: np.ndarray, inside: np.ndarray, scale: np.ndarray) -> None:
    """win[k, l] *= inside[k] · scale[l] (inside: 0/1 per row)."""
    n, n_l = win.shape
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
