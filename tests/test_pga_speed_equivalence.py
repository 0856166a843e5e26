"""PGA's faster paths give what the plain NumPy / scipy.fft expressions give: the one-pass image
power, the exact selection medians, the FFTs without scipy.fft's dispatch, the phase
correction."""

import numpy as np
import pytest
import scipy.fft as sfft

from budget.sar import pga_kernels as k
from budget.sar.pga import _median, apply_phase_correction
from budget.sar.pga_lines import fft_lines, ifft_lines

SHAPES = [(462, 135), (128, 128), (95, 7), (16, 2), (1000, 17)]


def _image(rng, shape):
    return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)


@pytest.mark.parametrize("shape", SHAPES)
def test_image_power_is_numpys_power_column_sums_and_peak(shape):
    """Bit for bit on two or more columns (PGA takes NumPy's sum for one)."""
    g = _image(np.random.default_rng(1), shape)
    power = g.real ** 2 + g.imag ** 2
    p, col, peak, finite = k.image_power(g)
    assert np.array_equal(p, power) and np.array_equal(col, power.sum(axis=0))
    assert peak == power.max() and finite
    g[shape[0] // 2, 0] = complex(0.0, np.nan)
    assert not k.image_power(g)[3]


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
        assert k.median_all(x) == np.median(x)
        cols = np.sort(rng.choice(shape[1], max(1, shape[1] // 3), replace=False))
        assert np.array_equal(k.median_columns(x, cols), np.median(x[:, cols], axis=0))
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
