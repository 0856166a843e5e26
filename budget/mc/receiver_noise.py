"""Receiver noise of one Monte Carlo trial, drawn apart from the noise-free echoes.

The echoes of a scene from the nominal track do not depend on the trial, so they are simulated
once per setup (:class:`budget.mc.chain.ChainSetup`); each trial adds only its own receiver noise
— the noise term of :func:`budget.sar.simulate_echoes` alone, at the same level and with the same
range window — drawn from the trial's own stream.
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from ..sar import SarGeometry


def receiver_noise_scale(geom: SarGeometry, snr_db: float) -> np.ndarray:
    """Scale of the unit normal draws of :func:`receiver_noise_spectrum` on each in-band range
    bin (``geom.range_band_index``), for the real and the imaginary part alike: the noise level
    at ``snr_db`` with the range window."""
    w_r = geom.window_range.samples(geom.band_bins)
    w_a = geom.window_azimuth.samples(geom.n_pulses)
    var_rc = (w_a.sum() ** 2 / (w_a ** 2).sum()) / 10.0 ** (snr_db / 10.0)
    s2 = var_rc * w_r.sum() ** 2 / (w_r ** 2).sum()
    return np.sqrt(s2 / 2.0) * w_r * (geom.n_range / w_r.sum())


def receiver_noise_draws(geom: SarGeometry, rng: np.random.Generator) -> np.ndarray:
    """The unit normal draws of one trial's receiver noise, (n_pulses, band_bins, 2): real and
    imaginary part of each in-band range bin of each pulse."""
    return rng.standard_normal((geom.n_pulses, geom.band_bins, 2))


def receiver_noise_spectrum(geom: SarGeometry, snr_db: float, rng: np.random.Generator) -> np.ndarray:
    """Range spectrum (DFT along range, (n_pulses, n_range)) of :func:`receiver_noise_echoes`: the
    same draws, for image formers that take range spectra."""
    noise = receiver_noise_draws(geom, rng).view(complex)[..., 0]  # re, im pairs
    full = np.zeros((geom.n_pulses, geom.n_range), dtype=complex)
    full[:, geom.range_band_index] = noise * receiver_noise_scale(geom, snr_db)[None, :]
    return full


def receiver_noise_echoes(geom: SarGeometry, snr_db: float, rng: np.random.Generator) -> np.ndarray:
    """Range-compressed receiver noise (n_pulses, n_range) at ``snr_db`` — the noise term of
    :func:`budget.sar.simulate_echoes` alone (same level and range window), so the noise-free
    echoes of a scene can be computed once and each trial adds only its own noise."""
    return sfft.ifft(receiver_noise_spectrum(geom, snr_db, rng), axis=1)
