"""PGA's compiled loops (budget/sar/pga_kernels.py) against the NumPy expressions they replace,
on seeded random inputs of the Monte Carlo's and the image chips' shapes, odd and even lengths."""

import numpy as np
import pytest

from budget.sar import pga_kernels as k

SHAPES = [(462, 41), (128, 39), (95, 7), (16, 1)]


def _lines(rng, shape):
    return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)


def _direct_ramp(h, shift):
    n = h.shape[0]
    return h * np.exp(-2j * np.pi * np.fft.fftfreq(n)[:, None] * np.asarray(shift)[None, :])


@pytest.mark.parametrize("shape", SHAPES)
def test_centre_in_place_moves_each_line_by_argmax_plus_the_parabolic_offset(shape):
    """The shift is argmax |spec| plus 0.5 (a₋ − a₊)/(a₋ − 2a₀ + a₊) (0 where that denominator
    is ≥ 0), and the line is ramped by e^{−j2π f_k s}; the powers formed by sequential products
    agree with the direct exponential to 1e-11 (n ≤ 462). Ties go to the first maximum."""
    rng = np.random.default_rng(1)
    h = _lines(rng, shape)
    spec = np.fft.fft(h, axis=0)
    mag = np.abs(spec)
    n = shape[0]
    cols = np.arange(shape[1])
    peaks = np.argmax(mag, axis=0)
    a_m, a_0, a_p = mag[(peaks - 1) % n, cols], mag[peaks, cols], mag[(peaks + 1) % n, cols]
    den = a_m - 2 * a_0 + a_p
    shift = peaks + np.where(den < 0, 0.5 * (a_m - a_p) / np.where(den < 0, den, -1.0), 0.0)
    got = h.copy()
    k.centre_in_place(got, spec)
    assert np.abs(got - _direct_ramp(h, shift)).max() < 1e-11
    flat = h.copy()
    k.centre_in_place(flat, np.ones(shape, complex))  # every sample ties: index 0, no shift
    assert np.array_equal(flat, h)


