"""Closed-form signature increments of the effect library against independent computations.

Independent references: the exact Allan variance from an autocovariance
(:func:`budget.imu.flicker.avar_from_acov`, a direct double sum), ``allantools.oadev`` and
``scipy.signal.welch`` on simulated or deterministic series. Tolerances are stated per test.
"""

from __future__ import annotations

import math

import allantools
import numpy as np
import pytest
from scipy import signal, stats

from budget.gap import theory as th
from budget.gap.signatures import SignatureGrid, overlapping_avar, series_signature
from budget.imu.flicker import avar_from_acov, flicker_bank, gm_acov
from budget.noise import allan_deviation

DT = 0.01
RATE = 100.0
M = 2 ** np.arange(14)


@pytest.mark.parametrize("tau_c", [0.004, 0.03, 1.0, 100.0, 1e5])
def test_gauss_markov_avar_closed_form_equals_double_sum(tau_c):
    exact = avar_from_acov(lambda k: gm_acov(k, DT, [tau_c], [1.0]), M, DT)
    np.testing.assert_allclose(th.avar_gm(M, DT, tau_c)[0], exact, rtol=1e-4)


def test_flicker_avar_matches_bank_and_ieee_floor():
    n = 2 ** 16
    tau, var = flicker_bank(1.0, DT, DT * (n - 1))
    m = np.array([4, 16, 64, 256])
    exact = avar_from_acov(lambda k: gm_acov(k, DT, tau, var), m, DT)
    np.testing.assert_allclose(th.avar_flicker(m, DT, n), exact, rtol=1e-6)
    # IEEE 952: flat at 2 ln2/π · B² inside the band (the bank's documented ±1 %)
    np.testing.assert_allclose(th.avar_flicker(m, DT, n), 2 * math.log(2) / math.pi, rtol=0.03)


def test_rrw_and_ramp_and_white_avar_against_simulation():
    rng = np.random.default_rng(3)
    n, trials, k = 8192, 200, 2e-3
    walk = np.cumsum(rng.standard_normal((trials, n)) * k * math.sqrt(DT), axis=1)
    m = np.array([1, 8, 64, 512])
    est = np.mean([overlapping_avar(w, m) for w in walk], axis=0)
    # 200 trials: standard error of the mean AVAR ≤ 10 % at m = 512 (EDF ≈ 8 per trial)
    np.testing.assert_allclose(est, k ** 2 * th.avar_rrw(m, DT), rtol=0.12)
    ramp = 3e-3 * np.arange(n) * DT
    np.testing.assert_allclose(overlapping_avar(ramp, m), (3e-3 * m * DT) ** 2 / 2, rtol=1e-9)


def test_sinusoid_avar_exact_for_sampled_data():
    f, a = 3.7, 0.5
    n = 40_000
    t = np.arange(n) * DT
    m = np.array([1, 3, 10, 30, 100])
    phases = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    est = np.mean([overlapping_avar(a * np.sin(2 * np.pi * f * t + p), m) for p in phases], axis=0)
    np.testing.assert_allclose(est, a ** 2 * th.avar_sinusoid(m, DT, f), rtol=2e-3)


def test_sinusoid_and_ramp_psd_equal_welch():
    L, n = 1024, 20 * 1024
    f = th.welch_freqs(L, DT)
    t = np.arange(n) * DT
    phases = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    p = np.mean([signal.welch(np.sin(2 * np.pi * 3.37 * t + ph), fs=RATE, nperseg=L)[1] for ph in phases], axis=0)
    band = slice(int(3.37 / f[1]) - 4, int(3.37 / f[1]) + 5)
    np.testing.assert_allclose(p[band], th.psd_sinusoid(f, L, DT, 3.37)[band], rtol=0.02)
    assert np.sum(th.psd_sinusoid(f, L, DT, 3.37)) * f[1] == pytest.approx(0.5, rel=1e-3)  # A²/2
    ramp = 0.2 * t
    np.testing.assert_allclose(signal.welch(ramp, fs=RATE, nperseg=L)[1][4:40],
                               0.04 * th.psd_ramp(L, DT, n)[4:40], rtol=1e-9)


def test_gm_and_quantization_psd_integrate_to_variance():
    f = th.welch_freqs(1 << 14, DT)
    # one-sided PSD integrates (trapezoid rule) to the variance over 0…fs/2
    assert np.trapezoid(th.psd_gm(f, DT, 0.5), f) == pytest.approx(1.0, rel=1e-3)
    assert np.trapezoid(th.psd_quantization(f, DT), f) == pytest.approx(2.0 / DT ** 2, rel=1e-3)


def test_overlapping_avar_equals_noise_lab_and_allantools():
    x = np.random.default_rng(5).standard_normal(10_000)
    m = 2 ** np.arange(12)
    ours = overlapping_avar(x, m)
    np.testing.assert_allclose(ours, allan_deviation(x, RATE, taus=m / RATE).adev ** 2, rtol=1e-12)
    _, ad, _, _ = allantools.oadev(x, rate=RATE, data_type="freq", taus=m / RATE)
    np.testing.assert_allclose(ours, ad ** 2, rtol=1e-9)


def test_signature_of_gaussian_white_noise():
    n = 1 << 15
    grid = SignatureGrid.for_log(n, RATE)
    x = 5.0 + np.random.default_rng(8).standard_normal(n) * 0.1
    sig = series_signature(x, grid)
    assert abs(sig.kurtosis) < 5 * math.sqrt(27 / n)
    # k_N puts 5 expected Gaussian exceedances in the record
    assert stats.norm.sf(grid.tail_k) * 2 * n == pytest.approx(5.0, rel=1e-9)
    assert sig.tail_count < 20
    assert sig.sigma_r == pytest.approx(0.1 * math.sqrt(2), rel=0.03)
    assert abs(sig.slope) < 5 * 0.1 * math.sqrt(12 / (n * (n / RATE) ** 2))  # OLS slope SE
    np.testing.assert_allclose(sig.psd[grid.band_start[0]:grid.bin_stop].mean(), 2 * 0.1 ** 2 / RATE, rtol=0.03)


@pytest.mark.parametrize("tau_c", [0.02, 0.3])
def test_avar_and_diff_var_from_psd_equal_the_exact_ar1_values(tau_c):
    """The spectral kernels behind ``lowpass`` (Allan variance and first-difference variance of a
    series from its one-sided PSD) against the exact AR(1) values: avar_gm (checked above by
    a double sum) and 2σ²(1 − φ). A fine rfft grid (2¹⁶ points): agreement to 0.5 %."""
    freq = np.fft.rfftfreq(1 << 16, DT)
    psd = th.psd_gm(freq, DT, tau_c)
    m = M[:10]
    np.testing.assert_allclose(th.avar_from_psd(psd, freq, m, DT), th.avar_gm(m, DT, tau_c)[0], rtol=5e-3)
    phi = math.exp(-DT / tau_c)
    assert th.diff_var_from_psd(psd, freq, DT) == pytest.approx(2.0 * (1.0 - phi), rel=5e-3)
