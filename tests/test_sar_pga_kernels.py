"""PGA's compiled loops (budget/sar/pga_kernels.py) against the NumPy expressions they replace,
on seeded random inputs of the Monte Carlo's and the image chips' shapes, odd and even lengths."""

import numpy as np
import pytest

from budget.sar import pga_kernels as k

SHAPES = [(462, 41), (128, 39), (95, 7), (16, 1)]


def _lines(rng, shape):
    return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)


@pytest.mark.parametrize("shape", SHAPES)
def test_peak_shift_is_argmax_plus_the_parabolic_offset(shape):
    rng = np.random.default_rng(1)
    mag = np.abs(_lines(rng, shape))
    n = shape[0]
    cols = np.arange(shape[1])
    peaks = np.argmax(mag, axis=0)
    a_m, a_0, a_p = mag[(peaks - 1) % n, cols], mag[peaks, cols], mag[(peaks + 1) % n, cols]
    den = a_m - 2 * a_0 + a_p
    expected = peaks + np.where(den < 0, 0.5 * (a_m - a_p) / np.where(den < 0, den, -1.0), 0.0)
    assert np.array_equal(k.peak_shift(mag), expected)
    assert k.peak_shift(np.zeros(shape)).tolist() == [0.0] * shape[1]  # ties: the first, as argmax


@pytest.mark.parametrize("shape", SHAPES)
def test_ramps_equal_the_direct_exponential(shape):
    """The powers formed by sequential products agree with e^{−j2π f_k s} to 1e-11 (n ≤ 462)."""
    rng = np.random.default_rng(2)
    n, n_l = shape
    h = _lines(rng, shape)
    shift = rng.uniform(-n, n, n_l)
    direct = h * np.exp(-2j * np.pi * np.fft.fftfreq(n)[:, None] * shift[None, :])
    z = np.exp(-2j * np.pi * shift / n)
    inplace = h.copy()
    k.ramp_in_place(inplace, z)
    assert np.abs(inplace - direct).max() < 1e-11
    cols = np.arange(n_l)[::2]
    assert np.abs(k.ramp_columns(h, cols, z[cols]) - direct[:, cols]).max() < 1e-11


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
    scale = rng.random(n_l)
    win = a.copy()
    k.window_in_place(win, inside, scale)
    assert np.array_equal(win, np.where(inside[:, None], a * scale[None, :], 0.0))
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
