"""PGA's candidate range lines and what is done to them each iteration (Wahl, Eichel, Ghiglia &
Jakowatz, IEEE TAES 30(3), 1994, steps 2–5): centre shift, window, line weights, the kernels'
integrated estimate, detrending and smoothing. The algorithm, its constants and its outcomes are
described in :mod:`budget.sar.pga`, which drives these steps."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.fft as sfft
from scipy.signal import savgol_coeffs

from .pga_kernels import (centroid_slope, line_weights, peak_shift, power, ramp_columns, ramp_in_place,
                          window_in_place)

# Fast-phase bands: the span is the bins where the candidate lines' energy is within 10 dB of its
# peak.
_SPAN_FRACTION = 0.1


_LN2 = float(np.log(2.0))


# Savitzky–Golay length of the increment smoothing in units of n/W (see _lowpass): increments are
# smoothed a little beyond the window's phase bandwidth.
_SG_STRETCH_INC = 2.5


_SG_MAX_FRACTION = 0.7


def _window_width(summed: np.ndarray, win_db: float, win_scale: float) -> int:
    """Width (samples) of the region around index 0 where ``summed`` stays within ``win_db``."""
    n = summed.size
    thr = summed[0] * 10 ** (-win_db / 10)
    below = summed[1:n // 2] < thr
    right = int(np.argmax(below)) if below.any() else n // 2
    below = summed[::-1][:n // 2] < thr
    left = int(np.argmax(below)) if below.any() else n // 2
    return int(np.ceil(win_scale * (right + left + 1)))


def _line_weights(pw: np.ndarray, rows: np.ndarray, c_line: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(SCR, kernel weight) per centre-shifted line (step 4) from the window's ``rows``. A
    clutter-only line centred on its brightest of n samples holds ≈ (W − 1 + H_n) c in a W-sample
    window (H_n ≈ ln n + 0.577, the mean maximum of n unit exponentials), so the SCR is counted
    beyond that bias b = (H_n − 1)/W; the weight SCR/(2 SCR + 1) per unit clutter then leaves
    clutter-only lines ≈ 0."""
    n = pw.shape[0]
    return line_weights(pw, rows, c_line, (np.log(n) + 0.5772 - 1.0) / max(rows.size, 1))


