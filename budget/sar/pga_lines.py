"""PGA's candidate range lines and what is done to them each iteration (Wahl, Eichel, Ghiglia &
Jakowatz, IEEE TAES 30(3), 1994, steps 2–5): centre shift, window, line weights, the kernels'
integrated estimate, detrending and smoothing; before them, the image's power and the exact
medians that set the clutter levels. The algorithm, its constants and its outcomes are
described in :mod:`budget.sar.pga`, which drives these steps."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.fft as sfft
from numba import njit
from scipy.signal import savgol_coeffs

try:  # scipy.fft's own pocketfft binding, called without its dispatch layers (the same transform)
    from scipy.fft._pocketfft.helper import _workers
    from scipy.fft._pocketfft.pypocketfft import c2c as _c2c, dct as _dct
except ImportError:  # pragma: no cover - another scipy layout: the public functions
    _c2c = _dct = None

from .pga_kernels import (band_weight, centre_in_place, detrend, line_weights, ml_increment, phase_corrected, power,
                          refine_ramp, savgol_in_place, savgol_span, window_in_place, window_width)

# Fast-phase bands: the span is the bins where the candidate lines' energy is within 10 dB of its
# peak.
_SPAN_FRACTION = 0.1


_LN2 = float(np.log(2.0))


# Savitzky–Golay length of the increment smoothing in units of n/W (see _lowpass): increments are
# smoothed a little beyond the window's phase bandwidth.
_SG_STRETCH_INC = 2.5


_SG_MAX_FRACTION = 0.7


def fft_lines(a: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``scipy.fft.fft(a, axis=0)`` of a complex array, bit for bit, into ``out`` when given (which
    may be ``a`` itself). PGA makes some 30 such calls per image, most on small arrays, where
    scipy.fft's dispatch costs as much as a quarter of the transform."""
    if _c2c is None:
        return sfft.fft(a, axis=0)
    return _c2c(a, (0,), True, 0, out, _workers(None))


