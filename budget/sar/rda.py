"""Range-Doppler image formation for the nominal straight track (Cumming & Wong 2005, ch. 6–8).

Input: motion-compensated, range-compressed data d(t_n, r_j). Steps (f_η Doppler, f_r range
frequency, F = sqrt((f0 + f_r)² − (c f_η / 2V)²), D(f_η) = sqrt(1 − (λ f_η / 2V)²)):

1. azimuth window over slow time (zero-padded to ``geom.n_azimuth`` samples when the scene is
   wider than the aperture), 2-D FFT;
2. bulk focusing at the reference range R_c, exact in the 2-D frequency domain (range-cell
   migration correction and secondary range compression for R_c):
   H_ref = exp(+j 4π R_c (F − f_r) / c)   (Cumming & Wong eq. 8.3, the ω-k reference function);
3. back to range: a target at R_c + ΔR now lies at R_c + ΔR/D(f_η); the residual, range-variant
   migration ΔR (1/D − 1) is removed by 8-tap windowed-sinc interpolation (skipped when it is
   below 0.02 bin everywhere);
4. residual azimuth matched filter exp(+j 4π ΔR D / λ), so that the total azimuth filter is the
   exact hyperbolic one exp(+j 4π r D / λ) of each range bin;
5. gain e^{jπ/4} PRF / (√K_a(r) Σ w_n) (stationary-phase amplitude), so that a unit target
   peaks at 1 with its own phase, as in backprojection; azimuth inverse FFT.

The differential secondary range compression of targets away from R_c is neglected (phase
≈ 4πΔR sin²θ f_r² / (2 c f0) at most, far below 0.1 rad for the presets).
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft
from scipy import sparse

from ..units import two_way_wavenumber_at_frequency_rad_m, two_way_wavenumber_rad_m
from .geometry import SarGeometry

_TAPS = 8


def _sinc_resample(data: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """Sample each row of ``data`` (circular) at fractional bin positions ``pos`` (same shape)."""
    n = data.shape[1]
    base = np.floor(pos).astype(np.int64)
    frac = pos - base
    k = np.arange(-_TAPS // 2 + 1, _TAPS // 2 + 1)
    d = frac[..., None] - k  # distance from each tap
    h = np.sinc(d) * (0.5 + 0.5 * np.cos(np.pi * d / (_TAPS // 2 + 1)))
    h /= h.sum(axis=-1, keepdims=True)
    idx = np.mod(base[..., None] + k, n)
    rows = np.arange(data.shape[0])[:, None, None]
    return np.einsum("ijk,ijk->ij", data[rows, idx], h)


def _focus_factors(geom: SarGeometry) -> dict:
    """What the range-Doppler steps 1–5 need from the geometry alone: azimuth window, zero-padding,
    H_ref (step 2), the residual-migration positions in bins (step 3; None below 0.02 bin), and
    the residual azimuth matched filter times the gain (steps 4–5)."""
    lam, c, v = geom.wavelength_m, geom.c_m_s, geom.speed_m_s
    f0, r_c = geom.carrier_frequency_hz, geom.ref_range_m
    w_a = geom.window_azimuth.samples(geom.n_pulses)
    n_az = geom.n_azimuth
    f_eta = np.fft.fftfreq(n_az, 1.0 / geom.prf_hz)
    f_r = np.fft.fftfreq(geom.n_range, 1.0 / geom.range_sample_rate_hz)
    big_f = np.sqrt((f0 + f_r)[None, :] ** 2 - (c * f_eta / (2 * v))[:, None] ** 2)
    h_ref = np.exp(1j * two_way_wavenumber_at_frequency_rad_m(big_f - f_r[None, :], c) * r_c)
    dee = np.sqrt(1.0 - (lam * f_eta / (2 * v)) ** 2)
    d_r = geom.range_axis_m - r_c
    shift = d_r[None, :] * (1.0 / dee[:, None] - 1.0) / geom.range_bin_m
    pos = np.arange(geom.n_range)[None, :] + shift if np.max(np.abs(shift)) > 0.02 else None
    k_a = 2.0 * v ** 2 / (lam * geom.range_axis_m)
    gain = np.exp(1j * np.pi / 4) * geom.prf_hz / (np.sqrt(k_a) * w_a.sum())
    az_filter = np.exp(1j * two_way_wavenumber_rad_m(lam) * d_r[None, :] * dee[:, None]) * gain[None, :]
    return {"window": w_a, "pad": (n_az - geom.n_pulses) // 2, "reference_function": h_ref,
            "resample_positions": pos, "azimuth_filter": az_filter}


def range_doppler(geom: SarGeometry, data: np.ndarray) -> np.ndarray:
    """Focused complex image (n_azimuth, n_range) on ``geom.image_azimuth_axis_m`` × r_j;
    a unit target peaks at 1."""
    fac = _focus_factors(geom)
    w_a, pad, n_az = fac["window"], fac["pad"], geom.n_azimuth  # pad > 0: scene wider than the aperture
    if pad:
        padded = np.zeros((n_az, geom.n_range), dtype=complex)
        padded[pad:pad + geom.n_pulses] = data * w_a[:, None]
        s = sfft.fft2(padded)
    else:
        s = sfft.fft2(data * w_a[:, None])
    s *= fac["reference_function"]
    s = sfft.ifft(s, axis=1)
    if fac["resample_positions"] is not None:
        s = _sinc_resample(s, fac["resample_positions"])
    s *= fac["azimuth_filter"]
    return sfft.ifft(s, axis=0)


def _resample_operator(pos: np.ndarray) -> sparse.csr_matrix:
    """The linear map of :func:`_sinc_resample` (rows of ``pos``'s shape, flattened) as a sparse
    real matrix: output sample (i, j) = Σ_k h_ijk · input (i, idx_ijk)."""
    n_rows, n = pos.shape
    base = np.floor(pos).astype(np.int64)
    frac = pos - base
    k = np.arange(-_TAPS // 2 + 1, _TAPS // 2 + 1)
    d = frac[..., None] - k
    h = np.sinc(d) * (0.5 + 0.5 * np.cos(np.pi * d / (_TAPS // 2 + 1)))
    h /= h.sum(axis=-1, keepdims=True)
    cols = np.mod(base[..., None] + k, n) + n * np.arange(n_rows)[:, None, None]
    rows = np.broadcast_to(np.arange(n_rows * n).reshape(n_rows, n, 1), cols.shape)
    return sparse.csr_matrix((h.ravel(), (rows.ravel(), cols.ravel())), shape=(n_rows * n, n_rows * n))


class RangeDopplerPlan:
    """:func:`range_doppler` for one geometry and a stack of data sets (B, n_pulses, n_range).

    The same steps 1–5 (module docstring), with everything that depends only on the geometry
    computed once: the azimuth window, the reference function H_ref, the residual-migration
    interpolator (a sparse matrix of the 8-tap kernels), and the residual azimuth matched filter
    times the gain. The transforms run along the trailing axes of the stack.
    """

    def __init__(self, geom: SarGeometry):
        fac = _focus_factors(geom)
        self.n_pulses, self.n_range, self.n_azimuth = geom.n_pulses, geom.n_range, geom.n_azimuth
        self.pad = fac["pad"]
        self.window = fac["window"][:, None]
        self.reference_function = fac["reference_function"]
        pos = fac["resample_positions"]
        self.resample = None if pos is None else _resample_operator(pos)
        self.azimuth_filter = fac["azimuth_filter"]

    def range_compressed_spectrum(self, data: np.ndarray, windowed: bool = False) -> np.ndarray:
        """Steps 1–3 up to the range inverse DFT: (B, n_azimuth, n_range) in (f_η, r);
        ``windowed``: ``data`` already carries the azimuth window (``self.window``)."""
        data = np.asarray(data)
        weighted = data if windowed else data * self.window
        if self.pad:
            padded = np.zeros(data.shape[:-2] + (self.n_azimuth, self.n_range), dtype=complex)
            padded[..., self.pad:self.pad + self.n_pulses, :] = weighted
            s = sfft.fft2(padded, axes=(-2, -1))
        else:
            s = sfft.fft2(weighted, axes=(-2, -1))
        s *= self.reference_function
        return sfft.ifft(s, axis=-1, overwrite_x=True)

    def __call__(self, data: np.ndarray, windowed: bool = False) -> np.ndarray:
        """Focused images (B, n_azimuth, n_range) of motion-compensated data (B, n_pulses, n_range)
        (``windowed``: already multiplied by the azimuth window)."""
        s = self.range_compressed_spectrum(data, windowed)
        if self.resample is not None:
            lead = s.shape[:-2]
            flat = np.ascontiguousarray(s.reshape(-1, self.n_azimuth * self.n_range).T)  # (N, B)
            out = self.resample @ flat.view(float)  # real kernels act on re and im alike
            s = np.ascontiguousarray(out.view(complex).T).reshape(lead + (self.n_azimuth, self.n_range))
        s *= self.azimuth_filter
        return sfft.ifft(s, axis=-2, overwrite_x=True)
