"""Motion compensation of range-compressed data with the MEASURED trajectory (fast image former).

Two steps, as in real strip-map/spotlight processors:

1. first order (bulk, range-invariant): the line-of-sight range change to the scene centre C,
   Δr_c(t) = |p_meas(t) − C| − |p_nom(t) − C|, is removed by a range shift and a phase,
   D(t, f) · exp(+j 4π (f0 + f) Δr_c(t) / c);
2. second order (range-dependent phase): for each range bin r the change to the ground point at
   azimuth 0 and closest range r, Δr(t, r) − Δr_c(t), is removed by a phase exp(+j 4π(·)/λ);
   the envelope is not shifted again (the differential shift is a small fraction of a bin for
   offsets of metres).

What remains for a target at azimuth x ≠ 0 is δp · (u_target(t) − u_ref(t, r)), the motion
error times the change of line of sight across the scene: space-variant, not compensated here
(backprojection compensates it exactly per pixel). With measured = true it is the only error
left; with measured ≠ true the residual true − measured enters the data exactly like a real one.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ..units import range_to_phase, two_way_wavenumber_at_frequency_rad_m
from .complex_product import FUSED
from .geometry import SarGeometry
from .mocomp_kernels import first_order_product_into, second_order_in_place


def los_range_change_m(geom: SarGeometry, offset_m: np.ndarray, ground_points_m: np.ndarray) -> np.ndarray:
    """|p_nom + δp − P| − |p_nom − P| for every pulse and point: (n_pulses, n_points), m."""
    nom = geom.nominal_apc_m()
    d_off = np.linalg.norm((nom + offset_m)[:, None, :] - ground_points_m[None], axis=-1)
    d_nom = np.linalg.norm(nom[:, None, :] - ground_points_m[None], axis=-1)
    return d_off - d_nom


def motion_compensate(geom: SarGeometry, data: np.ndarray, measured_offset_m: np.ndarray) -> np.ndarray:
    """First- and second-order motion compensation to the nominal track (see module docstring)."""
    if not np.any(measured_offset_m):
        return data
    centre = geom.scene_centre_m[None, :]
    dr_c = los_range_change_m(geom, measured_offset_m, centre)[:, 0]
    f = np.fft.fftfreq(geom.n_range, 1.0 / geom.range_sample_rate_hz)
    spec = np.fft.fft(data, axis=1)
    k = two_way_wavenumber_at_frequency_rad_m(geom.carrier_frequency_hz + f, geom.c_m_s)
    spec *= np.exp(1j * k[None, :] * dr_c[:, None])
    out = np.fft.ifft(spec, axis=1)
    refs = geom.scene_point_m(np.zeros(geom.n_range), geom.range_axis_m)
    dr = los_range_change_m(geom, measured_offset_m, refs) - dr_c[:, None]
    out *= np.exp(-1j * range_to_phase(dr, geom.wavelength_m))
    return out


def cis(phase_rad: np.ndarray) -> np.ndarray:
    """e^{jφ} of a real array, built from cos and sin (cheaper than the complex exponential)."""
    phase_rad = np.asarray(phase_rad, dtype=float)
    out = np.empty(phase_rad.shape, dtype=complex)
    np.cos(phase_rad, out=out.real)
    np.sin(phase_rad, out=out.imag)
    return out


def _weights(pulse_weight: np.ndarray | None) -> np.ndarray:
    """Per-pulse weights as the compiled loop takes them (empty: none)."""
    return np.empty(0) if pulse_weight is None else np.ascontiguousarray(pulse_weight, dtype=float).ravel()


# NumPy's temporary elision threshold (NPY_MIN_ELIDE_BYTES)
_ELIDE_BYTES = 256 * 1024


class MotionCompensator:
    """:func:`motion_compensate` for one geometry and a stack of measured trajectories.

    The same two steps as :func:`motion_compensate` (see the module docstring); what does not
    depend on the trajectory is computed once: the nominal ranges to the scene centre and to the
    reference points of every range bin, and the range frequencies. The first-order phase
    exp(+j 4π (f0 + f_k) Δr_c / c) of the DFT bin f_k = k Δf, k = S·a + b (0 ≤ b < S), is the
    product (e^{jθ0} e^{jSθa}) · e^{jθb}, θ0 = 4π f0 Δr_c / c, θ = 4π Δf Δr_c / c: a few phasors
    per pulse and one complex product per sample instead of one complex exponential per sample
    (rounding ≈ 2 ulp). Input is the range spectrum of the data (DFT along range), so data that
    every trajectory shares is transformed once. The per-sample products and the second-order
    phase run as compiled loops (:mod:`budget.sar.mocomp_kernels`), without stack-sized temporaries.
    """

    #: S of the first-order factorisation k = S·a + b.
    STEP = 8

    def __init__(self, geom: SarGeometry):
        self.n_range = geom.n_range
        self.wavelength_m = geom.wavelength_m
        nom = geom.nominal_apc_m()
        self.nominal_apc_m = nom
        self.centre_m = np.asarray(geom.scene_centre_m, dtype=float)
        refs = geom.scene_point_m(np.zeros(geom.n_range), geom.range_axis_m)
        self.reference_points_m = refs
        self.nominal_centre_range_m = np.linalg.norm(nom - self.centre_m[None, :], axis=-1)
        self.nominal_reference_range_m = np.linalg.norm(nom[:, None, :] - refs[None], axis=-1)
        k = np.rint(np.fft.fftfreq(geom.n_range) * geom.n_range).astype(np.int64)  # f_k = k Δf
        a = np.floor_divide(k, self.STEP)
        self._a_values = np.arange(a.min(), a.max() + 1)
        self._b_values = np.arange(self.STEP)
        self._a_index = a - a.min()  # bin k → its (a, b) in the coarse and fine phasors
        self._b_index = k - a * self.STEP
        self.carrier_wavenumber_rad_m = two_way_wavenumber_at_frequency_rad_m(geom.carrier_frequency_hz, geom.c_m_s)
        self.bin_wavenumber_rad_m = two_way_wavenumber_at_frequency_rad_m(
            geom.range_sample_rate_hz / geom.n_range, geom.c_m_s)

    def centre_range_change_m(self, offset_m: np.ndarray) -> np.ndarray:
        """Δr_c = |p_nom + δp − C| − |p_nom − C| for stacked offsets (…, n_pulses, 3), m."""
        d = self.nominal_apc_m + offset_m - self.centre_m
        return np.sqrt(np.sum(d * d, axis=-1)) - self.nominal_centre_range_m

    def _phasors(self, dr_c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(coarse, fine) phasors of the first-order factor: e^{jθ0} e^{jSθa} for every a,
        e^{jθb} for b = 0 … S−1, (…, n_pulses, n_a) and (…, n_pulses, S)."""
        theta = self.bin_wavenumber_rad_m * dr_c[..., None]
        coarse = cis(self.carrier_wavenumber_rad_m * dr_c[..., None] + (self.STEP * self._a_values) * theta)
        return coarse, cis(self._b_values * theta)

    def apply(self, range_spectrum: np.ndarray, offset_m: np.ndarray,
              pulse_weight: np.ndarray | None = None) -> np.ndarray:
        """Motion-compensated data (B, n_pulses, n_range) from the range spectrum of the data
        ((n_pulses, n_range), shared, or (B, n_pulses, n_range)) and B measured offsets
        (B, n_pulses, 3) m; with ``pulse_weight`` (n_pulses,) each pulse is then multiplied by
        its weight (an azimuth window), in the same pass."""
        return self.apply_groups([range_spectrum], offset_m, pulse_weight)[0]

    def apply_groups(self, range_spectra, offset_m: np.ndarray,
                     pulse_weight: np.ndarray | None = None) -> np.ndarray:
        """:meth:`apply` to G data sets seen along the same B trajectories (e.g. a scene's echoes
        and the same echoes with receiver noise): (G, B, n_pulses, n_range), group g that of
        ``range_spectra[g]``. The phasors and the second-order phase of each trajectory are formed
        once for the G data sets; every number is that of :meth:`apply` on each alone."""
        off = np.asarray(offset_m, dtype=float)
        dr_c = self.centre_range_change_m(off)  # (B, n_pulses)
        coarse, fine = self._phasors(dr_c)
        shape = coarse.shape[:-1] + (self.n_range,)
        out = np.empty((len(range_spectra),) + shape, dtype=complex)
        for g, spectrum in enumerate(range_spectra):
            spec = np.asarray(spectrum, dtype=complex)
            # operand order of the former NumPy product spectrum · phasor: NumPy reused the phasor
            # temporary for a stacked spectrum of ≥ 256 KiB and then multiplied it first (its
            # temporary elision); the numbers stay those of that form to the last bit
            phasor_first = spec.ndim == 3 and spec.nbytes >= _ELIDE_BYTES
            first_order_product_into(out[g], np.broadcast_to(spec, shape), coarse, fine, self._a_index,
                                     self._b_index, FUSED, phasor_first)
        out = sfft.ifft(out, axis=-1, overwrite_x=True)
        p = self.nominal_apc_m + off  # reference points lie on x = 0, z = 0 at ground range y_r
        second_order_in_place(out, np.ascontiguousarray(p), np.ascontiguousarray(self.reference_points_m[:, 1]),
                              self.nominal_reference_range_m, np.ascontiguousarray(dr_c), -4.0 * math.pi,
                              self.wavelength_m, _weights(pulse_weight), FUSED)
        return out