def ifft_lines(a: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``scipy.fft.ifft(a, axis=0)`` of a complex array, bit for bit (see :func:`fft_lines`)."""
    if _c2c is None:
        return sfft.ifft(a, axis=0)
    return _c2c(a, (0,), False, 2, out, _workers(None))


def dct_lines(a: np.ndarray, inverse: bool = False) -> np.ndarray:
    """``scipy.fft.dct(a, axis=0, norm="ortho")`` (``inverse``: ``idct``) of a real float64 array,
    bit for bit (see :func:`fft_lines`)."""
    if _dct is None:
        return (sfft.idct if inverse else sfft.dct)(a, axis=0, norm="ortho")
    return _dct(a, 3 if inverse else 2, (0,), 1, None, _workers(None), None)


def _window_width(summed: np.ndarray, win_db: float, win_scale: float) -> int:
    """Width (samples) of the region around index 0 where ``summed`` stays within ``win_db``
    (:func:`~budget.sar.pga_kernels.window_width`)."""
    return int(window_width(summed, win_db, win_scale))


def _line_weights(pw: np.ndarray, rows: np.ndarray, c_line: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(SCR, kernel weight) per centre-shifted line (step 4) from the window's ``rows``. A
    clutter-only line centred on its brightest of n samples holds ≈ (W − 1 + H_n) c in a W-sample
    window (H_n ≈ ln n + 0.577, the mean maximum of n unit exponentials), so the SCR is counted
    beyond that bias b = (H_n − 1)/W; the weight SCR/(2 SCR + 1) per unit clutter then leaves
    clutter-only lines ≈ 0."""
    n = pw.shape[0]
    return line_weights(pw, rows, c_line, (np.log(n) + 0.5772 - 1.0) / max(rows.size, 1))


def _bias(d: _Lines, rows: np.ndarray) -> float:
    """The bias b of :func:`_line_weights` for the window ``rows``."""
    return d.bias_numerator / max(rows.size, 1)


def _detrend(phi: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """``phi`` less its least-squares constant + linear term in the bin index, weighted (closed
    form, :func:`~budget.sar.pga_kernels.detrend`)."""
    return detrend(np.ascontiguousarray(phi, dtype=float), np.ascontiguousarray(weight, dtype=float))


@lru_cache(maxsize=128)
def _savgol_parts(length: int) -> tuple[np.ndarray, np.ndarray]:
    """(coefficients, end-fit operator) of a cubic Savitzky–Golay filter of ``length`` bins: the
    interior output is the dot product of the coefficients with the ``length`` bins around it; the
    ``length``//2 outputs at each end are the least-squares cubic through the first (last)
    ``length`` bins evaluated there (scipy's mode="interp")."""
    v = np.vander(np.arange(length, dtype=float), 4)
    return savgol_coeffs(length, 3, use="dot"), v @ np.linalg.pinv(v)


def _lowpass(phi: np.ndarray, mask_weight: np.ndarray, window: float, stretch: float = 1.0) -> np.ndarray:
    """``phi`` over the bins from the first to the last whose ``mask_weight`` is ≥ 0.1 × its peak
    smoothed by a cubic Savitzky–Golay filter of ``stretch`` · n/``window`` bins, at most
    ``_SG_MAX_FRACTION`` of the span (longer, the local fit becomes one global cubic). Lines
    windowed to W samples carry phase that varies at most W/2 cycles per n bins (a W-sample
    function's DFT), so faster wiggles of an estimate are its noise; a cubic SG filter of L bins
    passes ≈ 2.5/L cycles per bin (−3 dB), so ``stretch`` = 5 matches that bandwidth. A local
    cubic keeps polynomial errors exact (a truncated DCT rings at the ends). Fewer than 8 such
    bins, or a filter shorter than 7: ``phi`` unchanged."""
    lo, hi, length = savgol_span(mask_weight, float(window), float(stretch), _SG_MAX_FRACTION)
    if length == 0:
        return phi
    out = phi.copy()
    coef, ends = _savgol_parts(int(length))
    savgol_in_place(out, lo, hi, coef, ends)
    return out


def _predicted_noise(scr: np.ndarray) -> float:
    """Per-bin rms (rad) of a common-phase estimate from lines of per-bin signal-to-clutter
    ratios ``scr``: 1/√(2 Σ SCR_r) (white clutter, high SCR; Jakowatz & Wahl 1993)."""
    total = float(np.sum(scr))
    return float(np.sqrt(0.5 / total)) if total > 0 else float("inf")


# Clutter levels (setup): the image's power and exact medians, compiled.


@njit(cache=True)
def image_power(g: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, bool]:
    """(|g|² per pixel, Σ over axis 0 of it per column, its largest value, all of g finite) of a
    C-ordered complex image, in one pass: the columns' sums add row after row, as NumPy's
    ``power.sum(axis=0)`` on a C-ordered array of more than one column does (a single column it
    sums pairwise)."""
    n, n_l = g.shape
    out = np.empty((n, n_l))
    col = np.zeros(n_l)
    peak = -np.inf
    finite = True
    for k in range(n):
        for j in range(n_l):
            v = g[k, j]
            if not (np.isfinite(v.real) and np.isfinite(v.imag)):
                finite = False
            p = v.real * v.real + v.imag * v.imag
            out[k, j] = p
            col[j] += p
            if p > peak:
                peak = p
    return out, col, peak, finite


@njit(cache=True)
def _select(buf: np.ndarray, m: int, k: int) -> float:
    """The k-th smallest (from 0) of buf[:m], reordering buf[:m] so that buf[:k] holds values ≤ it
    (quickselect, median-of-three pivot, Hoare partition)."""
    lo = 0
    hi = m - 1
    while hi > lo:
        mid = (lo + hi) // 2
        a, b, c = buf[lo], buf[mid], buf[hi]
        if a > b:
            a, b = b, a
        if b > c:
            b = c
            if a > b:
                b = a
        pivot = b
        i = lo
        j = hi
        while i <= j:
            while buf[i] < pivot:
                i += 1
            while buf[j] > pivot:
                j -= 1
            if i <= j:
                t = buf[i]
                buf[i] = buf[j]
                buf[j] = t
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            return buf[k]
    return buf[k]


@njit(cache=True)
def _median_of(buf: np.ndarray, m: int) -> float:
    """Median of buf[:m] (reordered): the middle value, or the mean of the two middle ones."""
    k = m // 2
    upper = _select(buf, m, k)
    if m % 2:
        return upper
    lower = buf[0]
    for i in range(1, k):
        if buf[i] > lower:
            lower = buf[i]
    return (lower + upper) / 2


@njit(cache=True)
def median_all(x: np.ndarray) -> float:
    """``np.median(x)`` of a finite C-ordered 2-D array, exactly (an order statistic, or the mean
    of two, is the same value whatever the algorithm). The candidates are bracketed first by the
    order statistics of a strided sample of 1 in 64 around the median's rank (± 5 standard
    deviations of a sample quantile), so that only the values inside the bracket are selected
    among; when the bracket misses the middle rank, the whole array is."""
    flat = x.ravel()
    m = flat.size
    k = m // 2
    step = 64
    if m >= 16 * step:
        sample = flat[::step].copy()
        sample.sort()
        s = sample.size
        half = int(5.0 * np.sqrt(0.25 * s)) + 2
        centre = int(k / m * s)
        lo_v = sample[max(centre - half, 0)]
        hi_v = sample[min(centre + half, s - 1)]
        below = 0
        buf = np.empty(m)
        cnt = 0
        for i in range(m):  # without branches: the values fall either side at random
            v = flat[i]
            buf[cnt] = v
            below += v < lo_v
            cnt += (v >= lo_v) & (v <= hi_v)
        # both middle ranks (k − 1 and k for an even count) inside the bracket
        first = k - 1 if m % 2 == 0 else k
        if below <= first and k < below + cnt:
            upper = _select(buf, cnt, k - below)
            if m % 2:
                return upper
            lower = buf[0]
            for i in range(1, k - below):
                if buf[i] > lower:
                    lower = buf[i]
            return (lower + upper) / 2
    return _median_of(flat.copy(), m)


@njit(cache=True)
def median_columns(x: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """``np.median(x[:, cols], axis=0)``, exactly, without forming the copy."""
    n = x.shape[0]
    out = np.empty(cols.size)
    buf = np.empty(n)
    for j in range(cols.size):
        c = cols[j]
        for i in range(n):
            buf[i] = x[i, c]
        out[j] = _median_of(buf, n)
    return out


def _median(x: np.ndarray, axis: int | None = None):
    """``np.median(x, axis)`` of a finite real array (axis None or 0, at most 2-D), exactly
    (:func:`~budget.sar.pga_kernels.median_all`, :func:`~budget.sar.pga_kernels.median_columns`:
    selections, at a fraction of np.median's time on the image)."""
    x = np.ascontiguousarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    if axis is None:
        return median_all(x)
    return median_columns(x, np.arange(x.shape[1]))


def _power_stats(g: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, bool]:
    """(|g|² per pixel, its sums over axis 0, its peak, every pixel finite) of a 2-D image: one
    compiled pass for a C-ordered complex image, NumPy's expressions otherwise."""
    if g.dtype == np.complex128 and g.flags.c_contiguous and g.shape[1] > 1:  # one column: NumPy sums pairwise
        return image_power(g)
    power = g.real ** 2 + g.imag ** 2
    return power, power.sum(axis=0), float(power.max()), bool(np.all(np.isfinite(g)))


@dataclass
class _Lines:
    """The candidate lines' phase histories and clutter levels, and the settings of a run."""

    hist: np.ndarray  # (n, L) phase histories, numpy order
    c_line: np.ndarray  # clutter level per line
    kernel: str
    tol_rad: float
    win_db: float
    win_scale: float
    shrink: float
    min_window: int
    band_db: float
    smooth: float

    def __post_init__(self) -> None:
        n = self.hist.shape[0]
        self.freq = np.fft.fftfreq(n)
        self.pos = self.freq * n  # signed sample index: the centre-shifted peak sits at 0
        #: the lines' energy per bin (numpy order)
        self.energy = (self.hist.real ** 2 + self.hist.imag ** 2).sum(axis=1)
        self.n_signal_bins = int(np.sum(self.energy >= _SPAN_FRACTION * self.energy.max()))
        #: numerator of :func:`_line_weights`' bias, (H_n − 1) ≈ ln n + 0.5772 − 1
        self.bias_numerator = np.log(n) + 0.5772 - 1.0
        self.unshifted = None  # :func:`_centre` of the uncorrected lines, once computed

    def centred_uncorrected(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:func:`_centre` with a zero estimate, computed once (every run starts there; read-only)."""
        if self.unshifted is None:
            self.unshifted = _centre(self, np.zeros(self.hist.shape[0]))
        return self.unshifted


def _centre(d: _Lines, phi_c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step 2, first part: (phase histories of the centre-shifted lines, the lines, their
    intensity) of the lines corrected with ``phi_c`` (centred bins): each line's brightest point
    (parabolic fit) moved to index 0 by a phase ramp on its phase history."""
    corr = phase_corrected(d.hist, phi_c)
    spec = fft_lines(corr)
    centre_in_place(corr, spec)
    shifted = fft_lines(corr, out=spec)
    return corr, shifted, power(shifted)


@lru_cache(maxsize=64)
def _window(n: int, width: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows (numpy order) of a centred window of ``width`` samples out of n; e^{j2πx/n} on them;
    the window as a 0/1 mask over the n rows). Cached: read-only."""
    inside = np.abs(np.fft.fftfreq(n) * n) <= width / 2.0
    rows = np.flatnonzero(inside)
    return rows, np.exp(2j * np.pi * rows / n), inside


def _refine(d: _Lines, h_shift: np.ndarray, shifted: np.ndarray, width: float,
            w_line: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step 2, second part, and step 3 for the lines of non-zero weight: each line's centre
    refined to the centroid given by the mean phase slope of its windowed phase history (unbiased
    for a sinc, unlike the parabolic peak fit), windowed again and scaled by √weight. Returns
    (the lines used, mask over the candidates; windowed lines; their phase histories, numpy
    order: :func:`~budget.sar.pga_kernels.line_sums` reads them in centred order).

    The mean slope Σ_k h(k+1) h*(k) of the windowed line's phase history h = IDFT(w) is computed in
    the image domain: circularly it is (1/n) Σ_x |w(x)|² e^{j2πx/n} (Wiener–Khinchin), less the
    wrap-around term h(0) h*(n−1), h(0) = Σ w/n, h(n−1) = Σ w(x) e^{−j2πx/n}/n."""
    n = d.hist.shape[0]
    used = w_line > 0
    cols = np.flatnonzero(used)
    rows, rot, inside = _window(n, width)
    win = refine_ramp(shifted, h_shift, rows, rot, cols)
    win = fft_lines(win, out=win)
    window_in_place(win, inside, w_line, cols)
    return used, win, ifft_lines(win)


def _increment(d: _Lines, hist_w: np.ndarray, win: np.ndarray, prod: np.ndarray,
               energy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(detrended increment, weight per bin), centred bins, from windowed lines ``win``, their
    phase histories ``hist_w`` (numpy order), the ML kernel's line sums ``prod`` and the lines'
    ``energy`` per bin (:func:`~budget.sar.pga_kernels.line_sums`) (step 4 and the integration
    of step 5): bins more than ``band_db`` below the peak energy carry no gradient and no weight;
    the rest carry their energy as the detrending's weight."""
    if d.kernel == "ml":
        return ml_increment(prod, energy, d.band_db)
    n = hist_w.shape[0]
    weight = band_weight(energy, d.band_db)
    big_g = np.fft.fftshift(hist_w, axes=0)
    d_g = np.fft.fftshift(sfft.ifft(win * (2j * np.pi * d.pos / n)[:, None], axis=0), axes=0)
    grad = np.where(weight > 0, np.imag(np.conj(big_g) * d_g).sum(axis=1) / np.maximum(weight, 1e-300), 0.0)
    return _detrend(np.concatenate([[0.0], np.cumsum(0.5 * (grad[1:] + grad[:-1]))]), weight), weight


def _corrected(hist: np.ndarray, phi: np.ndarray, overwrite: bool = False) -> np.ndarray:
    """The image of the phase history ``hist`` (complex128, numpy order along axis 0) multiplied
    by e^{−jφ} (``phi`` centred), as :func:`apply_phase_correction` forms it; ``overwrite``: in
    ``hist`` itself."""
    out = hist if overwrite else hist.copy()
    out *= np.exp(-1j * np.fft.ifftshift(phi))[:, None]
    return fft_lines(out, out=out)