@pytest.mark.parametrize("shape", SHAPES)
def test_refine_ramp_moves_the_selected_lines_by_their_centroid(shape):
    rng = np.random.default_rng(2)
    n, n_l = shape
    h = _lines(rng, shape)
    shifted = np.fft.fft(h, axis=0)
    rows = np.flatnonzero(np.abs(np.fft.fftfreq(n) * n) <= max(n // 6, 1))
    rot = np.exp(2j * np.pi * rows / n)
    cols = np.arange(n_l)[::2]
    slope = k.centroid_slope(shifted, rows, rot, cols)
    expected = _direct_ramp(h[:, cols], slope * n / (2 * np.pi))
    assert np.abs(k.refine_ramp(shifted, h, rows, rot, cols) - expected).max() < 1e-11


@pytest.mark.parametrize("shape", SHAPES)
def test_phase_corrected_is_the_ifftshifted_phasor(shape):
    rng = np.random.default_rng(7)
    h = _lines(rng, shape)
    phi = rng.uniform(-20, 20, shape[0])
    expected = h * np.exp(-1j * np.fft.ifftshift(phi))[:, None]
    assert np.abs(k.phase_corrected(h, phi) - expected).max() < 1e-14


@pytest.mark.parametrize("shape", SHAPES)
def test_centroid_slope_is_the_mean_phase_increment_of_the_windowed_history(shape):
    """The image-domain form equals arg Σ_k h(k+1) h*(k) of h = IDFT(windowed line), k = 0 … n−2."""
    rng = np.random.default_rng(3)
    n, n_l = shape
    shifted = _lines(rng, shape)
    rows = np.flatnonzero(np.abs(np.fft.fftfreq(n) * n) <= max(n // 6, 1))
    cols = np.arange(n_l)[::2]
    got = k.centroid_slope(shifted, rows, np.exp(2j * np.pi * rows / n), cols)
    win = np.zeros((n, cols.size), complex)
    win[rows] = shifted[rows][:, cols]
    h = np.fft.ifft(win, axis=0)
    expected = np.angle((h[1:] * np.conj(h[:-1])).sum(axis=0))
    assert np.allclose(np.exp(1j * got), np.exp(1j * expected), atol=1e-9)


@pytest.mark.parametrize("shape", SHAPES)
def test_window_power_and_line_sums(shape):
    rng = np.random.default_rng(4)
    n, n_l = shape
    a = _lines(rng, shape)
    inside = rng.random(n) < 0.3
    w_line = rng.random(n_l + 3)
    cols = np.arange(n_l) + 3 * (n_l > 1)
    cols = cols[cols < w_line.size]
    win = a[:, :cols.size].copy()
    k.window_in_place(win, inside, w_line, cols)
    assert np.array_equal(win, np.where(inside[:, None], a[:, :cols.size] * np.sqrt(w_line[cols])[None, :], 0.0))
    assert np.array_equal(k.power(a), a.real ** 2 + a.imag ** 2)
    energy, prod = k.line_sums(a)
    g = np.fft.fftshift(a, axes=0)
    assert np.allclose(energy, (np.abs(g) ** 2).sum(axis=1), rtol=1e-12)
    assert prod[0] == 0
    assert np.allclose(prod[1:], (g[1:] * np.conj(g[:-1])).sum(axis=1), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("shape", SHAPES)
def test_line_weights_weighted_rows_and_group_products(shape):
    rng = np.random.default_rng(5)
    n, n_l = shape
    pw = rng.random(shape) * 10.0
    rows = np.flatnonzero(np.abs(np.fft.fftfreq(n) * n) <= max(n // 8, 1))
    c_line = rng.random(n_l) + 0.5
    bias = (np.log(n) + 0.5772 - 1.0) / rows.size
    scr_exp = np.maximum(pw[rows].sum(axis=0) / (rows.size * c_line) - 1.0 - bias, 0.0)
    scr, weight = k.line_weights(pw, rows, c_line, bias)
    assert np.allclose(scr, scr_exp, rtol=1e-12, atol=1e-15)
    assert np.allclose(weight, scr_exp / (2 * scr_exp + 1) / (rows.size * c_line), rtol=1e-12, atol=1e-15)
    w = rng.random(n_l)
    assert np.allclose(k.weighted_rows(pw, w), pw @ w, rtol=1e-12)
    h = _lines(rng, shape)
    g = np.fft.fftshift(h, axes=0)
    starts = np.unique(np.r_[0, rng.integers(0, n_l, 3)])
    lo, hi = n // 5, n - n // 7
    expected = np.add.reduceat(g[lo + 1:hi] * np.conj(g[lo:hi - 1]), starts, axis=1)
    assert np.allclose(k.group_products(h, lo, hi, starts), expected, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("shape", [(462, 135), (128, 128), (95, 7), (16, 1)])
def test_pga_median_equals_numpy(shape):
    """PGA's one-partition median equals np.median exactly, whole array and per column."""
    from budget.sar.pga import _median
    x = np.random.default_rng(6).random(shape) ** 4
    assert _median(x) == np.median(x)
    assert np.array_equal(_median(x, axis=0), np.median(x, axis=0))


def _np_detrend(phi, weight):
    x = np.arange(phi.size, dtype=float)
    if weight.sum() <= 0:
        return phi
    coef = np.polyfit(x, phi, 1, w=np.sqrt(weight))  # independent: weighted least squares
    return phi - np.polyval(coef, x)


@pytest.mark.parametrize("n", [462, 128, 95, 16])
def test_detrend_and_ml_increment(n):
    """detrend equals a weighted least-squares line fit (np.polyfit, weights √w) removed; the ML
    increment is the cumulative arg of the products between bins within band_db of the peak
    energy, detrended with that energy; wrms is the weighted rms."""
    rng = np.random.default_rng(8)
    phi = rng.standard_normal(n).cumsum() + 0.3 * np.arange(n)
    weight = rng.random(n) ** 3
    assert np.allclose(k.detrend(phi, weight), _np_detrend(phi, weight), atol=1e-9)
    assert np.array_equal(k.detrend(phi, np.zeros(n)), phi)
    prod = _lines(rng, (n,))
    energy = 10 ** (rng.uniform(-5, 0, n))
    inc, w = k.ml_increment(prod, energy, 30.0)
    w_exp = np.where(energy >= energy.max() * 1e-3, energy, 0.0)
    assert np.array_equal(w, w_exp)
    assert np.array_equal(k.band_weight(energy, 30.0), w_exp)
    dphi = np.angle(prod[1:]) * (w_exp[1:] > 0) * (w_exp[:-1] > 0)
    assert np.allclose(inc, _np_detrend(np.r_[0.0, np.cumsum(dphi)], w_exp), atol=1e-9)
    assert np.isclose(k.wrms(inc, w_exp), np.sqrt(np.sum(w_exp * inc ** 2) / w_exp.sum()), rtol=1e-12)


def test_savgol_span_and_filter_match_scipy():
    """savgol_in_place over the span equals scipy's savgol_filter(mode="interp") of the span;
    the span runs from the first to the last bin with weight ≥ 0.1 × the peak, and the length is
    min(stretch·n/window, 0.7·span), odd, ≤ span; too short or too few bins: length 0."""
    from scipy.signal import savgol_filter
    from budget.sar.pga_lines import _savgol_parts
    rng = np.random.default_rng(11)
    for n, lo, hi, window in ((462, 60, 373, 10.0), (128, 20, 84, 30.0), (200, 50, 151, 8.0)):
        weight = np.zeros(n)
        weight[lo:hi] = 0.5 + rng.random(hi - lo)
        weight[lo] = weight[hi - 1] = 1.0
        span = hi - lo
        length = min(int(2.5 * n / window), int(0.7 * span)) | 1
        length = min(length, span if span % 2 else span - 1)
        assert k.savgol_span(weight, window, 2.5, 0.7) == (lo, hi, length)
        x = rng.standard_normal(n)
        got = x.copy()
        k.savgol_in_place(got, lo, hi, *_savgol_parts(length))
        assert np.allclose(got[lo:hi], savgol_filter(x[lo:hi], length, 3, mode="interp"), atol=1e-12)
        assert np.array_equal(got[:lo], x[:lo]) and np.array_equal(got[hi:], x[hi:])
    few = np.zeros(100)
    few[10:17] = 1.0
    assert k.savgol_span(few, 10.0, 2.5, 0.7) == (0, 0, 0)  # 7 bins < 8
    assert k.savgol_span(np.ones(100), 1000.0, 2.5, 0.7) == (0, 0, 0)  # length < 7


@pytest.mark.parametrize("n", [462, 128, 17, 16])
def test_window_width_matches_the_threshold_search(n):
    rng = np.random.default_rng(12)
    for _ in range(20):
        summed = np.roll(np.exp(-0.5 * ((np.arange(n) - n // 2) / rng.uniform(0.5, n / 3)) ** 2), -(n // 2))
        summed *= 1 + 0.2 * rng.random(n)
        thr = summed[0] * 0.1
        below = summed[1:n // 2] < thr
        right = int(np.argmax(below)) if below.any() else n // 2
        below = summed[::-1][:n // 2] < thr
        left = int(np.argmax(below)) if below.any() else n // 2
        assert k.window_width(summed, 10.0, 1.5) == int(np.ceil(1.5 * (right + left + 1)))


def test_group_starts_and_band_phases():
    rng = np.random.default_rng(13)
    groups = np.array([0, 0, 1, 2, 2, 2, 3, 4, 4])
    keep = np.array([True, False, True, False, True, True, True, True, False])
    assert np.array_equal(k.group_starts(groups, keep), np.flatnonzero(np.diff(groups[keep], prepend=-1)))
    assert k.group_starts(groups, np.zeros(9, bool)).size == 0
    per_group = _lines(rng, (50, 4))
    est, jk = k.band_phases(per_group)
    total = per_group.sum(axis=1)
    assert np.allclose(est, np.r_[0.0, np.cumsum(np.angle(total))], atol=1e-12)
    jk_exp = np.vstack([np.zeros((1, 4)), np.cumsum(np.angle(total[:, None] - per_group), axis=0)])
    assert np.allclose(jk, jk_exp, atol=1e-12)
