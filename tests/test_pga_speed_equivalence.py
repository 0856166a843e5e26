"""PGA's faster paths give what the plain NumPy / scipy.fft expressions give: the one-pass image
power, the exact selection medians, the FFTs without scipy.fft's dispatch, the phase
correction."""

import numpy as np
import pytest
import scipy.fft as sfft

from budget.sar import pga_kernels as k
from budget.sar.pga import _median, apply_phase_correction
from budget.sar import pga_fast as fast
from budget.sar import pga_lines as lines
from budget.sar.pga_lines import fft_lines, ifft_lines

SHAPES = [(462, 135), (128, 128), (95, 7), (16, 2), (1000, 17)]


def _image(rng, shape):
    return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)


@pytest.mark.parametrize("shape", SHAPES)
def test_image_power_is_numpys_power_column_sums_and_peak(shape):
    """Bit for bit on two or more columns (PGA takes NumPy's sum for one)."""
    g = _image(np.random.default_rng(1), shape)
    power = g.real ** 2 + g.imag ** 2
    p, col, peak, finite = lines.image_power(g)
    assert np.array_equal(p, power) and np.array_equal(col, power.sum(axis=0))
    assert peak == power.max() and finite
    g[shape[0] // 2, 0] = complex(0.0, np.nan)
    assert not lines.image_power(g)[3]


@pytest.mark.parametrize("shape", SHAPES + [(16, 1)])
def test_selection_medians_equal_numpy_with_ties_and_zeros(shape):
    """Exactly np.median, also where the strided sample's bracket cannot hold the middle (half the
    values tied at zero) and with many ties."""
    rng = np.random.default_rng(2)
    for case in range(6):
        x = rng.random(shape) ** rng.uniform(1, 8)
        if case % 3 == 1:
            x = np.round(x * 10) / 10
        if case % 3 == 2:
            x[:, : max(shape[1] // 2, 1)] = 0.0
        assert lines.median_all(x) == np.median(x)
        cols = np.sort(rng.choice(shape[1], max(1, shape[1] // 3), replace=False))
        assert np.array_equal(lines.median_columns(x, cols), np.median(x[:, cols], axis=0))
        assert _median(x) == np.median(x)
        assert np.array_equal(_median(x, axis=0), np.median(x, axis=0))


@pytest.mark.parametrize("shape", [(462, 41), (128, 39), (95, 7)])
def test_line_ffts_are_scipy_ffts_bit_for_bit(shape):
    a = _image(np.random.default_rng(3), shape)
    assert np.array_equal(fft_lines(a), sfft.fft(a, axis=0))
    assert np.array_equal(ifft_lines(a), sfft.ifft(a, axis=0))
    b = a.copy()
    assert fft_lines(b, out=b) is b and np.array_equal(b, sfft.fft(a, axis=0))


def test_phase_correction_is_the_plain_expression():
    rng = np.random.default_rng(4)
    g = _image(rng, (128, 64))
    phi = rng.standard_normal(128)
    plain = sfft.fft(sfft.ifft(g, axis=0) * np.exp(-1j * np.fft.ifftshift(phi))[:, None], axis=0)
    assert np.array_equal(apply_phase_correction(g, phi), plain)
    g64 = g.astype(np.complex64)
    plain = sfft.fft(sfft.ifft(g64, axis=0) * np.exp(-1j * np.fft.ifftshift(phi))[:, None], axis=0)
    assert np.array_equal(apply_phase_correction(g64, phi), plain)


@pytest.mark.parametrize("shape", [(462, 41), (128, 39), (95, 7)])
def test_fused_line_kernels_equal_their_parts(shape):
    """The fused kernels of the iterations and the fast-phase bands give what their parts give, bit
    for bit (the bands' angles: NumPy's arctan2, to 1e-12 rad of the compiled one)."""
    from budget.sar.pga_lines import _SG_MAX_FRACTION, _savgol_parts, _window
    rng = np.random.default_rng(5)
    n, n_l = shape
    h = _image(rng, shape)
    shifted = fft_lines(h)
    pw = k.power(shifted)
    c_line = rng.random(n_l) * np.median(pw, axis=0)
    rows, rot, inside = _window(n, max(n // 6, 8))
    bias = (np.log(n) + 0.5772 - 1.0) / rows.size
    scr, w, cols = k.weights_and_lines(pw, rows, c_line, bias)
    scr0, w0 = k.line_weights(pw, rows, c_line, bias)
    assert np.array_equal(scr, scr0) and np.array_equal(w, w0) and np.array_equal(cols, np.flatnonzero(w0 > 0))
    summed = k.weighted_rows(pw, w0)
    assert k.measured_width(pw, rows, c_line, bias, 10.0, 1.5, 7) == k.window_width(summed, 10.0, 1.5)
    assert k.measured_width(pw, rows, c_line * 1e9, bias, 10.0, 1.5, 7) == 7  # no line weighs: fallback
    phi = rng.standard_normal(n)
    assert np.array_equal(fast.corrected_refine_ramp(shifted, h, rows, rot, cols, phi),
                          k.refine_ramp(shifted, k.phase_corrected(h, phi), rows, rot, cols))
    inc, weight, lo, hi, length = k.ml_step(h, 30.0, 16.0, 2.5, _SG_MAX_FRACTION)
    energy, prod = k.line_sums(h)
    inc0, weight0 = k.ml_increment(prod, energy, 30.0)
    assert np.array_equal(inc, inc0) and np.array_equal(weight, weight0)
    assert (lo, hi, length) == k.savgol_span(weight0, 16.0, 2.5, _SG_MAX_FRACTION)
    if length:
        rms = k.smoothed_rms(inc, weight, lo, hi, *_savgol_parts(int(length)))
        k.savgol_in_place(inc0, lo, hi, *_savgol_parts(int(length)))
        assert np.array_equal(inc, inc0) and rms == k.wrms(inc0, weight0)
    starts = np.arange(0, n_l, 2)
    im, re = fast.band_sums(h, 3, n - 3, starts)
    est, jk = fast.accumulate_phases(np.arctan2(im, re))
    est0, jk0 = k.band_phases(k.group_products(h, 3, n - 3, starts))
    assert np.abs(est - est0).max() < 1e-12 and np.abs(jk - jk0).max() < 1e-12


def test_dct_lines_is_scipys_orthonormal_dct():
    from budget.sar.pga_lines import dct_lines
    rng = np.random.default_rng(6)
    for a in (rng.standard_normal(300), rng.standard_normal((301, 7))):
        assert np.array_equal(dct_lines(a), sfft.dct(a, axis=0, norm="ortho"))
        assert np.array_equal(dct_lines(a, inverse=True), sfft.idct(a, axis=0, norm="ortho"))


def test_percentile_and_jackknife_noise_equal_numpy():
    from budget.sar.pga_fast import _percentile
    rng = np.random.default_rng(7)
    for n in range(1, 300):
        x = rng.random(n) ** 3
        assert _percentile(x, 5.0) == np.percentile(x, 5)
    coef = rng.standard_normal((60, 9))
    band = coef[4:21]
    expected = np.sum(8 / 9 * ((band - band.mean(axis=1, keepdims=True)) ** 2).sum(axis=1))
    assert abs(fast.jackknife_noise(coef, 3, 20) - expected) <= 1e-13 * expected