def _detrend(phi: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """``phi`` less its least-squares constant + linear term in the bin index, weighted (closed form)."""
    k = np.arange(phi.size, dtype=float)
    sw = weight.sum()
    if sw <= 0:
        return phi
    km, pm = (weight * k).sum() / sw, (weight * phi).sum() / sw
    var = (weight * (k - km) ** 2).sum()
    slope = (weight * (k - km) * (phi - pm)).sum() / var if var > 0 else 0.0
    return phi - pm - slope * (k - km)


@lru_cache(maxsize=128)
def _savgol_parts(length: int) -> tuple[np.ndarray, np.ndarray]:
    """(coefficients, end-fit operator) of a cubic Savitzky–Golay filter of ``length`` bins: the
    interior output is the dot product of the coefficients with the ``length`` bins around it; the
    ``length``//2 outputs at each end are the least-squares cubic through the first (last)
    ``length`` bins evaluated there (scipy's mode="interp")."""
    v = np.vander(np.arange(length, dtype=float), 4)
    return savgol_coeffs(length, 3, use="dot"), v @ np.linalg.pinv(v)


def _savgol(x: np.ndarray, length: int) -> np.ndarray:
    """Cubic Savitzky–Golay filter of ``length`` (odd, ≤ x.size) bins, mode="interp"."""
    coef, ends = _savgol_parts(length)
    half = length // 2
    out = np.empty_like(x)
    out[half:x.size - half] = np.correlate(x, coef, mode="valid")
    out[:half] = ends[:half] @ x[:length]
    out[x.size - half:] = ends[length - half:] @ x[x.size - length:]
    return out


def _lowpass(phi: np.ndarray, mask: np.ndarray, window: float, stretch: float = 1.0) -> np.ndarray:
    """``phi`` over the bins of ``mask`` (first to last) smoothed by a cubic Savitzky–Golay filter
    of ``stretch`` · n/``window`` bins, at most ``_SG_MAX_FRACTION`` of the span (longer, the
    local fit becomes one global cubic). Lines windowed to W samples carry phase that varies at
    most W/2 cycles per n bins (a W-sample function's DFT), so faster wiggles of an estimate are
    its noise; a cubic SG filter of L bins passes ≈ 2.5/L cycles per bin (−3 dB), so
    ``stretch`` = 5 matches that bandwidth. A local cubic keeps polynomial errors exact (a
    truncated DCT rings at the ends)."""
    idx = np.nonzero(mask)[0]
    if idx.size < 8 or window <= 0:
        return phi
    lo, hi = idx[0], idx[-1] + 1
    span = hi - lo
    length = min(int(stretch * phi.size / window), int(_SG_MAX_FRACTION * span)) | 1
    length = min(length, span if span % 2 else span - 1)
    if length < 7:
        return phi
    out = phi.copy()
    out[lo:hi] = _savgol(phi[lo:hi], length)
    return out


def _predicted_noise(scr: np.ndarray) -> float:
    """Per-bin rms (rad) of a common-phase estimate from lines of per-bin signal-to-clutter
    ratios ``scr``: 1/√(2 Σ SCR_r) (white clutter, high SCR; Jakowatz & Wahl 1993)."""
    total = float(np.sum(scr))
    return float(np.sqrt(0.5 / total)) if total > 0 else float("inf")


def _wrms(phi: np.ndarray, weight: np.ndarray) -> float:
    return float(np.sqrt(np.sum(weight * phi ** 2) / max(weight.sum(), 1e-300)))


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
        energy = (self.hist.real ** 2 + self.hist.imag ** 2).sum(axis=1)
        self.n_signal_bins = int(np.sum(energy >= _SPAN_FRACTION * energy.max()))


def _ramp_factors(n: int, shift: np.ndarray) -> np.ndarray:
    """z_l = e^{−j2π s_l/n} of the phase ramps e^{−j2π f_k s_l} that move line l by s_l samples
    (:func:`~budget.sar.pga_kernels.ramp_in_place` forms its powers)."""
    return np.exp(-2j * np.pi * np.asarray(shift, dtype=float) / n)


def _centre(d: _Lines, phi_np: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step 2, first part: (phase histories of the centre-shifted lines, the lines, their
    intensity) of the lines corrected with ``phi_np`` (numpy order): each line's brightest point
    (parabolic fit) moved to index 0 by a phase ramp on its phase history."""
    n = d.hist.shape[0]
    corr = d.hist * np.exp(-1j * phi_np)[:, None]
    ramp_in_place(corr, _ramp_factors(n, peak_shift(np.abs(sfft.fft(corr, axis=0)))))
    shifted = sfft.fft(corr, axis=0)
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
    slope = centroid_slope(shifted, rows, rot, cols)
    win = sfft.fft(ramp_columns(h_shift, cols, _ramp_factors(n, slope * n / (2.0 * np.pi))), axis=0)
    window_in_place(win, inside, np.sqrt(w_line[cols]))
    return used, win, sfft.ifft(win, axis=0)


def _integrated_estimate(d: _Lines, hist_w: np.ndarray, win: np.ndarray, prod: np.ndarray,
                         weight: np.ndarray) -> np.ndarray:
    """Phase estimate (centred bins, not detrended) from windowed lines ``win``, their phase
    histories ``hist_w`` (numpy order) and the ML kernel's line sums ``prod`` (centred bins,
    :func:`~budget.sar.pga_kernels.line_sums`) (step 4 and the integration of step 5)."""
    n = hist_w.shape[0]
    if d.kernel == "ml":
        dphi = np.angle(prod[1:]) * (weight[1:] > 0) * (weight[:-1] > 0)
        return np.concatenate([[0.0], np.cumsum(dphi)])
    big_g = np.fft.fftshift(hist_w, axes=0)
    d_g = np.fft.fftshift(sfft.ifft(win * (2j * np.pi * d.pos / n)[:, None], axis=0), axes=0)
    grad = np.where(weight > 0, np.imag(np.conj(big_g) * d_g).sum(axis=1) / np.maximum(weight, 1e-300), 0.0)
    return np.concatenate([[0.0], np.cumsum(0.5 * (grad[1:] + grad[:-1]))])
